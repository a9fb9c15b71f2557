"""Certified passive set of one controller parameter under sampled-data control.

The controllers are polynomial in the parameter ``λ`` ([`seapass.sampled.family`][seapass.sampled.family]), so
the weighted power polynomial is ``P̃(x; λ) = Σ_k λ^k P̃_k(x)`` with ball polynomials
``P̃_k`` computed once, and the characteristic polynomial of the loop with the port held is
``χ(z; λ) = Σ_a λ^a χ_a(z)``.  A box ``[λ_lo, λ_hi]`` is

* **passive** when, for every ``λ`` in it, ``χ`` is Schur-stable and ``P̃(x; λ) > 0`` on
  ``[−1, 1]`` (both proven with coefficient enclosures over the whole box);
* **not passive** when every ``λ`` in it has a proven negative value of ``P̃`` or an
  unstable loop;
* otherwise split in two.

Boxes are split until they are decided or narrower than the tolerance; the undecided
leaves that remain hold the edges (each an enclosure of width ``≤ rtol·|λ|``).  Nothing is
sampled: a passive island wider than the tolerance cannot be missed, because every box is
either proven or split.  Values where the deployed controller differs from the family (a
degree of ``C(s)`` drops, a pole cancels) are decided one by one as points.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from flint import arb, arb_poly, fmpq, fmpq_poly

from ..outcome import Outcome
from ..progress import Progress
from .alias import AliasSums
from .certified import (
    Sign,
    bernstein,
    modulus_on_circle,
    negative_at,
    precision,
    schur_stable,
    sign_on,
)
from .family import ControllerFamily, joint_polys
from .plant import PlantKey
from .power import weighted_polynomials
from .verdict import (
    PRECISIONS,
    SampledReason,
    alias_injection,
    cached_sums,
    characteristic,
    needed_sums,
    precision_ladder,
)

__all__ = ["MAX_BOXES", "BoxVerdict", "DecidedShare", "bound_boxes"]

#: Most boxes examined in one bound (bounds time; what is left is reported undecided).
MAX_BOXES = 20000

SPECIAL_GAP = Fraction(1, 10**6)
"""Boxes touching a special value of the family (see `bound_boxes`) narrower than this
fraction of the range (or ``rtol`` of it, if larger) are left undecided, not bisected."""


@dataclass(frozen=True, kw_only=True)
class BoxVerdict:
    """The certified outcome of every value of the parameter in ``[lo, hi]``."""

    lo: Fraction
    hi: Fraction
    outcome: Outcome
    reason: SampledReason = SampledReason.NONE


def _fq(x: Fraction) -> fmpq:
    return fmpq(x.numerator, x.denominator)


def _shift(polys: Sequence[Any], c: arb) -> list[Any]:
    """Taylor coefficients in ``δ`` of ``Σ_k p_k (c + δ)^k`` (``p_k`` polys or scalars)."""
    K = len(polys) - 1
    out = []
    for j in range(K + 1):
        acc = None
        for k in range(j, K + 1):
            term = polys[k] * (math.comb(k, j) * c ** (k - j))
            acc = term if acc is None else acc + term
        out.append(acc)
    return out


@dataclass
class _Setup:
    sums: AliasSums
    p_family: list[arb_poly]  # P̃_k
    chi_family: list[list[arb]]  # χ_a coefficients (z ascending)
    dl_family: list[list[arb]]  # d_L in z, per λ power
    prec: int
    chi_circle: list[arb_poly] = field(default_factory=list)
    dl_circle: list[arb_poly] = field(default_factory=list)


def _z_coeffs(polys: Sequence[fmpq_poly], e: int) -> list[list[arb]]:
    """``z^e p(1/z)`` coefficients for every λ-power ``p``."""
    out = []
    for p in polys:
        c = [arb(x) for x in p.coeffs()] + [arb(0)] * (e + 1 - len(p.coeffs()))
        out.append(list(reversed(c)))
    return out


def _setup(
    key: PlantKey, period: Fraction, fam: ControllerFamily, names: tuple[str, ...], prec: int
) -> _Setup:
    sums = cached_sums(key, period, names, prec)
    a, load = fam.actuator, fam.load
    vfam, rest = joint_polys(a, load)
    with precision(prec):
        p_family = weighted_polynomials(sums, vfam)
        e = max((p.degree() for p in (*a.num, *a.den)), default=0)
        e = max(e, 0)
        chi = []
        for k in range(max(len(a.num), len(a.den))):
            na = a.num[k] if k < len(a.num) else fmpq_poly([0])
            da = a.den[k] if k < len(a.den) else fmpq_poly([0])
            coeffs = (
                characteristic(sums, na, da, pad=e) if not (na.is_zero() and da.is_zero()) else []
            )
            chi.append([c.real for c in coeffs])
        n = max((len(c) for c in chi), default=0)
        chi = [c + [arb(0)] * (n - len(c)) for c in chi]
        el = max((p.degree() for p in rest), default=0)
        dl = _z_coeffs(list(rest), max(el, 0))
        return _Setup(sums, p_family, chi, dl, prec, modulus_on_circle(chi), modulus_on_circle(dl))


def _coeff_box(family: list[list[arb]], a: arb, w: arb) -> list[arb]:
    """Enclosures over ``λ ∈ [a, a + w]`` of the coefficients of ``Σ_k λ^k f_k``."""
    if not family:
        return []
    out = []
    for col in zip(*family, strict=True):
        ctrl = bernstein(_shift(list(col), a), w)
        box = ctrl[0]
        for c in ctrl[1:]:
            box = box.union(c)
        out.append(box)
    return out


def _stable_on_box(family: list[list[arb]], circle: list[arb_poly], a: arb, w: arb) -> bool | None:
    """Schur stability for every ``λ`` in ``[a, a + w]`` (``None``: not proven either way).

    Stable (or unstable) at ``λ = a`` and no root on the unit circle anywhere in the box
    (``|χ(e^{jφ}; λ)|² > 0``, with a leading coefficient that never vanishes) proves the
    same for the whole box: roots move continuously and cannot cross the circle.
    """
    if not family:
        return True
    at_a = _coeff_box(family, a, arb(0))
    first = schur_stable(at_a)
    if first is None:
        return None
    box = _coeff_box(family, a, w)
    if schur_stable(box) is True:
        return True
    lead = box[-1]
    if not (lead > 0 or lead < 0):
        return None
    if (
        sign_on(bernstein(_shift(circle, a), w), Fraction(-1), Fraction(1), budget=100).sign
        is Sign.POSITIVE
    ):
        return first
    return None


def _value(poly: arb_poly, x: float) -> float:
    return float(poly(arb(x)).mid())


def _deepest(poly: arb_poly, x: Fraction) -> Fraction:
    """Walk from a negative point towards the local minimum of ``poly`` (ball midpoints at
    the working precision: floats cannot see values far below the coefficients)."""
    best = float(x)
    best_val = _value(poly, best)
    for k in (2, 5, 8, 11, 14, 17, 20, 24, 28):
        h = 2.0**-k
        for t in range(-8, 9):
            y = min(1.0, max(-1.0, best + h * t / 8))
            v = _value(poly, y)
            if v < best_val:
                best, best_val = y, v
    return Fraction(best)


def _classify(
    s: _Setup,
    lo: Fraction,
    hi: Fraction,
    load_zero: bool,
    start: Sequence[tuple[Fraction, Fraction]] = (),
) -> tuple[Outcome, SampledReason, tuple[tuple[Fraction, Fraction], ...]]:
    with precision(s.prec):
        a = arb(_fq(lo))
        w = arb(_fq(hi - lo))
        stable = _stable_on_box(s.chi_family, s.chi_circle, a, w)
        if stable is False:
            return Outcome.NOT_PASSIVE, SampledReason.UNSTABLE, ()
        dl_ok = True if load_zero else _stable_on_box(s.dl_family, s.dl_circle, a, w)
        if dl_ok is False:
            return Outcome.NOT_PASSIVE, SampledReason.UNSTABLE, ()
        controls = bernstein(_shift(s.p_family, a), w)
        res = sign_on(controls, Fraction(-1), Fraction(1), budget=200, start=start)
        if res.sign is Sign.NEGATIVE:
            return Outcome.NOT_PASSIVE, SampledReason.NEGATIVE_POWER, ()
        if res.sign is Sign.POSITIVE and stable and dl_ok:
            return Outcome.PASSIVE, SampledReason.NONE, ()
        if res.sign is Sign.POSITIVE:
            return Outcome.UNDECIDED, SampledReason.NONE, res.partition
        # the centre alone: a deep negative point of the centre often holds for the box
        centre_poly = _shift(s.p_family, arb(_fq((lo + hi) / 2)))[0]
        centre = sign_on([centre_poly], Fraction(-1), Fraction(1), budget=60)
        if centre.sign is Sign.NEGATIVE and centre.witness is not None:
            for x in (_deepest(centre_poly, centre.witness), *_global_minimum(centre_poly)):
                if negative_at(controls, x):
                    return Outcome.NOT_PASSIVE, SampledReason.NEGATIVE_POWER, ()
        if centre.sign is Sign.UNDECIDED:
            # not even the centre is decided at this precision: the balls are what fails
            # (the power within their radius of 0), and no split in λ can help
            return Outcome.UNDECIDED, SampledReason.PRECISION, ()
    return Outcome.UNDECIDED, SampledReason.NONE, ()


def _dc_power_vanishes(s: _Setup, value: Fraction) -> bool:
    """Whether the family's power at ``λ = value`` may be 0 at ``ω = 0`` (``x = 1``)."""
    with precision(s.prec):
        return bool(_shift(s.p_family, arb(_fq(value)))[0](arb(1)).contains(0))


