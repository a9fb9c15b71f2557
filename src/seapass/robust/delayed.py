"""Robust passivity of a delayed design: a verdict at a delay, and the delay margin, for every
plant of a box.

`robust_delayed_check` decides whether a design with a delay ``exp(-NAME*s)`` is passive
at its delay for every plant of a box; `robust_delay_margin` encloses
``τ*_robust = min_box τ*(plant)``.  Both rest on one certificate (`certify_delays`): every plant
of the box is passive for every delay in ``[τ_a, τ_b]`` when

1. the structure is uniform on the box (checked on exact polynomials in the box
   parameters, ball bounds on the box): a retarded loop (``deg_s D_k < deg_s D_0``,
   leading coefficient of ``D_0`` away from 0), the growth at infinity (``Z ~ c s`` with
   ``c > 0`` or slower), the pole at ``s = 0`` simple with a positive residue;
2. the centre plant is stable at ``τ_a`` (exact root count at ``τ_a = 0``, the delay
   module's crossing count otherwise) and ``|D(jω, e^{-jωτ})/(jω)^k|² > 0`` for every
   ``ω ≥ 0``, delay and plant: no root of the loop reaches the imaginary axis, and the
   roots of a retarded loop move continuously, so every plant is stable at every delay;
3. ``Re Z(jω) ≥ 0``: ``F = |D|² Re Z`` (divided by ``ω²`` exactly when it vanishes at 0)
   is proven positive on ``[0, Ω] × [τ_a, τ_b] × box`` by mean-value ball enclosures and
   branch and bound, and beyond ``Ω`` by the dominant term
   ([`seapass.robust.delayform`][seapass.robust.delayform]).

By Phragmén–Lindelöf (as [`seapass.delay.passivity`][seapass.delay.passivity] for one
plant) 1–3 make every plant passive.  A negative answer is a **worst plant** verified by
the ordinary certified verdict ([`delayed_passivity`][seapass.delay.passivity.delayed_passivity],
[`delay_margin`][seapass.delay.margin.delay_margin]); anything else is undecided, never
passive.  The check at a delay ``τ`` certifies ``[0, τ]`` when ``τ`` is covered by the
box's margin, else ``[τ, τ]``.

References
----------
.. [1] W. Michiels and S.-I. Niculescu, *Stability and Stabilization of Time-Delay
   Systems*, SIAM, 2007, ch. 1 (continuity of the roots of retarded quasi-polynomials).
.. [2] R. E. Moore, R. B. Kearfott and M. J. Cloud, *Introduction to Interval Analysis*,
   SIAM, 2009, ch. 6 (mean-value form).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from types import MappingProxyType
from typing import Any

from flint import fmpq

from ..delay.balls import ball, precision, round_down, round_up
from ..delay.margin import delay_margin
from ..delay.marginresult import DelayMarginResult
from ..delay.passivity import delayed_passivity
from ..delay.stability import characteristic, rhp_count, stability_at
from ..errors import NotPassiveError, ParameterError
from ..exact import poly as ep
from ..exact.rounding import decimal_down, decimal_up
from ..files.limits import MIN_RTOL
from ..outcome import Outcome
from .box import UncertainBox, uncertain_box
from .delayform import (
    CellStatus,
    DelayedFamily,
    Poly,
    coeff_of,
    eval_ball,
    high_cutoff,
    over_box,
    positive_on,
    s_degree,
)
from .delayresult import DEFAULT_ROBUST_RTOL, RobustDelayMargin
from .verdict import Method, RobustResult, WorstCase

__all__ = [
    "DEFAULT_DELAY_BUDGET",
    "RobustDelayMargin",
    "robust_delay_margin",
    "robust_delayed_check",
]

DEFAULT_DELAY_BUDGET = 20_000
"""Cells (frequency × delays × sub-box) the branch and bound may examine."""


def _fixed(model: Any, box: UncertainBox, values: Mapping[str, Any] | None) -> dict[str, Any]:
    merged = {**model.values, **(values or {})}
    return {k: v for k, v in merged.items() if k not in box.names}


def _points(box: UncertainBox) -> list[dict[str, float]]:
    """The centre, then the vertices (the common worst plants)."""
    ivs = box.intervals
    out = [box.center()]
    for corner in itertools.product(*ivs.values()):
        out.append(dict(zip(ivs, corner, strict=True)))
    return out


def _positive(exact: list[tuple[fmpq, fmpq]], num: Poly, den: Poly | None = None) -> bool:
    """``num/den > 0`` on the whole box (ball bounds on halved pieces)."""

    def bound(params: list[Any]) -> bool | None:
        v = eval_ball(num, 0, params)
        if den is not None:
            v = v / eval_ball(den, 0, params)
        return True if v > 0 else None

    return over_box(exact, bound) is not None


def _retarded(fam: DelayedFamily, exact: list[tuple[fmpq, fmpq]]) -> str:
    """Why the loop is not retarded with a leading coefficient away from 0 ("" when it is)."""
    dp = fam.dprime
    top = s_degree(dp[0])
    if any(s_degree(p) >= top for p in dp[1:]):
        return "the loop is not of retarded type for every plant"
    lead = coeff_of(dp[0], top)
    sign = 1 if eval_ball(lead, 0, [ball(a, b) for a, b in exact]).mid() > 0 else -1
    if not _positive(exact, {k: sign * c for k, c in lead.items()}):
        return "the leading coefficient of the loop may vanish on the box"
    return ""


def _structure(fam: DelayedFamily, exact: list[tuple[fmpq, fmpq]]) -> str:
    """Why the structure is not uniform on the box ("" when it is)."""
    why = _retarded(fam, exact)
    if why:
        return why
    dp = fam.dprime
    top = s_degree(dp[0])
    lead = coeff_of(dp[0], top)
    dn = max(s_degree(p) for p in fam.num)
    dd = top + fam.s_order
    if dn - dd >= 2:
        return f"Z grows like s^{dn - dd}"
    if dn - dd == 1:
        if any(s_degree(p) >= dn for p in fam.num[1:]):
            return "the delay reaches the leading term of Z"
        if not _positive(exact, coeff_of(fam.num[0], dn), lead):
            return "Z ~ c s at high frequency with c > 0 is not proven on the box"
    if fam.s_order >= 2:
        return "a pole of order >= 2 at s = 0"
    if fam.s_order == 1:
        n0: Poly = {}
        for p in fam.num:
            for k, c in coeff_of(p, 0).items():
                n0[k] = n0.get(k, fmpq(0)) + c
        n0 = {k: c for k, c in n0.items() if c != 0}
        if n0:
            d0: Poly = {}
            for p in dp:
                for k, c in coeff_of(p, 0).items():
                    d0[k] = d0.get(k, fmpq(0)) + c
            if not _positive(exact, n0, d0):
                return "the residue of the pole at s = 0 is not proven positive on the box"
    return ""


@dataclass(frozen=True, kw_only=True)
class DelayCertificate:
    outcome: Outcome
    cells: int
    detail: str
    point: tuple[fmpq, ...] | None = None  # (ω, τ, plant) where F < 0 is proven


def certify_delays(
    fam: DelayedFamily, box: UncertainBox, tau_a: fmpq, tau_b: fmpq, budget: int
) -> DelayCertificate:
    """Every plant of ``box`` passive for every delay in ``[tau_a, tau_b]``? (module docstring)."""
    exact = [(ep.rational(a), ep.rational(b)) for a, b in box.exact()]
    with precision(128):
        why = _structure(fam, exact)
    if why:
        return DelayCertificate(outcome=Outcome.UNDECIDED, cells=0, detail=f"structure: {why}")
    centre = [ep.rational(Fraction(v)) for v in box.center().values()]
    den_c = fam.at(fam.den, centre)
    if tau_a == 0:
        dp_c = fam.at(fam.dprime, centre)
        total = dp_c[0]
        for p in dp_c[1:]:
            total += p
        stable = rhp_count(total) == 0
    else:
        stable = stability_at(characteristic(den_c), tau_a).stable is True
    if not stable:
        return DelayCertificate(
            outcome=Outcome.UNDECIDED, cells=0, detail="the centre plant is not proven stable"
        )
    used = 0
    for form, what in ((fam.loop_magnitude(), "|D(jw)|^2"), (fam.real_part(), "Re Z(jw)")):
        cuts = over_box(exact, lambda params, f=form: high_cutoff(f, tau_b == 0, params))
        omega1 = None if cuts is None else max(cuts)
        if omega1 is None:
            return DelayCertificate(
                outcome=Outcome.UNDECIDED,
                cells=used,
                detail=f"{what}: no uniform high-frequency bound",
            )
        steps = max(1, math.ceil(float(omega1 * tau_b) / 2))
        if steps > budget - used:  # bounded work: one cell per 2 rad of w*tau at least
            return DelayCertificate(
                outcome=Outcome.UNDECIDED, cells=used,
                detail=f"{what}: the delay makes it oscillate {steps} times up to "
                f"{float(omega1):.4g} rad/s, beyond the budget of {budget} cells",
            )  # fmt: skip
        pieces = [(omega1 * k / steps, omega1 * (k + 1) / steps) for k in range(steps)]
        cells = [((a, b), (tau_a, tau_b), *exact) for a, b in pieces]
        status, point, n = positive_on(form, cells, budget=budget - used)
        used += n
        if status is CellStatus.COUNTER and what == "Re Z(jw)":
            return DelayCertificate(
                outcome=Outcome.NOT_PASSIVE, cells=used, detail=f"{what} < 0 proven", point=point
            )
        if status is not CellStatus.PROVEN:
            return DelayCertificate(outcome=Outcome.UNDECIDED, cells=used,
                detail=f"{what} > 0 was not proven within the budget of {budget} cells",
            )  # fmt: skip
    return DelayCertificate(
        outcome=Outcome.PASSIVE, cells=used, detail="certified for every plant of the box"
    )


def unstable_at(fam: DelayedFamily, point: list[fmpq], tau: fmpq) -> bool:
    """The loop ``D(s, e^{-sτ})`` at an exact parameter point has a root in ``Re s >= 0``
    (proven by the delay module's crossing count; False when stable or undecided)."""
    return stability_at(characteristic(fam.at(fam.den, point)), tau).stable is False


def crossing_free(
    fam: DelayedFamily, box: UncertainBox, tau: fmpq, budget: int
) -> tuple[bool, int]:
    """No root of the loop is on the imaginary axis for any plant of ``box`` at the delay
    ``τ``, and the loop is retarded with a leading coefficient away from 0 on the box: the
    number of its roots in ``Re s > 0`` is then the same for every plant of the box
    (continuity of the roots of a retarded loop [1]_).  Returns ``(proven, cells used)``."""
    exact = [(ep.rational(a), ep.rational(b)) for a, b in box.exact()]
    with precision(128):
        if _retarded(fam, exact):
            return False, 0
    form = fam.loop_magnitude()
    cuts = over_box(exact, lambda params: high_cutoff(form, tau == 0, params))
    if cuts is None:
        return False, 0
    omega1 = max(cuts)
    steps = max(1, math.ceil(float(omega1 * tau) / 2))
    if steps > budget:
        return False, 0
    cells = [
        ((omega1 * k / steps, omega1 * (k + 1) / steps), (tau, tau), *exact) for k in range(steps)
    ]
    status, _point, n = positive_on(form, cells, budget=budget)
    return status is CellStatus.PROVEN, n


def point_values(box: UncertainBox, point: tuple[fmpq, ...]) -> dict[str, float]:
    out = {}
    for (name, (lo, hi)), q in zip(box.intervals.items(), point, strict=True):
        out[name] = min(max(float(ep.to_fraction(q)), lo), hi)
    return out


def _tau_of(model: Any, fam: DelayedFamily, values: Mapping[str, Any] | None) -> Any:
    merged = {**model.values, **(values or {})}
    tau = merged.get(fam.delay)
    if tau is None:
        raise ParameterError(
            f"no value for the delay {fam.delay}: give it in seconds, e.g. "
            f"values={{{fam.delay!r}: 0.001}} (or use robust_delay_margin)",
            argument="values",
        )
    return tau


def robust_delayed_check(
    system: Any,
    *,
    box: Mapping[str, Any] | UncertainBox,
    values: Mapping[str, Any] | None = None,
    budget: int = DEFAULT_DELAY_BUDGET,
    throw: bool = False,
) -> RobustResult:
    """Is a delayed design passive at its delay for every plant of ``box``?  (certified)

    Returns a [`RobustResult`][seapass.robust.verdict.RobustResult] (``method``
    ``"certified"``; a ``worst`` plant is verified not passive by
    [`delayed_passivity`][seapass.delay.passivity.delayed_passivity]).

    Examples
    --------
    >>> from seapass.model.sea import SEA
    >>> sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
    ...           values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25, tau=0.01))
    >>> robust_delayed_check(sea, box={"m": (0.9, 1.1)}).outcome
    <Outcome.PASSIVE: 'passive'>
    """
    checked = uncertain_box(system, box, delay_ok=True)
    fixed = _fixed(system, checked, values)
    fam = DelayedFamily.of(system, checked.names, fixed)
    tau = _tau_of(system, fam, values)
    delay = {"name": fam.delay, "tau": float(tau)}

    def done(outcome: Outcome, worst: WorstCase | None, cells: int, detail: str) -> RobustResult:
        r = RobustResult(outcome=outcome, box=checked, worst=worst, method=Method.CERTIFIED,
                         boxes=cells, detail=detail, delay=MappingProxyType(delay))  # fmt: skip
        if throw and not r.passive:
            raise NotPassiveError(f"not robustly passive at the delay: {detail}")
        return r

    def verify(at: Mapping[str, float]) -> WorstCase | None:
        res = delayed_passivity(system, values={**fixed, **at, fam.delay: tau})
        if res.outcome is Outcome.NOT_PASSIVE:
            return WorstCase(values=dict(at), frequency=res.omega, result=res)
        return None

    for at in _points(checked):
        w = verify(at)
        if w is not None:
            return done(Outcome.NOT_PASSIVE, w, 0, _worst_text(w))
    t = ep.rational(Fraction(repr(float(tau))) if isinstance(tau, float) else Fraction(tau))
    cert = certify_delays(fam, checked, fmpq(0), t, budget)
    if cert.outcome is not Outcome.PASSIVE and t > 0:
        again = certify_delays(fam, checked, t, t, budget)  # only at the delay
        cert = DelayCertificate(
            outcome=again.outcome, cells=cert.cells + again.cells, detail=again.detail,
            point=again.point,
        )  # fmt: skip
    if cert.outcome is Outcome.PASSIVE:
        return done(Outcome.PASSIVE, None, cert.cells,
                    f"passive at {fam.delay} = {float(tau):g} s for every plant of the box "
                    f"({cert.cells} cells)")  # fmt: skip
    if cert.point is not None:
        w = verify(point_values(checked, cert.point[2:]))
        if w is not None:
            return done(Outcome.NOT_PASSIVE, w, cert.cells, _worst_text(w))
    return done(Outcome.UNDECIDED, None, cert.cells, cert.detail)


def _worst_text(w: WorstCase) -> str:
    at = ", ".join(f"{k}={v:.10g}" for k, v in w.values.items())
    return f"not passive at the plant {at}: {w.result.detail}"


def robust_delay_margin(
    system: Any,
    delay: str,
    *,
    box: Mapping[str, Any] | UncertainBox,
    values: Mapping[str, Any] | None = None,
    rtol: float = DEFAULT_ROBUST_RTOL,
    budget: int = DEFAULT_DELAY_BUDGET,
    throw: bool = False,
) -> RobustDelayMargin:
    """Certified enclosure of ``min_box τ*(plant)``, the delay margin of every plant of ``box``.

    Parameters
    ----------
    system : SEA, Design or catalog name
        As for [`delay_margin`][seapass.delay.margin.delay_margin] (a delay-free design
        gets ``exp(-delay*s)`` on its controllers).
    delay : str
        The delay parameter.
    box : mapping of str to (lo, hi), or UncertainBox
    values : mapping, optional
    rtol : float, default 1e-3
        Relative width aimed at (``certified`` says whether it was reached).
    budget : int, default 20000
        Cells of the branch and bound (over all attempts) before the answer is undecided.
    throw : bool, default False
        Raise `NotPassiveError` unless passive.

    Examples
    --------
    >>> from seapass.model.sea import SEA
    >>> ours = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
    ...            values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25, tau=None))
    >>> r = robust_delay_margin(ours, "tau", box={"m": (0.9, 1.1)}, rtol=1e-2)
    >>> r.outcome, r.tau_star[0] <= r.tau_star[1] < 0.0414
    (<Outcome.PASSIVE: 'passive'>, True)
    """
    from ..delay.structure import controller_delay, has_model_delay

    if not (isinstance(rtol, int | float) and math.isfinite(rtol) and MIN_RTOL <= rtol <= 0.5):
        raise ParameterError(f"rtol must be in [{MIN_RTOL:g}, 0.5], got {rtol!r}", argument="rtol")
    if isinstance(budget, bool) or not isinstance(budget, int) or budget < 1:
        raise ParameterError(
            f"budget must be a positive integer, got {budget!r}", argument="budget"
        )
    if not has_model_delay(system):
        system = controller_delay(system, delay)
    checked = uncertain_box(system, box, delay_ok=True)
    fixed = {k: v for k, v in _fixed(system, checked, values).items() if k != delay}
    fam = DelayedFamily.of(system, checked.names, fixed)
    if fam.delay != delay:
        raise ParameterError(f"delay: the design's delay is exp(-{fam.delay}*s), not {delay!r}", argument="delay")  # fmt: skip
    rt = ep.rational(Fraction(repr(float(rtol))))

    def margin_at(at: Mapping[str, float]) -> DelayMarginResult:
        return delay_margin(system, delay, values={**fixed, **at}, rtol=min(float(rtol) / 4, 1e-2))

    def result(outcome: Outcome, lo: fmpq | None, hi: fmpq | None, worst: Any, cells: int,
               detail: str) -> RobustDelayMargin:  # fmt: skip
        star = None if hi is None else (0.0 if lo is None else round_down(lo), round_up(hi))
        r = RobustDelayMargin(
            delay=delay, outcome=outcome, tau_star=star, box=checked,
            worst_values=None if worst is None else MappingProxyType(dict(worst[0])),
            worst_margin=None if worst is None else worst[1],
            certified=lo is not None and hi is not None and hi - lo <= rt * hi, rtol=float(rtol),
            cells=cells, detail=detail, exact=None if lo is None or hi is None else (lo, hi),
        )  # fmt: skip
        if throw and not r.passive:
            raise NotPassiveError(f"robust delay margin: {outcome.label}: {detail}")
        return r

    best: tuple[dict[str, float], DelayMarginResult] | None = None
    for at in _points(checked):
        m = margin_at(at)
        if not m.passive_at_zero:
            return result(Outcome.NOT_PASSIVE, None, None, (at, m), 0,
                          f"not passive without delay at {at}: {m.detail}")  # fmt: skip
        if m.exact is not None and (best is None or best[1].exact is None or m.exact[1] < best[1].exact[1]):  # fmt: skip
            best = (at, m)
    if best is None or best[1].exact is None:
        return result(Outcome.UNDECIDED, None, None, best, 0,
                      "no plant tried has a finite delay margin; a box-wide delay-independent "
                      "certificate is not implemented")  # fmt: skip
    cells = 0
    lo: fmpq | None = None
    backoff = rt / 2
    while cells < budget:
        hi = best[1].exact[1]
        target = hi * (1 - backoff)
        cert = certify_delays(fam, checked, fmpq(0), target, budget - cells)
        cells += cert.cells
        if cert.outcome is Outcome.PASSIVE:
            lo = target
            break
        if cert.point is not None:
            at = point_values(checked, cert.point[2:])
            m = margin_at(at)
            if m.exact is not None and m.exact[1] < hi:
                best = (at, m)
                continue
        if cert.cells == 0 or backoff >= fmpq(1, 2):
            break
        backoff = min(backoff * 4, fmpq(1, 2))
    hi = best[1].exact[1]  # type: ignore[index]
    if lo is None:
        return result(Outcome.UNDECIDED, None, hi, best, cells,
                      f"no delay was certified for the whole box within the budget of {budget} "
                      f"cells; tau* <= {decimal_up(hi, 6)} s is proven at the worst plant found")  # fmt: skip
    return result(Outcome.PASSIVE, lo, hi, best, cells,
                  f"every plant of the box is passive for every delay up to {decimal_down(lo, 6)} s; "
                  f"the worst plant found loses passivity beyond {decimal_up(hi, 6)} s")  # fmt: skip
