"""The positive-real conditions of a family of impedances, as polynomials on the box.

With the uncertain parameters ``p`` symbolic and every other parameter an exact
rational, the impedance is ``Z = N(s; p)/D(s; p)`` with coefficients polynomial in
``p``.  Write ``D = s^j D̃`` with ``j`` the generic multiplicity of the pole at
``s = 0``, and scale so that the leading coefficient of ``D̃`` is positive at the
centre of the box.  Every plant in the box passes the exact positive-real test of
[`seapass.analysis.passivity`][seapass.analysis.passivity] if, on the whole box,

* **stability**: every coefficient of ``D̃`` is positive and every Hurwitz
  determinant ``Δ_2 … Δ_{n−1}`` of ``D̃`` is positive (Routh–Hurwitz: ``D̃`` is
  Hurwitz for every ``p``, so there is no pole in the closed right half-plane but
  the one at 0, and no hidden unstable mode);
* **pole at 0** (``j = 1``): ``N(0) > 0`` (a simple pole with positive residue);
* **relative degree**: the leading coefficient of ``N`` keeps its sign (it is
  positive when ``deg D − deg N = −1``), so the relative degree never changes;
* **real part**: ``P(x; p) = Re N(jω) D(−jω)``, ``x = ω²``, without its generic
  factor ``x^k``, compactified by ``x = t/(1 − t)``:
  ``Q(t; p) = (1 − t)^{d−k} P(t/(1 − t); p)/x^k > 0`` on ``[0, 1] × box``
  (``t = 1`` is the leading coefficient, the behaviour at infinite frequency).

Each condition is a polynomial in ``(t, p)`` (``t`` only for the real part) that
must be positive on the box; [`seapass.robust.bernstein`][seapass.robust.bernstein]
proves it or finds an exact point where it fails.  The conditions are sufficient;
the Hurwitz and real-part conditions are also necessary pointwise, so a point where
one fails is checked by the ordinary exact test and, when not passive there, is a
counterexample.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from fractions import Fraction

import numpy as np
import sympy as sp
from flint import fmpq

from ..errors import ParameterError
from ..model.expr import S, symbol
from ..model.sea import SEA, Impedance
from ..model.stiffness import load_impedance
from .bernstein import from_terms
from .box import UncertainBox

__all__ = ["Condition", "ConditionKind", "FamilyConditions", "family_conditions", "fixed_values"]

_T = sp.Symbol("t")
_W = sp.Symbol("w")


class ConditionKind(StrEnum):
    """What a condition guards."""

    COEFFICIENT = "coefficient"
    HURWITZ = "hurwitz"
    POLE_AT_ZERO = "pole_at_zero"
    RELATIVE_DEGREE = "relative_degree"
    REAL_PART = "real_part"


@dataclass(frozen=True, kw_only=True)
class Condition:
    """One polynomial that must be positive on ``[0, 1] × box``.

    ``coeffs`` is dense (axes ``t, p_1, …, p_k``; length 1 along ``t`` when the
    condition does not depend on frequency).
    """

    kind: ConditionKind
    label: str
    coeffs: np.ndarray


@dataclass(frozen=True, kw_only=True)
class FamilyConditions:
    """The conditions of a family, or why none is needed.

    ``generic_failure`` names a structural defect (relative degree, a repeated pole
    at 0, a coefficient identically zero) that makes every plant non-passive where
    the generic structure holds; then ``conditions`` is empty.
    """

    names: tuple[str, ...]
    conditions: tuple[Condition, ...] = ()
    generic_failure: str = ""


def fixed_values(system: SEA | Impedance, box: UncertainBox) -> dict[str, float]:
    """The values of every parameter not in ``box`` (all must be given)."""
    fixed = {k: v for k, v in system.values.items() if k not in box.intervals and v is not None}
    free = [n for n in system.parameters if n not in box.intervals and n not in fixed]
    if free:
        raise ParameterError(
            f"no value for parameter(s) {', '.join(free)}: give them, "
            f"e.g. values={{{free[0]!r}: 1.0}}"
        )
    return {k: float(v) for k, v in fixed.items()}


def _num_den(system: SEA | Impedance, box: UncertainBox) -> tuple[sp.Expr, sp.Expr]:
    """``N`` and ``D`` as the exact test sees them: cancelled with every parameter symbolic,
    then the fixed values substituted (no cancellation after it, so a common factor that
    appears only at these values stays visible, as it does to the exact test)."""
    fixed = fixed_values(system, box)
    subs = {symbol(k): sp.Rational(Fraction(v)) for k, v in fixed.items()}
    if isinstance(system, SEA):
        z = load_impedance(system.with_values(**dict.fromkeys(box.names)))
    else:
        z = system.expr
    num, den = sp.fraction(sp.cancel(sp.together(z)))
    return sp.expand(num.xreplace(subs)), sp.expand(den.xreplace(subs))


def _dense(expr: sp.Expr, params: list[sp.Symbol]) -> np.ndarray:
    gens = [_T, *params]
    expr = sp.expand(expr)
    if expr == 0:
        return from_terms({}, len(gens))
    poly = sp.Poly(expr, *gens, domain="QQ")
    terms = {
        tuple(int(e) for e in mon): fmpq(int(c.p), int(c.q))
        for mon, c in zip(poly.monoms(), poly.coeffs(), strict=True)
    }
    return from_terms(terms, len(gens))


def _re_im(coeffs: list[sp.Expr]) -> tuple[sp.Expr, sp.Expr]:
    re = sum((c * (-1) ** (k // 2) * _W**k for k, c in enumerate(coeffs) if k % 2 == 0), sp.S.Zero)
    im = sum((c * (-1) ** (k // 2) * _W**k for k, c in enumerate(coeffs) if k % 2 == 1), sp.S.Zero)
    return sp.expand(re), sp.expand(im)


def _at(expr: sp.Expr, center: dict[sp.Symbol, sp.Rational]) -> sp.Rational:
    return sp.Rational(sp.expand(expr).xreplace(center))


def _hurwitz_determinants(desc: list[sp.Expr]) -> list[sp.Expr]:
    """``Δ_2 … Δ_{n−1}`` of ``a_0 s^n + a_1 s^{n−1} + … + a_n`` (``desc = [a_0, …, a_n]``)."""
    n = len(desc) - 1

    def a(i: int) -> sp.Expr:
        return desc[i] if 0 <= i <= n else sp.S.Zero

    h = sp.Matrix(n, n, lambda i, j: a(2 * (j + 1) - (i + 1)))
    return [sp.expand(h[:k, :k].det(method="berkowitz")) for k in range(2, n)]


def family_conditions(system: SEA | Impedance, box: UncertainBox) -> FamilyConditions:
    """The conditions (module docstring) of ``system`` over ``box``."""
    names = box.names
    params = [symbol(n) for n in names]
    center = {symbol(k): sp.Rational(Fraction(v)) for k, v in box.center().items()}
    num, den = _num_den(system, box)
    if den == 0:
        raise ParameterError("the impedance has a zero denominator")
    nc = sp.Poly(num, S).all_coeffs()[::-1] if num != 0 else [sp.S.Zero]
    dc = sp.Poly(den, S).all_coeffs()[::-1]
    j = next(i for i, c in enumerate(dc) if sp.expand(c) != 0)
    dt = dc[j:]
    if _at(dt[-1], center) < 0:
        nc, dc, dt = [-c for c in nc], [-c for c in dc], [-c for c in dt]
    rel = (len(dc) - 1) - (len(nc) - 1)
    if num == 0:
        return FamilyConditions(names=names, generic_failure="")
    if rel not in (-1, 0, 1):
        return FamilyConditions(names=names, generic_failure=f"relative degree {rel}")
    if j >= 2:
        return FamilyConditions(names=names, generic_failure="repeated pole at s = 0")
    conds: list[Condition] = []

    def add(kind: ConditionKind, label: str, expr: sp.Expr) -> None:
        conds.append(Condition(kind=kind, label=label, coeffs=_dense(expr, params)))

    desc = list(reversed(dt))
    for i, c in enumerate(desc):
        if sp.expand(c) == 0:
            return FamilyConditions(
                names=names, generic_failure=f"coefficient of s^{len(desc) - 1 - i} is zero"
            )
        add(ConditionKind.COEFFICIENT, f"coefficient of s^{len(desc) - 1 - i} of D", c)
    for k, delta in enumerate(_hurwitz_determinants(desc), start=2):
        add(ConditionKind.HURWITZ, f"Hurwitz determinant {k} of D", delta)
    if j == 1:
        add(ConditionKind.POLE_AT_ZERO, "residue of the pole at s = 0", nc[0])
    lead_n = nc[-1]
    sign = 1 if rel == -1 or _at(lead_n, center) > 0 else -1
    add(ConditionKind.RELATIVE_DEGREE, "leading coefficient of N", sign * lead_n)
    nr, ni = _re_im(nc)
    dr, di = _re_im(dc)
    pw = sp.Poly(sp.expand(nr * dr + ni * di), _W)
    cx = [sp.expand(pw.coeff_monomial(_W ** (2 * i))) for i in range(pw.degree() // 2 + 1)]
    nz = [i for i, c in enumerate(cx) if c != 0]
    if nz:
        k, d = nz[0], nz[-1]
        q = sum((cx[i] * _T ** (i - k) * (1 - _T) ** (d - i) for i in range(k, d + 1)), sp.S.Zero)
        add(ConditionKind.REAL_PART, "Re Z(jw) numerator P(x), x = t/(1 - t)", q)
    return FamilyConditions(names=names, conditions=tuple(conds))
