"""The sympy side of the parser: symbols, the sympy algebra, validation of sympy input.

Only the symbolic analyses (conditions, regions, the stiffness derivation shown to
people, plots of formulas) build sympy expressions; the numeric path works on exact
rational functions ([`seapass.model.rational`][seapass.model.rational]) and never
imports this module.  The parser proper (the whitelist, the fold of a checked tree)
lives in [`seapass.model.expr`][seapass.model.expr].

What lives here: `S`, `W`, `symbol`, `Delay` (the sympy form of a delay factor
``exp(-NAME*s)``, see [`seapass.model.delayatom`][seapass.model.delayatom]),
`sympy_expression`, `check_sympy_input`, `exact_from_sympy`.
May import: [`seapass.errors`][seapass.errors], [`seapass.files`][seapass.files] and
the modules of [`seapass.model`][seapass.model] below it (`expr`, `budget`, `rational`).
"""

from __future__ import annotations

import ast
from collections.abc import Iterable
from fractions import Fraction
from typing import Any

import sympy as sp
from flint import fmpq

from ..errors import ExpressionError
from .budget import check_symbolic_size
from .delayatom import check_one_delay, delay_variable
from .expr import evaluate
from .rational import RatFunc, context, variables

__all__ = [
    "Delay",
    "S",
    "W",
    "check_sympy_input",
    "delay_atoms",
    "delay_names",
    "exact_from_sympy",
    "symbol",
    "sympy_expression",
]

S = sp.Symbol("s")
"""Laplace variable and angular frequency."""
W = sp.Symbol("w", real=True)


def symbol(name: str) -> sp.Symbol:
    """Return the positive real sympy symbol used for parameter ``name``."""
    return sp.Symbol(name, positive=True)


class Delay(sp.Function):
    """``e^{-s·τ}`` of the delay parameter ``τ`` (``Delay(tau)``); printed ``exp(-tau*s)``.

    For sympy it is a constant (it does not contain ``s``): a generator ``E``.

    Examples
    --------
    >>> from seapass.model.expr import parse_expression
    >>> z = parse_expression("kd*exp(-2*tau*s)", ["kd", "tau"])
    >>> z, delay_names(z)
    (kd*exp(-tau*s)**2, ('tau',))
    """

    nargs = 1

    def _sympystr(self, printer: Any) -> str:
        arg = printer._print(self.args[0])
        if not self.args[0].is_Symbol:
            arg = f"({arg})"
        return f"exp(-{arg}*s)"

    def _latex(self, printer: Any) -> str:
        return rf"e^{{-{printer._print(self.args[0])} s}}"


def delay_atoms(expr: Any) -> set[sp.Expr]:
    """The distinct delay applications ``Delay(τ)`` in ``expr``."""
    if not isinstance(expr, sp.Basic):
        return set()
    return set(expr.atoms(Delay))


def delay_names(expr: Any) -> tuple[str, ...]:
    """Names of the delay parameters in ``expr``, sorted."""
    return tuple(sorted(str(a.args[0]) for a in delay_atoms(expr)))


class _Sympy:
    """The sympy algebra of [`evaluate`][seapass.model.expr.evaluate]."""

    def __init__(self, src: str) -> None:
        self.src = src

    def number(self, value: Fraction) -> sp.Expr:
        return sp.Integer(value.numerator) if value.denominator == 1 else sp.Rational(value)

    def laplace(self) -> sp.Expr:
        return S

    def parameter(self, name: str) -> sp.Expr:
        return symbol(name)

    def add(self, left: sp.Expr, right: sp.Expr) -> sp.Expr:
        return left + right

    def sub(self, left: sp.Expr, right: sp.Expr) -> sp.Expr:
        return left - right

    def mul(self, left: sp.Expr, right: sp.Expr) -> sp.Expr:
        return left * right

    def div(self, left: sp.Expr, right: sp.Expr) -> sp.Expr:
        # bounded before expanding: sp.simplify here could run for minutes
        check_symbolic_size(right, repr(self.src))
        if right == 0 or sp.expand(sp.numer(sp.together(right))) == 0:
            raise ZeroDivisionError
        return left / right

    def neg(self, operand: sp.Expr) -> sp.Expr:
        return -operand

    def power(self, base: sp.Expr, exponent: int) -> sp.Expr:
        if exponent < 0 and base == 0:
            raise ZeroDivisionError
        return base**exponent

    def delay(self, name: str, multiple: int) -> sp.Expr:
        return Delay(symbol(name)) ** multiple


def sympy_expression(tree: ast.expr, src: str) -> sp.Expr:
    """The sympy expression of a tree checked by [`parse_tree`][seapass.model.expr.parse_tree]."""
    expr = evaluate(tree, _Sympy(src), src)
    check_symbolic_size(expr, repr(src))
    return expr


def check_sympy_input(expr: sp.Expr, allowed: Iterable[str], what: str) -> sp.Expr:
    """Validate a sympy expression given directly (not as text).

    Checks that its free symbols are ``s`` or allowed parameter names and that
    it is a rational function of ``s``; returns it with parameters mapped to
    the canonical positive symbols.
    """
    try:
        expr = sp.sympify(expr, strict=True)  # already a sympy/numeric object, not user text
    except (sp.SympifyError, TypeError) as exc:
        raise ExpressionError(f"{what}: not a sympy expression ({exc})") from None
    allowed_set = set(allowed)
    subs = {}
    for sym in expr.free_symbols:
        name = str(sym)
        if name == "s":
            subs[sym] = S
        elif name in allowed_set:
            subs[sym] = symbol(name)
        else:
            raise ExpressionError(f"{what}: unknown symbol {name!r}")
    expr = expr.xreplace(subs)
    check_one_delay(delay_names(expr), what)
    if any(not a.args[0].is_Symbol for a in delay_atoms(expr)):
        raise ExpressionError(f"{what}: a delay must be exp(-NAME*s) with NAME a parameter")
    if not expr.is_rational_function(S):
        raise ExpressionError(f"{what}: {expr} is not a rational function of s")
    check_symbolic_size(expr, what)
    return expr


def exact_from_sympy(expr: sp.Expr, what: str) -> RatFunc:
    """The exact rational function of a validated sympy expression (see `check_sympy_input`).

    Raises
    ------
    ExpressionError
        When a coefficient is not a rational number (``sqrt(2)*s``, say).
    """
    # a delay Delay(tau) is the exact variable _E_tau (see seapass.model.delayatom)
    expr = expr.xreplace({a: sp.Symbol(delay_variable(str(a.args[0]))) for a in delay_atoms(expr)})
    num, den = sp.fraction(sp.together(expr))
    gens = [x for x in (num.free_symbols | den.free_symbols)]
    ctx = context(variables(str(x) for x in gens if x != S))
    order = [next(x for x in gens if str(x) == n) if n != "s" else S for n in ctx.names()]

    def poly(e: sp.Expr) -> Any:
        try:
            p = sp.Poly(sp.expand(e), *order, domain="QQ")
        except (sp.PolynomialError, sp.CoercionFailed, sp.GeneratorsNeeded) as exc:
            raise ExpressionError(f"{what}: {expr} has a coefficient that is not rational") from exc
        return ctx.from_dict(
            {m: fmpq(int(c.p), int(c.q)) for m, c in zip(p.monoms(), p.coeffs(), strict=True)}
        )

    try:
        return RatFunc.from_polys(poly(num), poly(den))
    except ZeroDivisionError:
        raise ExpressionError(f"{what}: division by zero in {expr}") from None
