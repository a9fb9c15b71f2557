"""The one transcendental atom the parser accepts: a pure delay ``exp(-NAME*s)``.

A delay factor ``e^{-sτ}`` with ``τ`` a parameter (seconds) is a call node of the
checked tree (`delay_call` validates it).  Every algebra of
[`seapass.model.expr`][seapass.model.expr] folds it with its ``delay`` operation:

- the exact algebra ([`seapass.model.rational`][seapass.model.rational]) makes it the
  variable ``_E_tau`` (`delay_variable`; a leading underscore is never a user's name), a
  constant generator for every rational-function tool, so a model with a delay is a
  rational function of ``s`` and ``E`` and the free-body derivation is unchanged;
- the sympy algebra makes it ``Delay(tau)``
  ([`seapass.model.symbolic`][seapass.model.symbolic]).

The delay parameter stays a parameter of the model (``SEA.parameters`` lists it and
``values`` gives it).  What a delay *means* (``E = e^{-sτ}`` on the imaginary axis, in
the characteristic equation) is decided in [`seapass.delay`][seapass.delay], never here.
Substituting values into a polynomial that still holds ``E``
([`seapass.model.rational.univariate`][seapass.model.rational.univariate]) raises
[`DelayError`][seapass.errors.DelayError]: a rational analysis never sees a delay as a
number.

Accepted spellings: ``exp(-tau*s)``, ``exp(-s*tau)``, ``exp(-(tau*s))`` and a positive
whole multiple ``exp(-2*tau*s)`` (``= E**2``).  Anything else with ``exp`` (or any other
call) is refused with the parser's usual function-call message.  This module imports
neither sympy nor the model classes.

Examples
--------
>>> import ast
>>> delay_call(ast.parse("exp(-2*tau*s)", mode="eval").body, frozenset({"tau"}), "")
('tau', 2)
>>> delay_variable("tau"), delay_of_variable("_E_tau"), delay_of_variable("tau")
('_E_tau', 'tau', None)
"""

from __future__ import annotations

import ast
from collections.abc import Iterable
from typing import Any

from ..errors import DelayError, ExpressionError, did_you_mean
from ..files.limits import MAX_DELAY_MULTIPLE

__all__ = [
    "DELAY_HINT",
    "DELAY_PREFIX",
    "call_names",
    "check_one_delay",
    "delay_call",
    "delay_of_variable",
    "delay_refusal",
    "delay_variable",
    "model_delays",
    "tree_delays",
]

DELAY_HINT = "the one function allowed is a delay exp(-NAME*s) with NAME a parameter in seconds"

DELAY_PREFIX = "_E_"
"""Prefix of the exact variable ``E = e^{-s·NAME}`` (never a user's name: it starts with ``_``)."""


def delay_variable(name: str) -> str:
    """The exact algebra's variable for the delay parameter ``name``."""
    return DELAY_PREFIX + name


def delay_of_variable(variable: str) -> str | None:
    """The delay parameter of an exact variable ``_E_NAME`` (None for another variable)."""
    return variable[len(DELAY_PREFIX) :] if variable.startswith(DELAY_PREFIX) else None


def delay_refusal(name: str) -> DelayError:
    """The error of a rational analysis given a model with the delay ``exp(-name*s)``."""
    return DelayError(
        f"a delay exp(-{name}*s) in the model: this rational analysis does not apply to a "
        "delayed design; seapass.is_passive, seapass.delay_margin and the commands "
        "'seapass check' and 'seapass delay-margin' decide delayed designs"
    )


def model_delays(system: Any) -> tuple[str, ...]:
    """The delay parameters of an `SEA`, an `Impedance` or a `RatFunc`, sorted.

    Read from the exact forms (no sympy); anything else has none.
    """
    names: set[str] = set()
    if hasattr(system, "exact_elements"):  # an SEA
        for f in system.exact_elements().values():
            names |= f.names()
    elif hasattr(system, "exact") and callable(system.exact):  # an Impedance
        names |= system.exact().names()
    elif hasattr(system, "names") and hasattr(system, "num"):  # a RatFunc
        names |= system.names()
    return tuple(sorted(d for n in names if (d := delay_of_variable(n)) is not None))


def tree_delays(tree: ast.AST) -> frozenset[str]:
    """The delay parameters of a checked tree (the ``NAME`` of each ``exp(-NAME*s)``)."""
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            out.add(delay_call(node, None, "")[0])
    return frozenset(out)


def call_names(tree: ast.AST) -> frozenset[str]:
    """The names used as functions in a tree (``exp``): not parameters."""
    return frozenset(
        n.func.id
        for n in ast.walk(tree)
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)
    )


def check_one_delay(names: Iterable[str], where: str) -> None:
    """Refuse two different delays (``exp(-tau*s)`` and ``exp(-tau2*s)``) in one model.

    Powers of one delay (``exp(-2*tau*s)``) are fine: they are one delay, commensurate.
    """
    names = sorted(set(names))
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


def delay_call(node: ast.Call, allowed: frozenset[str] | None, src: str) -> tuple[str, int]:
    """``(NAME, k)`` of a call node ``exp(-k*NAME*s)``, or the parser's function-call error.

    ``k`` is an optional positive whole number (default 1), ``NAME`` a known parameter
    (any name when ``allowed`` is None: the tree was checked before).
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
            f"{MAX_DELAY_MULTIPLE}; "
            "give the longer delay its own value instead"
        )
    name = params[0]
    if allowed is not None and name not in allowed:
        known = ", ".join(sorted(allowed)) or "none"
        raise ExpressionError(
            f"unknown symbol {name!r} in {src!r}{did_you_mean(name, allowed)}: known symbols "
            f"are s, {known}; a delay parameter needs a value in seconds, "
            f"e.g. values={{{name!r}: 0.001}}"
        )
    return name, multiple
