"""Figures for the core analysis: stiffness frequency responses and passive regions.

Plotting only consumes result objects from the analysis modules.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from ..analysis.freqresp import FrequencyResponse
from ..analysis.region import PassiveIntervals, PassiveMap

__all__ = ["plot_passive_intervals", "plot_passive_map", "plot_stiffness_response"]

plt.rcParams.update(
    {"font.size": 11, "axes.titlesize": 12, "axes.labelsize": 11, "legend.fontsize": 9}
)


def plot_stiffness_response(
    responses: FrequencyResponse | Sequence[FrequencyResponse],
    *,
    title: str = "",
    reference: float | None = None,
    ax: Any = None,
) -> Any:
    """Log-log plot of ``|F_L/X_L(jω)|``; returns the figure."""
    items = [responses] if isinstance(responses, FrequencyResponse) else list(responses)
    if ax is None:
        fig, ax = plt.subplots(figsize=(5.5, 3.8), constrained_layout=True)
    else:
        fig = ax.figure
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
    return fig


def plot_passive_intervals(
    result: PassiveIntervals, *, paper_bound: float | None = None, ax: Any = None
) -> Any:
    """Horizontal bar of the exact passive set of one parameter."""
    if ax is None:
        fig, ax = plt.subplots(figsize=(6, 1.8), constrained_layout=True)
    else:
        fig = ax.figure
    ax.axhspan(0, 1, color="#f4c7c3", label="not passive")
    for i, (a, b) in enumerate(result.intervals):
        ax.axvspan(a, b, color="#b7e1cd", label="passive (exact)" if i == 0 else None)
    if paper_bound is not None:
        ax.axvline(paper_bound, color="k", ls="--", label=f"paper's bound {paper_bound:.4g}")
    ax.set_xlim(result.lo, result.hi)
    ax.set_yticks([])
    ax.set_xlabel(result.param)
    ax.legend(loc="upper right", ncol=3, fontsize=8)
    return fig


def plot_passive_map(
    pmap: PassiveMap,
    *,
    paper_bound: tuple[np.ndarray, np.ndarray] | None = None,
    title: str = "",
    units: tuple[str, str] = ("", ""),
    ax: Any = None,
) -> Any:
    """Filled map of the passive region over two parameters, exact along each column."""
    if ax is None:
        fig, ax = plt.subplots(figsize=(5.5, 4.2), constrained_layout=True)
    else:
        fig = ax.figure
    ax.contourf(
        pmap.x,
        pmap.y,
        pmap.mask.astype(float),
        levels=[-0.5, 0.5, 1.5],
        colors=["#f4c7c3", "#b7e1cd"],
    )
    for xv, ivs in zip(pmap.x, pmap.intervals, strict=True):
        for a, b in ivs:
            ax.plot([xv, xv], [a, b], color="#2e7d32", lw=0.6, alpha=0.5)
    if paper_bound is not None:
        ax.plot(paper_bound[0], paper_bound[1], "k--", lw=1.5, label="paper's sufficient bound")
    ax.plot([], [], color="#b7e1cd", lw=8, label="passive (exact)")
    ax.plot([], [], color="#f4c7c3", lw=8, label="not passive")
    ux, uy = units
    ax.set_xlabel(f"{pmap.param_x} {ux}".strip())
    ax.set_ylabel(f"{pmap.param_y} {uy}".strip())
    ax.set_ylim(pmap.y[0], pmap.y[-1])
    if title:
        ax.set_title(title)
    ax.legend(loc="best", fontsize=8)
    return fig
