"""Heat maps of a sweep: passive fraction and settling time over two parameters.

Figures only consume [`seapass.sweep.heatmap.HeatmapData`][seapass.sweep.heatmap.HeatmapData]; nothing is computed here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..model.expr import UNITS
from ..sweep.heatmap import HeatmapData
from .style import axes_grid

__all__ = ["plot_sweep_heatmap"]


def _label(name: str) -> str:
    unit = UNITS.get(name)
    return f"{name} [{unit}]" if unit else name


def _edges(c: np.ndarray) -> np.ndarray:
    if c.size == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def plot_sweep_heatmap(data: HeatmapData, *, title: str = "", axes: Any = None) -> Any:
    """Passive fraction (left) and mean settling time of settled designs (right).

    The passive region's boundary (passive fraction 0.5) is drawn on both panels.
    Returns the Axes (one, or two when the sweep has settling times).
    """
    from matplotlib.lines import Line2D

    panels = 2 if data.settling_time is not None else 1
    axes = axes_grid(axes, 1, panels, figsize=(6.0 * panels, 4.8))
    fig = axes[0, 0].figure
    xe, ye = _edges(data.x_centers), _edges(data.y_centers)
    ax = axes[0, 0]
    m = ax.pcolormesh(xe, ye, data.passive_fraction, cmap="RdYlGn", vmin=0.0, vmax=1.0)
    fig.colorbar(m, ax=ax, label="fraction of designs passive")
    ax.set_title("passive region")
    panels_axes = [ax]
    if data.settling_time is not None:
        ax2 = axes[0, 1]
        m2 = ax2.pcolormesh(xe, ye, data.settling_time, cmap="viridis_r")
        fig.colorbar(m2, ax=ax2, label="mean settling time of settled designs [s]")
        ax2.set_title("2 % settling time")
        panels_axes.append(ax2)
    frac = data.passive_fraction
    show_contour = (
        data.x_centers.size > 1
        and data.y_centers.size > 1
        and np.nanmin(frac) < 0.5 < np.nanmax(frac)
    )
    for a in panels_axes:
        a.set_xlabel(_label(data.x), fontsize=11)
        a.set_ylabel(_label(data.y), fontsize=11)
        if show_contour:
            a.contour(
                data.x_centers, data.y_centers, np.ma.masked_invalid(frac), levels=[0.5],
                colors="k", linewidths=1.2,
            )  # fmt: skip
            handle = Line2D([], [], color="k", linewidth=1.2, label="passivity boundary")
            a.legend(handles=[handle], loc="upper right", fontsize=9)
    if title:
        fig.suptitle(title)
    return axes[0]
