"""Candidate destabilizing environments for [`witness`][seapass.analysis.witness], and their scores.

Construction (Colgate and Hogan [1]_).  At a frequency ``ω0`` where
``Z(jω0) = R + jX`` has ``R < 0``, an environment with ``b_e < −R`` and
reactance ``m_e ω0 − k_e/ω0 = −X`` makes ``Z + Z_e`` real and negative at
``jω0``.  Near the root ``s*`` of ``Z + Z_e`` close to ``jω0``,
``s* − jω0 ≈ −(Z + Z_e)(jω0) / (Z + Z_e)'(jω0)``; adding a resonant tank
(equal extra reactances ``T`` in ``m_e ω0`` and ``k_e/ω0``) makes
``Z_e' = m_e + k_e/ω0²`` dominate, so ``Re s* ≈ (−R − b_e)/(m_e + k_e/ω0²) > 0``.

Within bounds (`bounded_candidates`) the frequencies are those where an
environment of the box can put a coupled pole on the axis with ``R < −b_lo``
([`crossing_cells`][seapass.analysis.environment_box.crossing_cells]), the
tank is as large as the box allows, and a grid of the box competes.  Without
bounds (`unbounded_candidates`) tanks of many sizes and a grid scaled to the
impedance are tried.  Every candidate is scored exactly (`score`) and the best
is improved by a pattern search (`refine`) that stays in the box.

References
----------
.. [1] J. E. Colgate and N. Hogan, "Robust control of dynamically interacting
   systems", Int. J. Control 48(1), 1988.
"""

from __future__ import annotations

import itertools
import math
from enum import StrEnum

import numpy as np
from flint import fmpq, fmpq_poly

from ..exact import poly as ep
from ..exact.axis import at_j_omega, negative_point, real_part_polynomial
from ..exact.halfline import HalfLinePoint
from .coupled import (
    Environment,
    characteristic_from_polys,
    classify_polynomial,
    polynomial_roots,
    to_float,
)
from .environment_box import EnvironmentBounds, crossing_cells

__all__ = [
    "REFINE_DECADES",
    "REFINE_STEPS",
    "TANK_FACTORS",
    "Candidate",
    "Growth",
    "bounded_candidates",
    "refine",
    "score",
    "unbounded_candidates",
]

TANK_FACTORS = (0.0, *(10.0 ** (k / 2) for k in range(-4, 13)))
"""Tank sizes tried without bounds, relative to ``|Z'(jω0)| ω0`` (the SEA's own reactance slope)."""
REFINE_STEPS = 60
"""Steps of the local refinement that maximizes the growth rate of the best candidate, and how far
(in decades) it may move each parameter: the witness should stay a plausible object, not the
degenerate limit a pure growth maximization runs to.
"""
REFINE_DECADES = 2.0

Candidate = tuple[Environment, float | None]
"""An environment and the frequency ``ω0`` it was tuned at (None: from a grid)."""


def z_at(num: fmpq_poly, den: fmpq_poly, w: fmpq) -> tuple[fmpq, fmpq]:
    """Exact ``(Re, Im)`` of ``Z(jw)``; ``ZeroDivisionError`` at a pole."""
    nr, ni = (p(w) for p in at_j_omega(num))
    dr, di = (p(w) for p in at_j_omega(den))
    mag = dr * dr + di * di
    if mag == 0:
        raise ZeroDivisionError("w is a pole of Z")
    return (nr * dr + ni * di) / mag, (ni * dr - nr * di) / mag


def _eval_jw(p: fmpq_poly, w: fmpq) -> tuple[fmpq, fmpq]:
    re, im = at_j_omega(p)
    return re(w), im(w)


def _dz_abs(num: fmpq_poly, den: fmpq_poly, w: fmpq) -> float:
    """``|Z'(jw)|``, exact until the final conversion (no overflow for extreme values)."""
    nr, ni = _eval_jw(num, w)
    dr, di = _eval_jw(den, w)
    dnr, dni = _eval_jw(num.derivative(), w)
    ddr, ddi = _eval_jw(den.derivative(), w)
    # (N' D - N D') / D^2, numerator and |D|^2 as exact complex pairs
    ar, ai = (
        dnr * dr - dni * di - (nr * ddr - ni * ddi),
        dnr * di + dni * dr - (nr * ddi + ni * ddr),
    )
    mag2 = dr * dr + di * di
    if mag2 == 0:
        return math.inf
    num_abs = math.hypot(to_float(ar), to_float(ai))
    return num_abs / to_float(mag2) if to_float(mag2) > 0 else math.inf


def _env(m: float, b: float, k: float) -> Environment | None:
    """An environment, or None when a value is not a finite non-negative float."""
    if all(math.isfinite(v) and v >= 0 for v in (m, b, k)):
        return Environment(mass=m, damping=b, stiffness=k)
    return None


# ---------------------------------------------------------------- without bounds


