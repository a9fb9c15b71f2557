"""``region X Y`` at a fixed delay: the certified passive set of ``Y`` at each of some ``X``.

As [`seapass.analysis.region.passive_map`][seapass.analysis.region.passive_map] does for a
delay-free design, every column ``x_i`` is decided along ``Y`` in full: the column is a
[`DelayGainIntervals`][seapass.delay.gainbound.DelayGainIntervals] (intervals of ``Y``
certified passive for every value, certified enclosures of their ends, undecided gaps).
Nothing is claimed between the columns; a cell is passive only inside a certified
interval of its column, never from a grid of frequencies.

Examples
--------
>>> from seapass.model.sea import SEA
>>> wall = SEA(D1="k1", CA="kd*exp(-tau*s)",
...            values=dict(m=1, b=None, k1=1000, kd=None, tau=0.002))
>>> m = delay_passive_map(wall, "b", [5, 10], "kd", (0, 8000), points=5)
>>> [[round(x) for x in ivs[0]] for ivs in m.intervals]     # kd <= b/tau
[[0, 2500], [0, 5000]]
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import ParameterError
from ..files.limits import MAX_REGION_COLUMNS
from ..model.display import html_card, short_repr
from ..model.sea import SEA, Impedance
from ..outcome import Outcome
from .gainbound import DelayGainIntervals, passive_gain_intervals

__all__ = ["DelayPassiveMap", "delay_passive_map"]


@dataclass(frozen=True, kw_only=True, repr=False)
class DelayPassiveMap:
    """Certified passive sets of ``param_y`` at each ``x`` of ``param_x``, at one delay.

    ``columns[i]`` is the result along ``param_y`` at ``x[i]``; ``intervals[i]`` its
    certified intervals; ``outcome`` is ``passive`` when every column's ends are enclosed,
    ``undecided`` when some gap is undecided, ``not_passive`` when no column has a passive
    value (at the values computed).
    """

    param_x: str
    param_y: str
    x: tuple[float, ...]
    y: tuple[float, float]
    columns: tuple[DelayGainIntervals, ...]

    @property
    def intervals(self) -> tuple[tuple[tuple[float, float], ...], ...]:
        return tuple(c.intervals for c in self.columns)

    @property
    def outcome(self) -> Outcome:
        outs = {c.outcome for c in self.columns}
        if Outcome.UNDECIDED in outs:
            return Outcome.UNDECIDED
        return Outcome.PASSIVE if Outcome.PASSIVE in outs else Outcome.NOT_PASSIVE

    @property
    def tau(self) -> float:
        return self.columns[0].tau

    @property
    def delay(self) -> str:
        return self.columns[0].delay

    def to_dict(self) -> dict[str, Any]:
        return {
            "param_x": self.param_x,
            "param_y": self.param_y,
            "x": list(self.x),
            "intervals": [[list(iv) for iv in ivs] for ivs in self.intervals],
            "edges": [c.to_dict()["edges"] for c in self.columns],
            "undecided": [[list(g) for g in c.undecided] for c in self.columns],
            "outcome": str(self.outcome),
            "delay": {"name": self.delay, "tau": self.tau},
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """Each column's certified set (green), undecided gaps (grey); returns the Axes."""
        from ..plot.delay import plot_delay_map

        return plot_delay_map(self, ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr("DelayPassiveMap", {"x": self.param_x, "y": self.param_y,
                                              "columns": len(self.x), "tau": self.tau,
                                              "outcome": str(self.outcome)})  # fmt: skip

    def _repr_html_(self) -> str:
        rows = [(f"{self.param_x} = {x:g}", "; ".join(c.lines()))
                for x, c in zip(self.x, self.columns, strict=True)]  # fmt: skip
        return html_card(f"Passive region at {self.delay} = {self.tau:g} s", rows,
                         note="Certified per column; nothing is claimed between columns.")  # fmt: skip


def delay_passive_map(
    system: SEA | Impedance,
    param_x: str,
    xs: Sequence[float],
    param_y: str,
    y_range: tuple[float, float],
    *,
    tau: float | None = None,
    values: Mapping[str, float | None] | None = None,
    points: int = 9,
    rtol: float = 1e-6,
) -> DelayPassiveMap:
    """The certified passive set of ``param_y`` in ``y_range`` at each ``x`` in ``xs``.

    Parameters
    ----------
    system : SEA or Impedance
        A design with one delay factor; ``tau`` (seconds) or its stored value is the delay.
    param_x, param_y : str
        The column parameter and the parameter decided along each column.
    xs : sequence of float
        The columns (2 to `MAX_REGION_COLUMNS`).
    y_range : (float, float)
        The range of ``param_y``.
    tau, values, points, rtol
        As [`passive_gain_intervals`][seapass.delay.gainbound.passive_gain_intervals].

    Returns
    -------
    DelayPassiveMap
    """
    if param_x == param_y:
        raise ParameterError("param_x and param_y must be different parameters")
    xs = tuple(float(x) for x in xs)
    if not 1 <= len(xs) <= MAX_REGION_COLUMNS or not all(math.isfinite(x) for x in xs):
        raise ParameterError(f"xs: give 1 to {MAX_REGION_COLUMNS} finite values")
    if not isinstance(system, SEA | Impedance) or param_x not in system.parameters:
        raise ParameterError(f"param_x: {param_x!r} is not a parameter of the design", argument="param_x")  # fmt: skip
    lo, hi = (float(v) for v in y_range)
    columns = tuple(
        passive_gain_intervals(
            system,
            param_y,
            lo,
            hi,
            tau=tau,
            values={**(values or {}), param_x: x},
            points=points,
            rtol=rtol,
        )
        for x in xs
    )
    return DelayPassiveMap(param_x=param_x, param_y=param_y, x=xs, y=(lo, hi), columns=columns)