def _global_minimum(poly: arb_poly) -> list[Fraction]:
    xs = [math.cos(math.pi * i / 256) for i in range(257)] + [1 - 2.0**-k for k in range(12, 48, 4)]
    vals = [_value(poly, x) for x in xs]
    return [_deepest(poly, Fraction(xs[min(range(len(xs)), key=vals.__getitem__)]))]


def bound_boxes(
    key: PlantKey,
    period: Fraction,
    fam: ControllerFamily,
    lo: Fraction,
    hi: Fraction,
    *,
    rtol: Fraction,
    atol: Fraction,
    start_precision: int = PRECISIONS[0],
    max_precision: int = PRECISIONS[-1],
    max_boxes: int = MAX_BOXES,
    advance: Callable[[float], None] | None = None,
) -> list[BoxVerdict]:
    """Partition ``[lo, hi]`` into proven boxes and undecided leaves (sorted).

    A box that is not decided is split in two, unless the verdict at its centre is not
    decided either at the box's precision: then the balls, not the width, are what
    fails, and the box is examined again at the next precision (each box carries its own
    precision, so only the boxes that need more bits pay for them).  Undecided leaves that
    are not edges (proven boxes of opposite verdicts on both sides) are examined again at
    the next precision, up to ``max_precision``.  At most ``max_boxes`` boxes are
    examined: what is left then is reported ``undecided`` with reason ``SampledReason.BUDGET``.
    ``advance(width)`` is called with the share of ``[lo, hi]`` each decided box covers.
    """
    a_zero, l_zero = fam.actuator.is_zero, fam.load.is_zero
    if a_zero and l_zero:
        return [BoxVerdict(lo=lo, hi=hi, outcome=Outcome.PASSIVE, reason=SampledReason.NO_CONTROL)]
    if not l_zero and alias_injection(key):
        no = Outcome.NOT_PASSIVE
        return [BoxVerdict(lo=lo, hi=hi, outcome=no, reason=SampledReason.ALIAS_INJECTION)]
    names = needed_sums(a_zero, l_zero)
    if "Sg" not in names:
        names = (*names, "Sg")
    ladder = [p for p in precision_ladder(max_precision) if p >= start_precision] or [max_precision]
    setups: dict[int, _Setup] = {}

    def setup(level: int) -> _Setup:
        if level not in setups:
            setups[level] = _setup(key, period, fam, names, ladder[level])
        return setups[level]

    tol_rel = rtol / 4  # adjacent leaves may merge into one enclosure
    undecided = Outcome.UNDECIDED
    # where the family's structure changes so that the power vanishes at ω = 0 (ki = 0
    # removes an integrator) no box touching the value is ever decided: below `gap` such a
    # box stays undecided (the value itself is decided alone by the caller); other special
    # values (a cancellation, tz = tp) are bisected like any value
    gap = max(rtol, SPECIAL_GAP) * (hi - lo)
    specials = [v for v in fam.special if lo <= v <= hi and _dc_power_vanishes(setup(0), v)]
    done: list[BoxVerdict] = []
    stack: list[tuple[Fraction, Fraction, int, tuple[tuple[Fraction, Fraction], ...]]]
    stack = [(lo, hi, 0, ())]
    boxes = 0
    while stack:
        leaves: list[tuple[Fraction, Fraction, int]] = []
        while stack:
            a, b, level, start = stack.pop()
            if boxes >= max_boxes:
                done.append(BoxVerdict(lo=a, hi=b, outcome=undecided, reason=SampledReason.BUDGET))
                continue
            boxes += 1
            s = setup(level)
            outcome, reason, part = _classify(s, a, b, l_zero, start)
            if outcome is not Outcome.UNDECIDED:
                done.append(BoxVerdict(lo=a, hi=b, outcome=outcome, reason=reason))
                if advance:
                    advance(float((b - a) / (hi - lo)))
                continue
            if b - a <= gap and any(a <= v <= b for v in specials):
                done.append(BoxVerdict(lo=a, hi=b, outcome=undecided, reason=SampledReason.SPECIAL))
                continue
            if b - a <= max(tol_rel * max(abs(a), abs(b)), atol):
                leaves.append((a, b, level))
                continue
            if reason is SampledReason.PRECISION and level + 1 < len(ladder):
                stack.append((a, b, level + 1, ()))  # more bits, not a narrower box
                continue
            mid = (a + b) / 2
            stack.append((mid, b, level, part))
            stack.append((a, mid, level, part))
        # only decided boxes are sides of an edge (not those the budget left unexamined)
        proven = sorted((v for v in done if v.outcome is not undecided), key=lambda v: v.lo)
        for ga, gb, level in _merge(leaves):
            if _is_edge((ga, gb), proven):
                done.append(BoxVerdict(lo=ga, hi=gb, outcome=undecided, reason=SampledReason.EDGE))
            elif level + 1 < len(ladder):
                stack.append((ga, gb, level + 1, ()))  # BUDGET when the budget is spent
            else:
                done.append(
                    BoxVerdict(lo=ga, hi=gb, outcome=undecided, reason=SampledReason.UNDECIDED)
                )
    return sorted(done, key=lambda v: v.lo)


