"""Destabilizing passive environments: the physical meaning of "not passive".

For a design that fails the positive-real test, `find_destabilizing_environment`
looks for a passive mass-spring-damper environment ``Z_e = m_e s + b_e + k_e/s``
(``m_e, b_e, k_e >= 0``: a plausible person or object) that makes the coupled
system unstable, and returns it with the coupled poles and a simulation of the
growing oscillation as evidence.

Construction (Colgate and Hogan [1]_).  At a frequency ``ω0`` where
``Z(jω0) = R + jX`` has ``R < 0``, an environment with ``b_e < −R`` and
reactance ``m_e ω0 − k_e/ω0 = −X`` makes ``Z + Z_e`` real and negative at
``jω0``.  Near the root ``s*`` of ``Z + Z_e`` close to ``jω0``,
``s* − jω0 ≈ −(Z + Z_e)(jω0) / (Z + Z_e)'(jω0)``; adding a resonant tank
(equal extra reactances ``T`` in ``m_e ω0`` and ``k_e/ω0``) makes
``Z_e' = m_e + k_e/ω0²`` dominate, so ``Re s* ≈ (−R − b_e)/(m_e + k_e/ω0²) > 0``.
Tanks of several sizes are tried and every candidate is verified exactly
([`seapass.analysis.coupled.coupled_stability`][seapass.analysis.coupled.coupled_stability]); the one with the fastest growth is
returned.  Failures of the other conditions (a pole in the right half-plane,
a repeated or wrongly signed pole on the axis, a cancelled unstable mode) are
handled by the same tank when ``Re Z(jω)`` dips below zero, and otherwise by
an exactly verified search over springs, dampers, masses and their
combinations, starting with the free port.

References
----------
.. [1] J. E. Colgate and N. Hogan, "Robust control of dynamically interacting
   systems", Int. J. Control 48(1), 1988.
.. [2] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Sec. II.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, TypeAlias

import numpy as np
import sympy as sp

from ..errors import NotPassiveError
from ..exact import poly as ep
from ..exact.axis import at_j_omega, even_to_x, negative_point
from ..model.sea import SEA, Impedance
from .coupled import (
    CoupledResult,
    Environment,
    characteristic_from_polys,
    classify_polynomial,
    coupled_stability,
    polynomial_roots,
    to_float,
)
from .coupled_response import CoupledSimulation, simulate_coupled
from .impedance import exact_rational_function
from .passivity import PassivityResult, Reason, is_passive

__all__ = [
    "WitnessResult",
    "find_destabilizing_environment",
]

SystemLike: TypeAlias = SEA | Impedance | str | sp.Expr | tuple[Sequence[Any], Sequence[Any]]

TANK_FACTORS = (0.0, *(10.0 ** (k / 2) for k in range(-4, 13)))
"""Tank sizes tried, relative to ``|Z'(jω0)| ω0`` (the SEA's own reactance slope)."""
REFINE_STEPS = 60
"""Steps of the local refinement that maximizes the growth rate of the best candidate, and how far
(in decades) it may move each parameter: the witness should stay a plausible object, not the
degenerate limit a pure growth maximization runs to.
"""
REFINE_DECADES = 2.0


@dataclass(frozen=True)
class WitnessResult:
    """Outcome of `find_destabilizing_environment`.

    Attributes
    ----------
    passive : bool
        The design is passive; then no passive environment destabilizes it and
        ``found`` is False.
    reason : str
        The positive-real test's failure code (``""`` when passive).
    found : bool
        A destabilizing passive environment was found and verified exactly.
    environment : Environment or None
        The environment (``mass, damping, stiffness >= 0``).
    method : str
        ``"free port"``, ``"tuned at w0"`` (the construction) or ``"search"``.
    omega : float or None
        The frequency ``ω0`` [rad/s] the environment was tuned at.
    coupled : CoupledResult or None
        Exact verdict and poles of the coupled system.
    simulation : CoupledSimulation or None
        The growing response.
    candidates : int
        Number of environments verified.
    """

    passive: bool
    reason: str
    found: bool
    environment: Environment | None = None
    method: str = ""
    omega: float | None = None
    coupled: CoupledResult | None = None
    simulation: CoupledSimulation | None = None
    candidates: int = 0
    detail: str = ""
    passivity: PassivityResult | None = field(default=None, repr=False)

    def to_dict(self) -> dict[str, Any]:
        return {
            "passive": self.passive,
            "reason": self.reason,
            "found": self.found,
            "detail": self.detail,
            "environment": self.environment.to_dict() if self.environment else None,
            "method": self.method,
            "omega": self.omega,
            "candidates": self.candidates,
            "coupled": self.coupled.to_dict() if self.coupled else None,
            "max_real_part": self.coupled.max_real_part if self.coupled else None,
            "simulation": self.simulation.to_dict() if self.simulation else None,
        }


# ---------------------------------------------------------------- candidates


def _z_at(num: ep.Poly, den: ep.Poly, w: Fraction) -> tuple[Fraction, Fraction]:
    """Exact ``(Re, Im)`` of ``Z(jw)``."""
    nr, ni = (ep.evaluate(p, w) for p in at_j_omega(num))
    dr, di = (ep.evaluate(p, w) for p in at_j_omega(den))
    mag = dr * dr + di * di
    if mag == 0:
        raise ZeroDivisionError("w is a pole of Z")
    return (nr * dr + ni * di) / mag, (ni * dr - nr * di) / mag


def _eval_jw(p: ep.Poly, w: Fraction) -> tuple[Fraction, Fraction]:
    re, im = at_j_omega(p)
    return ep.evaluate(re, w), ep.evaluate(im, w)


def _dz_abs(num: ep.Poly, den: ep.Poly, w: Fraction) -> float:
    """``|Z'(jw)|``, exact until the final conversion (no overflow for extreme values)."""
    nr, ni = _eval_jw(num, w)
    dr, di = _eval_jw(den, w)
    dnr, dni = _eval_jw(ep.derivative(num), w)
    ddr, ddi = _eval_jw(ep.derivative(den), w)
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


