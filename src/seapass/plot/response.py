"""Frequency-response figures: the magnitude of the rendered stiffness ``|F_L/X_L(jω)|``.

Plotting only consumes [`seapass.analysis.freqresp.FrequencyResponse`][seapass.analysis.freqresp.FrequencyResponse].
Its Bode plot (magnitude and phase) is
[`seapass.plot.passivity.plot_bode`][seapass.plot.passivity.plot_bode].
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..analysis.freqresp import FrequencyResponse
from .style import axes_grid

__all__ = ["plot_stiffness_response"]


def plot_stiffness_response(
    responses: FrequencyResponse | Sequence[FrequencyResponse],
    *,
    title: str = "",
    reference: float | None = None,
    ax: Any = None,
) -> Any:
    """Log-log plot of ``|F_L/X_L(jω)|``.

    Parameters
    ----------
    responses : FrequencyResponse or sequence of them
        One line each, labelled with its ``label``.
    title : str, optional
        Axes title.
    reference : float, optional
        A stiffness drawn as a dashed horizontal line (e.g. the spring ``k1``).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    matplotlib.axes.Axes
    """
    items = [responses] if isinstance(responses, FrequencyResponse) else list(responses)
    ax = axes_grid(ax, 1, 1, figsize=(5.5, 3.8))[0, 0]
    for r in items:
        ax.loglog(r.omega, r.magnitude, label=r.label or None, lw=1.8)
    if reference is not None:
        ax.axhline(
            reference, color="0.4", ls="--", lw=1, label=f"spring stiffness k1 = {reference:g} N/m"
        )
    ax.set_xlabel("frequency ω [rad/s]")
    ax.set_ylabel("rendered stiffness |F_L/X_L| [N/m]")
    if title:
        ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    if any(r.label for r in items) or reference is not None:
        ax.legend(loc="best")
    return ax
