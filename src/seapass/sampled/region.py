"""Z-width maps: the passive region of two controller parameters under sampled-data control.

Colgate and Brown's *Z-width* [1]_ is the range of impedances a haptic device renders
passively; for a virtual wall ``K + B s`` it is the region of stiffness against damping.
`sampled_region` computes that region for any two controller parameters ``P1``,
``P2`` of an SEA in a sampled loop, for several setups of that loop
([`SampledLoop`][seapass.model.loop.SampledLoop]s: ideal zero-order hold, a
computational delay, delay plus velocity filter): for each of ``n`` values of ``P2`` the
passive set of ``P1`` is *certified* by [`sampled_passive_bound`][seapass.sampled.bound.sampled_passive_bound]
(intervals with edge enclosures, islands included).  Only the spacing of the ``P2`` rows
is a sampling, and the figure says so.

References
----------
.. [1] J. E. Colgate, J. M. Brown, "Factors affecting the Z-width of a haptic display",
   Proc. IEEE ICRA 1994, pp. 3205–3210.
.. [2] J. E. Colgate, G. G. Schenkel, "Passivity of a class of sampled-data systems:
   application to haptic interfaces", J. Robotic Systems 14(1), 1997.
"""

from __future__ import annotations

import io
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..exact.rounding import decimal_down
from ..model.display import html_card, short_repr
from ..model.loop import SampledLoop, loop_argument
from ..model.sea import SEA
from ..progress import ProgressLike, as_progress, task
from .bound import SampledBoundResult, sampled_passive_bound
from .boxes import MAX_BOXES
from .passivity import check_precision
from .verdict import PRECISIONS

__all__ = ["ZWidthMap", "default_setups", "sampled_region"]

#: Most rows of one map (each row is a certified bound).
MAX_ROWS = 200


def default_setups(loop: SampledLoop) -> tuple[SampledLoop, ...]:
    """Ideal ZOH, ``max(loop.delay, 1)`` samples of delay, and that delay plus the loop's
    velocity filter (when it has one), at the loop's period and discretization."""
    d = max(loop.delay, 1)
    ideal = loop.replace(delay=0, velocity_filter=None)
    out = [ideal, ideal.replace(delay=d)]
    if loop.velocity_filter is not None:
        out.append(ideal.replace(delay=d, velocity_filter=loop.velocity_filter))
    return tuple(out)