def _negative_frequencies(num: ep.Poly, den: ep.Poly) -> list[float]:
    """Frequencies with ``Re Z(jω) < 0`` (exact check), the most negative first."""
    nr, ni = at_j_omega(num)
    dr, di = at_j_omega(den)
    px = even_to_x(ep.add(ep.mul(nr, dr), ep.mul(ni, di)))
    if not px:
        return []
    odd = ep.positive_roots_odd_multiplicity(px)
    if px[-1] > 0 and ep.count_real_roots(odd, Fraction(0), None) == 0:
        return []
    try:
        out = [negative_point(px)]
        # a few more, log-spaced across the band where P < 0, for robustness
        roots = [
            ep.root_value(ep.squarefree_part(px), a, b)
            for a, b in ep.isolate_real_roots(px, Fraction(0))
        ]
    except OverflowError:  # frequencies beyond the double range: leave it to the grid
        return []
    edges = [0.0, *roots, (roots[-1] * 100 + 1) if roots else 1e6]
    for lo, hi in itertools.pairwise(edges):
        for x in np.geomspace(max(lo, hi * 1e-6, 1e-300), hi, 7)[1:-1]:
            if ep.evaluate(px, Fraction(float(x))) < 0:
                out.append(math.sqrt(float(x)))
    return out


def _tuned(num: ep.Poly, den: ep.Poly, w0: float) -> list[Environment]:
    """The construction at ``w0``: ``b_e`` below ``−R``, reactance ``−X``, tanks of several sizes."""
    try:
        r, x = _z_at(num, den, Fraction(w0))
    except ZeroDivisionError:
        return []
    if r >= 0:
        return []
    slope = _dz_abs(num, den, Fraction(w0)) * w0
    if not (math.isfinite(slope) and slope > 0):
        slope = abs(to_float(r))
    out = []
    for be in (Fraction(0), -r / 2):
        for f in TANK_FACTORS:
            tank = f * slope
            me = (max(-to_float(x), 0.0) + tank) / w0
            ke = (max(to_float(x), 0.0) + tank) * w0
            env = _env(me, to_float(be), ke)
            if env is not None:
                out.append(env)
    return out