def _merge(
    leaves: list[tuple[Fraction, Fraction, int]],
) -> list[tuple[Fraction, Fraction, int]]:
    """Adjacent leaves joined; each group keeps the highest precision level of its leaves."""
    out: list[tuple[Fraction, Fraction, int]] = []
    for a, b, level in sorted(leaves):
        if out and out[-1][1] == a:
            out[-1] = (out[-1][0], b, max(out[-1][2], level))
        else:
            out.append((a, b, level))
    return out


def _is_edge(leaf: tuple[Fraction, Fraction], proven: list[BoxVerdict]) -> bool:
    a, b = leaf
    left = next((v.outcome for v in reversed(proven) if v.hi == a), None)
    right = next((v.outcome for v in proven if v.lo == b), None)
    return left is not None and right is not None and left != right


class DecidedShare:
    """The share of the range decided, as whole percent steps of ``progress``: the
    ``advance`` of `bound_boxes` (`finish` adds what no decided box covered)."""

    def __init__(self, progress: Progress) -> None:
        self.progress, self.decided, self.shown = progress, 0.0, 0

    def __call__(self, width: float) -> None:
        self.decided += width
        now = min(int(self.decided * 100), 100)
        if now > self.shown:
            self.progress.advance(now - self.shown, note=f"{now} % of the range decided")
            self.shown = now

    def finish(self) -> None:
        """The rest: edge enclosures and what was left undecided."""
        if self.shown < 100:
            self.progress.advance(100 - self.shown, note="done")
            self.shown = 100
