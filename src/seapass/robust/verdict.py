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
  plant can lie inside the box.  A condition that is zero, not negative, where the
  structure changes is handled apart: a face of the box is decided as a box with one
  parameter fewer and the condition replaced by quotients off it
  ([`seapass.robust.faces`][seapass.robust.faces]); where such faces meet at a corner,
  the faces through it are decided first and the condition is proven off them by
  blowing the corner up ([`seapass.robust.corners`][seapass.robust.corners]).

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
from fractions import Fraction
from typing import Any

import numpy as np
from flint import fmpq

from ..analysis.critical import CriticalValue, critical_polynomials_in, critical_values_in
from ..analysis.region import passive_intervals
from ..errors import NotPassiveError, ParameterError
from ..exact import poly as ep
from ..files.limits import MAX_BOX_BUDGET
from ..model.delayatom import model_delays
from ..model.sea import SEA, Impedance, exact_values
from ..outcome import Outcome
from .bernstein import BoxSign, positive_on_box
from .box import UncertainBox, uncertain_box
from .corners import CornerSign, positive_off_faces
from .faces import divide_out, split_top
from .family import Condition, ConditionKind, family_conditions, fixed_values
from .result import Method, RobustResult, WorstCase
from .witness import as_floats, failing, inside_near, with_values, worst_at

__all__ = ["DEFAULT_BUDGET", "Method", "RobustResult", "WorstCase", "robust_check"]

DEFAULT_BUDGET = 5000
"""Boxes the certified branch and bound may examine (all conditions together)."""


def _irrational_critical_values(
    system: SEA | Impedance, name: str, lo: float, hi: float, fixed: Mapping[str, float]
) -> list[CriticalValue]:
    """The irrational critical values of ``name`` in ``[lo, hi]`` (rational ones are decided
    exactly as points by `passive_intervals`)."""
    polys = critical_polynomials_in(system, name, exact_values(fixed))
    crit = critical_values_in(polys, Fraction(lo), Fraction(hi))
    return [c for c in crit if c.poly is not None]


def _enclosing_doubles(lo: Fraction, hi: Fraction) -> tuple[float, float]:
    """The tightest pair of doubles ``a <= lo``, ``b >= hi`` (outward rounding)."""
    a, b = float(lo), float(hi)
    if Fraction(a) > lo:
        a = math.nextafter(a, -math.inf)
    if Fraction(b) < hi:
        b = math.nextafter(b, math.inf)
    return a, b


def _across_irrational(
    system: SEA | Impedance,
    box: UncertainBox,
    fixed: Mapping[str, float],
    crit: list[CriticalValue],
    budget: int,
) -> RobustResult:
    """Decide the real points the exact cells leave out: each irrational critical value,
    by the certified branch and bound on a tiny box of doubles around its isolating
    interval (the cells on both sides are decided exactly by `passive_intervals`)."""
    (name,) = box.names
    used = 0
    for c in crit:
        a, b = _enclosing_doubles(c.lo, c.hi)
        lo, hi = box.intervals[name]
        tiny = UncertainBox(intervals={name: (max(a, lo), min(b, hi))})
        r = _certified(system, tiny, fixed, budget - used)
        used += r.boxes
        if r.outcome is Outcome.PASSIVE:
            continue
        if r.outcome is Outcome.NOT_PASSIVE:
            return RobustResult(
                outcome=Outcome.NOT_PASSIVE, box=box, worst=r.worst, boxes=used, detail=r.detail
            )
        # a touching point (the real part reaches 0 at the critical value): try the box whole
        return _certified(system, box, fixed, budget)
    return RobustResult(
        outcome=Outcome.PASSIVE,
        box=box,
        boxes=used,
        detail=f"the exact passive set of {name} contains [{box.intervals[name][0]:g}, "
        f"{box.intervals[name][1]:g}]; its {len(crit)} irrational critical value(s) inside "
        "are certified by Bernstein branch and bound on their isolating intervals",
    )


