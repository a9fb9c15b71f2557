"""Heat maps of a sweep: passive fraction and settling time over two parameters.

Figures only consume :class:`seapass.sweep.runner.HeatmapData`; nothing is computed here.
"""

from __future__ import annotations

import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ..files.atomic import atomic_save
from ..sweep.runner import HeatmapData

__all__ = ["plot_sweep_heatmap", "save_sweep_heatmap"]

_UNITS = {
    "kd": "N/m",
    "k1": "N/m",
    "k2": "N/m",
    "ki": "N/(m·s)",
    "bd": "N·s/m",
    "b1": "N·s/m",
    "b2": "N·s/m",
    "b": "N·s/m",
    "m": "kg",
    "m_L": "kg",
}


def _label(name: str) -> str:
    unit = _UNITS.get(name)
    return f"{name} [{unit}]" if unit else name


def _edges(c: np.ndarray) -> np.ndarray:
    if c.size == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def plot_sweep_heatmap(data: HeatmapData, *, title: str = "") -> Figure:
    """Passive fraction (left) and mean settling time of settled designs (right).

    The passive region's boundary (passive fraction 0.5) is drawn on both panels.
    """
    panels = 2 if data.settling_time is not None else 1
    fig, axes = plt.subplots(1, panels, figsize=(6.0 * panels, 4.8), squeeze=False)
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
    fig.tight_layout()
    return fig


def save_sweep_heatmap(data: HeatmapData, path: str | os.PathLike[str], *, title: str = "") -> None:
    """Render :func:`plot_sweep_heatmap` and save it atomically."""
    fig = plot_sweep_heatmap(data, title=title)
    try:
        atomic_save(path, lambda tmp: fig.savefig(tmp, dpi=120))
    finally:
        plt.close(fig)
