"""Robust two-port verdicts: absolutely stable and passive for every plant in a box.

`robust_two_port_check` decides, for every value of the uncertain parameters in a
box, Llewellyn's absolute stability and Raisbeck's passivity of a two-port
([`seapass.ports`][seapass.ports]); each verdict is reached like
[`robust_check`][seapass.robust.verdict.robust_check]'s:

* **one uncertain parameter: exact.**  The exact set of that parameter for which
  the criterion holds ([`port_intervals`][seapass.ports.bound.port_intervals])
  contains the interval (and no irrational critical value lies inside, where the
  set was never decided as a point), or a gap of it holds a failing plant.
* **several (or an irrational critical value inside): certified.**  The
  polynomial conditions of the family ([`seapass.robust.portfamily`][seapass.robust.portfamily]:
  Routh–Hurwitz conditions of the common denominator, the residues at 0 and at
  infinity, the frequency conditions in ``ω²`` compactified to ``[0, 1]``) are each
  proven positive on the box by exact Bernstein branch and bound
  ([`seapass.robust.bernstein`][seapass.robust.bernstein]) within a counted budget.
  No vertex reasoning: the conditions are polynomial in the parameters.

A negative verdict carries a **worst plant** (values and, when a frequency
condition fails, a frequency in its exact failing band) at which the ordinary
exact verdict [`check_two_port`][seapass.ports.check.check_two_port] fails.
A budget that runs out, or a failing condition whose point the exact verdict
passes, is `Outcome.UNDECIDED`, never passive.

References
----------
.. [1] F. B. Llewellyn, "Some fundamental properties of transmission systems",
   Proc. IRE 40(3), 1952.
.. [2] J. Garloff, "The Bernstein algorithm", Interval Computations 2, 1993.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from flint import fmpq

from ..errors import NotPassiveError, ParameterError
from ..exact import poly as ep
from ..model.sea import SEA
from ..outcome import Outcome
from ..ports.bound import Criterion, port_critical_values, port_intervals
from ..ports.check import TwoPortCheck, check_two_port
from ..ports.stability import as_two_port
from ..ports.twoport import TwoPort
from .bernstein import BoxSign, positive_on_box
from .box import UncertainBox, uncertain_box
from .portfamily import PortConditionKind, port_family
from .portresult import PortWorstCase, RobustPortVerdict, RobustTwoPortResult
from .verdict import DEFAULT_BUDGET, Method

__all__ = [
    "port_fixed_values",
    "robust_port_verdict",
    "robust_two_port_check",
]


def port_fixed_values(
    tp: TwoPort, box: UncertainBox, free: tuple[str, ...] = ()
) -> dict[str, float]:
    """The values of every parameter of ``tp`` not in ``box`` nor ``free`` (all must be given)."""
    skip = {*box.intervals, *free}
    fixed = {k: float(v) for k, v in tp.values.items() if k not in skip and v is not None}
    missing = [n for n in tp.parameters if n not in skip and n not in fixed]
    if missing:
        raise ParameterError(
            f"no value for parameter(s) {', '.join(missing)}: give them, "
            f"e.g. values={{{missing[0]!r}: 1.0}}"
        )
    return {k: v for k, v in fixed.items() if k in tp.parameters}


def _outcome(check: TwoPortCheck, criterion: Criterion) -> Outcome:
    return check.stability.outcome if criterion is Criterion.ABSOLUTE else check.passivity.outcome


def _frequency(
    check: TwoPortCheck, criterion: Criterion, hint: float | None
) -> tuple[str, float | None]:
    conds = (
        check.stability.conditions
        if criterion is Criterion.ABSOLUTE
        else check.passivity.conditions
    )
    failing = [c for c in conds if c.holds is False]
    first = failing[0]
    for c in failing:
        for b in c.bands:
            if hint is not None and b.lo < hint < b.hi:
                return c.name, hint
    for c in failing:
        for b in c.bands:
            if math.isinf(b.hi):
                return c.name, max(2 * b.lo, b.lo + 1.0)
            if b.hi > b.lo:
                return c.name, b.hi / 2 if b.lo == 0 else math.sqrt(b.lo * b.hi)
    return first.name, None


def _worst(
    tp: TwoPort,
    fixed: Mapping[str, float],
    at: Mapping[str, float],
    criterion: Criterion,
    hint: float | None = None,
) -> PortWorstCase | None:
    """The exact verdict at ``at``: a `PortWorstCase` when ``criterion`` fails there."""
    check = check_two_port(tp, values={**fixed, **at}, witness=False)
    if _outcome(check, criterion) is not Outcome.NOT_PASSIVE:
        return None
    name, omega = _frequency(check, criterion, hint)
    return PortWorstCase(values=dict(at), frequency=omega, condition=name, result=check)


def _as_floats(names: tuple[str, ...], point: tuple[fmpq, ...]) -> dict[str, float]:
    return {n: float(ep.to_fraction(q)) for n, q in zip(names, point, strict=True)}


def _at_text(at: Mapping[str, float]) -> str:
    return ", ".join(f"{k}={v:.6g}" for k, v in at.items())


def _cheap_plants(box: UncertainBox) -> list[dict[str, float]]:
    """The centre and (up to 3 parameters) the corners of the box: cheap exact checks."""
    plants = [box.center()]
    if len(box.names) <= 3:
        plants += box.corners()
    return plants


def _certified(
    tp: TwoPort, box: UncertainBox, fixed: Mapping[str, float], criterion: Criterion, budget: int
) -> RobustPortVerdict:
    fam = port_family(tp, box, fixed, criterion)

    def verdict(
        outcome: Outcome, detail: str, used: int = 0, worst: PortWorstCase | None = None
    ) -> RobustPortVerdict:
        return RobustPortVerdict(
            criterion=criterion, outcome=outcome, worst=worst, boxes=used, detail=detail
        )

    if fam.generic_failure:
        w = _worst(tp, fixed, box.center(), criterion)
        if w is not None:
            return verdict(
                Outcome.NOT_PASSIVE,
                f"fails at the centre of the box ({fam.generic_failure})",
                worst=w,
            )
        return verdict(Outcome.UNDECIDED, f"structural defect: {fam.generic_failure}")
    for plant in _cheap_plants(box):  # a failing corner or centre ends it without a search
        w = _worst(tp, fixed, plant, criterion)
        if w is not None:
            return verdict(
                Outcome.NOT_PASSIVE, f"fails at {_at_text(plant)}: {w.condition}", worst=w
            )
    region = [(fmpq(0), fmpq(1)), *((ep.rational(a), ep.rational(b)) for a, b in box.exact())]
    used = 0
    order = sorted(fam.conditions, key=lambda c: c.kind is PortConditionKind.FREQUENCY)
    for cond in order:
        search = positive_on_box(cond.coeffs, region, budget=budget - used)
        used += search.boxes
        if search.sign is BoxSign.PROVEN:
            continue
        if search.sign is BoxSign.BUDGET:
            return verdict(
                Outcome.UNDECIDED, f"budget of {budget} boxes exhausted proving {cond.label}", used
            )
        assert search.point is not None
        at = _as_floats(box.names, search.point[1:])
        t = search.point[0]
        hint = (
            math.sqrt(float(t / (1 - t)))
            if cond.kind is PortConditionKind.FREQUENCY and t < 1
            else None
        )
        w = _worst(tp, fixed, at, criterion, hint)
        if w is None:
            return verdict(
                Outcome.UNDECIDED,
                f"{cond.label} is not proven at {_at_text(at)}, where the exact verdict holds "
                "(a boundary case)",
                used,
            )
        return verdict(
            Outcome.NOT_PASSIVE, f"fails at {_at_text(at)}: {w.condition}", used, worst=w
        )
    if fam.keeps_pole:
        for cand in fam.keeps_pole:
            search = positive_on_box(cand.coeffs, region, budget=budget - used)
            used += search.boxes
            if search.sign is BoxSign.PROVEN:
                break
        else:
            return verdict(
                Outcome.UNDECIDED,
                "the pole at s = 0 may cancel in the box (a hidden mode at 0)",
                used,
            )
    return verdict(Outcome.PASSIVE, f"{len(fam.conditions)} conditions proven on the box", used)


def _one_parameter(
    tp: TwoPort, box: UncertainBox, fixed: Mapping[str, float], criterion: Criterion, budget: int
) -> RobustPortVerdict:
    (name,) = box.names
    lo, hi = box.intervals[name]

    def exact(
        outcome: Outcome, detail: str, worst: PortWorstCase | None = None
    ) -> RobustPortVerdict:
        return RobustPortVerdict(
            criterion=criterion, outcome=outcome, worst=worst, method=Method.EXACT, detail=detail
        )

    if lo == hi:
        w = _worst(tp, fixed, {name: lo}, criterion)
        if w is not None:
            return exact(Outcome.NOT_PASSIVE, "fails at the single plant", w)
        check = check_two_port(tp, values={**fixed, name: lo}, witness=False)
        return exact(_outcome(check, criterion), "a single plant")
    pi = port_intervals(tp, name, lo, hi, criterion=criterion, values=dict(fixed))
    if pi.intervals == ((lo, hi),):
        crit = port_critical_values(tp, name, lo, hi, criterion=criterion, values=dict(fixed))
        if any(a != b for a, b in crit):
            # an irrational critical value was never decided as a point: certify instead
            return _certified(tp, box, fixed, criterion, budget)
        return exact(
            Outcome.PASSIVE,
            f"the exact {criterion.label} set of {name} contains [{lo:g}, {hi:g}]",
        )
    ends = [lo, *(v for iv in pi.intervals for v in iv), hi]
    gaps = [(ends[i], ends[i + 1]) for i in range(0, len(ends), 2)]
    candidates: list[float] = []
    for a, b in sorted(gaps, key=lambda g: g[0] - g[1]):
        if b >= a:
            candidates.append((a + b) / 2)
            candidates += [c for c in pi.critical_values if a <= c <= b]
    for c in candidates:
        w = _worst(tp, fixed, {name: c}, criterion)
        if w is not None:
            shown = ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in pi.intervals) or "empty"
            return exact(
                Outcome.NOT_PASSIVE,
                f"fails at {name} = {c:.10g} (exact {criterion.label} set: {shown})",
                w,
            )
    return _certified(tp, box, fixed, criterion, budget)  # no failing plant found: certify


def robust_port_verdict(
    tp: TwoPort,
    box: UncertainBox,
    fixed: Mapping[str, float],
    criterion: Criterion,
    budget: int = DEFAULT_BUDGET,
) -> RobustPortVerdict:
    """One criterion of ``tp`` over the checked ``box`` (other parameters at ``fixed``)."""
    if len(box.names) == 1:
        return _one_parameter(tp, box, fixed, criterion, budget)
    return _certified(tp, box, fixed, criterion, budget)


def robust_two_port_check(
    system: TwoPort | SEA,
    *,
    box: Mapping[str, Any] | UncertainBox,
    values: Mapping[str, float] | None = None,
    budget: int = DEFAULT_BUDGET,
    throw: bool = False,
) -> RobustTwoPortResult:
    """Absolute stability and passivity of a two-port for every plant in ``box``.

    Parameters
    ----------
    system : TwoPort or SEA
        The two-port (an SEA: its person–environment two-port); every parameter not
        in ``box`` needs a value.
    box : mapping of str to (lo, hi), or UncertainBox
        The uncertain parameters, e.g. ``{"m": (0.9, 1.1), "b": (8, 12)}``
        (checked by [`uncertain_box`][seapass.robust.box.uncertain_box]: known
        names, ``lo <= hi``, physical plant values, bounded work).
    values : mapping, optional
        Extra or overriding parameter values.
    budget : int, default DEFAULT_BUDGET
        Boxes the certified branch and bound may examine, per criterion.
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] unless the
        two-port is proven absolutely stable for every plant.

    Returns
    -------
    RobustTwoPortResult

    Examples
    --------
    >>> from seapass import SEA
    >>> sea = SEA(D1="k1", CA="kd", values=dict(m=1, b=10, k1=1000, kd=500))
    >>> r = robust_two_port_check(sea, box={"m": (0.5, 2.0), "b": (5, 20)})
    >>> r.absolutely_stable, r.passive
    (True, True)
    >>> sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl",
    ...           values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25, kl=1500))
    >>> r = robust_two_port_check(sea, box={"m": (0.8, 1.2), "b": (8, 12)})
    >>> r.status, r.worst.condition
    ('not_passive', 're_p11')
    """
    if isinstance(budget, bool) or not isinstance(budget, int) or budget < 1:
        raise ParameterError(
            f"budget must be a positive integer, got {budget!r}", argument="budget"
        )
    tp = as_two_port(system)
    if values:
        tp = tp.with_values(**values)
    checked = uncertain_box(tp, box)
    fixed = port_fixed_values(tp, checked)
    stab = robust_port_verdict(tp, checked, fixed, Criterion.ABSOLUTE, budget)
    pas = robust_port_verdict(tp, checked, fixed, Criterion.PASSIVE, budget)
    result = RobustTwoPortResult(box=checked, stability=stab, passivity=pas, two_port=tp)
    if throw and not result.absolutely_stable:
        raise NotPassiveError(f"not robustly absolutely stable: {stab.detail}")
    return result
