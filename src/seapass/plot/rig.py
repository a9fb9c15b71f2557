"""Figures of the rig experiment; they only consume result objects of [`seapass.rig`][seapass.rig].

`plot_rig_sweep` follows the bottom row of the paper's Fig. 3 (settling
time and steady-state error against ``kd``, LP and Ours, one column per load
mass, LP's unstable gains shaded); `plot_impacts` shows the perceived stiffness
(Eq. (10) frequency response, ``k_out`` against the impact time scale and
against ``b1``; the paper's value only for the paper's rig); `plot_deploy` shows runs
of the deployed controller; `plot_rig_fit` shows a fit of the actuator to a log.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..rig.chirp import ChirpPlan
from ..rig.experiment import ExperimentResult, RigSweepResult
from ..rig.identify import RigFit
from ..rig.impacts import ImpactResult
from .style import axes_grid

__all__ = [
    "plot_chirp",
    "plot_deploy",
    "plot_impacts",
    "plot_rig_fit",
    "plot_rig_sweep",
    "plot_traces",
]


def plot_chirp(plan: ChirpPlan, *, ax: Any = None) -> Any:
    """The commanded force of a [`ChirpPlan`][seapass.rig.chirp.ChirpPlan] against time."""
    ax = axes_grid(ax, 1, 1, figsize=(7.0, 3.0))[0, 0]
    ax.plot(plan.time, plan.force, lw=0.6, color="tab:blue")
    for level in (plan.amplitude, -plan.amplitude):
        ax.axhline(level, color="0.5", ls=":", lw=1)
    lo, hi = plan.band
    ax.set_xlabel("time [s]")
    ax.set_ylabel("commanded force [N]")
    ax.set_title(f"chirp {lo:g}-{hi:g} Hz at {plan.rate:g} Hz, ±{plan.amplitude:g} N", fontsize=10)
    ax.grid(True, alpha=0.3)
    return ax


_COLORS = {"LP": "tab:red", "ours": "tab:blue"}
_LABEL = {"LP": "LP", "ours": "Ours"}


def plot_rig_sweep(result: ExperimentResult, *, axes: Any = None) -> Any:
    """Settling time (top) and steady-state error (bottom) against ``kd``, one column per load mass.

    Paper Fig. 3, bottom row, with the load masses side by side so each panel
    holds two lines (LP, Ours).  Gains where LP is unstable on the twin are
    shaded; the error is on a log scale in mm, each gain a marker.

    Returns
    -------
    numpy.ndarray of Axes, shape (2, number of load masses)
    """
    from matplotlib.ticker import FuncFormatter

    masses = sorted({s.load_mass for s in result.sweeps})
    n = max(len(masses), 1)
    grid = axes_grid(axes, 2, n, figsize=(5.2 * n + 0.6, 6.4), sharex=True)
    for col, mass in enumerate(masses):
        ax_t, ax_e = grid[0, col], grid[1, col]
        sweeps = [s for s in result.sweeps if s.load_mass == mass]
        for s in sweeps:
            kw = {
                "color": _COLORS.get(s.design, "tab:green"),
                "label": _LABEL.get(s.design, s.design),
            }
            ax_t.plot(s.kd, s.settling_time, marker="o", ms=3.5, lw=1.3, **kw)
            err = np.where(s.steady_state_error > 0, s.steady_state_error * 1e3, np.nan)
            ax_e.plot(s.kd, err, marker="o", ms=3.5, lw=0.8, alpha=0.9, **kw)
            if s.design == "LP" and s.unstable_gain_twin is not None:
                for ax in (ax_t, ax_e):
                    ax.axvspan(s.unstable_gain_twin, float(np.max(s.kd)) * 1.02,
                               color="tab:red", alpha=0.1, lw=0,
                               label="LP unstable (twin)" if ax is ax_t else None)  # fmt: skip
        ax_t.set_title(f"load mass $m_L$ = {mass:g} kg")
        ax_t.set_ylim(bottom=0)
        ax_e.set_yscale("log")
        ax_e.yaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
        gain = sweeps[0].gain if sweeps else "kd"
        ax_e.set_xlabel("controller stiffness $k_d$ (N/m)" if gain == "kd" else f"gain {gain}")
        for ax in (ax_t, ax_e):
            ax.grid(True, alpha=0.3)
    grid[0, 0].set_ylabel("2 % settling time (s)\n[gaps: did not settle in 2 s]")
    grid[1, 0].set_ylabel("steady-state error of $x_L$ (mm)")
    grid[0, 0].legend(fontsize=8, loc="upper left")
    grid[0, 0].figure.suptitle(f"Digital twin of {result.rig_name}: load from 20 mm to 0")
    return grid


def plot_traces(
    sweep: RigSweepResult, kd_values: list[float] | None = None, *, ax: Any = None
) -> Any:
    """Measured load position against time for a few gains of one sweep; returns the Axes."""
    ax = axes_grid(ax, 1, 1, figsize=(6, 4))[0, 0]
    picks = kd_values or list(np.unique(np.quantile(sweep.kd, [0.1, 0.4, 0.7, 1.0])))
    for kd in picks:
        i = int(np.argmin(np.abs(sweep.kd - kd)))
        name = "$k_d$" if sweep.gain == "kd" else sweep.gain
        ax.plot(sweep.t, sweep.x_L[i] * 1e3, label=f"{name} = {sweep.kd[i]:g} ({sweep.status[i]})")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("load position $x_L$ (mm)")
    ax.set_title(f"{_LABEL.get(sweep.design, sweep.design)}, $m_L$ = {sweep.load_mass:g} kg")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return ax


def plot_impacts(result: ImpactResult, *, axes: Any = None) -> Any:
    """Perceived stiffness: Eq. (10) response, ``k_out`` vs time scale and vs ``b1``.

    Returns the three Axes.
    """
    ax_f, ax_w, ax_b = axes_grid(axes, 1, 3, figsize=(13, 4))[0]
    ax_f.loglog(result.omega, result.eq10_magnitude, label="Eq. (10), massless port")
    ax_f.loglog(result.omega, result.eq10_with_load, "--", label="with load-side mass")
    ax_f.axhline(result.k1, color="gray", linestyle=":", label="$k_1$")
    paper = result.paper_k_out
    if paper is not None:
        ax_f.axhline(paper[0], color="k", linestyle="-.", linewidth=0.8, label="paper $k_{out}$")
    ax_f.set_xlabel("frequency $\\omega$ (rad/s)")
    ax_f.set_ylabel("$|F_L/X_L(j\\omega)|$ (N/m)")
    if result.design is None:
        ax_f.set_title(f"Ours, $k_d$={result.kd:g}, $b_d$={result.bd:g}")
    else:  # a design file's controller (in z: no Eq. (10), the panel stays empty)
        ax_f.set_title(f"design {result.design}")
    ax_w.loglog(
        result.windows * 1e3, result.k_out_vs_window, "o-", label="twin (friction, encoders)"
    )
    ax_w.loglog(
        result.windows * 1e3, result.k_out_linear_vs_window, "s--", label="linear, exact positions"
    )
    ax_w.axhline(result.k1, color="gray", linestyle=":", label="$k_1$")
    if result.static_stiffness is not None:
        ax_w.axhline(
            result.static_stiffness, color="gray", linestyle="--", linewidth=0.8, label="static"
        )
    if paper is not None:
        ax_w.axhspan(
            paper[0] - paper[1],
            paper[0] + paper[1],
            color="k",
            alpha=0.15,
            label=f"paper {paper[0]:g}±{paper[1]:g}",
        )
    ax_w.axvline(result.window * 1e3, color="k", linestyle=":", linewidth=0.8)
    ax_w.set_xlabel("read-out time after impact onset (ms)")
    ax_w.set_ylabel("$k_{out} = F_L/X_L$ (N/m)")
    ax_w.set_title("Dependence on impact time scale")
    ax_b.errorbar(
        result.b1_values,
        result.k_out_vs_b1,
        yerr=result.k_out_vs_b1_std,
        fmt="o-",
        capsize=3,
        label="twin, mean ± std",
    )
    ax_b.axhline(result.k1, color="gray", linestyle=":", label="$k_1$")
    if paper is not None:
        ax_b.axhspan(paper[0] - paper[1], paper[0] + paper[1], color="k", alpha=0.15, label="paper")
    ax_b.set_xlabel("damper viscous coefficient $b_1$ (N s/m)")
    ax_b.set_ylabel(f"$k_{{out}}$ at {result.window * 1e3:g} ms (N/m)")
    ax_b.set_title(f"{result.forces.size} impacts per $b_1$")
    for ax in (ax_f, ax_w, ax_b):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    return np.array([ax_f, ax_w, ax_b])


def plot_deploy(runs: Sequence[tuple[str, Any]], *, axes: Any = None) -> Any:
    """Load position and saturated force command of deployed-controller runs.

    ``runs`` holds ``(label, record)`` with a [`seapass.sampled.runtime.LoopRecord`][seapass.sampled.runtime.LoopRecord]
    each.  Returns the two Axes.
    """
    a1, a2 = axes_grid(axes, 1, 2, figsize=(10, 3.6))[0]
    for label, rec in runs:
        a1.plot(rec.t, np.asarray(rec.x_L) * 1e3, lw=1.4, label=label)
        a2.plot(rec.t, rec.command, lw=1.0, label=label)
    a1.set_xlabel("time [s]")
    a1.set_ylabel("measured load position x_L [mm]")
    a1.set_title("Load position (reference 0)")
    a2.set_xlabel("time [s]")
    a2.set_ylabel("force command [N]")
    a2.set_title("Saturated command")
    for ax in (a1, a2):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=9)
    return np.array([a1, a2])


def plot_rig_fit(fit: RigFit, *, axes: Any = None) -> Any:
    """The fit of the actuator to a log: model against applied force, and residuals in time.

    Each point is one modulating window (its ``φ``-weighted mean force): the
    force applied (command after delay and saturation) and the force the fitted
    model needs to move as logged; a perfect fit lies on the diagonal.
    Returns the two Axes.
    """
    ax_p, ax_r = axes_grid(axes, 1, 2, figsize=(10, 4.2))[0]
    applied, model = fit.force_applied, fit.force_model
    ax_p.plot(applied, model, ".", ms=3, color="tab:blue", label=f"{fit.windows_used} windows")
    lo = float(min(applied.min(), model.min())) if applied.size else -1.0
    hi = float(max(applied.max(), model.max())) if applied.size else 1.0
    ax_p.plot([lo, hi], [lo, hi], color="0.4", lw=0.8, ls="--", label="model = applied")
    ax_p.set_xlabel("applied force, window mean [N]")
    ax_p.set_ylabel("fitted model's force [N]")
    ax_p.legend(loc="upper left", fontsize=8)
    resid = applied - model
    ax_r.plot(fit.t_window, resid, ".", ms=3, color="tab:red")
    band = 1.96 * fit.residual_std
    ax_r.axhspan(-band, band, color="tab:red", alpha=0.1, lw=0, label="±1.96 σ")
    ax_r.axhline(0.0, color="0.3", lw=0.8)
    ax_r.set_xlabel("time [s]")
    ax_r.set_ylabel("applied − model [N]")
    ax_r.legend(loc="upper right", fontsize=8)
    for ax in (ax_p, ax_r):
        ax.grid(True, alpha=0.3)
    shown = [p for p in fit.parameters if p.name != "offset"]
    lines = [
        ", ".join(f"{p.name} = {p.value:.4g} ± {p.stderr:.2g} {p.unit}" for p in part)
        for part in (shown[:3], shown[3:])
    ]
    ax_p.figure.suptitle("\n".join(lines), fontsize=9)
    return np.array([ax_p, ax_r])
