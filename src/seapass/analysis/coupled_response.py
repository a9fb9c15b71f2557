"""Time-domain evidence of coupled (in)stability: the port's response to a force impulse.

The response of the port displacement of an SEA held by an environment is an
exact sum of modes of the coupled characteristic polynomial
([`seapass.analysis.coupled`][seapass.analysis.coupled]), sampled on a horizon that shows the slowest
mode's growth or decay.
"""

from __future__ import annotations

import itertools
import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import mpmath
import numpy as np
from flint import fmpq_poly

from .coupled import (
    Environment,
    Stability,
    SystemLike,
    characteristic_from_polys,
    classify_polynomial,
    polynomial_roots,
    system_polynomials,
    to_float,
)

__all__ = ["CoupledSimulation", "simulate_coupled"]


SAMPLES_PER_PERIOD = 24
"""Samples per oscillation period and the cap on samples in a simulation."""


MAX_SAMPLES = 20000


@dataclass(frozen=True, kw_only=True)
class CoupledSimulation:
    """Impulse response of the coupled system (computed, not plotted).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Time [s].
    y : ndarray, shape (n,)
        The output named by ``output``, per unit force impulse.
    output : str
        ``"port displacement"`` [m/(N·s)] or, when that transfer hides the
        unstable mode (a cancelled mode, or an improper transfer),
        ``"characteristic coordinate"`` (the solution ``w`` of ``χ(d/dt) w = δ``).
    growth_rate : float
        Largest real part of the poles of the simulated transfer [1/s].
    growth_factor : float
        ``max|y|`` over the last quarter divided by ``max|y|`` over the first quarter.
    """

    t: np.ndarray
    y: np.ndarray
    output: str
    growth_rate: float
    growth_factor: float

    def to_dict(self, *, samples: bool = False) -> dict[str, Any]:
        out: dict[str, Any] = {
            "output": self.output,
            "growth_rate": self.growth_rate,
            "growth_factor": self.growth_factor,
            "t_end": float(self.t[-1]) if self.t.size else 0.0,
            "samples": int(self.t.size),
        }
        if samples:
            out["t"] = self.t.tolist()
            out["y"] = self.y.tolist()
        return out


def _partial_fractions(num: fmpq_poly, den: fmpq_poly) -> tuple[np.ndarray, np.ndarray | None]:
    """Poles of strictly proper ``num/den`` and their residues (50 digits).

    Residues are ``None`` when poles are (nearly) repeated.
    """
    roots = polynomial_roots(den)
    if not roots.size or not np.all(np.isfinite(roots)):
        return roots, None
    # a residue is as accurate as each pole relative to its distance from the others:
    # poles far apart in magnitude (1 and 1e14) are well separated, not "nearly repeated"
    pairs = itertools.combinations(roots, 2)
    sep = min(
        (abs(a - b) / max(abs(a), abs(b), 1e-300) for a, b in pairs),
        default=math.inf,
    )
    if sep <= 1e-6:
        return roots, None
    with mpmath.workdps(50):
        nc = [mpmath.mpf(int(c.p)) / int(c.q) for c in reversed(num.coeffs())]
        dd = [mpmath.mpf(int(c.p)) / int(c.q) for c in reversed(den.derivative().coeffs())]
        res = [
            complex(mpmath.polyval(nc, mpmath.mpc(p.real, p.imag)) / mpmath.polyval(dd, p))
            for p in (mpmath.mpc(r.real, r.imag) for r in roots)
        ]
    return roots, np.array(res, dtype=complex)


def _impulse(
    num: fmpq_poly, den: fmpq_poly, roots: np.ndarray, res: np.ndarray | None, t: np.ndarray
) -> np.ndarray:
    """Impulse response: a sum of modes, or `scipy.signal.impulse` for repeated poles."""
    if not np.all(np.isfinite(roots)):  # poles beyond the double range: nothing to show
        return np.full(t.shape, np.nan)
    if res is not None:
        y = np.zeros_like(t, dtype=complex)
        for r, p in zip(res, roots, strict=True):
            y += r * np.exp(p * t)
        return np.asarray(y.real, dtype=float)
    from scipy import signal

    tf = (
        [to_float(c) for c in reversed(num.coeffs())],
        [to_float(c) for c in reversed(den.coeffs())],
    )
    with warnings.catch_warnings():
        # badly scaled coefficients: the response is evidence only, the verdict is exact
        warnings.simplefilter("ignore")
        _, y = signal.impulse(tf, T=t)
    return np.asarray(y, dtype=float)


