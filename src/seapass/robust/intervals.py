"""Robust passive intervals: the values of a gain for which every plant in a box is passive.

`robust_passive_intervals` returns the set ``G = {g : the design is passive for every
plant in the box}`` of one parameter ``g`` within ``[lo, hi]``:

* **one uncertain parameter ``u``: exact.**  The verdict over ``(g, u)`` changes only
  on the real zero sets of the critical polynomials ``f_k(g, u)`` of
  [`critical_polynomials`][seapass.analysis.region.critical_polynomials].  Over
  ``g`` the picture of ``[u_lo, u_hi]`` changes only at the real roots of the
  leading coefficients and discriminants in ``u`` of every ``f_k``, the resultants
  in ``u`` of every pair, ``f_k(g, u_lo)``, ``f_k(g, u_hi)`` and the factors in
  ``g`` alone (a cylindrical decomposition, as in
  [`seapass.analysis.boundary`][seapass.analysis.boundary]).  Between two such
  values the robust verdict is constant, so one exact one-parameter verdict
  ([`robust_check`][seapass.robust.verdict.robust_check] over ``u``) at a rational
  point of every gap, and at every rational critical value, gives ``G`` exactly.
* **several: certified inner and outer sets.**  Inner: the union of the
  ``g``-intervals on which [`robust_check`][seapass.robust.verdict.robust_check]
  proves the box ``{g-interval} × box`` passive (bisection down to ``rtol``).
  Outer: the intersection of the exact passive sets of ``g`` at the corners and
  the centre of the box and at every counterexample found (each plant's passive
  set contains ``G``).

* **a delay** ``exp(-NAME*s)`` in the model: certified inner and outer sets at the
  delay's value ([`seapass.robust.delayedgains`][seapass.robust.delayedgains]; the
  result's ``delay`` and ``excluded`` are set).

End points are rounded **inward** for ``intervals`` (every printed end is in ``G``)
and outward for ``outer``.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, cast

import sympy as sp
from flint import fmpq_poly

from ..analysis.region import critical_polynomials, passive_intervals
from ..errors import ParameterError
from ..exact import poly as ep
from ..files.limits import MAX_BOX_BUDGET, check_rtol
from ..model.delayatom import model_delays
from ..model.display import Shown, html_card, short_repr
from ..model.expr import symbol, to_fraction
from ..model.sea import SEA, Impedance
from ..outcome import Outcome
from . import pieces
from .box import UncertainBox, uncertain_box
from .verdict import DEFAULT_BUDGET, Method, robust_check

__all__ = ["RobustIntervals", "robust_passive_intervals"]

#: Most g-intervals examined by the certified inner set.
MAX_SEGMENTS = 400


@dataclass(frozen=True, repr=False, kw_only=True)
class RobustIntervals:
    """The robust passive set of one parameter over a box of plants.

    Attributes
    ----------
    param : str
    lo, hi : float
        The search range.
    box : UncertainBox
    intervals : tuple of (float, float)
        Inner set: every value in these intervals is passive for every plant in
        the box (exactly the robust set with ``method == "exact"``); ends rounded inward.
    outer : tuple of (float, float)
        Outer set: no value outside is robustly passive; ends rounded outward
        (equal to ``intervals`` up to rounding with the exact method).
    method : Method
        ``"exact"`` (one uncertain parameter) or ``"certified"``.
    delay : mapping or None
        ``{"name": ..., "tau": seconds}`` for a delayed design (the sets are at that delay,
        certified: [`seapass.robust.delayedgains`][seapass.robust.delayedgains]).
    excluded : tuple of mapping
        With a delay: the gain segments left out of ``outer``, each with a plant of the box
        (``values``), the ``reason`` (``"negative_real_part"`` at ``frequency`` rad/s, or
        ``"unstable"``) proven for every gain of the segment.
    cells : int
        With a delay: the cells of all its certificates (counted work).
    exhausted : bool
        With a delay: ``max_cells`` ran out, so the inner set is what was certified until
        then (possibly empty) and the outer set is wider than it would otherwise be.
    """

    param: str
    lo: float
    hi: float
    box: UncertainBox
    intervals: tuple[tuple[float, float], ...] = ()
    outer: tuple[tuple[float, float], ...] = ()
    method: Method = Method.EXACT
    delay: Mapping[str, Any] | None = None
    excluded: tuple[Mapping[str, Any], ...] = ()
    cells: int = 0
    exhausted: bool = False

    def contains(self, value: float) -> bool:
        return any(a <= value <= b for a, b in self.intervals)

    def to_dict(self) -> dict[str, Any]:
        return {
            "robust": True,
            "param": self.param,
            "range": [self.lo, self.hi],
            "box": self.box.to_dict(),
            "intervals": [list(iv) for iv in self.intervals],
            "outer": [list(iv) for iv in self.outer],
            "method": str(self.method),
            **(
                {}
                if self.delay is None
                else {
                    "delay": dict(self.delay),
                    "delay_time": self.delay["tau"],
                    "excluded": [dict(x) for x in self.excluded],
                    "cells": self.cells,
                    "exhausted": self.exhausted,
                }
            ),
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """The robust passive set (inner set) as a bar over the search range; returns the Axes."""
        from ..plot.region import plot_passive_intervals

        return plot_passive_intervals(cast(Any, self), ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "RobustIntervals",
            {
                "param": self.param,
                "intervals": Shown(pieces.text(self.intervals)),
                "method": str(self.method),
            },
        )

    def _repr_html_(self) -> str:
        rows = [("search range", f"[{self.lo:g}, {self.hi:g}]")]
        if self.delay is not None:
            rows.append(("delay", f"{self.delay['name']} = {self.delay['tau']:g} s"))
        rows += [(k, f"[{a:g}, {b:g}]") for k, (a, b) in self.box.intervals.items()]
        rows += [("passive for every plant", pieces.text(self.intervals))]
        if self.method is not Method.EXACT:
            rows.append(("outer enclosure", pieces.text(self.outer, outer=True)))
        return html_card(f"Robust passive set of {self.param}", rows)


def _poly_in(expr: sp.Expr, x: sp.Symbol) -> fmpq_poly:
    p = sp.Poly(sp.expand(expr), x, domain="QQ")
    return fmpq_poly([ep.rational(Fraction(int(c.p), int(c.q))) for c in p.all_coeffs()[::-1]])


def _g_critical(
    system: SEA | Impedance, fixed: Mapping[str, float], g: str, u: str,
    g_box: tuple[Fraction, Fraction], u_box: tuple[Fraction, Fraction],
) -> list[tuple[Fraction, Fraction]]:  # fmt: skip
    """Critical values of ``g`` in ``[lo, hi]``: ``(r, r)`` if rational, else an isolating interval."""
    x, y = symbol(g), symbol(u)
    polys = critical_polynomials(system, (g, u), values=dict(fixed))
    factors: dict[sp.Expr, None] = {}
    for e in polys:
        if e.has(x, y):
            for f, _m in sp.factor_list(sp.Poly(e, x, y, domain="QQ"))[1]:
                factors.setdefault(f.as_expr(), None)
    fy = [f for f in factors if f.has(y)]
    out: list[sp.Expr] = [f for f in factors if not f.has(y)]
    uq = [sp.Rational(v.numerator, v.denominator) for v in u_box]
    for f in fy:
        p = sp.Poly(f, y)
        out += [p.LC(), f.subs(y, uq[0]), f.subs(y, uq[1])]
        if p.degree() > 1:
            out.append(sp.discriminant(f, y))
    for f, h in itertools.combinations(fy, 2):
        out.append(sp.resultant(f, h, y))
    lo, hi = ep.rational(g_box[0]), ep.rational(g_box[1])
    crit: set[tuple[Fraction, Fraction]] = set()
    in_g: dict[sp.Expr, None] = {}
    for e in out:
        e = sp.expand(e)
        if e.has(x):
            for f, _m in sp.factor_list(sp.Poly(e, x, domain="QQ"))[1]:
                in_g.setdefault(f.monic().as_expr(), None)
    for e in in_g:
        q = _poly_in(e, x)
        if q.degree() == 1:
            r = ep.to_fraction(-q[0] / q[1])
            if g_box[0] <= r <= g_box[1]:
                crit.add((r, r))
            continue
        if q(lo) == 0:
            crit.add((g_box[0], g_box[0]))
        for a, b in ep.isolate_real_roots(q, lo, hi):
            scale = abs(b) if abs(b) > 1 else ep.rational(1)
            a, b = ep.refine(q, (a, b), scale * ep.rational(Fraction(1, 2**60)))
            crit.add((ep.to_fraction(a), ep.to_fraction(b)))
    return sorted(crit)


def _strictly_above(x: Fraction) -> float:
    f = pieces.up(x)
    return math.nextafter(f, math.inf) if Fraction(f) == x else f


def _strictly_below(x: Fraction) -> float:
    f = pieces.down(x)
    return math.nextafter(f, -math.inf) if Fraction(f) == x else f


def _exact(
    system: SEA | Impedance, g: str, lo: Fraction, hi: Fraction, box: UncertainBox,
    fixed: Mapping[str, float],
) -> RobustIntervals:  # fmt: skip
    (u,) = box.names
    crit = _g_critical(system, fixed, g, u, (lo, hi), box.exact()[0])

    def robust_at(v: Fraction) -> bool:
        return robust_check(system, box=box, values={**fixed, g: float(v)}).passive

    # cells in order: (start, end, passive, outer_start, outer_end); a point has start == end
    cells: list[tuple[Fraction, Fraction, bool, Fraction, Fraction]] = []

    def gap(start: Fraction, end: Fraction, outer_lo: Fraction, outer_hi: Fraction) -> None:
        mid = Fraction(float((start + end) / 2))
        inside = start < mid < end or start == mid == end
        # no float strictly inside a gap narrower than one ulp: left out (inner set)
        cells.append((start, end, inside and robust_at(mid), outer_lo, outer_hi))

    cursor, prev_lo = lo, lo
    for a, b in crit:
        if a > cursor:
            gap(cursor, a, prev_lo, b)
        if a == b:
            cells.append((a, a, robust_at(a), a, a))
        cursor, prev_lo = max(cursor, b), a
    if hi > cursor or not cells:
        gap(cursor, hi, prev_lo, hi)
    inner: list[tuple[float, float]] = []
    outer: list[tuple[float, float]] = []
    bad = {a for a, b, ok, _c, _d in cells if a == b and not ok}
    runs = [list(grp) for ok, grp in itertools.groupby(cells, key=lambda c: c[2]) if ok]
    for run in runs:
        first, last = run[0], run[-1]
        a_f = (
            _strictly_above(first[0])
            if first[0] in bad and first[0] != first[1]
            else pieces.up(first[0])
        )
        b_f = (
            _strictly_below(last[1])
            if last[1] in bad and last[0] != last[1]
            else pieces.down(last[1])
        )
        if first[0] == lo:
            a_f = pieces.up(lo)
        if last[1] == hi:
            b_f = pieces.down(hi)
        if a_f <= b_f:
            inner.append((a_f, b_f))
        outer.append((pieces.down(first[3]), pieces.up(last[4])))
    return RobustIntervals(
        param=g,
        lo=float(lo),
        hi=float(hi),
        box=box,
        intervals=tuple(inner),
        outer=tuple(outer),
        method=Method.EXACT,
    )


def _certified(
    system: SEA | Impedance, g: str, lo: Fraction, hi: Fraction, box: UncertainBox,
    fixed: Mapping[str, float], rtol: float, budget: int,
) -> RobustIntervals:  # fmt: skip

    def exact_set(plant: Mapping[str, float]) -> tuple[tuple[float, float], ...]:
        values = {**fixed, **plant}
        return passive_intervals(system, g, float(lo), float(hi), values=values).intervals

    def verdict(a: Fraction, b: Fraction) -> tuple[bool, dict[str, float] | None]:
        seg = {**box.intervals, g: (float(a), float(b))}
        r = robust_check(system, box=seg, values=dict(fixed), budget=budget)
        worst = None if r.worst is None else {k: v for k, v in r.worst.values.items() if k != g}
        return r.outcome is Outcome.PASSIVE, worst

    inner, outer, _seen = pieces.robust_gain_set(
        lo, hi, plants=[*box.corners(), box.center()], exact_set=exact_set, verdict=verdict,
        width=Fraction(rtol) * max(abs(lo), abs(hi), Fraction(1)), max_segments=MAX_SEGMENTS,
    )  # fmt: skip
    return RobustIntervals(
        param=g,
        lo=float(lo),
        hi=float(hi),
        box=box,
        intervals=pieces.as_floats(pieces.merge(inner), inward=True),
        outer=pieces.as_floats(outer, inward=False),
        method=Method.CERTIFIED,
    )


def _delayed(
    system: SEA | Impedance, g: str, lo: Fraction, hi: Fraction, box: UncertainBox,
    fixed: Mapping[str, float], rtol: float, budget: int, max_cells: int | None,
) -> RobustIntervals:  # fmt: skip
    from ..delay.structure import check_tau, delay_parameter
    from .delayedgains import SEGMENT_BUDGET, robust_delayed_gain_set

    if isinstance(budget, bool) or not isinstance(budget, int) or not 1 <= budget <= MAX_BOX_BUDGET:
        raise ParameterError(
            f"budget must be an integer in [1, {MAX_BOX_BUDGET}], got {budget!r}",
            argument="budget",
        )
    name = delay_parameter(system)
    if name in box.names or name == g:
        raise ParameterError(
            f"box[{name!r}]: {name} is the delay, not a plant or gain value; give it a value "
            "(robust_delay_margin encloses the largest delay over a box)",
            argument="box",
        )
    fixed = {**fixed, name: float(ep.to_fraction(check_tau(fixed.get(name), name)))}
    cells = SEGMENT_BUDGET if budget == DEFAULT_BUDGET else budget
    got = robust_delayed_gain_set(system, g, lo, hi, box=box, fixed=fixed, rtol=rtol, budget=cells,
                                  max_cells=max_cells)  # fmt: skip
    return RobustIntervals(
        param=g, lo=float(lo), hi=float(hi), box=box, intervals=got["intervals"],
        outer=got["outer"], method=Method.CERTIFIED, delay=got["delay"], excluded=got["excluded"],
        cells=got["cells"], exhausted=got["exhausted"],
    )  # fmt: skip


def robust_passive_intervals(
    system: SEA | Impedance,
    param: str,
    lo: float,
    hi: float,
    *,
    box: Mapping[str, Any] | UncertainBox,
    values: Mapping[str, float] | None = None,
    rtol: float = 1e-3,
    budget: int = DEFAULT_BUDGET,
    max_cells: int | None = None,
) -> RobustIntervals:
    """Values of ``param`` in ``[lo, hi]`` for which ``system`` is passive for every plant in ``box``.

    Parameters
    ----------
    system : SEA or Impedance
        Every parameter but ``param`` and the box needs a value.
    param : str
        The free parameter (a gain), e.g. ``"kd"``; not in ``box``.
    lo, hi : float
        Search range.
    box : mapping of str to (lo, hi), or UncertainBox
        The uncertain parameters.
    values : mapping, optional
        Extra or overriding values.
    rtol : float, default 1e-3
        Relative width below which the certified inner set stops bisecting.
    budget : int
        Branch-and-bound budget of each certified box verdict.
    max_cells : int or None
        With a delay only: the cells of all certificates of the gain set together (None: no
        cap beyond ``budget`` per segment); once spent, nothing more is certified or
        excluded (``exhausted`` is set, the inner set is never widened).

    Returns
    -------
    RobustIntervals

    Examples
    --------
    >>> from seapass.model.sea import SEA
    >>> sea = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000))
    >>> r = robust_passive_intervals(sea, "kd", 0, 2000, box={"k1": (800, 1200)})
    >>> r.intervals, str(r.method)
    (((0.0, 800.0),), 'exact')
    """
    lo_q, hi_q = to_fraction(lo, "lo"), to_fraction(hi, "hi")
    if lo_q > hi_q:
        raise ParameterError(f"empty range {lo}:{hi}: the lower bound must not exceed the upper")
    check_rtol(rtol)
    if values:
        system = (
            system.with_values(**values)
            if isinstance(system, SEA)
            else Impedance(expr=system.expr, values={**system.values, **values})
        )
    if param not in system.parameters:
        raise ParameterError(
            f"parameter {param!r} does not appear in the model (its parameters: "
            f"{', '.join(system.parameters)})"
        )
    raw = dict(box.intervals) if isinstance(box, UncertainBox) else dict(box)
    if param in raw:
        raise ParameterError(
            f"box[{param!r}]: {param} is the bounded parameter; it cannot also be uncertain",
            argument="box",
        )
    free_sys = (
        system.with_values(**{param: None})
        if isinstance(system, SEA)
        else Impedance(
            expr=system.expr, values={k: v for k, v in system.values.items() if k != param}
        )
    )
    delayed = bool(model_delays(free_sys))
    checked = uncertain_box(free_sys, raw, delay_ok=delayed)
    fixed = {
        k: float(v)
        for k, v in free_sys.values.items()
        if v is not None and k not in checked.intervals and k != param
    }
    missing = [n for n in free_sys.parameters if n != param and n not in checked.intervals
               and n not in fixed]  # fmt: skip
    if missing:
        raise ParameterError(
            f"no value for parameter(s) {', '.join(missing)}: give them, "
            f"e.g. values={{{missing[0]!r}: 1.0}}"
        )
    if max_cells is not None and (
        isinstance(max_cells, bool) or not isinstance(max_cells, int) or max_cells < 0
    ):
        raise ParameterError(
            f"max_cells must be None or an integer >= 0, got {max_cells!r}", argument="max_cells"
        )
    if delayed:
        return _delayed(free_sys, param, lo_q, hi_q, checked, fixed, rtol, budget, max_cells)
    if len(checked.names) == 1:
        return _exact(free_sys, param, lo_q, hi_q, checked, fixed)
    return _certified(free_sys, param, lo_q, hi_q, checked, fixed, rtol, budget)
