"""Figures of exact passive sets: one parameter's intervals, 2-D regions and maps, per-row bars.

Plotting only consumes [`seapass.analysis.region.PassiveIntervals`][seapass.analysis.region.PassiveIntervals],
[`PassiveMap`][seapass.analysis.region.PassiveMap], [`seapass.analysis.boundary.PassiveRegion`][seapass.analysis.boundary.PassiveRegion]
(or plain interval lists).  Axis labels carry the parameters' units
([`seapass.model.expr.UNITS`][seapass.model.expr.UNITS]).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..analysis.boundary import PassiveRegion
from ..analysis.region import PassiveIntervals, PassiveMap
from ..model.expr import UNITS
from ..robust.verdict import Method
from .style import axes_grid

__all__ = ["axis_label", "plot_kd_bars", "plot_passive_intervals", "plot_passive_map",
           "plot_passive_region", "plot_robust_map"]  # fmt: skip

_PASSIVE, _NOT_PASSIVE, _EDGE = "#b7e1cd", "#f4c7c3", "#1b5e20"
_ROBUST = "#2e7d32"


def axis_label(name: str, unit: str | None = None) -> str:
    """``name [unit]`` with the unit of a standard parameter when none is given."""
    unit = unit if unit is not None else UNITS.get(name, "")
    unit = unit.strip().strip("[]")
    return f"{name} [{unit}]" if unit else name


def _intervals_differ(
    a: Sequence[tuple[float, float]], b: Sequence[tuple[float, float]]
) -> list[tuple[float, float]]:
    """Where exactly one of two interval unions holds (its pieces, sorted)."""
    cuts = sorted({v for iv in (*a, *b) for v in iv})
    out: list[tuple[float, float]] = []
    for lo, hi in itertools.pairwise(cuts):
        mid = (lo + hi) / 2
        if any(p <= mid <= q for p, q in a) != any(p <= mid <= q for p, q in b):
            if out and out[-1][1] == lo:
                out[-1] = (out[-1][0], hi)
            else:
                out.append((lo, hi))
    return out


def plot_passive_region(
    region: PassiveRegion,
    *,
    paper_bound: tuple[np.ndarray, np.ndarray] | None = None,
    title: str = "",
    units: tuple[str | None, str | None] = (None, None),
    ax: Any = None,
) -> Any:
    """The exact passive region, bounded by its exact boundary curves; returns the Axes.

    Every cell of the decomposition is filled between its bounding branches;
    the boundary drawn is the branches that separate passive from non-passive
    cells (and vertical segments where the region ends at an x-critical value),
    never a raster edge.

    Parameters
    ----------
    region : PassiveRegion
        From [`seapass.analysis.boundary.passive_region`][seapass.analysis.boundary.passive_region].
    paper_bound : (x, y) arrays, optional
        A bound to overlay (dashed black).
    title : str, optional
    units : (str or None, str or None)
        Units of the two axes; None takes the parameter's standard unit.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = axes_grid(ax, 1, 1, figsize=(5.8, 4.4))[0, 0]
    (x0, x1), (y0, y1) = region.x_range, region.y_range
    ax.add_patch(_rectangle(x0, y0, x1 - x0, y1 - y0))
    previous: list[tuple[float, float]] | None = None
    for cell in region.cells:
        if cell.x.size == 0:
            continue
        edges = np.vstack([np.full(cell.x.size, y0), cell.branches, np.full(cell.x.size, y1)])
        for j, ok in enumerate(cell.passive):
            if ok:
                ax.fill_between(cell.x, edges[j], edges[j + 1], color=_PASSIVE, lw=0.6,
                                edgecolor=_PASSIVE, zorder=1)  # fmt: skip
        for j in cell.boundary:
            ax.plot(cell.x, cell.branches[j], color=_EDGE, lw=1.6, zorder=3)
        sets = cell.passive_sets(region.y_range)
        if previous is not None:
            xc = cell.x_range[0]
            for lo, hi in _intervals_differ(previous, sets[0]):
                ax.plot([xc, xc], [lo, hi], color=_EDGE, lw=1.6, zorder=3)
        previous = sets[-1]
    if paper_bound is not None:
        ax.plot(paper_bound[0], paper_bound[1], "k--", lw=1.5, zorder=4,
                label="paper's sufficient bound")  # fmt: skip
    ax.plot([], [], color=_PASSIVE, lw=8, label="passive (exact)")
    ax.plot([], [], color=_NOT_PASSIVE, lw=8, label="not passive")
    ax.plot([], [], color=_EDGE, lw=1.6, label="exact boundary")
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_xlabel(axis_label(region.param_x, units[0]))
    ax.set_ylabel(axis_label(region.param_y, units[1]))
    if title:
        ax.set_title(title)
    ax.legend(loc="best", fontsize=8)
    return ax