def _env(m: float, b: float, k: float) -> Environment | None:
    """An environment, or None when a value is not a finite non-negative float."""
    vals = (m, b, k)
    if all(math.isfinite(v) and v >= 0 for v in vals):
        return Environment(mass=m, damping=b, stiffness=k)
    return None


def _grid(num: ep.Poly, den: ep.Poly) -> list[Environment]:
    """Springs, dampers, masses and combinations, scaled to the impedance."""
    roots = polynomial_roots(den)
    mags = [abs(p) for p in roots if 0 < abs(p) < math.inf]
    with np.errstate(all="ignore"):
        wc = float(np.exp(np.mean(np.log(mags)))) if mags else 1.0
    if not (math.isfinite(wc) and wc > 0):
        wc = 1.0
    try:
        zc = math.hypot(*(to_float(v) for v in _z_at(num, den, Fraction(wc))))
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


# ---------------------------------------------------------------- entry point


def find_destabilizing_environment(
    system: SystemLike,
    *,
    values: Mapping[str, float] | None = None,
    simulate: bool = True,
    throw: bool = False,
) -> WitnessResult:
    """Find a passive environment that destabilizes a non-passive design.

    Parameters
    ----------
    system : SEA, Impedance, str, sympy.Expr or (num, den)
        The design (its port impedance is used), with numeric values.
    values : mapping, optional
        Parameter values overriding those stored in ``system``.
    simulate : bool, default True
        Also simulate the growing response (`simulate_coupled`).
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] describing the witness
        when one is found (for scripts that must stop on unsafe designs).

    Returns
    -------
    WitnessResult
        ``found`` is False for a passive design (none exists, by the passivity
        theorem) and when the search fails (reported in ``detail``).

    Examples
    --------
    >>> from seapass import SEA
    >>> lp = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=2000))
    >>> w = find_destabilizing_environment(lp, simulate=False)
    >>> w.found, w.coupled.rhp
    (True, True)
    """
    pr = is_passive(system, values=values)
    if pr.passive:
        return WitnessResult(
            passive=True,
            reason="",
            found=False,
            detail="passive: no passive environment can destabilize it (passivity theorem)",
            passivity=pr,
        )
    num, den = exact_rational_function(system, values)
    if den[-1] < 0:
        num, den = ep.scale(num, Fraction(-1)), ep.scale(den, Fraction(-1))
    g = ep.pgcd(num, den) if num else ep.monic(den)
    rn, rd = (ep.pdivmod(num, g)[0], ep.pdivmod(den, g)[0]) if num else (num, den)

    stages: list[tuple[str, list[tuple[Environment, float | None]]]] = [
        ("free port", [(Environment(), None)]),
    ]
    tuned: list[tuple[Environment, float | None]] = []
    for wneg in _negative_frequencies(rn, rd) if rn else []:
        tuned += [(env, wneg) for env in _tuned(rn, rd, wneg)]
    # the construction and the search compete: the fastest verified growth wins
    stages.append(("tuned at w0", tuned + [(env, None) for env in _grid(rn, rd)]))

    count = 0
    fallback: tuple[str, Environment, float | None] | None = None
    for method, cands in stages:
        best: tuple[float, Environment, float | None] | None = None
        for env, wc in cands:
            count += 1
            status, rate = _score(num, den, env)
            if status == "rhp" and (best is None or rate > best[0]):
                best = (rate, env, wc)
            elif status == "unstable" and fallback is None:
                fallback = (method, env, wc)
        if best is not None:
            env, extra = _refine(num, den, best[1], best[0])
            count += extra
            coupled = coupled_stability(system, env, values=values)
            if best[2] is None and method != "free port":
                method = "search"
            return _found(system, values, pr, method, env, best[2], coupled, count, simulate, throw)
    if fallback is not None:
        method, env, wf = fallback
        coupled = coupled_stability(system, env, values=values)
        return _found(system, values, pr, method, env, wf, coupled, count, simulate, throw)
    return WitnessResult(
        passive=False,
        reason=pr.reason,
        found=False,
        candidates=count,
        detail=f"not passive ({Reason(pr.reason).description}), but none of {count} mass-spring-damper "
        "environments tried destabilizes it",
        passivity=pr,
    )


