"""Figure of a destabilizing environment: the growing oscillation and the coupled poles.

Plotting only consumes [`seapass.analysis.witness.WitnessResult`][seapass.analysis.witness.WitnessResult].
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..analysis.passivity import Reason
from ..analysis.witness import WitnessResult
from .style import axes_grid

__all__ = ["plot_witness"]


def plot_witness(result: WitnessResult, *, title: str = "", axes: Any = None) -> Any:
    """Two panels: the coupled impulse response with its ``e^{σt}`` envelope, and the poles.

    Parameters
    ----------
    result : WitnessResult
        A result with ``found`` True and a simulation.
    title : str, optional
        Figure title (default: the environment's parameters).
    axes : sequence of two matplotlib.axes.Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    numpy.ndarray of matplotlib.axes.Axes
        The response and the pole panels.
    """
    if not result.found or result.simulation is None or result.coupled is None:
        raise ValueError("plot_witness needs a found witness with a simulation (simulate=True)")
    sim, env, coupled = result.simulation, result.environment, result.coupled
    assert env is not None
    ax1, ax2 = axes_grid(axes, 1, 2, figsize=(10, 4.2))[0]
    unit = "m/(N·s)" if sim.output == "port displacement" else "a.u."
    ax1.plot(sim.t, sim.y, lw=0.9, color="tab:blue", label=sim.output)
    if sim.growth_rate > 0:
        q = max(sim.t.size // 4, 1)
        tail = np.max(np.abs(sim.y[-q:]))
        envelope = tail * np.exp(sim.growth_rate * (sim.t - sim.t[-1]))
        ax1.plot(
            sim.t,
            envelope,
            "--",
            color="tab:red",
            lw=1.2,
            label=f"e^(σt), σ = {sim.growth_rate:.3g} 1/s",
        )
        ax1.plot(sim.t, -envelope, "--", color="tab:red", lw=1.2)
    ax1.set_xlabel("time [s]")
    ax1.set_ylabel(f"{sim.output} [{unit}]")
    ax1.set_title("response to a force impulse at the port")
    ax1.grid(True, alpha=0.3)
    ax1.legend(loc="upper left", fontsize=9)

    poles = coupled.poles
    ax2.axvline(0, color="0.3", lw=0.8)
    ax2.plot(poles.real, poles.imag, "x", ms=9, mew=2, color="tab:purple", label="coupled poles")
    lin = max(abs(coupled.max_real_part) / 10, 1e-6) if np.isfinite(coupled.max_real_part) else 1
    lin = 10.0 ** np.floor(np.log10(lin))  # a decade, so the ticks fall on powers of ten
    ax2.set_xscale("symlog", linthresh=lin)
    lo, hi = ax2.get_xlim()
    hi = max(hi, 2 * lin)
    ax2.axvspan(0, hi, color="tab:red", alpha=0.08, label="unstable half-plane")
    ax2.set_xlim(lo, hi)
    ax2.set_xticks(_symlog_ticks(lo, hi, lin))
    ax2.set_xlabel("Re s [1/s] (symmetric log scale)")
    ax2.set_ylabel("Im s [rad/s]")
    ax2.set_title(f"coupled system: {coupled.status}")
    ax2.grid(True, alpha=0.3)
    ax2.legend(loc="best", fontsize=9)
    ax1.figure.suptitle(
        title
        or (
            f"not passive ({Reason(result.reason).description}): destabilized by "
            f"m_e = {env.mass:.3g} kg, "
            f"b_e = {env.damping:.3g} N·s/m, k_e = {env.stiffness:.3g} N/m"
        ),
        fontsize=11,
    )
    return np.array([ax1, ax2])


def _symlog_ticks(lo: float, hi: float, lin: float) -> list[float]:
    """0 and at most three powers of ten per side: readable ticks on a symlog axis."""
    ticks = [0.0]
    for sign, end in ((-1.0, -lo), (1.0, hi)):
        if end <= lin:
            continue
        decades = np.arange(np.log10(lin), np.floor(np.log10(end)) + 1)
        stride = max(1, int(np.ceil(len(decades) / 3)))
        ticks += [sign * 10.0**d for d in decades[::-1][::stride]]
    return sorted(ticks)