def _one_parameter(
    system: SEA | Impedance, box: UncertainBox, fixed: Mapping[str, float], budget: int
) -> RobustResult:
    (name,) = box.names
    lo, hi = box.intervals[name]
    if lo == hi:
        w = worst_at(system, fixed, {name: lo})
        out = Outcome.PASSIVE if w is None else Outcome.NOT_PASSIVE
        return RobustResult(
            outcome=out, box=box, worst=w, method=Method.EXACT, detail="a single plant"
        )
    pi = passive_intervals(system, name, lo, hi, values=dict(fixed))
    irrational = _irrational_critical_values(system, name, lo, hi, fixed)
    if pi.intervals == ((lo, hi),) and irrational:
        # passive_intervals decides the doubles of [lo, hi]; a plant is a real number, and an
        # irrational critical value inside was never tested (it joins two passive cells)
        return _across_irrational(system, box, fixed, irrational, budget)
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
        w = worst_at(system, fixed, {name: c})
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


Face = tuple[int, bool]  # (axis of the Bernstein region, upper end)


def _off_face(
    cond: Condition, point: tuple[fmpq, ...], region: list[tuple[fmpq, fmpq]]
) -> tuple[Face, list[np.ndarray]] | None:
    """A face of the box through ``point`` on which ``cond`` vanishes, and the conditions
    that prove it positive off that face (`seapass.robust.faces`), or None."""
    for axis in range(1, len(region)):
        lo, hi = region[axis]
        if lo == hi or point[axis] not in (lo, hi):
            continue
        upper = point[axis] == hi
        c = hi if upper else lo
        whole = divide_out(cond.coeffs, axis, c, upper=upper)
        if whole is not None:
            return (axis, upper), [whole]
        if cond.kind is ConditionKind.REAL_PART and point[0] == 1:
            parts = split_top(cond.coeffs)
            if parts is not None:
                top = divide_out(parts[0], axis, c, upper=upper)
                if top is not None:
                    return (axis, upper), [top, parts[1]]
    return None


def _face(
    system: SEA | Impedance,
    box: UncertainBox,
    fixed: Mapping[str, float],
    face: Face,
    budget: int,
) -> RobustResult:
    """The robust verdict on one face of ``box`` (a box with one parameter fewer)."""
    name = box.names[face[0] - 1]
    value = box.intervals[name][1 if face[1] else 0]
    rest = {k: v for k, v in box.intervals.items() if k != name}
    at_face = with_values(system, {name: value})
    fixed_face = {**fixed, name: value}
    if not rest:
        w = worst_at(at_face, fixed_face, {})
        r = RobustResult(
            outcome=Outcome.PASSIVE if w is None else Outcome.NOT_PASSIVE, box=box, worst=w
        )
    elif len(rest) == 1:
        r = _one_parameter(at_face, UncertainBox(intervals=rest), fixed_face, budget)
    else:
        r = _certified(at_face, UncertainBox(intervals=rest), fixed_face, budget)
    if r.worst is None:
        return r
    # the face's worst plant, with the face's own coordinate (a plant of the whole box)
    merged = {**r.worst.values, name: value}
    worst = WorstCase(
        values={n: merged[n] for n in box.names if n in merged},
        frequency=r.worst.frequency,
        result=r.worst.result,
    )
    return RobustResult(
        outcome=r.outcome, box=r.box, worst=worst, method=r.method, boxes=r.boxes, detail=r.detail
    )


