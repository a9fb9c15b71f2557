"""The passivity delay margin ``τ*``: the largest delay ``τ`` such that the design is passive
for **every** delay in ``[0, τ]``, as a certified enclosure.

For a delay to the first power (``N`` and ``D`` linear in ``E = e^{-sτ}``) the margin is the
smallest of three exact or certified quantities:

* ``τ = 0`` (exactly), when for every ``τ > 0`` the high-frequency term is negative
  somewhere (the dangerous band is unbounded, [`highfreq`][seapass.delay.highfreq]) or the
  loop is of advanced (or strongly unstable neutral) type: loss ``"unbounded_band"``;
* ``τ_low``: the first positive root of the lowest Taylor coefficient ``f_i0(τ)`` of
  ``Re Z`` at ``ω = 0`` ([`lowfreq`][seapass.delay.lowfreq]), an algebraic number isolated
  exactly: loss ``"low_frequency"``;
* ``inf g`` over the dangerous band ([`firstdelay`][seapass.delay.firstdelay]), and the first
  delay at which a root of the characteristic quasi-polynomial reaches the axis
  ([`stability`][seapass.delay.stability]): loss ``"interior"`` with the frequency.

The upper end ``hi`` of the enclosure is a delay at which the design is proven **not**
passive (a witness ``Re Z(jω) < 0``, an unstable loop, or the exact ``τ_low``); the lower
end ``lo`` is proven passive together with every delay below it (exact low-frequency
bounds uniform in ``τ``, exact crossing delays, branch and bound on ``g``), with
``hi - lo ≤ rtol·hi``.  Printed bounds round inward for the passive end (a printed ``lo``
is itself certified) and outward for ``hi``.

Examples
--------
The virtual wall behind a delay, ``Z = m s + b + K e^{-sτ}/s``: ``τ* = b/K``, lost at
``ω → 0`` (the continuous-time form of Colgate and Schenkel's ``b > KT/2``).

>>> r = delay_margin("m*s + b + K*exp(-tau*s)/s", "tau", values=dict(m=1, b=2, K=50))
>>> str(r.loss), [round(x, 6) for x in r.tau_star]
('low_frequency', [0.04, 0.04])
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from flint import fmpq

from ..analysis.passivity import positive_real_test
from ..errors import DelayError, NotPassiveError, ParameterError, did_you_mean
from ..exact import poly as ep
from ..exact.axis import safe_float
from ..exact.rounding import decimal_down, decimal_up
from ..files.limits import MIN_RTOL
from ..model.sea import Impedance
from ..outcome import Outcome
from .balls import arb_of, lower, precision, round_down, round_up, upper
from .bands import dangerous_bands
from .firstdelay import FirstDelay
from .highfreq import high_frequency
from .lowfreq import limit_polynomial, uniform_cutoff
from .marginresult import DEFAULT_RTOL, LOSS_KINDS, DelayMarginResult, MarginCause, MarginLoss
from .passivity import growth_at_infinity
from .search import SearchStatus, prove_at_least, search_minimum
from .stability import (
    LoopKind,
    characteristic,
    crossings,
    delay_independent_stability,
    rhp_count,
    stability_at,
)
from .structure import (
    DelayedImpedance,
    SystemLike,
    controller_delay,
    delayed_impedance,
    has_model_delay,
)
from .trig import TrigRealPart, real_part

__all__ = [
    "DEFAULT_RTOL",
    "LOSS_KINDS",
    "DelayMarginResult",
    "MarginCause",
    "MarginLoss",
    "delay_margin",
    "margin_of",
]

DEFAULT_MARGIN_BUDGET = 50_000
"""Pieces of the branch and bound on ``g(ω)`` before the enclosure is undecided."""


@dataclass
class _Candidate:
    tau: fmpq  # a delay proven not passive (or the exact low-frequency root's upper end)
    loss: MarginLoss
    frequency: float | None
    cause: MarginCause


def _result(z: DelayedImpedance, **kw: Any) -> DelayMarginResult:
    return DelayMarginResult(delay=z.name, impedance=z, **kw)


def _zero_margin(
    z: DelayedImpedance, detail: str, loss: MarginLoss, **kw: Any
) -> DelayMarginResult:
    zero = fmpq(0)
    return _result(
        z, outcome=Outcome.PASSIVE, tau_star=(0.0, 0.0), loss=loss, exact=(zero, zero),
        detail=detail, **kw,
    )  # fmt: skip


def _undecided(z: DelayedImpedance, detail: str, hi: fmpq | None = None) -> DelayMarginResult:
    star = (0.0, round_up(hi)) if hi is not None else None
    return _result(z, outcome=Outcome.UNDECIDED, tau_star=star, certified=False, detail=detail)


def _low_frequency_root(fp: Any, rtol: float) -> tuple[fmpq, fmpq] | str | None:
    """The first positive sign change of ``f_i0(τ)`` as a tight interval, None if none,
    ``"even"`` when an even-multiplicity root comes first (undecided)."""
    odd = ep.positive_roots_odd_multiplicity(fp)
    first = None
    if odd.degree() > 0:
        roots = ep.isolate_real_roots(odd, 0)
        first = roots[0] if roots else None
    limit = first[1] if first is not None else None
    sf = ep.squarefree_part(fp)
    if sf.degree() > 0 and ep.count_real_roots(sf, 0, limit) > (1 if first is not None else 0):
        return "even"
    if first is None:
        return None
    a, b = first
    if a <= 0:
        a, b = ep.refine_past(odd, (a, b), 0)
    if a < b:
        a, b = ep.refine(odd, (a, b), a * ep.rational(rtol) / 8)
    return a, b


def _verified_interior(f: TrigRealPart, g: FirstDelay, omega: fmpq, rtol: float) -> fmpq | None:
    """A delay just above ``g(ω)`` at which ``F(ω; τ) < 0`` is proven (None if not found)."""
    with precision(128):
        gv = g.at(omega)
        if not gv.is_finite() or g.safe(arb_of(omega)):
            return None
        top = upper(gv)
        form = f.balls()
        for k in (16, 8, 4, 2, 1):
            tau = top * (1 + ep.rational(rtol) / k)
            if form.value(arb_of(omega), arb_of(tau)) < 0:
                return tau
    return None


def margin_of(
    z: DelayedImpedance,
    *,
    rtol: float = DEFAULT_RTOL,
    budget: int = DEFAULT_MARGIN_BUDGET,
) -> DelayMarginResult:
    """`delay_margin` of an exact delayed impedance (its delay value is ignored)."""
    res0 = positive_real_test(*z.at(fmpq(1)))
    if not res0.passive:
        return _result(
            z, outcome=Outcome.NOT_PASSIVE, passive_at_zero=False, certified=True,
            detail=f"not passive at zero delay: {res0.detail}",
        )  # fmt: skip
    f = real_part(z)
    ch = characteristic(z.den)
    if ch.kind is LoopKind.UNSUPPORTED or f.order > 1:
        raise DelayError(
            "the delay margin is computed for a delay to the first power: N(s,E) and D(s,E) "
            "linear in E = exp(-NAME*s); this design has exp(-k*NAME*s) with k >= 2 in Z"
        )
    if ch.kind is LoopKind.ADVANCED:
        return _zero_margin(z, "advanced-type loop: unstable for every delay > 0", MarginLoss.UNBOUNDED_BAND, cause=MarginCause.STABILITY)  # fmt: skip
    ratio = ch.neutral_ratio
    if ratio is not None and ratio > 1:
        return _zero_margin(z, "neutral loop with |q_n/p_n| > 1: unstable for every delay > 0", MarginLoss.UNBOUNDED_BAND, cause=MarginCause.STABILITY)  # fmt: skip
    if ratio is not None and ratio == 1:
        return _undecided(z, "neutral loop with |q_n/p_n| = 1: root chains approach the axis")
    if ch.s_power >= 2:
        return _undecided(z, "a pole of order >= 2 at s = 0 in D: the pole order may change with the delay")  # fmt: skip
    inf, _confirm = growth_at_infinity(z)
    if inf is not None:
        return _zero_margin(z, f"for every delay > 0: {inf.detail}", MarginLoss.UNBOUNDED_BAND, cause=MarginCause.INFINITY)  # fmt: skip
    hf = high_frequency(f)
    if hf.kind == "unbounded":
        return _zero_margin(
            z, "for every delay > 0, Re Z(jw) < 0 at arbitrarily high frequencies (the "
            "leading term changes sign with w*tau)", MarginLoss.UNBOUNDED_BAND, cause=MarginCause.REAL_PART,
        )  # fmt: skip
    if hf.kind == "tangent":
        return _undecided(z, "the leading high-frequency term of Re Z touches 0: undecided")
    if rhp_count(ch.p + ch.q) is None:
        return _undecided(z, "a root on the imaginary axis at zero delay")
    if ch.common.degree() > 0 and rhp_count(ch.common) is None:
        return _undecided(z, "a pole on the imaginary axis for every delay: its residue moves with the delay")  # fmt: skip
    bands = dangerous_bands(f) if f.order == 1 and hf.kind == "positive" else []
    di_stable = delay_independent_stability(ch)
    if not bands and di_stable:
        return _result(
            z, outcome=Outcome.PASSIVE, delay_independent=True,
            detail="passive for every delay (A >= 0 and A^2 >= B^2 + C^2 on the axis, "
            "stable for every delay)",
        )  # fmt: skip
    return _enclose(z, f, ch, bands, rtol, budget)


def _enclose(
    z: DelayedImpedance, f: TrigRealPart, ch: Any, bands: list[tuple[fmpq, fmpq]],
    rtol: float, budget: int,
) -> DelayMarginResult:  # fmt: skip
    cands: list[_Candidate] = []
    i0, fp = limit_polynomial(f)
    low: tuple[fmpq, fmpq] | None = None
    if i0 >= 0 and not fp.is_zero():
        if fp(0) == 0:
            first = next(c for c in fp.coeffs() if c != 0)
            if first < 0:
                return _zero_margin(z, "Re Z(jw) < 0 as w -> 0 for every delay > 0", MarginLoss.LOW_FREQUENCY, cause=MarginCause.REAL_PART)  # fmt: skip
            return _undecided(z, "the low-frequency coefficient of Re Z vanishes at zero delay")
        root = _low_frequency_root(fp, rtol)
        if root == "even":
            return _undecided(z, "the low-frequency coefficient of Re Z touches 0")
        if isinstance(root, tuple):
            low = root
            cands.append(_Candidate(root[1], MarginLoss.LOW_FREQUENCY, None, MarginCause.REAL_PART))
    every = crossings(ch) if ch.kind in (LoopKind.RETARDED, LoopKind.NEUTRAL) else []
    # lo must stay below every first crossing delay (balls may overlap: take them all)
    stab_floor = min((lower(c.delay) for c in every), default=None)
    crossing = min(every, key=lambda c: upper(c.delay)) if every else None
    if crossing is not None:
        tau_c = upper(crossing.delay) * (1 + ep.rational(rtol) / 16)
        if stability_at(ch, tau_c).stable is False:  # proven unstable just past the crossing
            cands.append(
                _Candidate(
                    tau_c,
                    MarginLoss.INTERIOR,
                    float(crossing.omega.mid()),
                    MarginCause.STABILITY,
                )
            )
    g = FirstDelay(f) if bands else None
    hf = high_frequency(f)
    omega1 = hf.omega1 if hf.omega1 is not None else fmpq(0)
    segments = [(lo, min(hi, omega1) if omega1 > 0 else hi) for lo, hi in bands]
    count = 0
    if g is not None:
        for w in search_minimum(g, segments):
            tau_h = _verified_interior(f, g, w, rtol)
            count += 1
            if tau_h is not None:
                cands.append(
                    _Candidate(tau_h, MarginLoss.INTERIOR, safe_float(w), MarginCause.REAL_PART)
                )
    if not cands:
        return _undecided(z, "no delay at which passivity is lost was found or proven")
    best = min(cands, key=lambda c: c.tau)
    for _round in range(8):
        hi = best.tau
        lo = hi * (1 - ep.rational(rtol) / 2)
        if low is not None and (lo >= low[0] or best.loss is MarginLoss.LOW_FREQUENCY):
            lo = low[0]
        if lo <= 0:
            return _undecided(z, "the margin is below the resolution of rtol", hi)
        if stab_floor is not None and not stab_floor > lo:
            lo = stab_floor * (1 - ep.rational(rtol) / 4)
        omega0 = fmpq(0)
        if i0 >= 0 and not fp.is_zero():
            if ep.count_real_roots(fp, 0, lo) != 0:
                return _undecided(z, "internal: the low-frequency root lies below lo", hi)
            target = segments[0][1] / 32 if segments else None
            cut, everywhere = uniform_cutoff(f, i0, lo, target=target)
            omega0 = cut if cut is not None else fmpq(0)
            if everywhere:
                segments_lo: list[tuple[fmpq, fmpq]] = []
            else:
                segments_lo = [(max(a, omega0), b) for a, b in segments if b > omega0]
        else:
            segments_lo = list(segments)
        if g is None or not segments_lo:
            return _final(z, lo, hi, best, rtol, count)
        status, counter, used = prove_at_least(g, segments_lo, lo, budget=budget)
        count += used
        if status is SearchStatus.OK:
            return _final(z, lo, hi, best, rtol, count)
        if status is SearchStatus.COUNTER and counter is not None:
            tau_h = _verified_interior(f, g, counter, rtol)
            if tau_h is not None and tau_h < best.tau:
                best = _Candidate(
                    tau_h,
                    MarginLoss.INTERIOR,
                    safe_float(counter),
                    MarginCause.REAL_PART,
                )
                continue
        return _result(
            z, outcome=Outcome.UNDECIDED, tau_star=(0.0, round_up(hi)), certified=False,
            loss=best.loss, frequency=best.frequency, cause=best.cause, evaluations=count,
            detail=f"passivity on [0, {decimal_down(lo, 6)}] s was not certified within "
            f"{budget} pieces; tau* <= {decimal_up(hi, 6)} s is proven",
        )  # fmt: skip
    return _undecided(z, "the enclosure did not settle", best.tau)


def _final(
    z: DelayedImpedance, lo: fmpq, hi: fmpq, best: _Candidate, rtol: float, count: int
) -> DelayMarginResult:
    lo_f, hi_f = round_down(lo), round_up(hi)
    where = "as w -> 0" if best.frequency is None else f"at w = {best.frequency:.6g} rad/s"
    what = (
        "a root of the loop reaches the imaginary axis"
        if best.cause is MarginCause.STABILITY
        else "Re Z(jw) < 0"
    )
    return _result(
        z, outcome=Outcome.PASSIVE, tau_star=(lo_f, hi_f), exact=(lo, hi),
        frequency=best.frequency, loss=best.loss, cause=best.cause, rtol=rtol,
        certified=bool(hi - lo <= ep.rational(rtol) * hi), evaluations=count,
        detail=f"passive for every delay up to {decimal_down(lo, 6)} s; beyond "
        f"{decimal_up(hi, 6)} s {what} {where}",
    )  # fmt: skip


def _raw(system: Any) -> bool:
    """A raw impedance (an `Impedance`, text or a sympy expression): no controller to delay."""
    return isinstance(system, str | Impedance) or type(system).__module__.startswith("sympy")


def delay_margin(
    system: SystemLike,
    delay: str | None = None,
    *,
    values: Mapping[str, float | None] | None = None,
    rtol: float = DEFAULT_RTOL,
    budget: int = DEFAULT_MARGIN_BUDGET,
    throw: bool = False,
) -> DelayMarginResult:
    """The passivity delay margin ``τ*`` of a design with one delay ``exp(-NAME*s)``.

    Parameters
    ----------
    system : SEA, Design, CatalogDesign, Impedance, str or sympy.Expr
        The design (its load impedance) or a raw impedance with one delay factor.  A
        design without a delay gets ``exp(-delay*s)`` on its controllers
        ([`controller_delay`][seapass.delay.structure.controller_delay]).
    delay : str, optional
        The delay parameter (``"tau"``); checked against the design's delay.
    values : mapping, optional
        Parameter values overriding the stored ones (a value of the delay is ignored).
    rtol : float, default 1e-6
        Relative width of the enclosure of ``τ*`` (``1e-12`` to ``1e-2``).
    budget : int, default 50000
        Pieces of the branch and bound before the enclosure is undecided.
    throw : bool, default False
        Raise `NotPassiveError` unless the outcome is ``passive``.

    Returns
    -------
    DelayMarginResult

    Examples
    --------
    >>> from seapass.model.sea import SEA
    >>> ours = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
    ...            values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25, tau=None))
    >>> r = delay_margin(ours, "tau")
    >>> str(r.loss), round(r.tau_star[0], 4), round(r.frequency, 1)
    ('interior', 0.0413, 36.5)
    """
    if not (isinstance(rtol, int | float) and math.isfinite(rtol) and MIN_RTOL <= rtol <= 1e-2):
        raise ParameterError(
            f"rtol must be in [{MIN_RTOL:g}, 1e-2] (the relative width of the enclosure of "
            f"tau*), got {rtol!r}",
            argument="rtol",
        )
    if not (isinstance(budget, int) and budget > 0):
        raise ParameterError(f"budget must be a positive whole number, got {budget!r}")
    if not _raw(system) and not has_model_delay(system):
        if delay is None:
            raise ParameterError("delay: name the delay, e.g. delay_margin(sea, 'tau')")
        system = controller_delay(system, delay)  # a delay-free design: its controllers lag
    z = delayed_impedance(system, values, free_delay=True)
    if delay is not None and delay != z.name:
        raise ParameterError(
            f"delay: {delay!r} is not the delay of the design{did_you_mean(delay, [z.name])}; "
            f"its delay is exp(-{z.name}*s)",
            argument="delay",
        )
    result = margin_of(z, rtol=float(rtol), budget=budget)
    if throw and result.outcome is not Outcome.PASSIVE:
        raise NotPassiveError(f"delay margin: {result.outcome.label}: {result.detail}")
    return result
