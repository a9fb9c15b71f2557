"""Exact rational functions of ``s`` and the parameters, on FLINT's multivariate polynomials.

A `Frac` is ``num/den`` with ``num, den`` `flint.fmpq_mpoly` in one context
whose first variable is ``s`` and whose others are parameter names, reduced by
FLINT's exact multivariate gcd.  The two-port's free-body equations are solved
with them (sympy's general ``cancel`` is about a hundred times slower), and
substituting values (all of them, or all but one or two parameters) gives the
exact polynomials the decisions and the critical gains are computed from.

Conversions to and from sympy are exact (`from_sympy`, `to_sympy`); nothing is
evaluated in floating point.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import sympy as sp
from flint import fmpq, fmpq_mpoly, fmpq_mpoly_ctx, fmpq_poly, fmpz
from sympy.polys.polyutils import expr_from_dict

from ..model.expr import S, symbol

__all__ = [
    "Frac",
    "cancelled",
    "context",
    "frac_of",
    "from_sympy",
    "to_fmpq_poly",
    "to_sympy",
    "variables_of",
]


@functools.lru_cache(maxsize=256)
def context(names: tuple[str, ...]) -> fmpq_mpoly_ctx:
    """The polynomial ring over ``("s", *names)`` (cached; ``s`` is variable 0)."""
    return fmpq_mpoly_ctx.get(("s", *names))


def variables_of(exprs: Iterable[sp.Expr]) -> tuple[str, ...]:
    """Sorted parameter names used by ``exprs`` (``s`` excluded)."""
    return tuple(sorted({str(x) for e in exprs for x in sp.sympify(e).free_symbols if x != S}))


@dataclass(frozen=True, kw_only=True)
class Frac:
    """``num/den`` in lowest terms; ``den``'s leading term has a positive coefficient."""

    num: fmpq_mpoly
    den: fmpq_mpoly

    @staticmethod
    def make(num: fmpq_mpoly, den: fmpq_mpoly) -> Frac:
        if den.is_zero():
            raise ZeroDivisionError("zero denominator")
        if num.is_zero():
            return Frac(num=num, den=den.context().from_dict({(0,) * den.context().nvars(): 1}))
        if den.is_constant():
            c = den.leading_coefficient()
            return Frac(num=num / c, den=den / c)
        g = num.gcd(den)
        if not g.is_constant():
            num, den = num / g, den / g
        lead = den.leading_coefficient()
        return Frac(num=num / lead, den=den / lead)

    def size(self) -> int:
        """Number of terms of numerator and denominator (a cost for choosing pivots)."""
        return len(self.num.to_dict()) + len(self.den.to_dict())

    @property
    def ctx(self) -> fmpq_mpoly_ctx:
        return self.num.context()

    def __add__(self, other: Frac) -> Frac:
        if self.den == other.den:
            return Frac.make(self.num + other.num, self.den)
        return Frac.make(self.num * other.den + other.num * self.den, self.den * other.den)

    def __sub__(self, other: Frac) -> Frac:
        if self.den == other.den:
            return Frac.make(self.num - other.num, self.den)
        return Frac.make(self.num * other.den - other.num * self.den, self.den * other.den)

    def __mul__(self, other: Frac) -> Frac:
        return Frac.make(self.num * other.num, self.den * other.den)

    def __truediv__(self, other: Frac) -> Frac:
        if other.num.is_zero():
            raise ZeroDivisionError("division by a zero rational function")
        return Frac.make(self.num * other.den, self.den * other.num)

    def __neg__(self) -> Frac:
        return Frac(num=-self.num, den=self.den)

    def is_zero(self) -> bool:
        return bool(self.num.is_zero())

    def substitute(
        self, values: Mapping[str, fmpq], keep: Sequence[str]
    ) -> tuple[fmpq_mpoly, fmpq_mpoly]:
        """``(N, D)`` with ``values`` substituted, in the context ``("s", *keep)`` (not reduced).

        The numerator and denominator are those of the generic reduced form:
        a factor that cancels only for these numbers is still there.
        """
        ctx = self.ctx
        names = ctx.names()[1:]
        used = [max(a, b) > 0 for a, b in zip(self.num.degrees(), self.den.degrees(), strict=True)][
            1:
        ]
        missing = [
            n for n, u in zip(names, used, strict=True) if u and n not in keep and n not in values
        ]
        if missing:
            raise KeyError(missing[0])
        subs: dict[str | int, int | fmpz | fmpq] = {
            n: values.get(n, fmpq(0)) for n in names if n not in keep
        }
        target = context(tuple(keep))
        out = []
        for p in (self.num, self.den):
            q = p.subs(subs) if subs else p
            index = [0] + [names.index(k) + 1 if k in names else None for k in keep]
            terms = {}
            for monom, c in q.to_dict().items():
                terms[tuple(monom[i] if i is not None else 0 for i in index)] = c
            out.append(target.from_dict(terms) if terms else target.from_dict({}))
        return out[0], out[1]