def _score(num: ep.Poly, den: ep.Poly, env: Environment) -> tuple[str, float]:
    """Exact class (``"rhp"``, ``"unstable"``, ``"bounded"``) and a float growth rate."""
    ne, de = env.polynomials()
    try:
        chi, _ = characteristic_from_polys(num, den, ne, de)
        _, rhp, repeated = classify_polynomial(chi)
    except (ValueError, ArithmeticError):
        return "bounded", -math.inf
    if not rhp:
        return ("unstable" if repeated else "bounded"), -math.inf
    roots = polynomial_roots(chi, fast=True)
    with np.errstate(all="ignore"):
        rate = float(np.max(roots.real)) if roots.size else 0.0
    return "rhp", rate if math.isfinite(rate) else 0.0


def _refine(num: ep.Poly, den: ep.Poly, env: Environment, rate: float) -> tuple[Environment, int]:
    """Pattern search on ``log m_e, log b_e, log k_e`` for a faster growth, each step exact."""
    x0 = x = np.array([env.mass, env.damping, env.stiffness])
    step, count = 0.5, 0
    while step > 0.05 and count < REFINE_STEPS:
        improved = False
        for i, sign in itertools.product(range(3), (1.0, -1.0)):
            if x[i] == 0:
                continue
            y = x.copy()
            y[i] = x[i] * 10.0 ** (sign * step)
            ratio = y[i] / x0[i]
            if not (np.all(np.isfinite(y)) and y[i] > 0 and 0 < ratio < math.inf):
                continue
            if abs(math.log10(ratio)) > REFINE_DECADES + 1e-9:
                continue
            count += 1
            cand = Environment(mass=float(y[0]), damping=float(y[1]), stiffness=float(y[2]))
            status, r = _score(num, den, cand)
            if status == "rhp" and r > rate * (1 + 1e-6):
                x, rate, env, improved = y, r, cand, True
        if not improved:
            step /= 2
    return env, count


def _found(
    system: SystemLike,
    values: Mapping[str, float] | None,
    pr: PassivityResult,
    method: str,
    env: Environment,
    w0: float | None,
    coupled: CoupledResult,
    count: int,
    simulate: bool,
    throw: bool,
) -> WitnessResult:
    sim, note = None, ""
    if simulate:
        try:
            sim = simulate_coupled(system, env, values=values)
        except (ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
            note = f" (no simulation: {exc})"
    kind = (
        f"a pole at Re s = {coupled.max_real_part:.4g} 1/s"
        if coupled.rhp
        else "a repeated pole on the imaginary axis"
    )
    detail = (
        f"not passive ({Reason(pr.reason).description}); the passive environment m_e = {env.mass:.6g} kg, "
        f"b_e = {env.damping:.6g} N*s/m, k_e = {env.stiffness:.6g} N/m makes the coupled "
        f"system unstable: {kind}{note}"
    )
    if throw:
        raise NotPassiveError(detail)
    return WitnessResult(
        passive=False,
        reason=pr.reason,
        found=True,
        environment=env,
        method=method,
        omega=w0,
        coupled=coupled,
        simulation=sim,
        candidates=count,
        detail=detail,
        passivity=pr,
    )