def _corner(
    system: SEA | Impedance,
    box: UncertainBox,
    fixed: Mapping[str, float],
    root: Condition,
    point: tuple[fmpq, ...],
    region: list[tuple[fmpq, fmpq]],
    faces: list[Face],
    decided: set[Face],
    budget: int,
) -> tuple[RobustResult | None, int]:
    """A condition zero at a passive plant ``point`` that no quotient proves: decide the
    faces of the box through ``point`` (a face of a face is a corner), then prove the
    condition off all faces decided apart by blowing up its corners
    ([`seapass.robust.corners`][seapass.robust.corners]).  ``(None, boxes)`` when proven;
    else the verdict (not passive with a verified plant, or undecided)."""
    ends = [(a, point[a] == region[a][1]) for a in range(1, len(region))]
    ends = [(a, up) for a, up in ends if region[a][0] < region[a][1] and point[a] in region[a]]
    through = [f for f in ends if f in faces] or ends
    used = 0
    for face in through:
        if face not in faces:
            faces.append(face)
        if face in decided:
            continue
        r = _face(system, box, fixed, face, budget - used)
        used += r.boxes
        decided.add(face)
        if r.outcome is not Outcome.PASSIVE:
            out = RobustResult(
                outcome=r.outcome,
                box=box,
                worst=r.worst,
                boxes=used,
                detail=f"on a face: {r.detail}",
            )
            return out, used
    if used >= budget:
        return RobustResult(
            outcome=Outcome.UNDECIDED, box=box, boxes=used, detail="budget exhausted on faces"
        ), used
    search = positive_off_faces(root.coeffs, region, faces, budget=budget - used)
    used += search.boxes
    if search.sign is CornerSign.PROVEN:
        return None, used
    if search.sign is CornerSign.BUDGET or search.point is None:
        return RobustResult(
            outcome=Outcome.UNDECIDED,
            box=box,
            boxes=used,
            detail=f"budget of {budget} boxes exhausted proving the {root.label} positive "
            "off the faces of the box",
        ), used
    at = as_floats(box.names, search.point[1:])
    w = worst_at(system, fixed, at)
    if w is None:
        w, at = inside_near(system, fixed, box, at)
    if w is None:
        return RobustResult(
            outcome=Outcome.UNDECIDED,
            box=box,
            boxes=used,
            detail=f"the {root.label} is not positive at {at}, where the plant is passive "
            f"({search.sign} after blowing up {search.charts} chart(s) of a corner)",
        ), used
    return failing(w, at, root, search.point, box, used), used


def _certified(
    system: SEA | Impedance, box: UncertainBox, fixed: Mapping[str, float], budget: int
) -> RobustResult:
    fam = family_conditions(system, box)
    center = box.center()
    if fam.generic_failure:
        w = worst_at(system, fixed, center)
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
    roots = sorted(fam.conditions, key=lambda c: c.kind == ConditionKind.REAL_PART)
    pending = [(c, i) for i, c in enumerate(roots)]  # (condition, index of its root)
    resolved: set[int] = set()  # roots proven off the faces by blowing up their corners
    faces: list[Face] = []
    decided: set[Face] = set()
    while pending:
        cond, root = pending.pop(0)
        if root in resolved:
            continue
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
        at = as_floats(box.names, search.point[1:])
        w = worst_at(system, fixed, at)
        split = None if w is not None else _off_face(cond, search.point, region)
        if split is not None:
            # zero, not negative, on a face where the structure changes: prove the condition
            # off the face and decide the face apart
            if split[0] not in faces:
                faces.append(split[0])
            off_label = (
                cond.label
                if cond.label.endswith("(off a face)")
                else (f"{cond.label} (off a face)")
            )
            pending[:0] = [
                (Condition(kind=cond.kind, label=off_label, coeffs=c), root) for c in split[1]
            ]
            continue
        if w is None:
            w, at = inside_near(system, fixed, box, at)
        if w is None:  # zero at a corner of faces: decide them, blow the corner up
            r, n = _corner(
                system, box, fixed, roots[root], search.point, region, faces, decided, budget - used
            )
            used += n
            if r is None:
                resolved.add(root)
                continue
            return r
        return failing(w, at, cond, search.point, box, used)
    for face in faces:
        if face in decided:
            continue
        r = _face(system, box, fixed, face, budget - used)
        used += r.boxes
        if r.outcome is not Outcome.PASSIVE:
            return RobustResult(
                outcome=r.outcome,
                box=box,
                worst=r.worst,
                boxes=used,
                detail=f"on a face: {r.detail}",
            )
    on_faces = f", off {len(faces)} face(s) of the box decided apart" if faces else ""
    if resolved:
        on_faces += f" ({len(resolved)} condition(s) proven off them by blowing up a corner)"
    return RobustResult(
        outcome=Outcome.PASSIVE,
        box=box,
        boxes=used,
        detail=f"{len(fam.conditions)} positive-real conditions proven on the box{on_faces}",
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
    if isinstance(budget, bool) or not isinstance(budget, int) or not 1 <= budget <= MAX_BOX_BUDGET:
        raise ParameterError(
            f"budget must be an integer in [1, {MAX_BOX_BUDGET}], got {budget!r}",
            argument="budget",
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
