"""Alias sums of the sampled SEA in closed form (the Colgate–Schenkel step).

Every alias sum ``Σ_k ψ(s_k)`` over ``s_k = j(ω + 2πk/T)`` of a rational
summand is a rational function of ``z = e^{jωT}``: partial fractions of ``ψ``
and ``Σ_k 1/(s_k − p) = (T/2)(z + e^{pT})/(z − e^{pT})`` and its
``p``-derivatives.  The plant's sums are cached per (plant, period).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import mpmath
import sympy as sp

from ..errors import ModelError, ParameterError, SymbolicLimitError
from ..exact import fraction_poly as ep
from ..model.expr import S
from ..model.sea import SEA

__all__ = [
    "COEFFICIENT_TAIL",
    "DPS",
    "AliasSum",
    "PlantSums",
    "alias_sum",
    "check_dissipative",
    "find_pole_key",
    "plant_key",
    "plant_sums",
    "to_mp",
]


DPS = 50  # working precision (decimal digits) of the alias sums


COEFFICIENT_TAIL = mpmath.mpf(10) ** (-(DPS - 15))


@dataclass(frozen=True)
class AliasSum:
    """``Σ_k ψ(s_k)`` as ``Σ A·G_j(e^{pT}, z)``; ``terms`` = (q, j, A)."""

    T: Any
    terms: tuple[tuple[Any, int, Any], ...]

    def __call__(self, z: Any) -> Any:
        T = self.T
        out = mpmath.mpc(0)
        for q, j, a in self.terms:
            if j == 1:
                out += a * T / 2 * (z + q) / (z - q)
            elif j == 2:
                out += a * T**2 * q * z / (z - q) ** 2
            else:
                out += a * T**3 * q * z * (z + q) / (2 * (z - q) ** 3)
        return out


def to_mp(c: Any) -> Any:
    r = sp.Rational(c)
    return mpmath.mpf(int(r.p)) / int(r.q)


def _taylor_shift(coeffs_desc: list[Any], p: Any, order: int) -> list[Any]:
    """First ``order`` Taylor coefficients of the polynomial at ``p`` (repeated Horner)."""
    c = list(coeffs_desc)
    out = []
    for _ in range(order):
        if not c:
            out.append(mpmath.mpc(0))
            continue
        acc = mpmath.mpc(0)
        quot = []
        for a in c:
            acc = acc * p + a
            quot.append(acc)
        out.append(quot.pop())
        c = quot
    return out


def alias_sum(psi: sp.Expr, T: Fraction) -> tuple[AliasSum | None, dict[Any, int]]:
    """Closed-form alias sum of ``psi(s)``; ``None`` if it diverges (relative degree < 2)."""
    num, den = sp.fraction(sp.cancel(sp.together(psi)))
    pn, pd = sp.Poly(num, S), sp.Poly(den, S)
    if pn.is_zero:
        return AliasSum(to_mp(T), ()), {}
    if pd.degree() - pn.degree() < 2:
        return None, {}
    _coeff, factors = sp.sqf_list(pd)
    roots: list[tuple[Any, int]] = []
    for f, mult in factors:
        if mult > 3:
            raise SymbolicLimitError(
                "pole of multiplicity > 3 in an alias sum; perturb a parameter"
            )
        cs = [to_mp(c) for c in sp.Poly(f, S).all_coeffs()]
        rts = (
            [mpmath.mpf(0)]
            if len(cs) == 2 and cs[1] == 0
            else mpmath.polyroots(cs, maxsteps=400, extraprec=4 * DPS)
        )
        roots.extend((mpmath.mpc(r), mult) for r in rts)
    lc = to_mp(pd.LC())
    ncoef = [mpmath.mpc(to_mp(c)) for c in pn.all_coeffs()]
    Tm = to_mp(T)
    terms = []
    poles: dict[Any, int] = {}
    for i, (p, m) in enumerate(roots):
        taylor_n = _taylor_shift(ncoef, p, m)
        q_ser = [mpmath.mpc(lc)] + [mpmath.mpc(0)] * (m - 1)
        for k, (p2, m2) in enumerate(roots):
            if k == i:
                continue
            for _ in range(m2):  # multiply the series by (eps + p - p2)
                d = p - p2
                q_ser = [q_ser[t] * d + (q_ser[t - 1] if t else 0) for t in range(m)]
        h: list[Any] = []  # series division taylor_n / q_ser
        for t in range(m):
            acc = taylor_n[t] - sum(h[u] * q_ser[t - u] for u in range(t))
            h.append(acc / q_ser[0])
        q = mpmath.exp(p * Tm) if p != 0 else mpmath.mpf(1)
        for j in range(1, m + 1):
            terms.append((q, j, h[m - j]))
        poles[q] = max(poles.get(q, 0), m)
    return AliasSum(Tm, tuple(terms)), poles


@dataclass
class PlantSums:
    T: Any
    sums: dict[str, AliasSum | None]
    poles: dict[Any, int] = field(default_factory=dict)


@functools.lru_cache(maxsize=64)
def plant_sums(key: str, T: Fraction) -> PlantSums:  # key: srepr of (m, b, D1, D2)
    m, b, D1, D2 = sp.sympify(key)
    alpha = m * S**2 + b * S
    den = sp.cancel(alpha + D1)
    a = sp.cancel(D1 / den)
    P = sp.cancel(1 / den)
    Z0 = sp.cancel((D1 * alpha + D2 * den) / (S * den))
    R = sp.cancel((Z0 + Z0.subs(S, -S)) / 2)
    check_dissipative(R)
    am = a.subs(S, -S)
    psis = {
        "S1": a * am / (-(S**2) * R),
        "S2": a**2 / (S**2 * R),
        "S3": a / (-(S**2) * R),
        "S4": 1 / (-(S**2) * R),
        "S5": a / (S**2 * R),
        "Sg": P / S,
    }
    with mpmath.workdps(DPS):
        sums: dict[str, AliasSum | None] = {}
        poles: dict[Any, int] = {}
        for name, psi in psis.items():
            sums[name], pl = alias_sum(psi, T)
            for q, mult in pl.items():
                key_q = find_pole_key(poles, q)
                poles[key_q] = max(poles.get(key_q, 0), mult)
        return PlantSums(to_mp(T), sums, poles)


def find_pole_key(poles: dict[Any, int], q: Any) -> Any:
    for k in poles:
        if abs(k - q) <= mpmath.mpf(10) ** (-(DPS - 10)) * max(1, abs(q)):
            return k
    return q


def check_dissipative(R: sp.Expr) -> None:
    """``Re Z0(jω) > 0`` for all ``ω ≥ 0``, decided exactly."""
    num, den = sp.fraction(sp.cancel(R))
    pn = sp.Poly(num, S)
    coeffs = pn.all_coeffs()[::-1]
    # num is even in s; Re Z0(jw) = num(jw)/|den(jw)|^2 with y = w^2
    ey = [
        Fraction(int(sp.Rational(c).p), int(sp.Rational(c).q)) * (-1) ** (i // 2)
        for i, c in enumerate(coeffs)
        if i % 2 == 0
    ]
    dpoly = sp.Poly(den, S)
    lead = dpoly.LC()
    sign = 1 if lead > 0 else -1
    ey = [sign * c for c in ey]
    p = ep.normalize(ey)
    if not p or ep.evaluate(p, Fraction(0)) <= 0 or ep.count_real_roots(p, Fraction(0), None):
        raise ModelError(
            "sampled passivity needs a strictly dissipative physical plant (Re Z0(jw) > 0 at "
            "every frequency); give the actuator damping b > 0"
        )


def plant_key(sea: SEA) -> str:
    e = sea.elements()
    vals = [sp.sympify(sea.numeric(e[k])) for k in ("m", "b", "D1", "D2")]
    for v in vals:
        if v.free_symbols - {S}:
            raise ParameterError(
                "plant parameters without values: "
                + ", ".join(sorted(str(x) for x in v.free_symbols - {S}))
            )
    return sp.srepr(sp.Tuple(*vals))
