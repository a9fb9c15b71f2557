"""Exact rational data of the continuous plant behind a sampled-data SEA port.

The analysis of [`seapass.sampled.passivity`][seapass.sampled.passivity] needs, for the plant ``m, b, D1, D2``
(``α = m s² + b s``), the rational functions

* ``a = D1/(α + D1)`` (actuator force → port force with the port held),
* ``P = 1/(α + D1)`` (actuator force → actuator position with the port held),
* ``Z0 = [D1 α + D2 (α + D1)]/(s (α + D1))`` (port impedance without control) and
  ``R = (Z0(s) + Z0(−s))/2`` (its even part, ``Re Z0`` on the imaginary axis),

and the six summands ``ψ`` whose alias sums make up the power function.  Everything
here is exact (python-flint rationals); nothing is rounded.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any, cast

from flint import acb, ctx, fmpq, fmpq_poly

from ..errors import ModelError, ParameterError
from ..exact.poly import as_poly, rational, to_fraction, to_fractions
from ..model.sea import SEA, exact_values

if TYPE_CHECKING:
    import sympy as sp

__all__ = [
    "Plant",
    "PlantKey",
    "RationalFunction",
    "continuous_impedance",
    "numeric_element",
    "plant_from_key",
    "plant_key",
    "plant_of",
    "rational_of",
    "reduced",
    "reflect",
]

RationalFunction = tuple[fmpq_poly, fmpq_poly]  # (numerator, denominator), reduced, monic den

_ONE = fmpq_poly([1])
_S = fmpq_poly([0, 1])


def _poly(expr: sp.Expr) -> fmpq_poly:
    import sympy as sp

    from ..model.expr import S

    return as_poly([sp.Rational(c) for c in reversed(sp.Poly(expr, S).all_coeffs())])


def reduced(num: fmpq_poly, den: fmpq_poly) -> RationalFunction:
    """``num/den`` in lowest terms with a monic denominator."""
    if den.is_zero():
        raise ModelError("a plant element has a denominator that is identically zero")
    if num.is_zero():
        return fmpq_poly([0]), _ONE
    g = num.gcd(den)
    num, den = num // g, den // g
    lead = den.leading_coefficient()
    return num / lead, den / lead


def rational_of(expr: sp.Expr) -> RationalFunction:
    """Exact ``(num, den)`` of a rational function of ``s`` with numeric coefficients (sympy)."""
    import sympy as sp

    num, den = sp.fraction(sp.together(sp.sympify(expr)))
    return reduced(_poly(sp.expand(num)), _poly(sp.expand(den)))


def reflect(p: fmpq_poly) -> fmpq_poly:
    """``p(−s)``."""
    return fmpq_poly([c if i % 2 == 0 else -c for i, c in enumerate(p.coeffs())])


def _mul(*fs: RationalFunction) -> RationalFunction:
    num, den = _ONE, _ONE
    for n, d in fs:
        num, den = num * n, den * d
    return reduced(num, den)


def _inv(f: RationalFunction) -> RationalFunction:
    return reduced(f[1], f[0])


@dataclass(frozen=True)
class Plant:
    """Exact plant data of one SEA (all parameters numeric).

    Attributes
    ----------
    a, P, Z0, R : RationalFunction
        See the module docstring.
    delta : fmpq_poly
        Numerator of ``α + D1``: its roots are the modes with the port held.
    """

    a: RationalFunction
    P: RationalFunction
    Z0: RationalFunction
    R: RationalFunction
    delta: fmpq_poly

    def summands(self) -> dict[str, RationalFunction]:
        """``ψ`` of the alias sums ``S1..S4, Sg`` (``S5 = −S3``), see the passivity module."""
        a, R = self.a, self.R
        a_reflected = (reflect(a[0]), reflect(a[1]))
        minus_s2 = (fmpq_poly([0, 0, -1]), _ONE)
        over_minus_s2_r = _inv(_mul(minus_s2, R))
        return {
            "S1": _mul(a, a_reflected, over_minus_s2_r),
            "S2": _mul(a, a, _inv(_mul((fmpq_poly([0, 0, 1]), _ONE), R))),
            "S3": _mul(a, over_minus_s2_r),
            "S4": over_minus_s2_r,
            "Sg": _mul(self.P, (_ONE, _S)),
        }

    def dc(self) -> dict[str, fmpq]:
        """``P(0)`` and ``R(0)`` (both finite by construction)."""
        return {"P0": self.P[0](0) / self.P[1](0), "R0": self.R[0](0) / self.R[1](0)}


def _positive_on_axis(num: fmpq_poly, den: fmpq_poly) -> bool:
    """``num(jω)/den(jω) > 0`` for every ``ω ≥ 0``, for even ``num``, ``den`` (exact)."""

    def in_y(p: fmpq_poly) -> fmpq_poly:  # p(jω) as a polynomial in y = ω²
        c = p.coeffs()
        return fmpq_poly([c[i] * (-1) ** (i // 2) for i in range(0, len(c), 2)])

    prod = in_y(num) * in_y(den)
    if prod.is_zero() or prod(0) <= 0:
        return False
    # no root of odd multiplicity in (0, ∞): square-free factors, Descartes then isolation
    for f, mult in prod.factor_squarefree()[1]:
        if mult % 2 == 0:
            continue
        if _has_positive_root(f):
            return False
    return True


def _has_positive_root(f: fmpq_poly) -> bool:
    """Does the square-free ``f`` with ``f(0) ≠ 0`` have a root in ``(0, ∞)``? (certified)"""
    coeffs = [c for c in f.coeffs() if c != 0]
    if all((x > 0) == (coeffs[0] > 0) for x in coeffs):
        return False  # Descartes: no sign variation, no positive root
    prec = 64
    while True:
        with ctx.workprec(prec):
            # FLINT returns real roots as balls with an exactly zero imaginary part
            roots: list[tuple[acb, int]] = cast(Any, f.complex_roots())  # (ball, multiplicity)
            real = [r.real for r, _m in roots if r.imag.is_zero()]
            if any(x > 0 for x in real):
                return True
            if all(x < 0 for x in real):
                return False
        prec *= 2


def _is_hurwitz(p: fmpq_poly) -> bool:
    """All roots in the open left half plane (Routh, exact)."""
    c = list(reversed(p.coeffs()))  # descending
    if any(x == 0 for x in c):
        return all(x == 0 for x in c[1:]) and len(c) == 1
    if len(c) == 1:
        return True
    sign = 1 if c[0] > 0 else -1
    rows = [c[0::2], c[1::2]]
    while len(rows[-1]) and any(x != 0 for x in rows[-1]):
        r0, r1 = rows[-2], rows[-1]
        if r1[0] == 0:
            return False
        nxt = [
            (
                r1[0] * (r0[i + 1] if i + 1 < len(r0) else 0)
                - r0[0] * (r1[i + 1] if i + 1 < len(r1) else 0)
            )
            / r1[0]
            for i in range(max(len(r0) - 1, 0))
        ]
        while nxt and nxt[-1] == 0 and len(nxt) > 1:
            nxt.pop()
        rows.append(nxt)
        if len(rows) > p.degree() + 1:
            break
    firsts = [r[0] for r in rows if r]
    return len(firsts) == p.degree() + 1 and all((x > 0) if sign > 0 else (x < 0) for x in firsts)


def plant_from_rationals(m: fmpq, b: fmpq, d1: RationalFunction, d2: RationalFunction) -> Plant:
    """Build and check the plant; raises `ModelError` outside the supported class."""
    alpha = fmpq_poly([0, b, m])
    n1, den1 = d1
    n2, den2 = d2
    delta = alpha * den1 + n1
    if delta(0) == 0:
        raise ModelError(
            "the sampled-data analysis needs a transmission with static stiffness "
            "(D1(0) ≠ 0): with D1(0) = 0 the actuator floats when the port is held"
        )
    z0 = reduced(n1 * alpha * den2 + n2 * delta, _S * delta * den2)
    zr = (reflect(z0[0]), reflect(z0[1]))
    r = reduced(z0[0] * zr[1] + zr[0] * z0[1], 2 * z0[1] * zr[1])
    if r[1](0) == 0 or not _positive_on_axis(r[0], r[1]):
        raise ModelError(
            "sampled passivity needs a strictly dissipative physical plant (Re Z0(jw) > 0 at "
            "every frequency, finite at w = 0); give the actuator damping b > 0"
        )
    if not (_is_hurwitz(delta) and _is_hurwitz(den2)):
        raise ModelError(
            "the physical plant is unstable with the port held (a root of m s^2 + b s + D1 or "
            "of the denominator of D2 is not in the open left half plane)"
        )
    return Plant(reduced(n1, delta), reduced(den1, delta), z0, r, delta)


def numeric_element(sea: SEA, name: str) -> RationalFunction:
    """Element ``name`` of ``sea`` at its values, exact, in lowest terms with a monic denominator."""
    f = sea.exact_elements()[name]
    env = exact_values(sea.values)
    missing = f.parameters() - set(env)
    if missing:
        raise ParameterError("plant parameters without values: " + ", ".join(sorted(missing)))
    return reduced(*f.evaluate(env))


PlantKey = tuple[tuple[Fraction, ...], ...]
"""Cache key of a numeric plant: ``m``, ``b`` and the coefficients of ``D1``, ``D2``."""


@functools.lru_cache(maxsize=128)
def plant_from_key(key: PlantKey) -> Plant:
    """The plant of a [`plant_key`][seapass.sampled.plant.plant_key] (cached)."""
    (m,), (b,), n1, d1, n2, d2 = key
    return plant_from_rationals(
        rational(m),
        rational(b),
        (as_poly(n1), as_poly(d1)),
        (as_poly(n2), as_poly(d2)),
    )


def plant_key(sea: SEA) -> PlantKey:
    """Cache key of the numeric plant (``m, b, D1, D2``), exact and hashable."""
    m, b, d1, d2 = (numeric_element(sea, k) for k in ("m", "b", "D1", "D2"))
    mb = tuple((x[0][0] / x[1][0],) for x in (m, b))
    return (
        *(tuple(to_fraction(v) for v in x) for x in mb),
        *(to_fractions(p) for p in (*d1, *d2)),
    )


def plant_of(sea: SEA) -> Plant:
    """Exact plant data of ``sea`` (cached on the numeric plant)."""
    return plant_from_key(plant_key(sea))


def continuous_impedance(sea: SEA) -> RationalFunction:
    """``Z_L(s) = [D2 + D1 (α + C_A + C_L)/(α + D1 + C_A)]/s`` exactly, not reduced.

    The continuous-time port impedance (the paper's Eq. 4 with the ``D1·D2`` term), built
    from the element rationals without symbolic derivation.
    """
    e = {k: numeric_element(sea, k) for k in ("D1", "D2", "CA", "CL", "m", "b")}
    m, b = e["m"][0][0] / e["m"][1][0], e["b"][0][0] / e["b"][1][0]
    alpha = (fmpq_poly([0, b, m]), _ONE)

    def add(*fs: RationalFunction) -> RationalFunction:
        num, den = fmpq_poly([0]), _ONE
        for n, d in fs:
            num, den = num * d + n * den, den * d
        return num, den

    inner_num = add(alpha, e["CA"], e["CL"])
    inner_den = add(alpha, e["D1"], e["CA"])
    frac = (e["D1"][0] * inner_num[0] * inner_den[1], e["D1"][1] * inner_num[1] * inner_den[0])
    k_num, k_den = add(e["D2"], frac)
    return k_num, k_den * _S
