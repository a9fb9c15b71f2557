"""The one transcendental atom the parser accepts: a pure delay ``exp(-NAME*s)``.

A delay factor ``e^{-sτ}`` with ``τ`` a parameter (seconds) is parsed into
``Delay(tau)``, a sympy function application of the delay parameter.  For every
rational-function tool above it is a constant generator ``E`` (it does not contain
``s``), so a model with a delay is a rational function of ``s`` and ``E`` and
the free-body derivation is unchanged; the delay parameter stays a parameter of the
model (``SEA.parameters`` lists it and ``values`` gives it).  What a delay *means*
(``E = e^{-sτ}`` on the imaginary axis, in the characteristic equation) is decided in
[`seapass.delay`][seapass.delay], never here.

Accepted spellings: ``exp(-tau*s)``, ``exp(-s*tau)``, ``exp(-(tau*s))`` and a positive
whole multiple ``exp(-2*tau*s)`` (``= Delay(tau)**2``).  Anything else with ``exp`` (or
any other call) is refused with the parser's usual function-call message.

Examples
--------
>>> from seapass.model.expr import parse_expression
>>> z = parse_expression("kd*exp(-tau*s)", ["kd", "tau"])
>>> z
kd*exp(-tau*s)
>>> delay_names(z)
('tau',)
>>> parse_expression("exp(-2*tau*s)", ["tau"]) == Delay(symbol("tau")) ** 2
True
"""

from __future__ import annotations

import ast
from typing import Any

import sympy as sp

from ..errors import ExpressionError
from ..files.limits import MAX_DELAY_MULTIPLE

__all__ = [
    "DELAY_HINT",
    "Delay",
    "check_one_delay",
    "delay_atoms",
    "delay_factor",
    "delay_names",
    "delay_text",
    "has_delay",
    "symbol",
]

DELAY_HINT = "the one function allowed is a delay exp(-NAME*s) with NAME a parameter in seconds"


def symbol(name: str) -> sp.Symbol:
    """The positive real parameter symbol (the same as `seapass.model.expr.symbol`)."""
    return sp.Symbol(name, positive=True)


class Delay(sp.Function):
    """``e^{-s·τ}`` of the delay parameter ``τ`` (``Delay(tau)``); printed ``exp(-tau*s)``."""

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


def has_delay(expr: Any) -> bool:
    """True if ``expr`` contains a delay factor."""
    return bool(delay_atoms(expr))


def delay_text(expr: Any) -> str:
    """``"a delay exp(-tau*s)"`` for messages (``"no delay"`` without one)."""
    atoms = sorted(delay_atoms(expr), key=str)
    if not atoms:
        return "no delay"
    return "a delay " + " and ".join(str(a) for a in atoms)


def delay_names(expr: Any) -> tuple[str, ...]:
    """Names of the delay parameters in ``expr``, sorted (numbers shown as text)."""
    return tuple(sorted(str(a.args[0]) for a in delay_atoms(expr)))


def check_one_delay(expr: Any, where: str) -> None:
    """Refuse two different delays (``exp(-tau*s)`` and ``exp(-tau2*s)``) in one model.

    Powers of one delay (``exp(-2*tau*s)``) are fine: they are one delay, commensurate.
    """
    names = delay_names(expr)
    if len(names) > 1:
        raise ExpressionError(
            f"{where}: two different delays ({', '.join(names)}); seapass supports one delay "
            "parameter per model: exp(-NAME*s) and its whole multiples exp(-2*NAME*s)"
        )


def _refuse(src: str) -> ExpressionError:
    return ExpressionError(
        f"function call is not allowed in {src!r}: use numbers, parameter names, s, "
        f"+ - * / and integer powers; {DELAY_HINT}, e.g. 'kd*exp(-tau*s)'"
    )


def _factors(node: ast.AST, sign: int, out: list[ast.AST]) -> int:
    """Flatten a product with unary signs into its factors; return the overall sign."""
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult):
        sign = _factors(node.left, sign, out)
        return _factors(node.right, sign, out)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        return _factors(node.operand, -sign if isinstance(node.op, ast.USub) else sign, out)
    out.append(node)
    return sign


def delay_factor(node: ast.Call, allowed: set[str], src: str) -> sp.Expr:
    """The delay atom of a call node ``exp(-k*NAME*s)``, or the parser's function-call error.

    ``k`` is an optional positive whole number (default 1), ``NAME`` a known parameter.
    """
    if not (
        isinstance(node.func, ast.Name)
        and node.func.id == "exp"
        and len(node.args) == 1
        and not node.keywords
    ):
        raise _refuse(src)
    factors: list[ast.AST] = []
    sign = _factors(node.args[0], 1, factors)
    names = [f.id for f in factors if isinstance(f, ast.Name)]
    consts = [f for f in factors if isinstance(f, ast.Constant)]
    others = [f for f in factors if not isinstance(f, ast.Name | ast.Constant)]
    params = [n for n in names if n != "s"]
    if others or names.count("s") != 1 or len(params) != 1:
        raise _refuse(src)
    multiple = 1
    for c in consts:
        v = c.value
        if isinstance(v, bool) or not isinstance(v, int | float) or v != int(v) or v < 1:
            raise ExpressionError(
                f"delay in {src!r}: a constant factor in exp(-k*NAME*s) must be a positive "
                f"whole number k; write the delay as one parameter, e.g. exp(-tau*s)"
            )
        multiple *= int(v)
    if sign > 0:
        raise ExpressionError(
            f"delay in {src!r}: exp(+NAME*s) is a prediction, not a delay; "
            f"{DELAY_HINT} (note the minus sign)"
        )
    if multiple > MAX_DELAY_MULTIPLE:
        raise ExpressionError(
            f"delay in {src!r}: the multiple {multiple} exceeds the limit of "
            f"{MAX_DELAY_MULTIPLE}; give the longer delay its own value instead"
        )
    name = params[0]
    if name not in allowed:
        from ..errors import did_you_mean

        known = ", ".join(sorted(allowed)) or "none"
        raise ExpressionError(
            f"unknown symbol {name!r} in {src!r}{did_you_mean(name, allowed)}: known symbols "
            f"are s, {known}; a delay parameter needs a value in seconds, "
            f"e.g. values={{{name!r}: 0.001}}"
        )
    return Delay(symbol(name)) ** multiple
