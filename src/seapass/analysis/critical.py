"""Critical values of one parameter: where the passivity verdict of a design may change.

With every parameter but one (``p``) fixed to exact rationals, each condition of the
positive-real test can change its truth value only at a real root of one of the
*critical polynomials* in ``p`` (`critical_polys`; the list is in the module docstring
of [`seapass.analysis.region`][seapass.analysis.region]).  `critical_values` isolates
their real roots in a range exactly: rational roots exactly, irrational ones by
pairwise disjoint isolating intervals of an irreducible factor (`CriticalValue`).

May import: [`seapass.exact`][seapass.exact] and [`seapass.model`][seapass.model].
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy as sp
from flint import fmpq, fmpq_poly

from ..errors import ParameterError
from ..exact import poly as ep
from ..model.expr import S, symbol
from ..model.sea import SEA, Impedance
from ..model.stiffness import load_impedance

__all__ = [
    "CriticalValue",
    "critical_polynomials",
    "critical_polys",
    "critical_values",
    "substituted",
]

_X = sp.Symbol("x")
_OM = sp.Symbol("omega")


def _univariate(expr: sp.Expr, p: sp.Symbol) -> fmpq_poly:
    """Exact polynomial in ``p`` (zero if identically zero)."""
    expr = sp.expand(expr)
    if expr == 0:
        return fmpq_poly([])
    poly = sp.Poly(expr, p, domain="QQ")
    return fmpq_poly([fmpq(int(c.p), int(c.q)) for c in poly.all_coeffs()[::-1]])


def _re_im_at_jw(expr: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """Real and imaginary parts of ``expr(jω)`` for a polynomial in ``s`` with real coefficients."""
    coeffs = sp.Poly(expr, S).all_coeffs()[::-1]
    re = sum((c * (-1) ** (k // 2) * _OM**k for k, c in enumerate(coeffs) if k % 2 == 0), sp.S.Zero)
    im = sum((c * (-1) ** (k // 2) * _OM**k for k, c in enumerate(coeffs) if k % 2 == 1), sp.S.Zero)
    return sp.expand(re), sp.expand(im)


def critical_polys(z: sp.Expr, p: sp.Symbol) -> list[sp.Expr]:
    """The critical polynomials in ``p`` of an impedance ``z`` (see the module docstring)."""
    num, den = sp.fraction(sp.cancel(sp.together(z)))
    # clear denominators in p so both are polynomials in (s, p)
    num, den = sp.expand(num), sp.expand(den)
    out: list[sp.Expr] = []
    pn, pd = sp.Poly(num, S), sp.Poly(den, S)
    out += [pn.LC(), pd.LC()]
    if pn.degree() > 0 and pd.degree() > 0:
        out.append(sp.resultant(num, den, S))
    else:
        out += [pn.as_expr(), pd.as_expr()] if pn.degree() <= 0 else [pd.as_expr()]
    re_d, im_d = _re_im_at_jw(den)
    re_n, im_n = _re_im_at_jw(num)
    g = sp.gcd(re_d, im_d) if im_d != 0 else re_d
    g = sp.expand(g)
    if im_d != 0:
        r1, r2 = sp.cancel(re_d / g), sp.cancel(im_d / g)
        if sp.Poly(r1, _OM).degree() > 0 and sp.Poly(r2, _OM).degree() > 0:
            out.append(sp.resultant(r1, r2, _OM))
        else:
            out += [sp.Poly(r1, _OM).LC(), sp.Poly(r2, _OM).LC()]
    if g.has(_OM):
        gp = sp.Poly(g, _OM)
        out += [gp.LC(), g.subs(_OM, 0)]
        if gp.degree() > 1:
            out.append(sp.discriminant(g, _OM))
        ddr, ddi = _re_im_at_jw(sp.diff(den, S))
        for res in (sp.expand(re_n * ddr + im_n * ddi), sp.expand(im_n * ddr - re_n * ddi)):
            if res != 0:
                out.append(sp.resultant(g, res, _OM) if gp.degree() > 0 else res)
    # real part polynomial in x = ω²
    pw = sp.expand(re_n * re_d + im_n * im_d)
    if pw != 0:
        px = sp.expand(pw.subs(_OM, sp.sqrt(_X)))
        poly = sp.Poly(px, _X)
        # remove the generic power of x and generic repeated factors
        k = min(m[0] for m in poly.monoms())
        q = sp.Poly(sp.cancel(px / _X**k), _X)
        q = sp.Poly(sp.sqf_part(q.as_expr()), _X) if q.degree() > 0 else q
        out += [poly.LC(), q.as_expr().subs(_X, 0)]
        if q.degree() > 1:
            out.append(sp.discriminant(q.as_expr(), _X))
        # each coefficient of P matters where P may vanish identically
        out += [c for c in poly.all_coeffs() if c.has(p)]
    return [sp.expand(e) for e in out if sp.expand(e) != 0]


def critical_polynomials(
    system: SEA | Impedance,
    params: Sequence[str],
    *,
    values: Mapping[str, float | None] | None = None,
) -> list[sp.Expr]:
    """Polynomials in ``params`` on whose real zero set the verdict of ``system`` may change.

    Every parameter of ``system`` not in ``params`` must have a value (in
    ``system`` or ``values``); the result holds the critical polynomials
    described in the module docstring, with all of ``params`` symbolic (used
    for 2-D regions by [`seapass.analysis.boundary`][seapass.analysis.boundary]).
    """
    base = substituted(system, {**(values or {}), **dict.fromkeys(params)})
    free = [n for n in base.parameters if n not in params and base.values.get(n) is None]
    if free:
        raise ParameterError(f"no value for parameter(s) {', '.join(free)}")
    z = load_impedance(base) if isinstance(base, SEA) else base.expr
    z = z.xreplace(base.substitutions())
    out: dict[sp.Expr, None] = {}
    for name in params:
        out.update(dict.fromkeys(critical_polys(z, symbol(name))))
    return list(out)


@dataclass(frozen=True, eq=False, kw_only=True)
class CriticalValue:
    """A critical value: the rational ``lo`` (``lo == hi``) or the only root of the
    irreducible ``poly`` (degree >= 2, so irrational) in ``(lo, hi]``."""

    lo: Fraction
    hi: Fraction
    poly: fmpq_poly | None = None

    def separated(self, other: CriticalValue) -> tuple[CriticalValue, CriticalValue]:
        """Both narrowed until their intervals are disjoint (distinct roots)."""
        a, b = self, other
        for _ in range(ep.MAX_BISECTIONS):
            if a.hi < b.lo or b.hi < a.lo or (a.lo == a.hi and b.lo == b.hi):
                return a, b
            a, b = a.halved(), b.halved()
        raise ArithmeticError("critical values could not be separated")

    def halved(self) -> CriticalValue:
        if self.poly is None:
            return self
        lo, hi = (ep.rational(x) for x in (self.lo, self.hi))
        lo, hi = ep.refine(self.poly, (lo, hi), (hi - lo) / 2)
        return CriticalValue(lo=ep.to_fraction(lo), hi=ep.to_fraction(hi), poly=self.poly)


def critical_values(
    polys: list[sp.Expr], p: sp.Symbol, lo: Fraction, hi: Fraction
) -> list[CriticalValue]:
    """Sorted critical values in ``[lo, hi]``: rational roots exactly, irrational ones by
    tight isolating intervals ``(a, b]`` (relative width 2^-60), pairwise disjoint."""
    factors: set[sp.Expr] = set()
    for e in polys:
        if not e.has(p):
            continue
        for f, _mult in sp.factor_list(sp.Poly(e, p, domain="QQ"))[1]:
            factors.add(f.monic().as_expr())
    out: dict[tuple[Fraction, Fraction], CriticalValue] = {}
    for f in factors:
        q = _univariate(f, p)
        if q.degree() == 1:
            r = ep.to_fraction(-q[0] / q[1])
            if lo <= r <= hi:
                out[r, r] = CriticalValue(lo=r, hi=r)
            continue
        for a, b in ep.isolate_real_roots(q, lo, hi):
            a, b = ep.refine(q, (a, b), max(abs(b), fmpq(1)) / fmpq(2) ** 40)
            scale_ = min(abs(a), abs(b)) or fmpq(1, 2**40)
            a, b = ep.refine(q, (a, b), scale_ / fmpq(2) ** 60)
            lo_, hi_ = ep.to_fraction(a), ep.to_fraction(b)
            out[lo_, hi_] = CriticalValue(lo=lo_, hi=hi_, poly=q)
    points = sorted(out.values(), key=lambda c: (c.lo, c.hi))
    for i in range(len(points) - 1):  # roots closer than 2^-60: narrow both
        if points[i + 1].lo <= points[i].hi:
            points[i], points[i + 1] = points[i].separated(points[i + 1])
    return sorted(points, key=lambda c: (c.lo, c.hi))


def substituted(system: SEA | Impedance, values: Mapping[str, Any]) -> SEA | Impedance:
    """``system`` with ``values``; a `Fraction` that is not a double is substituted exactly."""
    vals = {k: (float(v) if isinstance(v, Fraction) else v) for k, v in values.items()}
    exact = {k: v for k, v in values.items() if isinstance(v, Fraction)}
    if exact and any(Fraction(float(v)) != v for v in exact.values()):
        # a rational test point that is not a float: substitute it exactly
        subs = {symbol(k): sp.Rational(v.numerator, v.denominator) for k, v in exact.items()}
        expr = load_impedance(system) if isinstance(system, SEA) else system.expr
        rest = {k: v for k, v in vals.items() if k not in exact}
        z = expr.xreplace(subs)
        left = {str(x) for x in z.free_symbols}  # the substituted names are gone from z
        merged = {**system.values, **rest}
        return Impedance(expr=z, values={k: v for k, v in merged.items() if k in left})
    if isinstance(system, SEA):
        return system.with_values(**vals)
    return Impedance(expr=system.expr, values={**system.values, **vals})
