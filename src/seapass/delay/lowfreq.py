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

from flint import arb_poly, fmpq, fmpq_poly

from ..exact import poly as ep
from .balls import ball, lower, precision
from .trig import TrigRealPart

__all__ = [
    "MAX_TAYLOR_ORDER",
    "LowFrequency",
    "at_fixed_delay",
    "bounds",
    "dyadic_down",
    "dyadic_up",
    "limit_polynomial",
    "lower_bound_on",
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


@dataclass(frozen=True, kw_only=True)
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
                core = fmpq_poly([dyadic_down(c) for c in core.coeffs()])  # still <= F
                return LowFrequency(sign=1, order=first, cutoff=_first_root_below(core))
            core = -(hi // shift)
            core = fmpq_poly([dyadic_down(c) for c in core.coeffs()])  # -core still >= F
            cut = _first_root_below(core)
            return LowFrequency(
                sign=-1, order=first, witness=(cut / 2) if cut is not None else fmpq(1)
            )
        q *= 2
    return LowFrequency(sign=0)


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


def dyadic_down(q: fmpq, bits: int = 60) -> fmpq:
    """A dyadic rational ``<= q`` within a relative ``2^-bits`` (keeps exact bounds cheap)."""
    if q == 0:
        return q
    num, den = int(q.p), int(q.q)
    k = bits - (abs(num).bit_length() - den.bit_length())
    if k >= 0:
        return fmpq((num << k) // den, 1 << k)
    return fmpq((num // (den << -k)) << -k, 1)  # floor division rounds toward -inf


def dyadic_up(q: fmpq, bits: int = 60) -> fmpq:
    """A dyadic rational ``>= q`` within a relative ``2^-bits``."""
    return -dyadic_down(-q, bits)


def _cutoff_leaf(
    f: TrigRealPart, i0: int, coeffs: list[_TauPoly], q: int, a: fmpq, b: fmpq
) -> tuple[fmpq | None, bool]:
    """`uniform_cutoff` for ``τ ∈ [a, b]``: lower bounds of every Taylor coefficient there."""
    floor = lower_bound_on(coeffs[i0], a, b)
    if floor <= 0:
        return fmpq(0), False
    bound = [fmpq(0)] * len(coeffs)
    bound[i0] = dyadic_down(floor)
    with precision(128):
        t = ball(a, b)
        for i in range(i0 + 1, len(coeffs)):
            c = coeffs[i]
            if not c.is_zero():
                bound[i] = dyadic_down(lower(arb_poly(c)(t)))
    r = _remainder(f, q, b)
    low = fmpq_poly(bound) - fmpq_poly([dyadic_up(v) for v in r.coeffs()])
    core = low // fmpq_poly([0, 1]) ** i0
    cut = _first_root_below(core)
    return cut, cut is None


def uniform_cutoff(
    f: TrigRealPart, i0: int, tau_max: fmpq, *, target: fmpq | None = None, depth: int = 10
) -> tuple[fmpq | None, bool]:
    """``(ω0, everywhere)``: ``F(ω; τ) > 0`` on ``(0, ω0]`` for every ``τ ∈ [0, tau_max]``
    (on all of ``ω > 0`` when ``everywhere``).

    Every ``f_i``, ``i < i0``, must vanish identically and ``f_i0 > 0`` on ``[0, tau_max]``
    (as `limit_polynomial` and the caller ensure).  The delays are split into sub-intervals
    (at most ``depth`` halvings) until ``ω0 >= target``: on each, every Taylor coefficient
    is bounded below, so a positive next coefficient keeps ``ω0`` away from 0 even when
    ``f_i0`` is tiny near ``tau_max``.
    """
    q = max(2 * max(f.degree, 1) + 4, i0 + (i0 % 2))
    coeffs = taylor(f, q)
    if any(not c.is_zero() for c in coeffs[:i0]):
        raise ArithmeticError("a Taylor coefficient below i0 does not vanish")
    todo = [(fmpq(0), tau_max, 0)]
    best: fmpq | None = None
    while todo:
        a, b, level = todo.pop()
        cut, everywhere = _cutoff_leaf(f, i0, coeffs, q, a, b)
        if everywhere:
            continue
        assert cut is not None
        if (target is None or cut < target) and level < depth and b - a > tau_max / 2**depth:
            m = (a + b) / 2
            todo += [(a, m, level + 1), (m, b, level + 1)]
            continue
        if cut <= 0:
            return fmpq(0), False
        best = cut if best is None else min(best, cut)
    return best, best is None


def lower_bound_on(p: fmpq_poly, lo: fmpq, hi: fmpq) -> fmpq:
    """A rational lower bound of ``p`` on ``[lo, hi]``, as tight as the minimum allows.

    The minimum is at an end or at a root of ``p'``; each root is isolated exactly, its
    interval refined, and ``p`` bounded on it with a ball.  Positive whenever ``p > 0`` on
    ``[lo, hi]`` (the refinement continues until the ball is positive, a bounded number of
    times).
    """
    cands = [p(lo), p(hi)]
    dp = p.derivative()
    if not dp.is_zero() and dp.degree() > 0:
        for a, b in ep.isolate_real_roots(dp, lo, hi):
            width = (b - a) / 2**20 if b > a else fmpq(0)
            val = p(b)
            for _ in range(8):
                if b > a:
                    a, b = ep.refine(dp, (a, b), width)
                with precision(128):
                    val = lower(arb_poly(p)(ball(a, b)))
                if val > 0 or a == b:
                    break
                width /= 2**20
            cands.append(val)
    return min(cands)
