"""Two-ports and n-ports in pictures: η(ω) against 1, and the principal minors of ``P + P^H``.

Both consume results of [`seapass.ports`][seapass.ports]: the curves are sampled
on a grid for the picture only; the shaded bands are the exact failing bands the
results hold (isolated roots of exact polynomials), never read off the grid.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..ports.bound import PortRegion
from ..ports.passivity import MatrixPassivity
from ..ports.stability import AbsoluteStability
from .style import axes_grid

__all__ = ["plot_eta", "plot_minors", "plot_port_region"]

_FAIL = "tab:red"


def _shade(ax: Any, bands: Sequence[Sequence[float]], lo: float, hi: float, label: str) -> None:
    for i, (a, b) in enumerate(bands):
        b = hi if not math.isfinite(b) else b
        if b <= lo or a >= hi:
            continue
        ax.axvspan(
            max(a, lo), min(b, hi), color=_FAIL, alpha=0.18, lw=0, label=label if i == 0 else None
        )


def plot_eta(result: AbsoluteStability, *, title: str = "", ax: Any = None) -> Any:
    """η(ω) of a two-port with the line η = 1 and the bands where Llewellyn's conditions fail.

    Parameters
    ----------
    result : AbsoluteStability
        From [`absolute_stability`][seapass.ports.stability.absolute_stability].
    title : str, optional
        Axes title (default: the verdict and inf η).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = axes_grid(ax, 1, 1, figsize=(6.0, 3.8))[0, 0]
    data = result.response()
    w, eta = data["omega"], data["eta"]
    lo, hi = float(w[0]), float(w[-1])
    ax.semilogx(w, eta, lw=1.8, color="tab:blue", label="η(ω)")
    ax.axhline(1.0, color="0.3", lw=0.9, ls="--", label="η = 1")
    _shade(ax, data["bands"], lo, hi, "conditions fail (exact)")
    finite = eta[np.isfinite(eta)]
    if finite.size:
        top = float(np.percentile(finite, 95))
        bottom = float(finite.min())
        ax.set_ylim(min(bottom, 0.5) - 0.1 * abs(bottom), max(top, 2.0) * 1.1)
    ax.set_xlim(lo, hi)
    ax.set_xlabel("frequency ω [rad/s]")
    ax.set_ylabel("η(ω)")
    verdict = "absolutely stable" if result.absolutely_stable else f"{result.outcome.label}"
    verdict = verdict.replace("not passive", "not absolutely stable")
    ax.set_title(title or f"{verdict}; inf η = {result.eta.value:.4g} (exact)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="best", fontsize=9)
    return ax


def plot_minors(result: MatrixPassivity, *, title: str = "", ax: Any = None) -> Any:
    """The principal minors of ``P(jω) + P(jω)^H`` (symlog) with their exact failing bands.

    Parameters
    ----------
    result : MatrixPassivity
        From [`two_port_passivity`][seapass.ports.check.two_port_passivity] or
        [`mimo_is_passive`][seapass.ports.mimo.mimo_is_passive].
    title : str, optional
        Axes title (default: the verdict).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = axes_grid(ax, 1, 1, figsize=(6.0, 3.8))[0, 0]
    data = result.response()
    w = data["omega"]
    lo, hi = float(w[0]), float(w[-1])
    peak = 1.0
    for name, values in data["minors"].items():
        ax.semilogx(w, values, lw=1.5, label=name.replace("_", " "))
        finite = np.abs(values[np.isfinite(values)])
        if finite.size and finite.max() > 0:
            peak = max(peak, float(finite.max()))
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_yscale("symlog", linthresh=max(peak * 1e-6, 1e-12))
    _shade(ax, data["bands"], lo, hi, "a minor < 0 (exact)")
    ax.set_xlim(lo, hi)
    ax.set_xlabel("frequency ω [rad/s]")
    ax.set_ylabel("principal minors of P + P^H (symlog)")
    ax.set_title(title or f"{result.n}-port: {result.outcome.label} (exact)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    return ax


def plot_port_region(region: PortRegion, *, title: str = "", ax: Any = None) -> Any:
    """The exact set of the second parameter at each value of the first, as vertical bars.

    Parameters
    ----------
    region : PortRegion
        From [`port_region`][seapass.ports.bound.port_region].
    title : str, optional
        Axes title.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = axes_grid(ax, 1, 1, figsize=(6.0, 4.2))[0, 0]
    xs = region.x
    width = float(np.min(np.diff(xs))) * 0.9 if xs.size > 1 else 1.0
    for i, (x, col) in enumerate(zip(xs, region.columns, strict=True)):
        for j, (a, b) in enumerate(col.intervals):
            ax.bar(x, b - a, bottom=a, width=width, color="tab:green", alpha=0.55, lw=0,
                   label="holds (exact along y)" if i == 0 and j == 0 else None)  # fmt: skip
    ax.set_xlim(xs[0] - width, xs[-1] + width)
    ax.set_ylim(*region.y_range)
    ax.set_xlabel(region.param_x)
    ax.set_ylabel(region.param_y)
    what = region.criterion.label
    ax.set_title(title or f"{what} region (exact along {region.param_y})", fontsize=10)
    ax.grid(True, alpha=0.3)
    if any(col.intervals for col in region.columns):
        ax.legend(loc="best", fontsize=9)
    return ax