def _negative_frequencies(num: fmpq_poly, den: fmpq_poly) -> list[float]:
    """Frequencies with ``Re Z(jω) < 0`` (exact check), the most negative first."""
    px = real_part_polynomial(num, den)
    if px.is_zero():
        return []
    odd = ep.positive_roots_odd_multiplicity(px)
    if px.leading_coefficient() > 0 and ep.count_real_roots(odd, 0) == 0:
        return []
    try:
        out = [negative_point(px)]
        # a few more, log-spaced across the band where P < 0, for robustness
        roots = [ep.root_value(px, iv) for iv in ep.isolate_real_roots(px, 0)]
    except OverflowError:  # frequencies beyond the double range: leave it to the grid
        return []
    edges = [0.0, *roots, (roots[-1] * 100 + 1) if roots else 1e6]
    for lo, hi in itertools.pairwise(edges):
        for x in np.geomspace(max(lo, hi * 1e-6, 1e-300), hi, 7)[1:-1]:
            if px(ep.rational(float(x))) < 0:
                out.append(math.sqrt(float(x)))
    return out


def _tuned(num: fmpq_poly, den: fmpq_poly, w0: float) -> list[Environment]:
    """The construction at ``w0``: ``b_e`` below ``−R``, reactance ``−X``, tanks of several sizes."""
    try:
        r, x = z_at(num, den, ep.rational(w0))
    except ZeroDivisionError:
        return []
    if r >= 0:
        return []
    slope = _dz_abs(num, den, ep.rational(w0)) * w0
    if not (math.isfinite(slope) and slope > 0):
        slope = abs(to_float(r))
    out = []
    for be in (fmpq(0), -r / 2):
        for f in TANK_FACTORS:
            tank = f * slope
            env = _env(
                (max(-to_float(x), 0.0) + tank) / w0,
                to_float(be),
                (max(to_float(x), 0.0) + tank) * w0,
            )
            if env is not None:
                out.append(env)
    return out


def _scaled_grid(num: fmpq_poly, den: fmpq_poly) -> list[Environment]:
    """Springs, dampers, masses and combinations, scaled to the impedance."""
    roots = polynomial_roots(den)
    mags = [abs(p) for p in roots if 0 < abs(p) < math.inf]
    with np.errstate(all="ignore"):
        wc = float(np.exp(np.mean(np.log(mags)))) if mags else 1.0
    if not (math.isfinite(wc) and wc > 0):
        wc = 1.0
    try:
        zc = math.hypot(*(to_float(v) for v in z_at(num, den, ep.rational(wc))))
    except ZeroDivisionError:
        zc = 1.0
    if not (math.isfinite(zc) and zc > 0 and math.isfinite(wc) and wc > 0):
        zc, wc = 1.0, 1.0
    scales = [10.0**k for k in range(-4, 5)]
    cands = [_env(0.0, zc * f, 0.0) for f in scales]
    cands += [_env(0.0, 0.0, zc * wc * f) for f in scales]
    cands += [_env(zc / wc * f, 0.0, 0.0) for f in scales]
    for fm, fk in itertools.product(scales[::2], scales[::2]):
        cands.append(_env(zc / wc * fm, 0.0, zc * wc * fk))
        cands.append(_env(zc / wc * fm, zc * 1e-2, zc * wc * fk))
    return [e for e in cands if e is not None]


def unbounded_candidates(num: ep.PolyLike, den: ep.PolyLike) -> list[Candidate]:
    """The construction at every negative-real-part frequency, then the scaled grid."""
    num, den = ep.as_poly(num), ep.as_poly(den)
    tuned: list[Candidate] = []
    for wneg in _negative_frequencies(num, den) if not num.is_zero() else []:
        tuned += [(env, wneg) for env in _tuned(num, den, wneg)]
    return tuned + [(env, None) for env in _scaled_grid(num, den)]


# ---------------------------------------------------------------- within bounds


def _axis(lo: float, hi: float, n: int) -> list[float]:
    """``n`` values from ``lo`` to ``hi``, log-spaced (0 kept as its own value)."""
    if hi == lo:
        return [lo]
    start = lo if lo > 0 else hi * 1e-3
    values = [float(v) for v in np.geomspace(start, hi, n - (lo == 0))]
    return [0.0, *values] if lo == 0 else values