def _rectangle(x: float, y: float, w: float, h: float) -> Any:
    from matplotlib.patches import Rectangle

    return Rectangle((x, y), w, h, color=_NOT_PASSIVE, lw=0, zorder=0)


def plot_passive_intervals(
    result: PassiveIntervals, *, paper_bound: float | None = None, ax: Any = None
) -> Any:
    """Horizontal bar of the exact passive set of one parameter; returns the Axes."""
    ax = axes_grid(ax, 1, 1, figsize=(6, 1.8))[0, 0]
    ax.axhspan(0, 1, color=_NOT_PASSIVE, label="not passive")
    for i, (a, b) in enumerate(result.intervals):
        ax.axvspan(a, b, color=_PASSIVE, label="passive (exact)" if i == 0 else None)
    if paper_bound is not None:
        ax.axvline(paper_bound, color="k", ls="--", label=f"paper's bound {paper_bound:.4g}")
    ax.set_xlim(result.lo, result.hi)
    ax.set_yticks([])
    ax.set_xlabel(axis_label(result.param))
    ax.legend(loc="upper right", ncol=3, fontsize=8)
    return ax


def plot_passive_map(
    pmap: PassiveMap,
    *,
    paper_bound: tuple[np.ndarray, np.ndarray] | None = None,
    title: str = "",
    units: tuple[str | None, str | None] = (None, None),
    ax: Any = None,
) -> Any:
    """The passive region from exact columns: each column's passive set, joined between columns.

    The set along ``param_y`` is exact at every ``x`` of the map; between
    columns the band edges are joined by straight lines.  For the exact
    boundary curve between columns use `plot_passive_region`.  ``units``
    default to the parameters' standard units.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = axes_grid(ax, 1, 1, figsize=(5.5, 4.2))[0, 0]
    x, ivs = np.asarray(pmap.x, dtype=float), pmap.intervals
    ax.add_patch(_rectangle(x[0], pmap.y[0], x[-1] - x[0], pmap.y[-1] - pmap.y[0]))
    for i in range(x.size - 1):
        if len(ivs[i]) == len(ivs[i + 1]):
            # the k-th interval of both columns: a trapezoid between them
            for (a0, b0), (a1, b1) in zip(ivs[i], ivs[i + 1], strict=True):
                ax.fill_between(x[i : i + 2], [a0, a1], [b0, b1], color=_PASSIVE, lw=0.6,
                                edgecolor=_PASSIVE)  # fmt: skip
            continue
        mid = (x[i] + x[i + 1]) / 2
        for col in (i, i + 1):
            for a, b in ivs[col]:
                ax.fill_between([x[col], mid], a, b, color=_PASSIVE, lw=0.6, edgecolor=_PASSIVE)
    if x.size == 1:
        for a, b in ivs[0]:
            ax.plot([x[0], x[0]], [a, b], color=_PASSIVE, lw=6)
    if paper_bound is not None:
        ax.plot(paper_bound[0], paper_bound[1], "k--", lw=1.5, label="paper's sufficient bound")
    ax.plot([], [], color=_PASSIVE, lw=8, label="passive (exact per column)")
    ax.plot([], [], color=_NOT_PASSIVE, lw=8, label="not passive")
    ax.set_xlabel(axis_label(pmap.param_x, units[0]))
    ax.set_ylabel(axis_label(pmap.param_y, units[1]))
    if x.size > 1:
        ax.set_xlim(x[0], x[-1])
    ax.set_ylim(pmap.y[0], pmap.y[-1])
    if title:
        ax.set_title(title)
    ax.legend(loc="best", fontsize=8)
    return ax


def _column_edges(x: np.ndarray) -> np.ndarray:
    """Left and right edge of each column's bar: halfway to the neighbours, within the range."""
    if x.size == 1:
        half = max(abs(x[0]) * 0.05, 0.5)
        return np.array([x[0] - half, x[0] + half])
    return np.concatenate([[x[0]], (x[:-1] + x[1:]) / 2, [x[-1]]])


