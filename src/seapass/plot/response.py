"""Frequency-response figures: the rendered stiffness ``F_L/X_L(jω)``, magnitude and phase.

Plotting only consumes [`seapass.analysis.freqresp.FrequencyResponse`][seapass.analysis.freqresp.FrequencyResponse].
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..analysis.freqresp import FrequencyResponse
from .style import axes_grid

__all__ = ["plot_stiffness_bode", "plot_stiffness_response"]


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


def plot_stiffness_bode(
    response: FrequencyResponse,
    *,
    title: str = "",
    reference: float | None = None,
    axes: Any = None,
) -> Any:
    """Bode plot of ``F_L/X_L(jω)``: magnitude (log-log) above phase.

    Parameters
    ----------
    response : FrequencyResponse
        One response; no legend is drawn (the title names it).
    title : str, optional
        Title of the magnitude Axes.
    reference : float, optional
        A stiffness drawn as a dashed grey line on the magnitude (e.g. the spring ``k1``).
    axes : sequence of two Axes, optional
        ``(magnitude, phase)``; a new figure if None.

    Returns
    -------
    numpy.ndarray of two Axes
        ``(magnitude, phase)``.
    """
    ax_m, ax_p = axes_grid(
        axes, 2, 1, figsize=(5.5, 4.6), sharex=True, gridspec_kw={"height_ratios": [2, 1]}
    )[:, 0]
    ax_m.loglog(response.omega, response.magnitude, lw=1.8, color="tab:blue")
    if reference is not None:
        ax_m.axhline(reference, color="0.4", ls="--", lw=1)
    ax_m.set_ylabel("|F_L/X_L| [N/m]")
    ax_p.semilogx(response.omega, response.phase, lw=1.5, color="tab:orange")
    ax_p.set_ylabel("phase [°]")
    ax_p.set_xlabel("frequency ω [rad/s]")
    lo, hi = float(np.nanmin(response.phase)), float(np.nanmax(response.phase))
    step = 45.0 if hi - lo <= 180.0 else 90.0
    ax_p.set_yticks(np.arange(np.floor(lo / step) * step, np.ceil(hi / step) * step + 1, step))
    ax_p.set_ylim(np.floor(lo / step) * step - 5, np.ceil(hi / step) * step + 5)
    from matplotlib.ticker import FuncFormatter, LogLocator, NullLocator

    for ax in (ax_m, ax_p):
        ax.grid(True, which="major", alpha=0.3)
        # labelled 1-2-5 ticks; unlabelled minor ticks cost most of the drawing time
        ax.xaxis.set_minor_locator(NullLocator())
    finite = response.magnitude[np.isfinite(response.magnitude) & (response.magnitude > 0)]
    decades = float(np.log10(finite.max() / finite.min())) if finite.size else 1.0
    subs = (1.0, 2.0, 5.0) if decades <= 2.5 else (1.0, 3.0) if decades <= 4 else (1.0,)
    ax_m.yaxis.set_major_locator(LogLocator(base=10, subs=subs, numticks=12))
    ax_m.yaxis.set_major_formatter(FuncFormatter(_tick_label))
    ax_m.yaxis.set_minor_locator(NullLocator())
    if title:
        ax_m.set_title(title, fontsize=10)
    return np.array([ax_m, ax_p])


def _tick_label(value: float, _pos: int = 0) -> str:
    """Plain numbers from 0.001 to 99999, powers of ten beyond."""
    if value == 0 or 1e-3 <= abs(value) < 1e5:
        return f"{value:g}"
    exp = int(np.floor(np.log10(abs(value))))
    mant = value / 10.0**exp
    head = "" if abs(mant - 1) < 1e-9 else f"{mant:g}\\times "
    return f"${head}10^{{{exp}}}$"
