"""Figures for sampled-data passivity; they only consume result objects.

References
----------
.. [1] J. E. Colgate, G. G. Schenkel, "Passivity of a class of sampled-data
   systems: application to haptic interfaces", J. Robotic Systems, 1997.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..sampled.bound import SampledBoundResult
from ..sampled.region import ZWidthMap
from .region import axis_label
from .style import axes_grid

__all__ = [
    "plot_bound",
    "plot_bound_table",
    "plot_power_curve",
    "plot_robust_sampled_bound",
    "plot_sampled_limits",
    "plot_sampled_response",
    "plot_zwidth",
]


def plot_bound(result: SampledBoundResult, ax: Any = None, *, unit: str | None = None) -> Any:
    """Certified passive intervals of ``result.param``, edge enclosures, the design value.

    ``unit`` labels the axis (None: the parameter's standard unit, if any).  Returns the Axes.
    """
    ax = axes_grid(ax, 1, 1, figsize=(7, 2.6))[0, 0]
    for i, (lo, hi) in enumerate(result.intervals):
        if hi > lo:
            ax.axvspan(
                lo,
                hi,
                color="tab:green",
                alpha=0.3,
                label="passive (certified)" if i == 0 else None,
            )
        else:
            ax.axvline(lo, color="tab:green", lw=2, label="passive (isolated value)")
    for i, e in enumerate(result.edges):
        ax.axvline(
            0.5 * (e.lo + e.hi), color="k", ls="--", lw=1,
            label=f"edge ({e.kind.replace('_', ' ')}) ±{0.5 * (e.hi - e.lo):.1e}" if i == 0 else None,
        )  # fmt: skip
    for i, (lo, hi) in enumerate(result.undecided):
        ax.axvspan(lo, hi, color="tab:orange", alpha=0.6, label="undecided" if i == 0 else None)
    if result.design_value is not None:
        ax.plot([result.design_value], [0.5], "v", color="tab:blue", label=f"design {result.param}")
    ax.set_yticks([])
    ax.set_ylim(0, 1)
    ax.set_xlim(result.lo, result.hi)
    ax.set_xlabel(axis_label(result.param, unit))
    ax.set_title(f"Sampled-data passivity at T = {result.period * 1e3:g} ms (delay {result.delay})")
    ax.legend(loc="upper right", fontsize=8)
    return ax


def plot_zwidth(
    zmap: ZWidthMap, ax: Any = None, *, units: tuple[str | None, str | None] = (None, None)
) -> Any:
    """Z-width map: the certified passive set of ``p1`` on every ``p2`` row, one colour per
    loop setup (drawn as bars one row spacing wide: only the rows are certified).

    ``units`` are those of ``p1`` and ``p2`` (None: the standard unit, if any).

    Returns the Axes.
    """
    ax = axes_grid(ax, 1, 1, figsize=(7.5, 4.6))[0, 0]
    xs = np.asarray(zmap.p2_values)
    edges = np.concatenate([[xs[0]], 0.5 * (xs[1:] + xs[:-1]), [xs[-1]]])
    colors = ("tab:green", "tab:orange", "tab:red", "tab:purple", "tab:brown")
    for k, setup in enumerate(zmap.setups):
        color = colors[k % len(colors)]
        for i, row in enumerate(zmap.rows[setup.label]):
            for lo, hi in row.intervals:
                ax.fill_between(
                    [edges[i], edges[i + 1]], lo, hi, color=color, alpha=0.22, lw=0,
                )  # fmt: skip
        ax.plot(xs, zmap.upper_boundary(setup.label), "o-", ms=3, color=color, label=setup.label)
    ax.set_xlabel(axis_label(zmap.p2, units[1]))
    ax.set_ylabel("passive " + axis_label(zmap.p1, units[0]))
    ax.set_ylim(zmap.p1_range)
    ax.set_title(f"Z-width at T = {zmap.period * 1e3:g} ms: passive {zmap.p1} vs {zmap.p2}")
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(True, alpha=0.3)
    return ax


def plot_power_curve(
    omega: np.ndarray, values: np.ndarray, *, period: float, ax: Any = None, label: str = "N(ω)"
) -> Any:
    """The normalised power function ``N(ω)`` up to Nyquist (illustration only); returns the Axes."""
    ax = axes_grid(ax, 1, 1, figsize=(7, 3.2))[0, 0]
    ax.semilogx(omega / (2 * np.pi), values, label=label)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.axvline(1 / (2 * period), color="gray", ls=":", label="Nyquist")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("N(ω) (dimensionless, ≥ 0 ⇔ passive)")
    ax.legend(fontsize=9)
    return ax


def plot_bound_table(
    rows: Sequence[Mapping[str, Any]], *, title: str = "", axes: Any = None
) -> Any:
    """Largest passive ``kd`` vs ``bd`` (Ours, one line per ``b1``) and vs ``b1`` (LP).

    ``rows`` are dicts with keys ``design`` ("LP"/"Ours"), ``b1``, ``bd``,
    ``max_passive``.  Returns the two Axes.
    """
    a1, a2 = axes_grid(axes, 1, 2, figsize=(11, 4))[0]
    ours = [r for r in rows if r["design"] == "Ours"]
    for b1 in sorted({r["b1"] for r in ours}):
        pts = sorted((r["bd"], r["max_passive"]) for r in ours if r["b1"] == b1)
        xs = [p[0] for p in pts]
        ys = [np.nan if p[1] is None else p[1] for p in pts]
        a1.plot(xs, ys, "o-", label=f"b1 = {b1:g} N·s/m")
    a1.set_xlabel("controller damping bd (N·s/m)")
    a1.set_ylabel("largest passive kd (N/m)")
    a1.set_yscale("log")
    a1.set_title("Ours: C_A = kd + bd s")
    a1.legend(fontsize=9)
    lp = sorted((r["b1"], r["max_passive"]) for r in rows if r["design"] == "LP")
    a2.plot(
        [p[0] for p in lp],
        [np.nan if p[1] is None else p[1] for p in lp],
        "s-",
        color="tab:red",
        label="LP: C_L = kd",
    )
    a2.set_xlabel("transmission damping b1 (N·s/m)")
    a2.set_ylabel("largest passive kd (N/m)")
    a2.set_title("LP")
    a2.legend(fontsize=9)
    if title:
        a1.figure.suptitle(title)
    return np.array([a1, a2])


def plot_sampled_limits(rows: Sequence[tuple[Any, ...]], *, period: float, ax: Any = None) -> Any:
    """Largest passive ``kd``: continuous, sampled ideal, sampled with delay and filter.

    ``rows`` are ``(label, _, cap, continuous, ideal, rig)`` with None for "none"
    and ``inf`` for "every value up to ``cap``".  Returns the Axes.
    """
    labels = ("continuous", f"{1 / period:g} Hz ideal", f"{1 / period:g} Hz + delay + filter")
    ax = axes_grid(ax, 1, 1, figsize=(7.5, 3.8))[0, 0]
    width = 0.26
    for j, lab in enumerate(labels):
        xs, hs = [], []
        for i, r in enumerate(rows):
            v = r[3 + j]
            v = r[2] if v is not None and math.isinf(v) else (0.0 if v is None else v)
            xs.append(i + (j - 1) * width)
            hs.append(max(v, 1.0))
        ax.bar(xs, hs, width, label=lab)
        for x, h, r in zip(xs, hs, rows, strict=True):
            v = r[3 + j]
            text = "all (≥ limit)" if v is not None and math.isinf(v) else f"{h:.0f}"
            ax.text(x, h * 1.1, text, ha="center", va="bottom", fontsize=8)
    ax.set_yscale("log")
    ax.set_xticks(range(len(rows)), [r[0] for r in rows])
    ax.set_ylabel("largest passive kd [N/m]")
    ax.set_ylim(100, 1e6)
    ax.set_title(f"Passive kd, continuous vs sampled (T = {period * 1e3:g} ms)")
    ax.legend(fontsize=9, loc="upper left")
    ax.grid(True, axis="y", alpha=0.3)
    return ax


def plot_sampled_response(result: Any, ax: Any = None) -> Any:
    """``x_A`` and ``x_L`` of a [`SampledResponse`][seapass.sampled.response.SampledResponse]
    at the sampling instants (held between them), with the target.  Returns the Axes."""
    ax = axes_grid(ax, 1, 1, figsize=(7, 3.2))[0, 0]
    ax.step(result.time, result.x_A, where="post", label="x_A")
    ax.step(result.time, result.x_L, where="post", label="x_L")
    ax.axhline(result.target, color="0.6", lw=0.8, ls="--", label="target")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("position [m]")
    ax.legend(loc="best")
    return ax


def plot_robust_sampled_bound(result: Any, ax: Any = None, *, unit: str | None = None) -> Any:
    """A [`RobustSampledIntervals`][seapass.robust.sampled_intervals.RobustSampledIntervals]:
    the certified inner set, the undecided rest of the outer set, the failing values.

    Outside the outer set the value is certified not passive for some plant.  ``unit``
    labels the axis.  Returns the Axes.
    """
    ax = axes_grid(ax, 1, 1, figsize=(7, 2.6))[0, 0]
    ax.axhspan(0, 1, color="tab:red", alpha=0.15, label="not passive (outside the outer set)")
    for i, (lo, hi) in enumerate(result.undecided):
        ax.axvspan(lo, hi, color="tab:orange", alpha=0.5, label="undecided" if i == 0 else None)
    for i, (lo, hi) in enumerate(result.intervals):
        label = "passive for every plant (certified)" if i == 0 else None
        if hi > lo:
            ax.axvspan(lo, hi, color="tab:green", alpha=0.5, label=label)
        else:
            ax.axvline(lo, color="tab:green", lw=2, label=label)
    xs = [w.values[result.param] for w in result.failing if result.param in w.values]
    if xs:
        ax.plot(xs, [0.5] * len(xs), "x", color="k", label="verified failing value")
    ax.set_yticks([])
    ax.set_ylim(0, 1)
    if result.hi > result.lo:
        ax.set_xlim(result.lo, result.hi)
    ax.set_xlabel(axis_label(result.param, unit))
    loop = result.loop
    ax.set_title(f"Robust sampled passivity at T = {loop.period * 1e3:g} ms (delay {loop.delay})")
    ax.legend(loc="upper right", fontsize=8)
    return ax