def plot_robust_map(
    rmap: Any,
    *,
    title: str = "",
    units: tuple[str | None, str | None] = (None, None),
    ax: Any = None,
) -> Any:
    """Robust passive region (every plant in the box) drawn over the nominal one.

    ``rmap`` is a [`seapass.robust.region.RobustPassiveMap`][seapass.robust.region.RobustPassiveMap].
    Each column is decided on its own, so each is drawn as a bar as wide as the
    spacing of the columns: light green where the nominal plant is passive, dark
    green where every plant in the box is, and (certified method) the outer set's
    ends as dashes.  Nothing is claimed between two columns.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = axes_grid(ax, 1, 1, figsize=(5.5, 4.2))[0, 0]
    x = np.asarray(rmap.x, dtype=float)
    edges = _column_edges(x)
    y0, y1 = rmap.y_range
    ax.add_patch(_rectangle(edges[0], y0, edges[-1] - edges[0], y1 - y0))
    for i in range(x.size):
        left, width = edges[i], edges[i + 1] - edges[i]
        for a, b in rmap.nominal[i]:
            ax.bar(left, b - a, width=width, bottom=a, align="edge", color=_PASSIVE, lw=0)
        for a, b in rmap.intervals[i]:
            ax.bar(left, b - a, width=width, bottom=a, align="edge", color=_ROBUST, lw=0)
        if rmap.method is not Method.EXACT:
            for a, b in rmap.outer[i]:
                ax.hlines([a, b], left, left + width, colors="k", linestyles="--", lw=0.8)
    span = ", ".join(f"{k} in [{lo:g}, {hi:g}]" for k, (lo, hi) in rmap.box.intervals.items())
    ax.plot([], [], color=_ROBUST, lw=8, label=f"passive for every plant ({span})")
    nominal = ", ".join(f"{k}={v:g}" for k, v in rmap.nominal_values.items())
    ax.plot([], [], color=_PASSIVE, lw=8, label=f"passive for the nominal plant ({nominal})")
    ax.plot([], [], color=_NOT_PASSIVE, lw=8, label="not passive (nominal)")
    if rmap.method is not Method.EXACT:
        ax.plot([], [], "k--", lw=0.8, label="outer enclosure of the robust set")
    ax.set_xlabel(axis_label(rmap.param_x, units[0]))
    ax.set_ylabel(axis_label(rmap.param_y, units[1]))
    ax.set_xlim(edges[0], edges[-1])
    ax.set_ylim(y0, y1)
    if title:
        ax.set_title(title)
    ax.legend(loc="best", fontsize=7)
    return ax


def plot_kd_bars(
    bars: Sequence[tuple[str, Sequence[tuple[float, float]], Sequence[tuple[float, float]]]],
    *,
    hi: float,
    title: str = "",
    ax: Any = None,
) -> Any:
    """One row per design: the exact passive set of ``kd`` above what a bound admits.

    ``bars`` holds ``(name, exact intervals, bound's intervals)`` per row, top to bottom.
    """
    from matplotlib.patches import Patch

    ax = axes_grid(ax, 1, 1, figsize=(8.5, 0.45 * len(bars) + 1.6))[0, 0]
    for i, (_name, exact, paper) in enumerate(bars):
        y = len(bars) - 1 - i
        for a, b in exact:
            ax.barh(y + 0.15, max(b - a, hi * 2e-3), left=a, height=0.3, color="#2e7d32")
        for a, b in paper:
            ax.barh(y - 0.15, max(b - a, hi * 2e-3), left=a, height=0.3, color="0.55", hatch="//")
    handles = [
        Patch(color="#2e7d32", label="exact passive set"),
        Patch(facecolor="0.55", hatch="//", label="paper's bound admits"),
    ]
    ax.set_yticks(range(len(bars)), [b[0] for b in reversed(bars)])
    ax.set_xscale("symlog", linthresh=100.0)
    ax.set_xlim(0, hi)
    ax.set_xlabel("controller stiffness kd [N/m] (symlog scale)")
    if title:
        ax.set_title(title)
    ax.grid(True, axis="x", alpha=0.3)
    # rows 6-7 (load-side PD/PI) are never passive: the legend sits in their empty band
    ax.legend(handles=handles, loc="center right", bbox_to_anchor=(1.0, 0.45), fontsize=9)
    return ax
