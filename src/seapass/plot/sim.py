"""Figures for time-domain simulations and the paper's simulation study (Fig. 4).

Plotting only consumes result objects from :mod:`seapass.sim.simulate`,
:mod:`seapass.sim.metrics` and :mod:`seapass.paper.simstudy`.
"""

from __future__ import annotations

from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from ..sim.metrics import TrackingMetrics
from ..paper.simstudy import SimulationStudy
from ..sim.simulate import SimulationResult
from ..sim.tuning import DESIGNS

__all__ = ["plot_simulation", "plot_simulation_study"]

_MASS_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple")


def plot_simulation(
    result: SimulationResult,
    metrics: TrackingMetrics | None = None,
    *,
    title: str = "",
) -> Any:
    """Positions and actuator force of one run; the settling band and time if given."""
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.5, 5.2), sharex=True, constrained_layout=True)
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
    return fig


def plot_simulation_study(study: SimulationStudy) -> Any:
    """One panel per design: load position vs time for every load mass (paper Fig. 4)."""
    n = len(study.designs)
    fig, axes = plt.subplots(
        1, n, figsize=(4.6 * n, 3.9), sharey=True, constrained_layout=True, squeeze=False
    )
    for ax, design in zip(axes[0], study.designs, strict=True):
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
        ax.set_title(f"{DESIGNS[design].label}\n{gains}", fontsize=10)
        ax.set_xlabel("time [s]")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="lower right", fontsize=8)
    axes[0][0].set_ylabel("load position x_L [m]")
    fig.suptitle(
        f"{study.step:g} m step; gains tuned at m_L = "
        f"{next(iter(study.tuning.values())).options.load_mass:g} kg "
        "under the exact passivity constraint",
        fontsize=11,
    )
    return fig
