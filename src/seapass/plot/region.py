"""Figures of exact passive sets: one parameter's intervals, 2-D maps, per-row bars.

Plotting only consumes [`seapass.analysis.region.PassiveIntervals`][seapass.analysis.region.PassiveIntervals] and
[`PassiveMap`][seapass.analysis.region.PassiveMap] (or plain interval lists).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..analysis.region import PassiveIntervals, PassiveMap
from .style import axes_grid

__all__ = ["plot_kd_bars", "plot_passive_intervals", "plot_passive_map"]

_PASSIVE, _NOT_PASSIVE = "#b7e1cd", "#f4c7c3"


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
    ax.set_xlabel(result.param)
    ax.legend(loc="upper right", ncol=3, fontsize=8)
    return ax


def plot_passive_map(
    pmap: PassiveMap,
    *,
    paper_bound: tuple[np.ndarray, np.ndarray] | None = None,
    title: str = "",
    units: tuple[str, str] = ("", ""),
    ax: Any = None,
) -> Any:
    """Filled map of the passive region over two parameters, exact along each column.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = axes_grid(ax, 1, 1, figsize=(5.5, 4.2))[0, 0]
    ax.contourf(
        pmap.x,
        pmap.y,
        pmap.mask.astype(float),
        levels=[-0.5, 0.5, 1.5],
        colors=[_NOT_PASSIVE, _PASSIVE],
    )
    for xv, ivs in zip(pmap.x, pmap.intervals, strict=True):
        for a, b in ivs:
            ax.plot([xv, xv], [a, b], color="#2e7d32", lw=0.6, alpha=0.5)
    if paper_bound is not None:
        ax.plot(paper_bound[0], paper_bound[1], "k--", lw=1.5, label="paper's sufficient bound")
    ax.plot([], [], color=_PASSIVE, lw=8, label="passive (exact)")
    ax.plot([], [], color=_NOT_PASSIVE, lw=8, label="not passive")
    ux, uy = units
    ax.set_xlabel(f"{pmap.param_x} {ux}".strip())
    ax.set_ylabel(f"{pmap.param_y} {uy}".strip())
    ax.set_ylim(pmap.y[0], pmap.y[-1])
    if title:
        ax.set_title(title)
    ax.legend(loc="best", fontsize=8)
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