def _box_tuned(
    num: fmpq_poly, den: fmpq_poly, w0: float, b: EnvironmentBounds
) -> list[Environment]:
    """The construction at ``w0`` inside the box: the largest tank it allows, and two smaller."""
    try:
        r, x = (to_float(v) for v in z_at(num, den, ep.rational(w0)))
    except ZeroDivisionError:
        return []
    (m_lo, m_hi), (b_lo, _), (k_lo, k_hi) = b.mass, b.damping, b.stiffness
    if not (math.isfinite(r) and math.isfinite(x) and -r > b_lo):
        return []
    # k = m w0² + w0 X, with m and k in their ranges
    m_a = max(m_lo, (k_lo - w0 * x) / w0**2)
    m_b = min(m_hi, (k_hi - w0 * x) / w0**2)
    if not m_a <= m_b:
        return []
    masses = {m_b, m_a, math.sqrt(m_a * m_b) if m_a > 0 else (m_a + m_b) / 2}
    out = []
    for be in {b_lo, (b_lo - r) / 2}:
        for m in masses:
            out.append(b.clip(m, be, m * w0**2 + w0 * x))
    return out


def bounded_candidates(
    num: ep.PolyLike,
    den: ep.PolyLike,
    bounds: EnvironmentBounds,
    cells: list[tuple[HalfLinePoint, bool]] | None = None,
) -> list[Candidate]:
    """The construction at the frequencies where the box reaches the axis (``cells``, from
    [`crossing_cells`][seapass.analysis.environment_box.crossing_cells] if not given),
    then a grid of the box."""
    num, den = ep.as_poly(num), ep.as_poly(den)
    tuned: list[Candidate] = []
    if not num.is_zero():
        if cells is None:
            cells = crossing_cells(num, den, bounds)
        for point, strict in cells:
            if strict:
                try:
                    w0 = math.sqrt(float(point))
                except OverflowError:  # beyond the double range
                    continue
                tuned += [(env, w0) for env in _box_tuned(num, den, w0, bounds)]
    grid = [
        Environment(mass=m, damping=d, stiffness=k)
        for m in _axis(*bounds.mass, 5)
        for d in _axis(*bounds.damping, 3)
        for k in _axis(*bounds.stiffness, 5)
    ]
    # a very soft spring: the root that leaves s = 0 when Z(0) + b < 0
    k_hi = bounds.stiffness[1]
    soft = [
        bounds.clip(m, bounds.damping[0], k_hi * f) for m in bounds.mass for f in (1e-6, 1e-4, 1e-2)
    ]
    return tuned + [(env, None) for env in grid + soft]


# ---------------------------------------------------------------- scoring


class Growth(StrEnum):
    """How the coupled response of a candidate environment grows (decided exactly)."""

    RHP = "rhp"
    """Exponentially: a coupled pole in the open right half-plane."""
    REPEATED_AXIS = "unstable"
    """Polynomially: a repeated coupled pole on the imaginary axis."""
    BOUNDED = "bounded"
    """Not at all."""


def score(num: ep.PolyLike, den: ep.PolyLike, env: Environment) -> tuple[Growth, float]:
    """Exact `Growth` of the coupled system and a float growth rate."""
    ne, de = env.polynomials()
    try:
        chi, _ = characteristic_from_polys(num, den, ne, de)
        _, rhp, repeated = classify_polynomial(chi)
    except (ValueError, ArithmeticError):
        return Growth.BOUNDED, -math.inf
    if not rhp:
        return (Growth.REPEATED_AXIS if repeated else Growth.BOUNDED), -math.inf
    roots = polynomial_roots(chi, fast=True)
    with np.errstate(all="ignore"):
        rate = float(np.max(roots.real)) if roots.size else 0.0
    return Growth.RHP, rate if math.isfinite(rate) else 0.0


def refine(
    num: ep.PolyLike,
    den: ep.PolyLike,
    env: Environment,
    rate: float,
    bounds: EnvironmentBounds | None = None,
) -> tuple[Environment, int]:
    """Pattern search on ``log m_e, log b_e, log k_e`` for a faster growth, each step exact.

    Moves at most `REFINE_DECADES` from the start and never leaves ``bounds``.
    """
    x0 = x = np.array([env.mass, env.damping, env.stiffness])
    lo = np.array([v[0] for _n, v in bounds.items()]) if bounds else np.zeros(3)
    hi = np.array([v[1] for _n, v in bounds.items()]) if bounds else np.full(3, np.inf)
    step, count = 0.5, 0
    while step > 0.05 and count < REFINE_STEPS:
        improved = False
        for i, sign in itertools.product(range(3), (1.0, -1.0)):
            if x[i] == 0:
                continue
            y = x.copy()
            y[i] = min(max(x[i] * 10.0 ** (sign * step), lo[i]), hi[i])
            ratio = y[i] / x0[i]
            if y[i] == x[i] or not (np.all(np.isfinite(y)) and y[i] > 0 and 0 < ratio < math.inf):
                continue
            if abs(math.log10(ratio)) > REFINE_DECADES + 1e-9:
                continue
            count += 1
            cand = Environment(mass=float(y[0]), damping=float(y[1]), stiffness=float(y[2]))
            growth, r = score(num, den, cand)
            if growth is Growth.RHP and r > rate * (1 + 1e-6):
                x, rate, env, improved = y, r, cand, True
        if not improved:
            step /= 2
    return env, count
