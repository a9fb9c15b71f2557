"""The robust verdict: passive for every plant in a box, a verified worst case, or undecided.

`robust_check` decides whether a design is passive for **every** value of the
uncertain parameters in a box:

* **one uncertain parameter: exact.**  The exact passive set of that parameter
  ([`passive_intervals`][seapass.analysis.region.passive_intervals], critical
  values and one exact test per cell) contains the interval, or it does not.
* **several: certified.**  The positive-real conditions of the family
  ([`seapass.robust.family`][seapass.robust.family]: Routh–Hurwitz conditions of
  the denominator, the pole at 0, the relative degree and the compactified
  ``Re Z`` numerator on ``[0, ∞) × box``) are each proven positive on the box by
  exact Bernstein branch and bound ([`seapass.robust.bernstein`][seapass.robust.bernstein])
  with one counted budget.  No vertex reasoning: the conditions are polynomial,
  not multi-affine, in the parameters (the mass enters quadratically), so the worst
  plant can lie inside the box.

A negative verdict carries a **worst case**: a point of the box (and, when the
real part fails, a frequency) at which the ordinary exact test
[`is_passive`][seapass.analysis.passivity.is_passive] says *not passive*.  A
budget that runs out, or a failing condition whose point the exact test finds
passive, is `Outcome.UNDECIDED`, never passive.

References
----------
.. [1] B. R. Barmish, *New Tools for Robustness of Linear Systems*, Macmillan,
   1994 (robustness over boxes of parameters; vertex results need multi-affine
   structure).
.. [2] J. Garloff, "The Bernstein algorithm", Interval Computations 2, 1993.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from flint import fmpq

from ..analysis.critical import critical_polynomials_in, critical_values_in
from ..analysis.passivity import PassivityResult, is_passive
from ..analysis.region import passive_intervals
from ..errors import NotPassiveError, ParameterError
from ..exact import poly as ep
from ..model.delayatom import model_delays
from ..model.display import Shown, html_card, short_repr
from ..model.sea import SEA, Impedance, exact_values
from ..outcome import Outcome
from .bernstein import BoxSign, positive_on_box
from .box import UncertainBox, uncertain_box
from .family import ConditionKind, family_conditions, fixed_values

if TYPE_CHECKING:  # the sampled kernel loads only with robust.sampled_verdict
    from ..delay.passivity import DelayPassivityResult
    from ..sampled.passivity import SampledPassivityResult

__all__ = ["DEFAULT_BUDGET", "Method", "RobustResult", "WorstCase", "robust_check"]

DEFAULT_BUDGET = 5000
"""Boxes the certified branch and bound may examine (all conditions together)."""


class Method(StrEnum):
    """How a robust verdict was reached (the JSON value is the string)."""

    EXACT = "exact"
    CERTIFIED = "certified"


@dataclass(frozen=True, kw_only=True)
class WorstCase:
    """A plant of the box at which the design is not passive (verified by the ordinary test).

    Attributes
    ----------
    values : mapping of str to float
        The uncertain parameters at that plant.
    frequency : float or None
        A frequency [rad/s] where the design fails there: ``Re Z(jω) < 0`` (continuous)
        or a proven ``N(ω) < 0`` (sampled); None when the plant fails for another
        reason, e.g. an unstable pole.
    result : PassivityResult, SampledPassivityResult or DelayPassivityResult
        The ordinary verdict at that plant: the exact test (`robust_check`), the
        certified sampled-data verdict (`robust_sampled_check`) or the certified
        delayed verdict (`robust_check` of a delayed design).
    """

    values: Mapping[str, float]
    frequency: float | None
    result: PassivityResult | SampledPassivityResult | DelayPassivityResult = field(
        repr=False, compare=False
    )

    def to_dict(self) -> dict[str, Any]:
        return {
            "values": dict(self.values),
            "frequency": self.frequency,
            "reason": str(self.result.reason),
        }


@dataclass(frozen=True, repr=False, kw_only=True)
class RobustResult:
    """Outcome of a robust (box) passivity verdict.

    Attributes
    ----------
    outcome : Outcome
        ``PASSIVE``: passive for every plant in the box; ``NOT_PASSIVE``: `worst` is
        a plant of the box that is not passive; ``UNDECIDED``: neither was proven.
    box : UncertainBox
        The uncertain parameters.
    worst : WorstCase or None
        The verified counterexample of a negative verdict.
    method : Method
        ``"exact"`` (one parameter) or ``"certified"`` (Bernstein branch and bound).
    boxes : int
        Boxes examined by the branch and bound (0 for the exact method).
    detail : str
        Why, in words.
    delay : mapping or None
        ``{"name": ..., "tau": seconds}`` for a delayed design (the verdict is at that delay).
    """

    outcome: Outcome
    box: UncertainBox
    worst: WorstCase | None = None
    method: Method = Method.CERTIFIED
    boxes: int = 0
    detail: str = ""
    delay: Mapping[str, Any] | None = None

    @property
    def passive(self) -> bool:
        return self.outcome.passive

    @property
    def status(self) -> str:
        return str(self.outcome)

    def to_dict(self) -> dict[str, Any]:
        return {
            "robust": True,
            "passive": self.passive,
            "status": self.status,
            "box": self.box.to_dict(),
            "worst": None if self.worst is None else self.worst.to_dict(),
            "method": str(self.method),
            "boxes": self.boxes,
            "detail": self.detail,
            **({} if self.delay is None else {"delay": dict(self.delay)}),
        }

    def plot(self, kind: str = "real", *, ax: Any = None, omega: Any = None, **kwargs: Any) -> Any:
        """``Re Z(jω)`` (or the Nyquist plot) of the worst-case plant, with its failing bands.

        Only for a negative verdict (a passive box has no single plant to show); returns
        the matplotlib Axes.
        """
        if self.worst is None:
            raise ValueError(f"no worst-case plant to plot: the verdict is {self.outcome.label}")
        result = self.worst.result
        from ..delay.passivity import DelayPassivityResult

        assert isinstance(result, PassivityResult | DelayPassivityResult)  # continuous ones
        return result.plot(kind, ax=ax, omega=omega, **kwargs)

    def __repr__(self) -> str:
        worst = None
        if self.worst is not None:
            worst = Shown(", ".join(f"{k}={v:.6g}" for k, v in self.worst.values.items()))
        return short_repr(
            "RobustResult",
            {"outcome": str(self.outcome), "worst": worst, "method": str(self.method)},
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [("verdict", self.outcome.label), ("detail", self.detail)]
        rows += [(k, f"[{lo:g}, {hi:g}]") for k, (lo, hi) in self.box.intervals.items()]
        if self.worst is not None:
            at = ", ".join(f"{k} = {v:.6g}" for k, v in self.worst.values.items())
            rows.append(("worst case", at))
        return html_card(
            f"Robust passivity: {self.outcome.label}",
            rows,
            note=f"{self.method} verdict for every plant in the box",
        )


def _test(
    system: SEA | Impedance, fixed: Mapping[str, float], at: Mapping[str, float]
) -> PassivityResult:
    return is_passive(system, values={**fixed, **at})


def _worst(
    system: SEA | Impedance, fixed: Mapping[str, float], at: Mapping[str, float]
) -> WorstCase | None:
    """The exact test at ``at``: a `WorstCase` when not passive there."""
    res = _test(system, fixed, at)
    if res.passive:
        return None
    return WorstCase(values=dict(at), frequency=res.omega, result=res)


def _irrational_critical_inside(
    system: SEA | Impedance, name: str, lo: float, hi: float, fixed: Mapping[str, float]
) -> bool:
    """Whether an irrational critical value of ``name`` lies in ``[lo, hi]`` (rational ones
    are decided exactly as points by `passive_intervals`)."""
    polys = critical_polynomials_in(system, name, exact_values(fixed))
    crit = critical_values_in(polys, Fraction(lo), Fraction(hi))
    return any(c.poly is not None for c in crit)


def _one_parameter(
    system: SEA | Impedance, box: UncertainBox, fixed: Mapping[str, float], budget: int
) -> RobustResult:
    (name,) = box.names
    lo, hi = box.intervals[name]
    if lo == hi:
        w = _worst(system, fixed, {name: lo})
        out = Outcome.PASSIVE if w is None else Outcome.NOT_PASSIVE
        return RobustResult(
            outcome=out, box=box, worst=w, method=Method.EXACT, detail="a single plant"
        )
    pi = passive_intervals(system, name, lo, hi, values=dict(fixed))
    if pi.intervals == ((lo, hi),) and _irrational_critical_inside(system, name, lo, hi, fixed):
        # passive_intervals decides the doubles of [lo, hi]; a plant is a real number, and an
        # irrational critical value inside was never tested (it joins two passive cells):
        # decide the whole real interval with the certified branch and bound instead
        return _certified(system, box, fixed, budget)
    if pi.intervals == ((lo, hi),):
        return RobustResult(
            outcome=Outcome.PASSIVE,
            box=box,
            method=Method.EXACT,
            detail=f"the exact passive set of {name} contains [{lo:g}, {hi:g}]",
        )
    # the gaps of the passive set in [lo, hi]: test their middles and the critical values there
    ends = [lo, *(v for iv in pi.intervals for v in iv), hi]
    gaps = [(ends[i], ends[i + 1]) for i in range(0, len(ends), 2)]
    candidates: list[float] = []
    for a, b in sorted(gaps, key=lambda g: g[0] - g[1]):
        if b < a:
            continue
        candidates.append((a + b) / 2)
        candidates += [c for c in pi.critical_values if a <= c <= b]
    for c in candidates:
        w = _worst(system, fixed, {name: c})
        if w is not None:
            return RobustResult(
                outcome=Outcome.NOT_PASSIVE,
                box=box,
                worst=w,
                method=Method.EXACT,
                detail=f"not passive at {name} = {c:.10g} (exact passive set: "
                + (", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in pi.intervals) or "empty")
                + ")",
            )
    return RobustResult(  # pragma: no cover - the passive set has a gap with no failing point
        outcome=Outcome.UNDECIDED,
        box=box,
        method=Method.EXACT,
        detail="the passive set has a gap, but no failing plant was found in it",
    )


def _as_floats(names: tuple[str, ...], point: tuple[fmpq, ...]) -> dict[str, float]:
    return {n: float(ep.to_fraction(q)) for n, q in zip(names, point, strict=True)}


def _certified(
    system: SEA | Impedance, box: UncertainBox, fixed: Mapping[str, float], budget: int
) -> RobustResult:
    fam = family_conditions(system, box)
    center = box.center()
    if fam.generic_failure:
        w = _worst(system, fixed, center)
        if w is not None:
            return RobustResult(
                outcome=Outcome.NOT_PASSIVE,
                box=box,
                worst=w,
                detail=f"not passive at the centre of the box ({fam.generic_failure})",
            )
        return RobustResult(
            outcome=Outcome.UNDECIDED, box=box, detail=f"structural defect: {fam.generic_failure}"
        )
    region = [(fmpq(0), fmpq(1)), *((ep.rational(a), ep.rational(b)) for a, b in box.exact())]
    used = 0
    # real part last: it is the costliest, and stability failures are the plainer witnesses
    order = sorted(fam.conditions, key=lambda c: c.kind == ConditionKind.REAL_PART)
    for cond in order:
        search = positive_on_box(cond.coeffs, region, budget=budget - used)
        used += search.boxes
        if search.sign is BoxSign.PROVEN:
            continue
        if search.sign is BoxSign.BUDGET:
            return RobustResult(
                outcome=Outcome.UNDECIDED,
                box=box,
                boxes=used,
                detail=f"budget of {budget} boxes exhausted proving the {cond.label} positive",
            )
        assert search.point is not None
        at = _as_floats(box.names, search.point[1:])
        w = _worst(system, fixed, at)
        if w is None:
            return RobustResult(
                outcome=Outcome.UNDECIDED,
                box=box,
                boxes=used,
                detail=f"the {cond.label} is not positive at {at}, where the plant is passive "
                "(a boundary case)",
            )
        if cond.kind is ConditionKind.REAL_PART and w.frequency is None:
            t = search.point[0]
            if t < 1:
                w = WorstCase(
                    values=w.values, frequency=math.sqrt(float(t / (1 - t))), result=w.result
                )
        return RobustResult(
            outcome=Outcome.NOT_PASSIVE,
            box=box,
            worst=w,
            boxes=used,
            detail=f"not passive at {', '.join(f'{k}={v:.6g}' for k, v in at.items())}: "
            f"{w.result.detail}",
        )
    return RobustResult(
        outcome=Outcome.PASSIVE,
        box=box,
        boxes=used,
        detail=f"{len(fam.conditions)} positive-real conditions proven on the box",
    )


def robust_check(
    system: SEA | Impedance,
    *,
    box: Mapping[str, Any] | UncertainBox,
    values: Mapping[str, float] | None = None,
    budget: int = DEFAULT_BUDGET,
    throw: bool = False,
) -> RobustResult:
    """Decide whether ``system`` is passive for every plant in ``box``.

    Parameters
    ----------
    system : SEA or Impedance
        The design; every parameter not in ``box`` needs a value (in ``system``
        or ``values``).
    box : mapping of str to (lo, hi), or UncertainBox
        The uncertain parameters, e.g. ``{"m": (0.9, 1.1), "b": (8, 12)}``
        (checked by [`uncertain_box`][seapass.robust.box.uncertain_box]).
    values : mapping, optional
        Extra or overriding parameter values.
    budget : int, default DEFAULT_BUDGET
        Boxes the certified branch and bound may examine (several parameters).
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] unless the
        verdict is passive.

    Returns
    -------
    RobustResult

    Examples
    --------
    >>> from seapass.model.sea import SEA
    >>> sea = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))
    >>> robust_check(sea, box={"m": (0.5, 2.0)}).outcome
    <Outcome.PASSIVE: 'passive'>
    >>> r = robust_check(sea, box={"k1": (100, 1000), "m": (0.5, 2.0)})
    >>> r.outcome, r.worst.values["k1"] < 500
    (<Outcome.NOT_PASSIVE: 'not_passive'>, True)
    """
    if isinstance(budget, bool) or not isinstance(budget, int) or budget < 1:
        raise ParameterError(
            f"budget must be a positive integer, got {budget!r}", argument="budget"
        )
    if values:
        system = (
            system.with_values(**values)
            if isinstance(system, SEA)
            else Impedance(expr=system.expr, values={**system.values, **values})
        )
    if model_delays(system):  # a delay exp(-NAME*s): certified at the delay, over the box
        from .delayed import DEFAULT_DELAY_BUDGET, robust_delayed_check

        cells = DEFAULT_DELAY_BUDGET if budget == DEFAULT_BUDGET else budget
        return robust_delayed_check(system, box=box, budget=cells, throw=throw)
    checked = uncertain_box(system, box)
    fixed = fixed_values(system, checked)
    if len(checked.names) == 1:
        result = _one_parameter(system, checked, fixed, budget)
    else:
        result = _certified(system, checked, fixed, budget)
    if throw and not result.passive:
        raise NotPassiveError(f"not robustly passive: {result.detail}")
    return result
