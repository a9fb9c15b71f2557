"""Certified sign of ``Re Z(jω)`` of a delayed impedance over ``ω ∈ (0, ∞)`` at a fixed delay.

The half-line is cut into three parts, each decided by a proof:

1. ``ω → 0``: exact Taylor polynomials with a rigorous remainder
   ([`lowfreq`][seapass.delay.lowfreq]) prove ``F > 0`` on ``(0, ω0]`` or give an exact
   witness;
2. ``ω → ∞``: the exact leading trigonometric term
   ([`highfreq`][seapass.delay.highfreq]) proves ``F > 0`` beyond ``ω1`` for every delay,
   or shows that every delay ``τ > 0`` makes ``F`` negative at arbitrarily high frequencies
   (then a witness is found there);
3. the compact middle ``[ω0, ω1]`` (for a delay to the first power, only the dangerous
   band, [`bands`][seapass.delay.bands]): interval arithmetic with arb balls on
   sub-intervals, each ball a mean-value form ``F(c) + F'(I)(I - c)``, bisected until its
   sign is proven, with a counted budget and a precision ladder.

"Positive" is returned only when every piece is proven; a proven negative value
``F(ω) < 0`` (a ball entirely below zero at a rational ``ω``) is the witness; anything else
is undecided.

Examples
--------
>>> from fractions import Fraction
>>> from seapass.delay.structure import delayed_impedance
>>> from seapass.delay.trig import real_part
>>> z = delayed_impedance("m*s + b + K*exp(-tau*s)/s", values=dict(m=1, b=2, K=50, tau=0.03))
>>> certify(real_part(z), z.tau).outcome
<Outcome.PASSIVE: 'passive'>
>>> certify(real_part(z), ep.rational(Fraction(1, 20))).outcome   # b < K tau
<Outcome.NOT_PASSIVE: 'not_passive'>
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from flint import arb, fmpq

from ..errors import DelayError
from ..exact import poly as ep
from ..exact.axis import even_to_x, negative_point
from ..files.limits import MAX_DELAY_PIECES
from ..outcome import Outcome
from .balls import PRECISIONS, arb_of, ball, precision
from .bands import dangerous_bands
from .highfreq import HighFrequency, high_frequency
from .lowfreq import at_fixed_delay
from .trig import TrigRealPart

__all__ = [
    "DEFAULT_BUDGET",
    "MAX_PIECES",
    "SignCertificate",
    "certify",
    "negative_intervals",
    "scan_pieces",
    "witness_in_bands",
]

DEFAULT_BUDGET = 200_000
"""Sub-intervals evaluated before the answer is undecided (a count, not a time)."""

MAX_PIECES = MAX_DELAY_PIECES
"""`seapass.files.limits.MAX_DELAY_PIECES`: pieces of the middle range (``θ = ωτ`` advances
at most 1 rad per piece); a delay so long that ``Re Z`` oscillates more often is refused."""


LOSSLESS = "lossless"
"""The ``reason`` of a certificate whose real part vanishes identically."""


@dataclass(frozen=True, kw_only=True)
class SignCertificate:
    """Outcome of `certify`.

    ``witness``: a rational ``ω`` with ``F(ω) < 0`` proven; ``reason`` for undecided ones;
    ``omega0``/``omega1``: the ends of the scanned middle; ``negative``: sub-intervals
    proven negative (``collect=True`` only).
    """

    outcome: Outcome
    witness: fmpq | None = None
    reason: str = ""
    evaluations: int = 0
    precision: int = 0
    omega0: fmpq | None = None
    omega1: fmpq | None = None
    negative: tuple[tuple[fmpq, fmpq], ...] = field(default=())
    undecided: tuple[tuple[fmpq, fmpq], ...] = field(default=())

    @property
    def lossless(self) -> bool:
        """Re Z vanishes identically on the axis (passive, lossless)."""
        return self.reason == LOSSLESS


def _zero_delay(f: TrigRealPart) -> SignCertificate:
    px = even_to_x(f.at_zero_delay())
    if px.is_zero():
        return SignCertificate(outcome=Outcome.PASSIVE, reason=LOSSLESS)
    odd = ep.positive_roots_odd_multiplicity(px)
    if ep.count_real_roots(odd, 0) == 0 and px.leading_coefficient() > 0:
        return SignCertificate(outcome=Outcome.PASSIVE)
    w = negative_point(px)
    return SignCertificate(outcome=Outcome.NOT_PASSIVE, witness=ep.rational(w))


def high_witness(f: TrigRealPart, high: HighFrequency, tau: fmpq) -> fmpq | None:
    """A rational ``ω`` with ``F(ω; τ) < 0`` proven, at high frequency (band unbounded)."""
    for j in range(0, 64, 2):
        bits = 128 + j + 64
        with precision(bits):
            form = f.balls()
            t = arb_of(tau)
            k = arb(2) ** j
            w = (high.theta + 2 * arb.pi() * k) / t
            mid = w.mid()
            m, e = mid.man_exp()
            omega = fmpq(int(m)) * fmpq(2) ** int(e)
            if omega <= 0:
                continue
            if form.value(arb_of(omega), t) < 0:
                return omega
    return None


def witness_in_bands(f: TrigRealPart, tau: fmpq, bands: list[tuple[fmpq, fmpq]]) -> fmpq | None:
    """Try to prove ``F < 0`` near the worst point of each band: ``ωτ`` on the arc centre.

    Cheap (a few dozen ball evaluations); finds the witness of a long delay at once.
    """
    if f.order != 1 or tau == 0:
        return None
    a, b, c = f.cos[0], f.cos[1], f.sin[1]
    for lo, hi in bands:
        flo, fhi = float(lo), float(hi)
        if not (math.isfinite(flo) and math.isfinite(fhi)) or fhi <= 0:
            continue
        start = max(flo, fhi * 1e-6)
        for i in range(1, 24):
            wbar = start + (fhi - start) * i / 24
            av, bv, cv = (float(p(ep.rational(wbar))) for p in (a, b, c))
            if not all(math.isfinite(v) for v in (av, bv, cv)) or av >= math.hypot(bv, cv):
                continue
            gamma = math.pi + math.atan2(cv, bv)
            k = round((wbar * float(tau) - gamma) / (2 * math.pi))
            omega = ep.rational((gamma + 2 * math.pi * k) / float(tau))
            if omega <= 0:
                continue
            with precision(128 + max(0, int(math.log2(float(omega * tau) + 1)))):
                if f.balls().value(arb_of(omega), arb_of(tau)) < 0:
                    return omega
    return None


def scan_pieces(segments: list[tuple[fmpq, fmpq]], tau: fmpq) -> list[tuple[fmpq, fmpq]]:
    """Cut each segment so that ``θ`` advances at most 1 rad and ``hi/lo <= 2`` per piece."""
    step = 1 / tau if tau > 0 else None
    count = 0.0
    for lo, hi in segments:
        count += float((hi - lo) * tau) + math.log2(max(float(hi / lo), 1.0) if lo > 0 else 2.0)
    if count > MAX_PIECES:
        raise DelayError(
            f"the delay {float(tau):g} s makes Re Z(jw) oscillate about {count:.3g} times over "
            f"the band to certify ({float(segments[0][0]):.4g} to {float(segments[-1][1]):.4g} "
            f"rad/s), beyond the limit of {MAX_PIECES}: no certificate is possible in bounded "
            "time; give a shorter delay (a delay margin, 'seapass delay-margin', needs none)"
        )
    out = []
    for lo, hi in segments:
        cur = lo
        while cur < hi:
            nxt = hi
            if cur > 0:
                nxt = min(nxt, 2 * cur)
            if step is not None:
                nxt = min(nxt, cur + step)
            out.append((cur, nxt))
            cur = nxt
    return out


def _scan(
    f: TrigRealPart,
    tau: fmpq,
    pieces: list[tuple[fmpq, fmpq]],
    *,
    budget: int,
    max_precision: int,
    collect: bool,
) -> SignCertificate:
    ladder = [p for p in PRECISIONS if p <= max_precision] or [max_precision]
    count = 0
    negative: list[tuple[fmpq, fmpq]] = []
    todo = list(reversed(pieces))
    used = ladder[0]
    for level, bits in enumerate(ladder):
        used = bits
        harder: list[tuple[fmpq, fmpq]] = []
        with precision(bits):
            form = f.balls()
            t = arb_of(tau)
            while todo:
                a, b = todo.pop()
                count += 1
                if count > budget:
                    return SignCertificate(
                        outcome=Outcome.UNDECIDED, reason="budget", evaluations=count, precision=bits,
                        undecided=((a, b),),
                    )  # fmt: skip
                c = (a + b) / 2
                fc = form.value(arb_of(c), t)
                if fc < 0 and not collect:
                    return SignCertificate(
                        outcome=Outcome.NOT_PASSIVE, witness=c, evaluations=count, precision=bits
                    )
                slope = form.d_omega(ball(a, b), t)
                low = fc - abs(slope) * arb((b - a) / 2)
                if low > 0:
                    continue
                if collect and (fc + abs(slope) * arb((b - a) / 2)) < 0:
                    negative.append((a, b))
                    continue
                # collecting (pictures): a piece across a root of F stays undecided once
                # it is 2^-40 narrow; deciding (one sign): split down to the precision
                if b - a <= max(c, fmpq(1)) / fmpq(2) ** (40 if collect else bits - 24):
                    harder.append((a, b))  # this precision cannot split it further
                    continue
                todo.append((c, b))
                todo.append((a, c))
        if not harder:
            break
        if level == len(ladder) - 1:
            return SignCertificate(
                outcome=Outcome.UNDECIDED if not negative else Outcome.NOT_PASSIVE,
                witness=negative[0][0] if negative else None,
                reason="precision", evaluations=count, precision=bits,
                negative=tuple(negative), undecided=tuple(harder),
            )  # fmt: skip
        todo = list(reversed(harder))
    if negative:
        w = _point_in(f, tau, negative)
        return SignCertificate(
            outcome=Outcome.NOT_PASSIVE, witness=w, evaluations=count, precision=used,
            negative=tuple(negative),
        )  # fmt: skip
    return SignCertificate(outcome=Outcome.PASSIVE, evaluations=count, precision=used)


def _point_in(f: TrigRealPart, tau: fmpq, negative: list[tuple[fmpq, fmpq]]) -> fmpq | None:
    with precision(PRECISIONS[-1]):
        form = f.balls()
        for a, b in negative:
            c = (a + b) / 2
            if form.value(arb_of(c), arb_of(tau)) < 0:
                return c
    return None


def certify(
    f: TrigRealPart,
    tau: fmpq,
    *,
    budget: int = DEFAULT_BUDGET,
    max_precision: int = PRECISIONS[-1],
    collect: bool = False,
) -> SignCertificate:
    """Decide ``F(ω; τ) ≥ 0`` for every ``ω > 0`` (see the module docstring).

    ``collect=True`` scans the whole middle instead of stopping at the first witness and
    returns the sub-intervals proven negative (for plots).
    """
    if f.is_zero:
        return SignCertificate(outcome=Outcome.PASSIVE, reason=LOSSLESS)
    if tau == 0 or f.order == 0:
        return _zero_delay(f)
    high = high_frequency(f)
    if high.kind == "unbounded":
        w = high_witness(f, high, tau)
        if w is not None:
            return SignCertificate(outcome=Outcome.NOT_PASSIVE, witness=w, reason="unbounded_band")
        return SignCertificate(outcome=Outcome.UNDECIDED, reason="unbounded_band")
    if high.kind == "tangent":
        return SignCertificate(outcome=Outcome.UNDECIDED, reason="high_frequency_tangency")
    low = at_fixed_delay(f, tau)
    if low.sign < 0:
        return SignCertificate(
            outcome=Outcome.NOT_PASSIVE, witness=low.witness, reason="low_frequency"
        )
    if low.sign == 0:
        return SignCertificate(outcome=Outcome.UNDECIDED, reason="low_frequency_degenerate")
    if low.everywhere:
        return SignCertificate(outcome=Outcome.PASSIVE)
    assert low.cutoff is not None and high.omega1 is not None
    w0, w1 = low.cutoff, high.omega1
    if f.order == 1:
        bands = dangerous_bands(f)
        segments = [(max(lo, w0), min(hi, w1)) for lo, hi in bands]
        segments = [(lo, hi) for lo, hi in segments if lo < hi]
        if not collect:
            w = witness_in_bands(f, tau, bands)
            if w is not None:
                return SignCertificate(outcome=Outcome.NOT_PASSIVE, witness=w, omega0=w0, omega1=w1)
    else:
        segments = [(w0, w1)] if w0 < w1 else []
    if not segments:
        return SignCertificate(outcome=Outcome.PASSIVE, omega0=w0, omega1=w1)
    res = _scan(
        f, tau, scan_pieces(segments, tau), budget=budget, max_precision=max_precision,
        collect=collect,
    )  # fmt: skip
    return SignCertificate(
        outcome=res.outcome, witness=res.witness, reason=res.reason, evaluations=res.evaluations,
        precision=res.precision, omega0=w0, omega1=w1, negative=res.negative,
        undecided=res.undecided,
    )  # fmt: skip


def negative_intervals(
    f: TrigRealPart, tau: fmpq, lo: fmpq, hi: fmpq, *, budget: int = DEFAULT_BUDGET
) -> tuple[list[tuple[fmpq, fmpq]], list[tuple[fmpq, fmpq]]]:
    """Sub-intervals of ``[lo, hi]`` (``lo > 0``) proven negative, and those left undecided.

    For pictures: the whole range is scanned (no early stop); outside the dangerous band of
    a first-order delay nothing can be negative and nothing is scanned.
    """
    if f.is_zero or tau == 0 or f.order == 0:
        return [], []
    segments = [(lo, hi)]
    if f.order == 1 and high_frequency(f).kind == "positive":
        segments = [(max(a, lo), min(b, hi)) for a, b in dangerous_bands(f)]
        segments = [(a, b) for a, b in segments if a < b]
    if not segments:
        return [], []
    res = _scan(
        f, tau, scan_pieces(segments, tau), budget=budget, max_precision=PRECISIONS[1], collect=True
    )
    merged: list[tuple[fmpq, fmpq]] = []
    for a, b in sorted(res.negative):
        if merged and a <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(b, merged[-1][1]))
        else:
            merged.append((a, b))
    return merged, list(res.undecided)