def to_fmpq_poly(p: fmpq_mpoly) -> fmpq_poly:
    """A polynomial in ``s`` alone (context ``("s",)``) as a `flint.fmpq_poly`."""
    d = p.to_dict()
    if not d:
        return fmpq_poly([])
    deg = max(m[0] for m in d)
    coeffs = [fmpq(0)] * (deg + 1)
    for m, c in d.items():
        coeffs[m[0]] = c
    return fmpq_poly(coeffs)


_KNOWN: dict[sp.Expr, Frac] = {}
"""Fractions whose sympy form was made by `to_sympy`: converting back is a look-up."""
_KNOWN_MAX = 4096


def from_sympy(expr: sp.Expr, names: tuple[str, ...]) -> Frac:
    """``expr`` (rational in ``s`` and ``names``) as a reduced `Frac` in ``context(names)``."""
    known = _KNOWN.get(expr)
    if known is not None and tuple(known.ctx.names()[1:]) == tuple(names):
        return known
    return _from_sympy(expr, names)


def frac_of(expr: sp.Expr) -> Frac:
    """``expr`` as a reduced `Frac` in any context holding its parameters (perhaps more).

    A look-up when ``expr`` was made by `to_sympy`; else ``from_sympy`` over its own
    parameters.
    """
    known = _KNOWN.get(expr)
    if known is not None:
        return known
    return _from_sympy(expr, variables_of([expr]))


@functools.lru_cache(maxsize=2048)
def _from_sympy(expr: sp.Expr, names: tuple[str, ...]) -> Frac:
    ctx = context(names)
    gens = (S, *(symbol(n) for n in names))
    expr = sp.sympify(expr)
    num, den = sp.fraction(expr)
    if not (num.is_polynomial(*gens) and den.is_polynomial(*gens)):
        num, den = sp.fraction(sp.together(expr))
    polys = []
    for part in (num, den):
        poly = sp.Poly(sp.expand(part), *gens, domain="QQ")
        polys.append(
            ctx.from_dict({m: fmpq(int(c.p), int(c.q)) for m, c in poly.terms() if c != 0})
        )
    return Frac.make(polys[0], polys[1])


def _poly_expr(p: fmpq_mpoly, gens: Sequence[sp.Symbol]) -> sp.Expr:
    terms = {m: sp.Rational(int(c.p), int(c.q)) for m, c in p.to_dict().items()}
    return expr_from_dict(terms, *gens) if terms else sp.S.Zero


def to_sympy(f: Frac) -> sp.Expr:
    """The sympy expression of ``f`` (parameters as the positive symbols of `seapass.model.expr`).

    The denominator is written with coprime integer coefficients, as sympy's
    ``cancel`` writes it.
    """
    names = f.ctx.names()
    gens = [S, *(symbol(n) for n in names[1:])]
    coeffs = f.den.coeffs()
    lcm_den = functools.reduce(lambda a, b: a * b // math.gcd(a, b), (int(c.q) for c in coeffs), 1)
    gcd_num = functools.reduce(math.gcd, (abs(int(c.p)) for c in coeffs), 0) or 1
    scale = fmpq(lcm_den, gcd_num)
    num, den = _poly_expr(f.num * scale, gens), _poly_expr(f.den * scale, gens)
    return _remember(num / den if den != 1 else num, f)


def _remember(expr: sp.Expr, f: Frac) -> sp.Expr:
    if len(_KNOWN) >= _KNOWN_MAX:
        _KNOWN.clear()
    _KNOWN[expr] = f
    return expr


def cancelled(expr: sp.Expr) -> sp.Expr:
    """``expr`` as one cancelled fraction (FLINT's gcd; sympy's ``cancel`` is far slower)."""
    names = variables_of([expr])
    return to_sympy(from_sympy(expr, names))
