"""Figures for time-domain simulations and the paper's simulation study (Fig. 4).

Plotting only consumes result objects from [`seapass.sim.simulate`][seapass.sim.simulate],
[`seapass.sim.metrics`][seapass.sim.metrics] and [`seapass.paper.simstudy`][seapass.paper.simstudy].
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..model.catalog import design as catalog_design
from ..model.expr import UNITS
from ..model.units import unit_label
from ..paper.simstudy import SimulationStudy
from ..sim.metrics import TrackingMetrics
from ..sim.simulate import SimulationResult
from .style import axes_grid

__all__ = ["plot_simulation", "plot_simulation_study", "plot_step_responses", "plot_tradeoff"]

_MASS_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple")


def plot_simulation(
    result: SimulationResult,
    metrics: TrackingMetrics | None = None,
    *,
    title: str = "",
    axes: Any = None,
) -> Any:
    """Positions and actuator force of one run; the settling band and time if given.

    Returns the two Axes (positions, force).
    """
    ax1, ax2 = axes_grid(axes, 2, 1, figsize=(6.5, 5.2), sharex=True)[:, 0]
    ax1.plot(result.time, result.x_L, lw=1.8, label="load x_L")
    ax1.plot(result.time, result.x_A, lw=1.2, ls="--", label="actuator x_A")
    ax1.axhline(result.target, color="0.3", lw=0.8, label=f"target {result.target:g} m")
    if metrics is not None and metrics.band > 0:
        ax1.axhspan(
            result.target - metrics.band,
            result.target + metrics.band,
            color="0.85",
            label="±2 % band",
        )
        if metrics.settling_time is not None:
            ax1.axvline(
                metrics.settling_time,
                color="tab:red",
                lw=1,
                ls=":",
                label=f"settled at {metrics.settling_time:.3f} s",
            )
    ax1.set_ylabel("position [m]")
    status = result.status if metrics is None else metrics.status
    ax1.set_title(title or f"simulation ({status})")
    ax1.legend(loc="best")
    ax1.grid(True, alpha=0.3)
    ax2.plot(result.time, result.f_A, color="tab:purple", lw=1.2)
    ax2.set_xlabel("time [s]")
    ax2.set_ylabel("actuator force f_A [N]")
    ax2.grid(True, alpha=0.3)
    return np.array([ax1, ax2])


def plot_simulation_study(study: SimulationStudy, *, axes: Any = None) -> Any:
    """One panel per design: load position vs time for every load mass (paper Fig. 4).

    Returns the Axes, one per design.
    """
    n = len(study.designs)
    grid = axes_grid(axes, 1, n, figsize=(4.6 * n, 3.9), sharey=True)
    for ax, design in zip(grid[0], study.designs, strict=True):
        for i, mass in enumerate(study.masses):
            res = study.runs[(design, mass)]
            met = study.row(design, mass).metrics
            ts = (
                f"settles in {met.settling_time:.2f} s"
                if met.settling_time is not None
                else met.status
            )
            ax.plot(
                res.time,
                res.x_L,
                color=_MASS_COLORS[i % len(_MASS_COLORS)],
                lw=1.5,
                label=f"m_L = {mass:g} kg ({ts})",
            )
        ax.axhline(study.step, color="0.3", lw=0.8, ls="--")
        ax.axhspan(study.step * 0.98, study.step * 1.02, color="0.88", zorder=0)
        gains = ", ".join(f"{k}={v:.3g}" for k, v in study.tuning[design].gains.items())
        ax.set_title(f"{catalog_design(design).label}\n{gains}", fontsize=10)
        ax.set_xlabel("time [s]")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="lower right", fontsize=8)
    grid[0][0].set_ylabel("load position x_L [m]")
    grid[0][0].figure.suptitle(
        f"{study.step:g} m step; gains tuned at m_L = "
        f"{next(iter(study.tuning.values())).options.load_mass:g} kg "
        "under the exact passivity constraint",
        fontsize=11,
    )
    return grid[0]


def plot_tradeoff(
    maps: Sequence[tuple[Any, ...]], *, horizon: float | None = None, axes: Any = None
) -> Any:
    """Settling time over 2-D gain grids; grey where not passive.

    ``maps`` holds ``(label, x name, y name, xs, ys, passive mask, settling times,
    best[, marks])`` per panel: ``ts`` has axes ``(len(ys), len(xs))`` and NaN
    where the design did not settle, ``best = (time, x, y)`` of the fastest
    passive design or None, and ``marks`` optional ``(x, y, label)`` points to
    circle.  The colour scale is logarithmic up to ``horizon`` (default: the
    slowest settled design); a passive design that did not settle within it
    takes the scale's darkest colour, so the region reads continuous instead
    of speckled.  Axes may be non-uniform.  Returns the Axes, one per map.
    """
    from matplotlib.colors import LogNorm
    from matplotlib.patches import Patch
    from matplotlib.ticker import FuncFormatter

    grid = axes_grid(axes, 1, len(maps), figsize=(5.8 * len(maps), 4.6))[0]
    for ax, entry in zip(grid, maps, strict=True):
        label, xn, yn, xs, ys, pas, ts, best = entry[:8]
        marks = entry[8] if len(entry) > 8 else []
        settled = np.isfinite(ts) & pas
        top = horizon or (float(np.nanmax(ts[settled])) if settled.any() else 1.0)
        low = float(np.nanmin(ts[settled])) if settled.any() else top / 10
        cmap = _colormap("viridis_r").with_extremes(over="#2b0b3f")
        # not settled: above the scale (a finite value, so it takes the "over" colour)
        shown = np.where(pas, np.where(np.isfinite(ts), ts, 10.0 * top), np.nan)
        ax.pcolormesh(xs, ys, np.where(pas, np.nan, 1.0), cmap="Greys", vmin=0, vmax=2,
                      shading="nearest")  # fmt: skip
        mesh = ax.pcolormesh(xs, ys, shown, cmap=cmap, shading="nearest",
                             norm=LogNorm(vmin=max(low * 0.9, 1e-3), vmax=top))  # fmt: skip
        bar = ax.figure.colorbar(
            mesh,
            ax=ax,
            extend="max",
            label=f"2 % settling time [s] (darkest: not within {top:g} s)",
        )
        bar.ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
        bar.ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))  # fmt: skip
        handles = [Patch(color="0.5", label="not passive")]
        if best is not None:
            (h,) = ax.plot(best[1], best[2], "r*", ms=14, label=f"fastest passive: {best[0]:.3g} s")
            handles.append(h)
        for mx, my, mlabel in marks:
            (h,) = ax.plot(mx, my, "o", ms=11, mfc="none", mec="w", mew=2, label=mlabel)
            handles.append(h)
        ax.legend(handles=handles, loc="upper right", fontsize=8)
        ax.set_xlabel(unit_label(xn, UNITS))
        ax.set_ylabel(unit_label(yn, UNITS))
        ax.set_title(label, fontsize=11)
    return grid


def _colormap(name: str) -> Any:
    """A registered colormap by name, without pyplot."""
    import matplotlib

    return matplotlib.colormaps[name]


def plot_step_responses(
    runs: Sequence[tuple[float, Any, Any]], *, step: float, title: str = "", ax: Any = None
) -> Any:
    """Load position after a reference step, one line per load mass; returns the Axes.

    ``runs`` holds ``(load mass, SimulationResult, TrackingMetrics)``.  An
    unstable run is drawn until it leaves ±10 steps, so the axes stay readable.
    """
    ax = axes_grid(ax, 1, 1, figsize=(7, 3.8))[0, 0]
    limit = 10 * abs(step)
    for mass, res, met in runs:
        ts = f"settles in {met.settling_time:.3g} s" if met.settled else str(met.status)
        out = np.flatnonzero(np.abs(res.x_L) > limit)
        x = np.array(res.x_L, dtype=float)
        if out.size:
            x[out[0] :] = np.nan
            ts += f", |x_L| > {limit:g} m at {res.time[out[0]]:.3g} s"
        ax.plot(res.time, x, lw=1.5, label=f"m_L = {mass:g} kg ({ts})")
    ax.axhline(step, color="0.3", lw=0.8, ls="--", label=f"target {step:g} m")
    ax.axhspan(step * 0.98, step * 1.02, color="0.88", zorder=0)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("load position x_L [m]")
    if title:
        ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    return ax
