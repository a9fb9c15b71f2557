"""Robust passive regions: where two gains keep every plant in a box passive.

`robust_passive_map` is the robust form of
[`passive_map`][seapass.analysis.region.passive_map]: along each of the given values
of a parameter ``x`` it returns the robust passive set of a second parameter ``y``
from [`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals]
(exact with one uncertain parameter, certified inner and outer sets with several),
and beside it the exact passive set of ``y`` for the nominal plant (the box's centre,
or values you give), so a figure can show what robustness costs.

Every column is decided on its own; between columns nothing is claimed.  The inner
set's ends are rounded inward (a printed end is robustly passive), the outer set's
outward.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analysis.region import passive_intervals
from ..errors import ParameterError
from ..files.limits import MAX_REGION_COLUMNS
from ..model.display import Shown, html_card, short_repr
from ..model.sea import SEA, Impedance
from .box import UncertainBox
from .intervals import robust_passive_intervals
from .verdict import DEFAULT_BUDGET, Method

__all__ = ["RobustPassiveMap", "robust_passive_map"]

Intervals = tuple[tuple[float, float], ...]


@dataclass(frozen=True, repr=False, kw_only=True)
class RobustPassiveMap:
    """Robust and nominal passive sets of ``param_y`` along values of ``param_x``.

    Attributes
    ----------
    param_x, param_y : str
    x : numpy.ndarray, shape (n,)
        The values of ``param_x``, one per column.
    y_range : (float, float)
        The search range of ``param_y``.
    box : UncertainBox
    intervals : tuple of n interval tuples
        ``intervals[i]``: values of ``param_y`` passive for every plant in the box at
        ``x[i]`` (inner set, ends rounded inward).
    outer : tuple of n interval tuples
        ``outer[i]``: no value outside is robustly passive (ends rounded outward).
    nominal : tuple of n interval tuples
        ``nominal[i]``: the exact passive set at ``x[i]`` for the nominal plant.
    nominal_values : dict
        The plant used for ``nominal`` (the box's centre unless given).
    method : Method
        ``"exact"`` (one uncertain parameter) or ``"certified"``.
    delay : mapping or None
        ``{"name": ..., "tau": seconds}`` for a delayed design: every column is the
        certified robust set at that delay and ``nominal`` the certified intervals of
        [`passive_gain_intervals`][seapass.delay.gainbound.passive_gain_intervals].
    """

    param_x: str
    param_y: str
    x: np.ndarray
    y_range: tuple[float, float]
    box: UncertainBox
    intervals: tuple[Intervals, ...]
    outer: tuple[Intervals, ...]
    nominal: tuple[Intervals, ...]
    nominal_values: Mapping[str, float]
    method: Method
    delay: Mapping[str, Any] | None = None

    def robust_share(self) -> float:
        """Robust passive length over nominal passive length, summed over the columns.

        1 when robustness costs nothing; nan when no column has a nominal passive set.
        """
        rob = sum(b - a for ivs in self.intervals for a, b in ivs)
        nom = sum(b - a for ivs in self.nominal for a, b in ivs)
        return rob / nom if nom > 0 else float("nan")

    def to_dict(self) -> dict[str, Any]:
        def lists(rows: tuple[Intervals, ...]) -> list[list[list[float]]]:
            return [[list(iv) for iv in ivs] for ivs in rows]

        return {
            "robust": True,
            "param_x": self.param_x,
            "param_y": self.param_y,
            "x": self.x.tolist(),
            "y_range": list(self.y_range),
            "box": self.box.to_dict(),
            "intervals": lists(self.intervals),
            "outer": lists(self.outer),
            "nominal": lists(self.nominal),
            "nominal_values": dict(self.nominal_values),
            "method": str(self.method),
            **(
                {}
                if self.delay is None
                else {"delay": dict(self.delay), "delay_time": self.delay["tau"]}
            ),
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """The robust region drawn over the nominal one; returns the Axes."""
        from ..plot.region import plot_robust_map

        return plot_robust_map(self, ax=ax, **kwargs)

    def __repr__(self) -> str:
        share = self.robust_share()
        return short_repr(
            "RobustPassiveMap",
            {
                "x": Shown(f"{self.param_x} in [{self.x[0]:g}, {self.x[-1]:g}] ({self.x.size})"),
                "y": Shown(f"{self.param_y} in [{self.y_range[0]:g}, {self.y_range[1]:g}]"),
                "robust_share": None if np.isnan(share) else round(share, 4),
                "method": str(self.method),
            },
        )

    def _repr_html_(self) -> str:
        rows = [
            (self.param_x, f"{self.x.size} values in [{self.x[0]:g}, {self.x[-1]:g}]"),
            (self.param_y, f"robust set along [{self.y_range[0]:g}, {self.y_range[1]:g}]"),
        ]
        rows += [(k, f"[{a:g}, {b:g}]") for k, (a, b) in self.box.intervals.items()]
        share = self.robust_share()
        rows.append(("robust / nominal length", "-" if np.isnan(share) else f"{share:.1%}"))
        return html_card(f"Robust passive region over {self.param_x} and {self.param_y}", rows)


def _with(system: SEA | Impedance, values: Mapping[str, float]) -> SEA | Impedance:
    if isinstance(system, SEA):
        return system.with_values(**values)
    return Impedance(expr=system.expr, values={**system.values, **values})


def robust_passive_map(
    system: SEA | Impedance,
    param_x: str,
    x_values: Sequence[float] | np.ndarray,
    param_y: str,
    y_range: tuple[float, float],
    *,
    box: Mapping[str, Any] | UncertainBox,
    nominal: Mapping[str, float] | None = None,
    values: Mapping[str, float] | None = None,
    rtol: float = 1e-3,
    budget: int = DEFAULT_BUDGET,
) -> RobustPassiveMap:
    """Robust passive set of ``param_y`` at each value of ``param_x``, beside the nominal one.

    Parameters
    ----------
    system : SEA or Impedance
        Every parameter but ``param_x``, ``param_y`` and the box needs a value.
    param_x : str
        The parameter along the columns (a gain, not in ``box``).
    x_values : sequence of float
        Its values, 1 to ``MAX_REGION_COLUMNS`` of them.
    param_y : str
        The parameter whose robust set is computed in each column.
    y_range : (float, float)
        Search range of ``param_y``.
    box : mapping of str to (lo, hi), or UncertainBox
        The uncertain parameters.
    nominal : mapping, optional
        The nominal plant's values of the box parameters; default the box's centre.
        Each must lie in its interval.
    values : mapping, optional
        Extra or overriding values.
    rtol, budget
        As for `robust_passive_intervals` (several uncertain parameters).

    Returns
    -------
    RobustPassiveMap

    Examples
    --------
    >>> from seapass.model.sea import SEA
    >>> sea = SEA(D1="k1", CL="kd + bd*s", values=dict(m=1, b=10, k1=1000))
    >>> r = robust_passive_map(sea, "bd", [0, 5], "kd", (0, 2000), box={"k1": (800, 1200)})
    >>> r.intervals[0], r.nominal[0]
    (((0.0, 800.0),), ((0.0, 1000.0),))
    """
    xs = np.asarray(x_values, dtype=float)
    if xs.ndim != 1 or not 1 <= xs.size <= MAX_REGION_COLUMNS:
        raise ParameterError(
            f"x_values must be a 1-D sequence of 1 to {MAX_REGION_COLUMNS} values, "
            f"got shape {xs.shape}",
            argument="x_values",
        )
    if not np.all(np.isfinite(xs)):
        raise ParameterError("x_values must be finite numbers", argument="x_values")
    if param_x == param_y:
        raise ParameterError("param_x and param_y must be different parameters")
    raw = dict(box.intervals) if isinstance(box, UncertainBox) else dict(box)
    if param_x in raw:
        raise ParameterError(
            f"box[{param_x!r}]: {param_x} is the column parameter; it cannot also be uncertain",
            argument="box",
        )
    base = _with(system, dict(values or {}))
    columns = [
        robust_passive_intervals(
            base,
            param_y,
            y_range[0],
            y_range[1],
            box=box,
            values={param_x: float(xv)},
            rtol=rtol,
            budget=budget,
        )
        for xv in xs
    ]
    checked = columns[0].box
    centre = {k: (lo + hi) / 2 for k, (lo, hi) in checked.intervals.items()}
    nominal_values = {**centre, **(nominal or {})}
    for k, v in nominal_values.items():
        if k not in checked.intervals:
            raise ParameterError(
                f"nominal[{k!r}]: {k} is not an uncertain parameter of the box",
                argument="nominal",
            )
        lo, hi = checked.intervals[k]
        if not lo <= v <= hi:
            raise ParameterError(
                f"nominal[{k!r}] = {v:g} lies outside its interval [{lo:g}, {hi:g}]",
                argument="nominal",
            )
    delay = columns[0].delay
    if delay is None:
        nominal_sets = tuple(
            passive_intervals(
                base, param_y, y_range[0], y_range[1], values={**nominal_values, param_x: float(xv)}
            ).intervals
            for xv in xs
        )
    else:  # certified at the delay (every value of an interval proven passive)
        from ..delay.gainbound import passive_gain_intervals

        nominal_sets = tuple(
            passive_gain_intervals(
                base, param_y, float(y_range[0]), float(y_range[1]),
                values={**nominal_values, param_x: float(xv), param_y: None}, points=9,
            ).intervals
            for xv in xs
        )  # fmt: skip
    return RobustPassiveMap(
        param_x=param_x,
        param_y=param_y,
        x=xs,
        y_range=(float(y_range[0]), float(y_range[1])),
        box=checked,
        intervals=tuple(c.intervals for c in columns),
        outer=tuple(c.outer for c in columns),
        nominal=nominal_sets,
        nominal_values=nominal_values,
        method=Method.CERTIFIED
        if any(c.method is not Method.EXACT for c in columns)
        else Method.EXACT,
        delay=delay,
    )
