"""Passivity in pictures: Bode of ``F_L/X_L`` with phase, ``Re Z(jω)`` with failing bands, Nyquist.

Plotting only consumes
[`FrequencyResponse`][seapass.analysis.freqresp.FrequencyResponse] and
[`ImpedanceResponse`][seapass.analysis.portresponse.ImpedanceResponse].  The
shaded bands where ``Re Z(jω) < 0`` are the exact ones held by the response
(the real roots of the real-part polynomial, isolated exactly), never read off
the plotted grid, so a dip narrower than the grid is still shaded.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..analysis.freqresp import FrequencyResponse
from ..analysis.portresponse import ImpedanceResponse
from .style import axes_grid

__all__ = ["PLOT_KINDS", "plot_bode", "plot_impedance", "plot_nyquist", "plot_real_part"]

PLOT_KINDS = ("bode", "real", "nyquist")
"""The passivity plots: Bode of the stiffness, real part of Z, Nyquist of Z."""

_FAIL = "tab:red"


def plot_bode(
    responses: FrequencyResponse | Sequence[FrequencyResponse],
    *,
    title: str = "",
    reference: float | None = None,
    bands: Sequence[tuple[float, float]] = (),
    legend: bool | None = None,
    axes: Any = None,
) -> Any:
    """Bode plot of the rendered stiffness ``F_L/X_L(jω)``: magnitude (log-log) above phase.

    The one Bode plot of seapass: ``seapass plot bode``, the reports (one per
    design, a grid per paper table) and
    [`FrequencyResponse.plot`][seapass.analysis.freqresp.FrequencyResponse.plot] all draw it.

    Parameters
    ----------
    responses : FrequencyResponse or sequence of them
        One line each, labelled with its ``label``.
    title : str, optional
        Title of the magnitude Axes.
    reference : float, optional
        A stiffness drawn as a dashed grey line on the magnitude (e.g. the spring ``k1``).
    bands : sequence of (float, float), optional
        Exact bands where ``Re Z(jω) < 0`` (from an
        [`ImpedanceResponse`][seapass.analysis.portresponse.ImpedanceResponse]),
        shaded on both panels: there the phase leaves ``[0°, 180°]``.
    legend : bool, optional
        Draw the legend; by default when there is something to name (a label,
        the reference or the bands).  A grid of small panels passes False and
        says it in the figure's title.
    axes : two matplotlib Axes, optional
        Magnitude and phase; a new figure if None.

    Returns
    -------
    numpy.ndarray of matplotlib.axes.Axes, shape (2,)
        Magnitude and phase Axes.
    """
    from matplotlib.ticker import FuncFormatter, LogLocator, MultipleLocator, NullLocator

    items = [responses] if isinstance(responses, FrequencyResponse) else list(responses)
    ax_m, ax_p = axes_grid(
        axes, 2, 1, figsize=(6.0, 5.0), sharex=True, gridspec_kw={"height_ratios": [2, 1]}
    )[:, 0]
    for r in items:
        (line,) = ax_m.loglog(r.omega, r.magnitude, lw=1.8, label=r.label or None)
        ax_p.semilogx(r.omega, r.phase, lw=1.5, color=line.get_color())
    if reference is not None:
        ax_m.axhline(reference, color="0.4", ls="--", lw=1, label=f"spring k1 = {reference:g} N/m")
    ax_m.set_ylabel("|F_L/X_L| [N/m]")
    ax_p.set_ylabel("phase [°]")
    ax_p.set_xlabel("frequency ω [rad/s]")
    # Re Z >= 0 means arg Z in [-90°, 90°], so a passive port's stiffness s·Z keeps [0°, 180°]
    for edge in (0.0, 180.0):
        ax_p.axhline(edge, color="0.5", ls=":", lw=1)
    if items and bands:
        lo = min(float(r.omega[0]) for r in items)
        hi = max(float(r.omega[-1]) for r in items)
        for ax in (ax_m, ax_p):
            for i, (a, b) in enumerate(bands):
                if b > lo and a < hi:
                    label = "Re Z < 0 (exact)" if i == 0 and ax is ax_m else None
                    ax.axvspan(max(a, lo), min(b, hi), color=_FAIL, alpha=0.15, lw=0, label=label)
            ax.set_xlim(lo, hi)
    for ax in (ax_m, ax_p):
        ax.grid(True, which="major", alpha=0.3)
        # labelled 1-2-5 ticks; unlabelled minor ticks cost most of the drawing time
        ax.xaxis.set_minor_locator(NullLocator())
    phases = np.concatenate([np.asarray(r.phase, dtype=float) for r in items] or [np.zeros(1)])
    phases = phases[np.isfinite(phases)]
    spread = float(phases.max() - phases.min()) if phases.size else 0.0
    ax_p.yaxis.set_major_locator(MultipleLocator(45.0 if spread <= 180.0 else 90.0))
    mags = np.concatenate([np.asarray(r.magnitude, dtype=float) for r in items] or [np.ones(1)])
    mags = mags[np.isfinite(mags) & (mags > 0)]
    decades = float(np.log10(mags.max() / mags.min())) if mags.size else 1.0
    subs = (1.0, 2.0, 5.0) if decades <= 2.5 else (1.0, 3.0) if decades <= 4 else (1.0,)
    ax_m.yaxis.set_major_locator(LogLocator(base=10, subs=subs, numticks=12))
    ax_m.yaxis.set_major_formatter(FuncFormatter(_tick_label))
    ax_m.yaxis.set_minor_locator(NullLocator())
    if legend is None:
        legend = any(r.label for r in items) or reference is not None or bool(bands)
    if legend:
        ax_m.legend(loc="best", fontsize=9)
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


def plot_real_part(
    response: ImpedanceResponse, *, title: str = "", linthresh: float | None = None, ax: Any = None
) -> Any:
    """``Re Z(jω)`` against ``ω``, with the bands where it is negative shaded.

    Parameters
    ----------
    response : ImpedanceResponse
        The curve (sampled) and the exact failing bands.
    title : str, optional
        Axes title (default: the verdict on the real part).
    linthresh : float, optional
        Linear range of the symmetric-log y axis (default: from the data, so a
        shallow dip below zero stays visible).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = axes_grid(ax, 1, 1, figsize=(6.0, 3.8))[0, 0]
    w, re = response.omega, response.real
    ax.semilogx(w, re, lw=1.8, color="tab:blue", label=_label(response, "Re Z(jω)"))
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_yscale("symlog", linthresh=linthresh or _linthresh(re))
    lo, hi = float(w[0]), float(w[-1])
    for i, (a, b) in enumerate(response.negative_bands):
        ax.axvspan(
            max(a, lo),
            min(b, hi),
            color=_FAIL,
            alpha=0.18,
            lw=0,
            label="Re Z < 0 (exact)" if i == 0 else None,
        )
    ax.set_xlim(lo, hi)
    ax.set_xlabel("frequency ω [rad/s]")
    ax.set_ylabel("Re Z(jω) [N·s/m] (symlog)")
    ax.set_title(title or _real_title(response), fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="best", fontsize=9)
    return ax


