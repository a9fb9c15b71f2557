"""Figures of interaction-control tuning: the responses behind an objective.

Plotting only consumes the data of
[`ObjectiveTuningResult.response`][seapass.tuning.objective_result.ObjectiveTuningResult.response].
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from .style import axes_grid

__all__ = ["plot_objective_response"]

_YLABEL = {
    "rendering": "rendered stiffness |F_L/X_L| [N/m]",
    "force-bandwidth": "clamped-load force |G(jω)/G(0)|",
    "zwidth": "rendered stiffness |F_L/X_L| [N/m]",
}


def plot_objective_response(data: Mapping[str, Any], *, ax: Any = None, title: str = "") -> Any:
    """Log-log magnitudes of the optima (and the target, or the −3 dB line).

    Parameters
    ----------
    data : mapping
        ``omega`` (rad/s), ``curves`` (``{label: magnitude}``) and ``kind``.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure if None.
    title : str, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = axes_grid(ax, 1, 1, figsize=(5.5, 3.8))[0, 0]
    w = data["omega"]
    for label, mag in data["curves"].items():
        style = {"ls": "--", "color": "0.3"} if label == "target" else {}
        ax.loglog(w, mag, lw=1.6, label=label, **style)
    if data["kind"] == "force-bandwidth":
        ax.axhline(1 / math.sqrt(2), color="tab:red", lw=0.8, ls=":", label="-3 dB")
    ax.set_xlabel("frequency ω [rad/s]")
    ax.set_ylabel(_YLABEL.get(str(data["kind"]), "magnitude"))
    if title:
        ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="best")
    return ax