@dataclass(frozen=True, repr=False, kw_only=True)
class ZWidthMap:
    """Certified passive sets of ``p1`` for each value of ``p2`` and each loop setup.

    Attributes
    ----------
    setups : tuple of SampledLoop
        The loops overlaid (one period); each is named by its ``label``.
    rows : mapping of str to tuple of SampledBoundResult
        ``rows[setup.label][i]`` is the passive set of ``p1`` at ``p2 = p2_values[i]``.
    """

    p1: str
    p2: str
    p1_range: tuple[float, float]
    p2_values: tuple[float, ...]
    setups: tuple[SampledLoop, ...]
    rows: Mapping[str, tuple[SampledBoundResult, ...]]

    @property
    def period(self) -> float:
        """Control period (s) of every setup."""
        return self.setups[0].period

    @property
    def budget_exhausted(self) -> bool:
        """Some row's branch and bound stopped at its box budget (its rest is undecided)."""
        return any(r.budget_exhausted for rows in self.rows.values() for r in rows)

    def upper_boundary(self, label: str) -> np.ndarray:
        """Largest passive ``p1`` for every ``p2`` row (NaN where none)."""
        return np.array(
            [np.nan if r.max_passive is None else r.max_passive for r in self.rows[label]]
        )

    def to_csv(self) -> str:
        """One line per passive interval: setup, loop, ``p2``, ``p1`` interval, enclosures."""
        buf = io.StringIO()
        buf.write(f"setup,delay,velocity_filter,{self.p2},{self.p1}_lo,{self.p1}_hi\n")
        for s in self.setups:
            for v, r in zip(self.p2_values, self.rows[s.label], strict=True):
                filt = "" if s.velocity_filter is None else repr(s.velocity_filter)
                if not r.intervals:
                    buf.write(f'"{s.label}",{s.delay},{filt},{v!r},,\n')
                for a, b in r.intervals:
                    buf.write(f'"{s.label}",{s.delay},{filt},{v!r},{a!r},{b!r}\n')
        return buf.getvalue()

    def to_dict(self) -> dict[str, Any]:
        return {
            "p1": self.p1,
            "p2": self.p2,
            "period": self.period,
            "p1_range": list(self.p1_range),
            "p2_values": list(self.p2_values),
            "setups": [
                {"label": s.label, "delay": s.delay, "velocity_filter": s.velocity_filter}
                for s in self.setups
            ],
            "rows": {k: [r.to_dict() for r in v] for k, v in self.rows.items()},
        }

    def plot(self, *, ax: Any = None) -> Any:
        """The Z-width map: passive ``p1`` on every ``p2`` row, one colour per loop setup.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure if None.

        Returns
        -------
        matplotlib.axes.Axes
        """
        from ..plot.sampled import plot_zwidth

        return plot_zwidth(self, ax=ax)

    def __repr__(self) -> str:
        return short_repr(
            "ZWidthMap",
            {
                "p1": self.p1,
                "p2": self.p2,
                "period": self.period,
                "rows": len(self.p2_values),
                "setups": len(self.setups),
            },
        )

    def _repr_html_(self) -> str:
        xs = self.p2_values
        rows = [(f"{self.p2} rows", f"{len(xs)} in [{min(xs):.6g}, {max(xs):.6g}]")]
        for s in self.setups:
            top = self.upper_boundary(s.label)
            empty = int(np.sum(np.isnan(top)))
            text = (
                f"largest passive {self.p1} from {decimal_down(np.nanmin(top), 6)} to "
                f"{decimal_down(np.nanmax(top), 6)}"
                if empty < top.size
                else f"no passive {self.p1}"
            )
            rows.append(
                (s.label, text + (f"; none on {empty} rows" if 0 < empty < top.size else ""))
            )
        return html_card(
            f"Z-width at T = {self.period * 1e3:g} ms: passive {self.p1} against {self.p2}",
            rows,
            note=f"Every row certified over [{self.p1_range[0]:.6g}, {self.p1_range[1]:.6g}]; "
            f"only the spacing of the {self.p2} rows is a sampling.",
        )


