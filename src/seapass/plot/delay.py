"""Continuous delay in pictures: ``Re Z(jω)`` at a delay with its failing bands, the first
failing delay per frequency (the delay margin), the passive region in (gain, delay), the
certified passive set of a gain at a delay and the 2-D map of two gains at a delay.

Plot functions only consume results of [`seapass.delay`][seapass.delay]; the shaded
bands are the certified ones the results hold (proven by ball arithmetic, or exact),
never read off the plotted grid.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .style import axes_grid

__all__ = [
    "plot_delay_map",
    "plot_delay_margin",
    "plot_delay_region",
    "plot_delay_response",
    "plot_gain_intervals",
]

_FAIL = "tab:red"


def _linthresh(values: np.ndarray) -> float:
    finite = np.abs(values[np.isfinite(values)])
    finite = finite[finite > 0]
    return float(np.percentile(finite, 10)) if finite.size else 1.0


def plot_delay_response(
    response: Any, *, kind: str = "real", ax: Any = None, title: str = ""
) -> Any:
    """``Re Z(jω)`` at the delay (``kind="real"``) or the Nyquist curve (``"nyquist"``).

    Parameters
    ----------
    response : seapass.delay.response.DelayResponse
        The sampled curve and the certified bands.
    kind : {"real", "nyquist"}
        Which picture.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure if None.
    title : str, optional
        Axes title.

    Returns
    -------
    matplotlib.axes.Axes
    """
    if kind not in ("real", "nyquist"):
        raise ValueError(f"kind must be 'real' or 'nyquist', got {kind!r}")
    ax = axes_grid(ax, 1, 1, figsize=(6.0, 3.8))[0, 0]
    tau = f"{response.delay} = {response.tau:g} s"
    if kind == "nyquist":
        z = response.value
        ax.plot(z.real, z.imag, lw=1.6, color="tab:blue", label=f"Z(jω), {tau}")
        ax.plot(z.real, -z.imag, lw=1.0, color="tab:blue", ls="--", alpha=0.5)
        ax.axvline(0.0, color="0.3", lw=0.8)
        ax.set_xlabel("Re Z [N·s/m]")
        ax.set_ylabel("Im Z [N·s/m]")
        ax.set_title(title or f"Nyquist, {tau}", fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=9)
        return ax
    w, re = response.omega, response.real
    ax.semilogx(w, re, lw=1.6, color="tab:blue", label=f"Re Z(jω), {tau}")
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_yscale("symlog", linthresh=_linthresh(re))
    lo, hi = float(w[0]), float(w[-1])
    for i, (a, b) in enumerate(response.dangerous_bands):
        if b > lo and a < hi:
            ax.axvspan(max(a, lo), min(b, hi), color="tab:orange", alpha=0.08, lw=0,
                       label="some delay fails here (exact)" if i == 0 else None)  # fmt: skip
    for i, (a, b) in enumerate(response.negative_bands):
        ax.axvspan(max(a, lo), min(b, hi), color=_FAIL, alpha=0.25, lw=0,
                   label="Re Z < 0 (proven)" if i == 0 else None)  # fmt: skip
    for i, (a, b) in enumerate(response.undecided_bands):
        ax.axvspan(max(a, lo), min(b, hi), color="0.5", alpha=0.3, lw=0,
                   label="undecided" if i == 0 else None)  # fmt: skip
    ax.set_xlim(lo, hi)
    ax.set_xlabel("frequency ω [rad/s]")
    ax.set_ylabel("Re Z(jω) [N·s/m] (symlog)")
    verdict = "Re Z(jω) < 0 in the red bands" if response.negative_bands else "Re Z(jω) ≥ 0"
    ax.set_title(title or f"{verdict} at {tau}", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="best", fontsize=9)
    return ax


def plot_delay_margin(margin: Any, *, ax: Any = None, title: str = "") -> Any:
    """The first delay that makes ``Re Z(jω) < 0`` at each frequency, and ``τ*``.

    ``margin`` is a [`DelayMarginResult`][seapass.delay.margin.DelayMarginResult]; its
    ``curve()`` samples the first failing delay ``g(ω)`` over the dangerous band (a
    picture); the certified enclosure of ``τ* = inf g`` is drawn as a band.
    """
    ax = axes_grid(ax, 1, 1, figsize=(6.0, 3.8))[0, 0]
    w, g = margin.curve()
    if w.size:
        ax.loglog(w, g, lw=1.6, color="tab:blue", label="first failing delay at ω")
    if margin.tau_star is not None:
        lo, hi = margin.tau_star
        ax.axhspan(lo, hi, color=_FAIL, alpha=0.3, lw=0)
        ax.axhline(hi, color=_FAIL, lw=1.2, label=f"τ* ∈ [{lo:.6g}, {hi:.6g}] s")
        if margin.frequency is not None:
            ax.axvline(margin.frequency, color="0.4", ls=":", lw=1,
                       label=f"lost at ω = {margin.frequency:.4g} rad/s")  # fmt: skip
    ax.set_xlabel("frequency ω [rad/s]")
    ax.set_ylabel(f"delay {margin.delay} [s]")
    ax.set_title(title or f"passivity delay margin ({margin.loss or 'no loss'})", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    if w.size or margin.tau_star is not None:
        ax.legend(loc="best", fontsize=9)
    return ax


def plot_delay_region(region: Any, *, ax: Any = None, title: str = "") -> Any:
    """The passive region in (gain, delay): certified passive, not passive, undecided cells.

    ``region`` is a [`DelayRegion`][seapass.delay.gain.DelayRegion].
    """
    ax = axes_grid(ax, 1, 1, figsize=(6.0, 4.2))[0, 0]
    gains, taus = np.asarray(region.gains), np.asarray(region.taus)
    codes = np.asarray(region.codes, dtype=float)  # 1 passive, 0 not passive, 0.5 undecided
    from matplotlib.colors import ListedColormap

    cmap = ListedColormap(["#f4a6a6", "#cccccc", "#9fd79f"])
    ax.pcolormesh(gains, taus, codes.T, cmap=cmap, vmin=0, vmax=1, shading="nearest")
    if region.margins is not None:
        m = np.array([np.nan if v is None else v for v in region.margins], dtype=float)
        ax.plot(gains, m, color="k", lw=1.4, label="delay margin τ* (certified, lower end)")
        ax.legend(loc="best", fontsize=9)
    ax.set_xlabel(f"{region.gain}")
    ax.set_ylabel(f"delay {region.delay} [s]")
    if np.all(taus > 0) and math.isfinite(float(taus.max())):
        ax.set_yscale("log")
    ax.set_title(
        title
        or "passive for every delay up to τ (green), not (red), undecided (grey);"
        "\ncertified at each computed gain",
        fontsize=9,
    )
    return ax


_PASS = "#9fd79f"
_UNDECIDED = "0.75"


def plot_gain_intervals(result: Any, *, ax: Any = None, title: str = "") -> Any:
    """The certified passive set of a gain at a fixed delay, as a bar; returns the Axes.

    ``result`` is a [`DelayGainIntervals`][seapass.delay.gainbound.DelayGainIntervals]:
    green intervals are certified passive in full, grey gaps undecided, red ticks the
    gains proven not passive; nothing else is drawn (no grid verdict).
    """
    ax = axes_grid(ax, 1, 1, figsize=(6.0, 1.9))[0, 0]
    for i, (a, b) in enumerate(result.intervals):
        ax.axvspan(a, b, color=_PASS, label="passive (certified)" if i == 0 else None)
    for i, (a, b) in enumerate(result.undecided):
        ax.axvspan(a, b, color=_UNDECIDED, label="undecided" if i == 0 else None)
    bad = [k for k in result.not_passive if result.lo <= k <= result.hi]
    if bad:
        ax.plot(bad, [0.5] * len(bad), "|", color=_FAIL, ms=14, label="not passive (proven)")
    ax.set_xlim(result.lo, result.hi)
    ax.set_ylim(0, 1)
    ax.set_yticks([])
    ax.set_xlabel(result.gain)
    ax.set_title(title or f"{result.gain} at {result.delay} = {result.tau:g} s", fontsize=10)
    ax.legend(loc="upper right", ncol=3, fontsize=8)
    return ax


def plot_delay_map(pmap: Any, *, ax: Any = None, title: str = "") -> Any:
    """Certified passive sets of ``param_y`` per column of ``param_x`` at a fixed delay.

    ``pmap`` is a [`DelayPassiveMap`][seapass.delay.gainmap.DelayPassiveMap]; each column
    is a vertical bar (green certified passive, grey undecided), nothing between columns.
    """
    ax = axes_grid(ax, 1, 1, figsize=(5.5, 4.2))[0, 0]
    x = np.asarray(pmap.x, dtype=float)
    width = float(np.min(np.diff(x))) * 0.8 if x.size > 1 else 1.0
    for i, (xv, col) in enumerate(zip(x, pmap.columns, strict=True)):
        for j, (a, b) in enumerate(col.intervals):
            ax.bar(xv, b - a, bottom=a, width=width, color=_PASS, lw=0,
                   label="passive (certified)" if i == j == 0 else None)  # fmt: skip
        for a, b in col.undecided:
            ax.bar(xv, b - a, bottom=a, width=width, color=_UNDECIDED, lw=0)
    ax.set_ylim(*pmap.y)
    ax.set_xlabel(pmap.param_x)
    ax.set_ylabel(pmap.param_y)
    ax.set_title(title or f"passive region at {pmap.delay} = {pmap.tau:g} s", fontsize=10)
    if any(c.intervals for c in pmap.columns):
        ax.legend(loc="best", fontsize=8)
    return ax