def simulate_coupled(
    system: SystemLike,
    environment: Environment,
    *,
    values: Mapping[str, float] | None = None,
    t_end: float | None = None,
    times: np.ndarray | None = None,
) -> CoupledSimulation:
    """Response of the port displacement to a unit force impulse, SEA held by ``environment``.

    ``X/F = D D_e / (s χ · common)`` (see [`seapass.analysis.coupled`][seapass.analysis.coupled]).  When that
    transfer is improper or cancels the fastest-growing mode of ``χ``, the
    characteristic coordinate ``w`` (``χ(d/dt) w = δ``) is simulated instead.
    The response is the sum of modes (poles and residues in multiprecision),
    so no integrator error enters; with repeated poles scipy's impulse
    response is used.

    Parameters
    ----------
    system, environment, values
        As in [`seapass.analysis.coupled.coupled_stability`][seapass.analysis.coupled.coupled_stability].
    t_end : float, optional
        Horizon [s].  By default long enough for the fastest-growing mode to
        exceed every other mode's initial amplitude and then grow by ``e^6``
        (``σ t <= 700``), or 50 periods of the slowest mode when nothing grows.
    times : ndarray, shape (n,), optional
        Explicit sample times [s] (non-negative, increasing); overrides ``t_end``.

    Returns
    -------
    CoupledSimulation
    """
    zn, zd = system_polynomials(system, values)
    ne, de = environment.polynomials()
    chi, common = characteristic_from_polys(zn, zd, ne, de)  # one (zn, zd): consistent signs
    num = (zd * de) // common
    den = chi * fmpq_poly([0, 1])
    g = num.gcd(den)
    num, den = num // g, den // g
    output = "port displacement"
    status_full = classify_polynomial(chi)[0]
    if num.degree() >= den.degree() or (
        status_full == Stability.UNSTABLE and classify_polynomial(den)[0] != Stability.UNSTABLE
    ):
        num, den, output = fmpq_poly([1]), chi, "characteristic coordinate"
    roots, res = _partial_fractions(num, den)
    sigma = float(np.max(roots.real)) if roots.size else -math.inf
    if times is not None:
        t = np.asarray(times, dtype=float)
        if t.ndim != 1 or t.size < 2 or not np.all(np.isfinite(t)):
            raise ValueError(
                f"times must be a finite 1-D array of >= 2 samples, got shape {t.shape}"
            )
        if t[0] < 0 or np.any(np.diff(t) <= 0):
            raise ValueError("times must be non-negative and strictly increasing")
    else:
        if t_end is None:
            t_end = _horizon(roots, res)
        if not (math.isfinite(t_end) and t_end > 0):
            raise ValueError(f"t_end must be a positive finite time, got {t_end!r}")
        wmax = float(np.max(np.abs(roots.imag))) if roots.size else 0.0
        n = int(min(MAX_SAMPLES, max(2000, SAMPLES_PER_PERIOD * t_end * wmax / (2 * math.pi))))
        t = np.linspace(0.0, t_end, n)
    n = t.size
    with np.errstate(over="ignore", invalid="ignore"):
        y = _impulse(num, den, roots, res, t)
    q = max(n // 4, 1)
    first = float(np.max(np.abs(y[:q]))) or math.nan
    growth = float(np.max(np.abs(y[-q:]))) / first
    return CoupledSimulation(t=t, y=y, output=output, growth_rate=sigma, growth_factor=growth)


def _horizon(roots: np.ndarray, res: np.ndarray | None) -> float:
    if not roots.size:
        return 1.0
    sigma = float(np.max(roots.real))
    if sigma > 0:
        lead = 0.0
        if res is not None:
            top = roots.real >= sigma * (1 - 1e-9)
            r_top = float(np.sum(np.abs(res[top])))
            r_rest = float(np.sum(np.abs(res[~top])))
            if r_top > 0 and r_rest > 0:
                lead = max(0.0, math.log(r_rest / r_top))
        return min(lead + 6.0, 700.0) / sigma
    nonzero = np.abs(roots[np.abs(roots) > 0])
    slow = float(np.min(nonzero)) if nonzero.size else 1.0
    return 50 * 2 * math.pi / slow
