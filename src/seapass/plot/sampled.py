"""Figures for sampled-data passivity; they only consume result objects.

References
----------
.. [1] J. E. Colgate, G. G. Schenkel, "Passivity of a class of sampled-data
   systems: application to haptic interfaces", J. Robotic Systems, 1997.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from ..files.atomic import atomic_save
from ..sampled.passivity import SampledBoundResult

__all__ = ["plot_bound_scan", "plot_bound_table", "plot_power_curve", "save_figure"]

plt.rcParams.update({"font.size": 11, "axes.titlesize": 12, "axes.labelsize": 11})


def plot_bound_scan(result: SampledBoundResult, ax: Any = None) -> Any:
    """Passive intervals of ``result.param`` and the scan verdicts."""
    if ax is None:
        _fig, ax = plt.subplots(figsize=(7, 2.6))
    for i, (lo, hi) in enumerate(result.intervals):
        ax.axvspan(lo, hi, color="tab:green", alpha=0.25, label="passive" if i == 0 else None)
    xs = np.array([x for x, _ in result.samples])
    ok = np.array([v for _, v in result.samples], dtype=bool)
    ax.plot(xs[ok], np.zeros(ok.sum()), "o", color="tab:green", label="scan: passive")
    ax.plot(xs[~ok], np.zeros((~ok).sum()), "x", color="tab:red", label="scan: not passive")
    if result.max_passive is not None:
        ax.axvline(
            result.max_passive,
            color="k",
            ls="--",
            lw=1,
            label=f"max passive {result.param} = {result.max_passive:.6g}",
        )
    ax.set_yticks([])
    ax.set_xlim(result.lo, result.hi)
    ax.set_xlabel(f"{result.param} (SI units)")
    ax.set_title(f"Sampled-data passivity at T = {result.period * 1e3:g} ms")
    ax.legend(loc="upper right", fontsize=9)
    return ax


def plot_power_curve(
    omega: np.ndarray, values: np.ndarray, *, period: float, ax: Any = None, label: str = "N(ω)"
) -> Any:
    """The normalised power function ``N(ω)`` up to Nyquist (illustration only)."""
    if ax is None:
        _fig, ax = plt.subplots(figsize=(7, 3.2))
    ax.semilogx(omega / (2 * np.pi), values, label=label)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.axvline(1 / (2 * period), color="gray", ls=":", label="Nyquist")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("N(ω) (dimensionless, ≥ 0 ⇔ passive)")
    ax.legend(fontsize=9)
    return ax


def plot_bound_table(rows: Sequence[Mapping[str, Any]], *, title: str = "") -> Any:
    """Largest passive ``kd`` vs ``bd`` (Ours, one line per ``b1``) and vs ``b1`` (LP).

    ``rows`` are dicts with keys ``design`` ("LP"/"Ours"), ``b1``, ``bd``, ``max_passive``.
    """
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
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
        fig.suptitle(title)
    fig.tight_layout()
    return fig


def save_figure(fig: Any, path: str | os.PathLike[str]) -> None:
    """Save atomically and close."""
    atomic_save(path, fig.savefig)
    plt.close(fig)