def _linthresh(re: np.ndarray) -> float:
    finite = np.abs(re[np.isfinite(re)])
    top = float(finite.max()) if finite.size else 1.0
    if top == 0:
        return 1.0
    lin = 1e-3 * top
    neg = re[np.isfinite(re) & (re < 0)]
    if neg.size:
        lin = min(lin, 0.5 * float(np.abs(neg).max()))
    return 10.0 ** math.floor(math.log10(lin)) if lin > 0 else 1.0


def _real_title(response: ImpedanceResponse) -> str:
    if not response.negative_bands:
        return "Re Z(jω) ≥ 0 at every frequency (exact)"
    bands = ", ".join(f"({a:.4g}, {b:.4g})" for a, b in response.negative_bands)
    return f"Re Z(jω) < 0 for ω in {bands} rad/s (exact)"


def _label(response: ImpedanceResponse, default: str) -> str:
    return f"{response.label}: {default}" if response.label else default


def plot_nyquist(response: ImpedanceResponse, *, title: str = "", ax: Any = None) -> Any:
    """Nyquist plot of ``Z(jω)``: a passive port stays in the closed right half-plane.

    The curve for ``ω > 0`` is solid, its mirror image (``ω < 0``) dashed; the
    part inside the exact failing bands is drawn in red.  Points far beyond the
    bulk of the curve (near a pole on the axis) are left outside the view.

    Parameters
    ----------
    response : ImpedanceResponse
    title : str, optional
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = axes_grid(ax, 1, 1, figsize=(5.2, 5.0))[0, 0]
    w, z = response.omega, response.value
    ok = np.isfinite(z)
    ax.plot(z.real, z.imag, lw=1.6, color="tab:blue", label=_label(response, "Z(jω), ω > 0"))
    ax.plot(z.real, -z.imag, lw=0.9, ls="--", color="tab:blue", alpha=0.6, label="ω < 0")
    inside = np.zeros(w.size, dtype=bool)
    for a, b in response.negative_bands:
        inside |= (w >= a) & (w <= b)
    if inside.any():
        zz = np.where(inside, z, np.nan)
        ax.plot(zz.real, zz.imag, lw=2.4, color=_FAIL, label="Re Z < 0 (exact bands)")
    _arrow(ax, z, ok)
    radius = _view_radius(z[ok])
    if radius > 0:
        pts = z[ok][np.abs(z[ok]) <= radius]
        xs = np.concatenate([pts.real, [0.0]])
        ys = np.concatenate([pts.imag, -pts.imag, [0.0]])
        pad_x = 0.08 * (np.ptp(xs) or radius)
        pad_y = 0.08 * (np.ptp(ys) or radius)
        ax.set_xlim(xs.min() - pad_x, xs.max() + pad_x)
        ax.set_ylim(ys.min() - pad_y, ys.max() + pad_y)
    x0, _x1 = ax.get_xlim()
    if x0 < 0:
        ax.axvspan(x0, 0, color=_FAIL, alpha=0.06, lw=0)
    ax.axvline(0.0, color="0.3", lw=0.8)
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_xlabel("Re Z [N·s/m]")
    ax.set_ylabel("Im Z [N·s/m]")
    verdict = "inside" if not response.negative_bands else "NOT inside"
    ax.set_title(title or f"Nyquist plot of Z: {verdict} the right half-plane", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=9)
    return ax


def _view_radius(z: np.ndarray) -> float:
    """Radius that shows the bulk of the curve: 20× the median magnitude, at most the maximum."""
    if z.size == 0:
        return 0.0
    mag = np.abs(z)
    return float(min(mag.max(), 20.0 * np.median(mag)))


def _arrow(ax: Any, z: np.ndarray, ok: np.ndarray) -> None:
    """An arrow in the direction of increasing ω at the middle of the finite curve."""
    idx = np.flatnonzero(ok)
    if idx.size < 3:
        return
    i = idx[idx.size // 2]
    j = min(i + 1, z.size - 1)
    if not np.isfinite(z[j]) or z[j] == z[i]:
        return
    ax.annotate(
        "",
        xy=(z[j].real, z[j].imag),
        xytext=(z[i].real, z[i].imag),
        arrowprops={"arrowstyle": "->", "color": "tab:blue", "lw": 1.6},
    )


def plot_impedance(
    response: ImpedanceResponse, *, kind: str = "real", ax: Any = None, **kwargs: Any
) -> Any:
    """`plot_real_part` (``kind="real"``) or `plot_nyquist` (``kind="nyquist"``)."""
    if kind == "real":
        return plot_real_part(response, ax=ax, **kwargs)
    if kind == "nyquist":
        return plot_nyquist(response, ax=ax, **kwargs)
    raise ValueError(f"kind must be 'real' or 'nyquist', got {kind!r}")
