"""Exact low-frequency analysis of the real part ``F(ω; τ)``: Taylor polynomials with a
rigorous remainder, so that ``ω → 0`` is decided without a ball ever containing zero.

With ``C_q(x) = Σ_{j ≤ q/2} (-1)^j x^{2j}/(2j)!`` and ``S_q(x) = Σ_{j ≤ q/2} (-1)^j
x^{2j+1}/(2j+1)!`` (``q`` even), ``|cos x - C_q(x)| ≤ |x|^{q+2}/(q+2)!`` and
``|sin x - S_q(x)| ≤ |x|^{q+3}/(q+3)!`` for every real ``x``.  So

``Q(ω; τ) = Σ_m A_m(ω) C_q(mωτ) + B_m(ω) S_q(mωτ)``,
``R(ω; τ) = Σ_m |A_m|(ω) (mωτ)^{q+2}/(q+2)! + |B_m|(ω) (mωτ)^{q+3}/(q+3)!``

(``|P|`` is ``P`` with its coefficients in absolute value) give exact polynomial bounds
``Q - R ≤ F ≤ Q + R`` for all ``ω ≥ 0``, and the coefficients of ``ω^i``, ``i ≤ q + 1``, of
``Q`` are the Taylor coefficients ``f_i(τ)`` of ``F`` exactly (polynomials in ``τ``).

* At a fixed delay the first nonzero ``f_i`` decides: positive, and ``Q - R > 0`` on
  ``(0, ω0]`` for an exact rational ``ω0``; negative, and ``Q + R < 0`` at an exact
  rational witness ``ω`` (`at_fixed_delay`).
* Over all delays ``τ ∈ [0, T]`` the lowest nontrivial coefficient ``f_i0(τ)`` decides where
  ``ω → 0`` first fails (`limit_polynomial`: its first positive root ``τ_low`` is exact),
  and `uniform_cutoff` gives one ``ω0`` for every ``τ ∈ [0, T]`` with ``T < τ_low``.

Examples
--------
A rigid device with a delayed virtual spring, ``Z = m s + b + K e^{-sτ}/s``:
``Re Z(jω) = b - K sin(ωτ)/ω``, so ``f(τ) = b - Kτ`` decides ``ω → 0``:

>>> from seapass.delay.structure import delayed_impedance
>>> from seapass.delay.trig import real_part
>>> f = real_part(delayed_impedance("m*s + b + K*exp(-tau*s)/s",
...                                 values=dict(m=1, b=2, K=50, tau=0.01)))
>>> i0, poly = limit_polynomial(f)
>>> i0, poly              # F = (2 - 50 τ) ω² + O(ω⁴)
(2, (-50)*x + 2)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from flint import fmpq, fmpq_poly

from ..exact import poly as ep
from .trig import TrigRealPart

__all__ = [
    "MAX_TAYLOR_ORDER",
    "LowFrequency",
    "at_fixed_delay",
    "bounds",
    "limit_polynomial",
    "taylor",
    "uniform_cutoff",
]

MAX_TAYLOR_ORDER = 96
"""Highest Taylor order searched for the first nonzero coefficient of ``F`` at ``ω = 0``."""

# a coefficient of ω^i as a polynomial in τ
_TauPoly = fmpq_poly


def _abs(p: fmpq_poly) -> fmpq_poly:
    return fmpq_poly([abs(c) for c in p.coeffs()])


def taylor(f: TrigRealPart, q: int) -> list[_TauPoly]:
    """``Q`` of the module docstring: ``[q_0(τ), q_1(τ), ...]``, ``q_i`` the coefficient of ``ω^i``."""
    if q % 2:
        raise ValueError("q must be even")
    size = f.degree + q + 3
    out: list[list[fmpq]] = [[fmpq(0)] * (q + 3) for _ in range(max(size, 1))]
    for m in range(len(f.cos)):
        for p, c in enumerate(f.cos[m].coeffs()):
            if c == 0:
                continue
            if m == 0:
                out[p][0] += c
                continue
            for j in range(q // 2 + 1):
                e = 2 * j
                out[p + e][e] += c * (-1) ** j * fmpq(m**e, math.factorial(e))
        if m == 0:
            continue
        for p, c in enumerate(f.sin[m].coeffs()):
            if c == 0:
                continue
            for j in range(q // 2 + 1):
                e = 2 * j + 1
                out[p + e][e] += c * (-1) ** j * fmpq(m**e, math.factorial(e))
    return [fmpq_poly(row) for row in out]


def _remainder(f: TrigRealPart, q: int, tau: fmpq) -> fmpq_poly:
    """``R(ω; τ)`` of the module docstring at a delay (or a bound on the delays) ``τ``."""
    r = fmpq_poly([])
    w = fmpq_poly([0, 1])
    for m in range(1, len(f.cos)):
        x = fmpq(m) * tau
        r += _abs(f.cos[m]) * w ** (q + 2) * (x ** (q + 2) / math.factorial(q + 2))
        r += _abs(f.sin[m]) * w ** (q + 3) * (x ** (q + 3) / math.factorial(q + 3))
    return r


def _at(coeffs: list[_TauPoly], tau: fmpq) -> fmpq_poly:
    return fmpq_poly([c(tau) for c in coeffs])


def bounds(f: TrigRealPart, tau: fmpq, q: int) -> tuple[fmpq_poly, fmpq_poly]:
    """Exact polynomials ``L ≤ F(·; τ) ≤ U`` on ``ω ≥ 0`` (Taylor order ``q``)."""
    qpoly = _at(taylor(f, q), tau)
    r = _remainder(f, q, tau)
    return qpoly - r, qpoly + r


@dataclass(frozen=True)
class LowFrequency:
    """What ``ω → 0`` says at a fixed delay.

    ``sign`` of the first nonzero Taylor coefficient (0: none up to `MAX_TAYLOR_ORDER`);
    ``order`` its power of ``ω``; ``cutoff``: ``F > 0`` on ``(0, cutoff]`` (sign > 0; None
    when the bound holds on all of ``ω > 0``); ``witness``: an exact rational ``ω`` with
    ``F(ω) < 0`` (sign < 0).
    """

    sign: int
    order: int = -1
    cutoff: fmpq | None = None
    witness: fmpq | None = None

    @property
    def everywhere(self) -> bool:
        """``F > 0`` on all of ``ω > 0`` (proven by the polynomial bound alone)."""
        return self.sign > 0 and self.cutoff is None


def _first_root_below(p: fmpq_poly) -> fmpq | None:
    """A rational ``a > 0`` below the first positive root of ``p`` (None: no positive root)."""
    roots = ep.isolate_real_roots(p, 0)
    if not roots:
        return None
    a, b = roots[0]
    if a <= 0:
        a, b = ep.refine_past(p, (a, b), 0)
    return a


def at_fixed_delay(f: TrigRealPart, tau: fmpq) -> LowFrequency:
    """Decide the sign of ``F(·; τ)`` near ``ω = 0`` exactly (see the module docstring)."""
    q = 2 * max(f.degree, 1) + 4
    while q <= MAX_TAYLOR_ORDER:
        lo, hi = bounds(f, tau, q)
        coeffs = _at(taylor(f, q), tau).coeffs()
        first = next((i for i, c in enumerate(coeffs[: q + 2]) if c != 0), None)
        if first is not None:
            shift = fmpq_poly([0, 1]) ** first
            if coeffs[first] > 0:
                core = lo // shift  # lo has no terms below ω^first (they are f_i = 0)
                return LowFrequency(1, first, _first_root_below(core))
            core = -(hi // shift)
            cut = _first_root_below(core)
            return LowFrequency(-1, first, witness=(cut / 2) if cut is not None else fmpq(1))
        q *= 2
    return LowFrequency(0)


def limit_polynomial(f: TrigRealPart) -> tuple[int, _TauPoly]:
    """``(i0, f_i0(τ))``: the lowest power of ``ω`` whose Taylor coefficient is not identically
    zero in ``τ``, and that coefficient (``(-1, 0)`` if none up to `MAX_TAYLOR_ORDER`)."""
    q = 2 * max(f.degree, 1) + 4
    while q <= MAX_TAYLOR_ORDER:
        coeffs = taylor(f, q)
        for i, c in enumerate(coeffs[: q + 2]):
            if not c.is_zero():
                return i, c
        q *= 2
    return -1, fmpq_poly([])


def uniform_cutoff(
    f: TrigRealPart, i0: int, floor: fmpq, tau_max: fmpq
) -> tuple[fmpq | None, bool]:
    """``(ω0, everywhere)``: ``F(ω; τ) > 0`` on ``(0, ω0]`` for every ``τ ∈ [0, tau_max]``
    (on all of ``ω > 0`` when ``everywhere``).

    ``floor > 0`` must be a lower bound of ``f_i0`` on ``[0, tau_max]`` and every ``f_i``,
    ``i < i0``, must vanish identically (as `limit_polynomial` gives).
    """
    if floor <= 0:
        raise ValueError("the floor of f_i0 must be positive")
    q = max(2 * max(f.degree, 1) + 4, i0 + (i0 % 2))
    coeffs = taylor(f, q)
    bound = [fmpq(0)] * len(coeffs)
    bound[i0] = floor
    for i, c in enumerate(coeffs):
        if i <= i0:
            if i < i0 and not c.is_zero():
                raise ArithmeticError("a Taylor coefficient below i0 does not vanish")
            continue
        bound[i] = -sum((abs(v) * tau_max**j for j, v in enumerate(c.coeffs())), fmpq(0))
    low = fmpq_poly(bound) - _remainder(f, q, tau_max)
    core = low // fmpq_poly([0, 1]) ** i0
    cut = _first_root_below(core)
    return cut, cut is None
