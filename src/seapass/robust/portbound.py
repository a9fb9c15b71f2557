"""Robust gain sets of a two-port: the values of a gain that keep the criterion for every plant.

`robust_port_intervals` returns certified inner and outer enclosures of
``G = {g : the two-port meets the criterion (absolute stability or passivity) for
every plant in the box}`` within ``[lo, hi]``, as
[`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals]
does for a one-port with several uncertain parameters:

* **outer**: the intersection of the exact sets of ``g``
  ([`port_intervals`][seapass.ports.bound.port_intervals]) at the corners and the
  centre of the box and at every worst plant found (each plant's exact set
  contains ``G``);
* **inner**: the union of the ``g``-intervals ``[a, b]`` on which the robust verdict
  ([`robust_port_verdict`][seapass.robust.twoport.robust_port_verdict]) proves the
  box ``[a, b] × box`` (bisection down to ``rtol``).

With one uncertain parameter the inner set is not claimed exact: the cylindrical
argument of [`seapass.robust.intervals`][seapass.robust.intervals] needs the
critical polynomials of the two-port in two parameters, which
[`seapass.ports.criticals`][seapass.ports.criticals] does not provide; the two
enclosures meet up to ``rtol`` wherever the boundary is not a single point.

End points are rounded **inward** for ``intervals`` (every printed end is in ``G``)
and **outward** for ``outer``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, cast

from ..errors import ParameterError
from ..files.limits import check_rtol
from ..model.display import Shown, html_card, short_repr
from ..model.expr import to_fraction
from ..model.sea import SEA
from ..outcome import Outcome
from ..ports.bound import Criterion, criterion_of, port_intervals
from ..ports.stability import as_two_port
from ..ports.twoport import TwoPort
from . import pieces
from .box import UncertainBox, uncertain_box
from .twoport import port_fixed_values, robust_port_verdict
from .verdict import DEFAULT_BUDGET, Method

__all__ = ["MAX_PORT_SEGMENTS", "RobustPortIntervals", "robust_port_intervals"]

MAX_PORT_SEGMENTS = 200
"""Most ``g``-intervals examined by the certified inner set."""


@dataclass(frozen=True, repr=False, kw_only=True)
class RobustPortIntervals:
    """The robust set of one gain of a two-port over a box of plants.

    Attributes
    ----------
    param : str
    criterion : Criterion
    lo, hi : float
        The search range.
    box : UncertainBox
    intervals : tuple of (float, float)
        Inner set: every value here meets the criterion for every plant of the box
        (ends rounded inward).
    outer : tuple of (float, float)
        Outer set: no value outside meets it for every plant (ends rounded outward).
    segments : int
        ``g``-intervals examined for the inner set.
    method : Method
        ``"certified"``.
    """

    param: str
    criterion: Criterion
    lo: float
    hi: float
    box: UncertainBox
    intervals: tuple[tuple[float, float], ...] = ()
    outer: tuple[tuple[float, float], ...] = ()
    segments: int = 0
    method: Method = Method.CERTIFIED

    def contains(self, value: float) -> bool:
        return any(a <= value <= b for a, b in self.intervals)

    def to_dict(self) -> dict[str, Any]:
        return {
            "robust": True,
            "param": self.param,
            "criterion": self.criterion.value,
            "range": [self.lo, self.hi],
            "box": self.box.to_dict(),
            "intervals": [list(iv) for iv in self.intervals],
            "outer": [list(iv) for iv in self.outer],
            "segments": self.segments,
            "method": str(self.method),
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """The inner set as a bar over the search range; returns the Axes."""
        from ..plot.region import plot_passive_intervals

        return plot_passive_intervals(cast(Any, self), ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "RobustPortIntervals",
            {
                "param": self.param,
                "criterion": self.criterion.value,
                "intervals": Shown(pieces.text(self.intervals)),
            },
        )

    def _repr_html_(self) -> str:
        rows = [("search range", f"[{self.lo:g}, {self.hi:g}]")]
        rows += [(k, f"[{a:g}, {b:g}]") for k, (a, b) in self.box.intervals.items()]
        rows += [(f"{self.criterion.label} for every plant", pieces.text(self.intervals))]
        rows.append(("outer enclosure", pieces.text(self.outer, outer=True)))
        return html_card(f"Robust set of {self.param} ({self.criterion.label})", rows)


def robust_port_intervals(
    system: TwoPort | SEA,
    param: str,
    lo: float,
    hi: float,
    *,
    box: Mapping[str, Any] | UncertainBox,
    criterion: Criterion | str = Criterion.ABSOLUTE,
    values: Mapping[str, float] | None = None,
    rtol: float = 1e-3,
    budget: int = DEFAULT_BUDGET,
) -> RobustPortIntervals:
    """Values of ``param`` in ``[lo, hi]`` meeting ``criterion`` for every plant in ``box``.

    Parameters
    ----------
    system : TwoPort or SEA
        Every parameter but ``param`` and the box needs a value.
    param : str
        The free parameter (a gain), not in ``box``.
    lo, hi : float
        Search range.
    box : mapping of str to (lo, hi), or UncertainBox
        The uncertain parameters.
    criterion : {"absolute", "passive"}, default "absolute"
        Llewellyn's absolute stability or passivity of the two-port.
    values : mapping, optional
        Extra or overriding values.
    rtol : float, default 1e-3
        Relative width below which the inner set stops bisecting.
    budget : int
        Branch-and-bound budget of each box verdict.

    Returns
    -------
    RobustPortIntervals

    Examples
    --------
    >>> from seapass import SEA
    >>> sea = SEA(D1="k1", CA="kd", values=dict(m=1.0, b=10.0, k1=1000.0, kd=None))
    >>> r = robust_port_intervals(sea, "kd", 100, 5000, box={"m": (0.9, 1.1)})
    >>> r.intervals, r.outer
    (((100.0, 5000.0),), ((100.0, 5000.0),))
    """
    crit = criterion_of(criterion)
    lo_q, hi_q = to_fraction(lo, "lo"), to_fraction(hi, "hi")
    if lo_q > hi_q:
        raise ParameterError(f"empty range {lo}:{hi}: the lower bound must not exceed the upper")
    check_rtol(rtol)
    if isinstance(budget, bool) or not isinstance(budget, int) or budget < 1:
        raise ParameterError(
            f"budget must be a positive integer, got {budget!r}", argument="budget"
        )
    tp = as_two_port(system)
    if values:
        tp = tp.with_values(**values)
    if param not in tp.parameters:
        raise ParameterError(
            f"parameter {param!r} does not appear in the two-port (its parameters: "
            f"{', '.join(tp.parameters)})"
        )
    raw = dict(box.intervals) if isinstance(box, UncertainBox) else dict(box)
    if param in raw:
        raise ParameterError(
            f"box[{param!r}]: {param} is the bounded parameter; it cannot also be uncertain",
            argument="box",
        )
    free_tp = tp.with_values(**{param: None})
    checked = uncertain_box(free_tp, raw)
    fixed = port_fixed_values(free_tp, checked, free=(param,))

    def exact_set(plant: Mapping[str, float]) -> tuple[tuple[float, float], ...]:
        pi = port_intervals(
            free_tp, param, float(lo_q), float(hi_q), criterion=crit, values={**fixed, **plant}
        )
        return (*pi.intervals, *pi.undecided)  # ends rounded inward

    def verdict(a: Fraction, b: Fraction) -> tuple[bool, dict[str, float] | None]:
        seg = UncertainBox(intervals={**checked.intervals, param: (float(a), float(b))})
        v = robust_port_verdict(free_tp, seg, fixed, crit, budget)
        worst = None if v.worst is None else {k: x for k, x in v.worst.values.items() if k != param}
        return v.outcome is Outcome.PASSIVE, worst

    inner, outer, seen = pieces.robust_gain_set(
        lo_q, hi_q, plants=[*checked.corners(), checked.center()], exact_set=exact_set,
        verdict=verdict, width=Fraction(rtol) * max(abs(lo_q), abs(hi_q), Fraction(1)),
        max_segments=MAX_PORT_SEGMENTS,
    )  # fmt: skip
    return RobustPortIntervals(
        param=param,
        criterion=crit,
        lo=float(lo_q),
        hi=float(hi_q),
        box=checked,
        intervals=pieces.as_floats(pieces.merge(inner), inward=True),
        outer=pieces.as_floats(outer, inward=False),
        segments=seen,
    )