def sampled_region(
    sea: SEA,
    p1: str,
    p2: str,
    *,
    loop: SampledLoop | None = None,
    p1_range: tuple[float, float],
    p2_range: tuple[float, float],
    n: int = 25,
    setups: Sequence[SampledLoop] | None = None,
    rtol: float = 1e-6,
    log_p2: bool = False,
    max_precision: int = PRECISIONS[-1],
    max_boxes: int = MAX_BOXES,
    progress: ProgressLike = None,
    **old: Any,
) -> ZWidthMap:
    """Z-width map: certified passive sets of ``p1`` on ``n`` rows of ``p2``.

    Parameters
    ----------
    sea : SEA
        The design; ``p1`` and ``p2`` appear in ``CA``/``CL`` only, every other parameter
        needs a value.
    p1, p2 : str
        The bounded parameter (certified per row) and the row parameter.
    loop : SampledLoop
        The deployed loop: its period and discretization for every setup, its delay and
        velocity filter for the default setups.
    p1_range, p2_range : (float, float)
        Range of ``p1`` to partition and of the ``p2`` rows (ends included).
    n : int, default 25
        Number of ``p2`` rows, in ``[2, 200]``.
    setups : sequence of SampledLoop, optional
        Loops to overlay, at ``loop``'s period; `default_setups` of ``loop`` by default.
    rtol : float, default 1e-6
        Relative width of every edge enclosure.
    log_p2 : bool
        Space the rows logarithmically (``p2_range`` must then be positive).
    max_precision : int
        Precision cap (bits) of the balls, as in
        [`sampled_passive_bound`][seapass.sampled.bound.sampled_passive_bound].
    max_boxes : int, default 20000
        Budget of each row's branch and bound in boxes (as in
        [`sampled_passive_bound`][seapass.sampled.bound.sampled_passive_bound]); a row
        that reaches it has ``budget_exhausted`` set (see `ZWidthMap.budget_exhausted`).
    progress : Progress, optional
        Where the map reports: one task with a step per row and setup, each row's bound
        a task inside it (default: none).  A callable ``f(done, total)``, the old
        spelling, still works for one release.
    **old
        ``period=, method=``: the loop's old spelling (then the default setups have one
        sample of delay and a 50 Hz filter), accepted for one release with a
        [`SeapassDeprecationWarning`][seapass.errors.SeapassDeprecationWarning].

    Returns
    -------
    ZWidthMap

    Examples
    --------
    >>> wall = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1005, b1=30))
    >>> ideal = SampledLoop(period=0.002)
    >>> z = sampled_region(wall, "kd", "bd", loop=ideal, p1_range=(0, 1e5),
    ...                    p2_range=(0, 50), n=2, setups=[ideal])
    >>> [round(v) for v in z.upper_boundary("ideal ZOH")]
    [10033, 54519]
    """
    if loop is None and old:  # the old spelling: period=, method=; 1 sample and 50 Hz setups
        loop = loop_argument(None, old, where="sampled_region")
        loop = loop if setups is not None else loop.replace(delay=1, velocity_filter=50.0)
    else:
        loop = loop_argument(loop, old, where="sampled_region")
    shown = as_progress(
        progress, where="sampled_region", call=lambda f: lambda done, total, note: f(done, total)
    )
    max_precision = check_precision(max_precision)
    if p1 == p2:
        raise ParameterError("sampled region needs two different parameters")
    if not 2 <= int(n) <= MAX_ROWS:
        raise ParameterError(f"n (rows) must be in [2, {MAX_ROWS}], got {n!r}")
    lo2, hi2 = (float(x) for x in p2_range)
    if not (math.isfinite(lo2) and math.isfinite(hi2) and lo2 < hi2):
        raise ParameterError(f"need a finite range lo < hi for {p2}, got {p2_range}")
    if log_p2 and lo2 <= 0:
        raise ParameterError(f"a logarithmic {p2} axis needs a positive range, got {p2_range}")
    values = np.geomspace(lo2, hi2, int(n)) if log_p2 else np.linspace(lo2, hi2, int(n))
    setups = tuple(setups or default_setups(loop))
    if any(s.period != loop.period for s in setups):
        raise ParameterError(
            f"setups: every setup runs at the loop's period {loop.period:g} s", argument="setups"
        )
    rows: dict[str, list[SampledBoundResult]] = {s.label: [] for s in setups}
    base = sea.with_values(**{p1: None, p2: None})
    total = len(setups) * len(values)
    with task(shown, f"Z-width map of {p1} against {p2}: {total} rows", total):
        for s in setups:
            for v in values:
                row = sampled_passive_bound(
                    base.with_values(**{p2: float(v)}), p1, loop=s,
                    lo=float(p1_range[0]), hi=float(p1_range[1]), rtol=rtol,
                    max_precision=max_precision, max_boxes=max_boxes, progress=shown,
                )  # fmt: skip
                rows[s.label].append(row)
                shown.advance(1, note=f"{s.label}, {p2} = {float(v):.6g}")
    return ZWidthMap(
        p1=p1, p2=p2, p1_range=(float(p1_range[0]), float(p1_range[1])),
        p2_values=tuple(float(v) for v in values), setups=setups,
        rows=MappingProxyType({k: tuple(v) for k, v in rows.items()}),
    )  # fmt: skip
