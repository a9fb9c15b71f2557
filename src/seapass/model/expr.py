"""Safe parsing of rational expressions and parameter values.

User text is never given to `eval` or to a plain `sympy.sympify`.
It is parsed by `ast` in ``eval`` mode and every node is checked against a
whitelist (`parse_tree`): numeric literals, whitelisted names, ``+ - * /``, unary
signs, integer powers (``**`` or ``^``) and one delay factor ``exp(-NAME*s)`` (the only
call allowed; see [`seapass.model.delayatom`][seapass.model.delayatom]).  The checked tree is then folded node
by node by `evaluate`, with one dispatch table from node kinds to the operations of
an *algebra*, so no user string ever reaches a code path that can execute code.
Two algebras exist: exact rational functions of ``s`` and the parameters
(`exact_expression`, [`seapass.model.rational`][seapass.model.rational]; no sympy)
and sympy expressions (`parse_expression`, for the symbolic analyses; sympy is
imported on first use).  A new kind of atom is one more entry of the table and one
more algebra operation, as the delay factor is (``delay``).
"""

from __future__ import annotations

import ast
import functools
import math
import warnings
from collections.abc import Callable, Iterable, Mapping
from fractions import Fraction
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Generic, Protocol, TypeVar

from ..errors import ExpressionError, ParameterError, SymbolicLimitError, did_you_mean
from ..files.limits import MAX_EXPONENT, MAX_EXPRESSION_LENGTH, MAX_NODES
from .delayatom import call_names, check_one_delay, delay_call, delay_variable, tree_delays
from .values import (
    check_ascii,
    check_name,
    finite_number,
    parse_value,
    to_fraction,
    underflows,
    validate_values,
)

if TYPE_CHECKING:  # sympy is imported on first use: the numeric path never needs it
    import sympy as sp

    from .rational import RatFunc

    S: sp.Symbol
    W: sp.Symbol

__all__ = [
    "STANDARD_SYMBOLS",
    "UNITS",
    "Algebra",
    "S",
    "W",
    "check_ascii",
    "check_name",
    "check_rational_in_s",
    "evaluate",
    "exact_expression",
    "finite_number",
    "parse_assignment",
    "parse_expression",
    "parse_tree",
    "parse_value",
    "symbol",
    "to_fraction",
    "tree_names",
    "underflows",
    "validate_values",
]

STANDARD_SYMBOLS: tuple[str, ...] = ("m", "b", "k1", "k2", "b1", "b2", "kd", "bd", "ki")
"""Parameter names every model may use without declaring them."""

UNITS: Mapping[str, str] = MappingProxyType(
    {"m": "kg", "b": "N·s/m", "k1": "N/m", "k2": "N/m", "b1": "N·s/m", "b2": "N·s/m",
     "kd": "N/m", "bd": "N·s/m", "ki": "N/(m·s)", "m_L": "kg"}
)  # fmt: skip
"""SI units of the standard parameters (and of the load mass ``m_L``), for labels."""


def __getattr__(name: str) -> Any:
    """``S`` and ``W`` (sympy symbols) are made on first use, so importing this is cheap."""
    if name in ("S", "W"):
        from . import symbolic

        return getattr(symbolic, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def symbol(name: str) -> sp.Symbol:
    """Return the positive real sympy symbol used for parameter ``name``."""
    from .symbolic import symbol as make

    return make(name)


def parse_tree(text: str, allowed: Iterable[str] = STANDARD_SYMBOLS) -> ast.expr:
    """Parse ``text`` and check every node against the whitelist; return the checked tree.

    Parameters
    ----------
    text : str
        Arithmetic in ``s`` and parameter names, e.g. ``"k1 + b1*s"``.
    allowed : iterable of str
        Parameter names that may appear (``s`` is always allowed).

    Raises
    ------
    ExpressionError
        On syntax errors, unknown names, function calls, attribute access,
        non-integer or huge powers, or over-long input.

    Examples
    --------
    >>> ast.dump(parse_tree("kd*s"))
    "BinOp(left=Name(id='kd', ctx=Load()), op=Mult(), right=Name(id='s', ctx=Load()))"
    """
    return _checked_tree(_source(text), frozenset(allowed))


def _source(text: str) -> str:
    if not isinstance(text, str):
        raise ExpressionError(f"expression must be a string, got {type(text).__name__}")
    src = text.strip()
    if not src:
        raise ExpressionError("empty expression: write e.g. 'k1 + b1*s', or '0'")
    if len(src) > MAX_EXPRESSION_LENGTH:
        raise ExpressionError(
            f"expression is {len(src)} characters long; the limit is {MAX_EXPRESSION_LENGTH}"
        )
    return src


@functools.lru_cache(maxsize=1024)
def _checked_tree(src: str, allowed: frozenset[str]) -> ast.expr:
    """`parse_tree` of stripped text (cached: models are rebuilt often; trees are not mutated)."""
    check_ascii(src, "")
    try:
        with warnings.catch_warnings():
            # e.g. '1inf': a SyntaxWarning would be a second line on stderr; it is an error
            warnings.simplefilter("error", SyntaxWarning)
            tree = ast.parse(src.replace("^", "**"), mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(f"cannot parse expression {src!r}: {exc.msg}") from None
    nodes = sum(1 for _ in ast.walk(tree))
    if nodes > MAX_NODES:
        raise ExpressionError(f"expression {src!r} is too large ({nodes} nodes > {MAX_NODES})")
    _check(tree.body, allowed, src)
    check_one_delay(tree_delays(tree.body), repr(src))
    return tree.body


def tree_names(tree: ast.AST) -> frozenset[str]:
    """The parameter names a checked tree uses (``s`` and function names left out)."""
    names = frozenset(n.id for n in ast.walk(tree) if isinstance(n, ast.Name))
    return names - call_names(tree) - {"s"}


def _check(node: ast.AST, allowed: frozenset[str], src: str) -> None:
    """Raise `ExpressionError` for the first node (left to right) outside the whitelist."""
    if isinstance(node, ast.Constant):
        _literal(node, src)
    elif isinstance(node, ast.Name):
        if node.id != "s" and node.id not in allowed:
            known = ", ".join(sorted(allowed)) or "none"
            raise ExpressionError(
                f"unknown symbol {node.id!r} in {src!r}{did_you_mean(node.id, allowed)}: known "
                f"symbols are s, {known}; a new parameter needs a value, "
                f"e.g. values={{{node.id!r}: 1.0}}"
            )
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.UAdd | ast.USub):
        _check(node.operand, allowed, src)
    elif isinstance(node, ast.BinOp) and isinstance(node.op, _BINARY):
        _check(node.left, allowed, src)
        if isinstance(node.op, ast.Pow):
            _integer_exponent(node.right, src)
        else:
            _check(node.right, allowed, src)
    elif isinstance(node, ast.Call):  # the one extension point: a delay exp(-NAME*s)
        delay_call(node, allowed, src)
    else:
        what = type(node).__name__
        if isinstance(node, ast.Attribute):
            what = "attribute access"
        raise ExpressionError(
            f"{what} is not allowed in {src!r}: use numbers, parameter names, s, + - * / and "
            "integer powers"
        )


_BINARY = (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow)


def _literal(node: ast.Constant, src: str) -> Fraction:
    """The exact value of a checked numeric literal (floats convert exactly)."""
    val = node.value
    if isinstance(val, bool) or not isinstance(val, int | float):
        raise ExpressionError(f"only numbers are allowed as literals in {src!r}")
    if isinstance(val, float) and not math.isfinite(val):
        raise ExpressionError(f"non-finite number in {src!r}")
    if val == 0 and isinstance(val, float):
        literal = ast.get_source_segment(src.replace("^", "**"), node) or ""
        if underflows(literal):
            raise ExpressionError(
                f"the number {literal} in {src!r} is too small for a float (it would "
                "become 0); write 0 or a value above 1e-308"
            )
    return Fraction(val)


def _integer_exponent(node: ast.AST, src: str) -> int:
    sign = 1
    while isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        if isinstance(node.op, ast.USub):
            sign = -sign
        node = node.operand
    if (
        isinstance(node, ast.Constant)
        and isinstance(node.value, int)
        and not isinstance(node.value, bool)
    ):
        exponent = sign * node.value
        if abs(exponent) > MAX_EXPONENT:
            raise ExpressionError(
                f"exponent {exponent} in {src!r} exceeds the limit of {MAX_EXPONENT}"
            )
        return exponent
    raise ExpressionError(f"only integer constant powers are allowed in {src!r}")


# ---------------------------------------------------------------- folding a checked tree

T = TypeVar("T")


class Algebra(Protocol[T]):
    """What `evaluate` needs to build a value of type ``T`` from a checked tree.

    ``div`` and ``power`` raise ``ZeroDivisionError`` when the divisor is
    identically zero.
    """

    def number(self, value: Fraction) -> T: ...
    def laplace(self) -> T: ...
    def parameter(self, name: str) -> T: ...
    def add(self, left: T, right: T) -> T: ...
    def sub(self, left: T, right: T) -> T: ...
    def mul(self, left: T, right: T) -> T: ...
    def div(self, left: T, right: T) -> T: ...
    def neg(self, operand: T) -> T: ...
    def power(self, base: T, exponent: int) -> T: ...
    def delay(self, name: str, multiple: int) -> T: ...


class _Fold(Generic[T]):
    """One fold of a checked tree: the dispatch table from node kinds to algebra operations."""

    def __init__(self, algebra: Algebra[T], src: str) -> None:
        self.algebra = algebra
        self.src = src
        self.rules: dict[type[ast.AST], Callable[[Any], T]] = {
            ast.Constant: self.constant,
            ast.Name: self.name,
            ast.UnaryOp: self.unary,
            ast.BinOp: self.binary,
            ast.Call: self.call,
        }

    def __call__(self, node: ast.AST) -> T:
        return self.rules[type(node)](node)

    def constant(self, node: ast.Constant) -> T:
        return self.algebra.number(_literal(node, self.src))

    def name(self, node: ast.Name) -> T:
        return self.algebra.laplace() if node.id == "s" else self.algebra.parameter(node.id)

    def unary(self, node: ast.UnaryOp) -> T:
        inner = self(node.operand)
        return self.algebra.neg(inner) if isinstance(node.op, ast.USub) else inner

    def call(self, node: ast.Call) -> T:
        return self.algebra.delay(*delay_call(node, None, self.src))

    def binary(self, node: ast.BinOp) -> T:
        a = self.algebra
        left = self(node.left)
        if isinstance(node.op, ast.Pow):
            return a.power(left, _integer_exponent(node.right, self.src))
        right = self(node.right)
        ops: dict[type[ast.operator], Callable[[T, T], T]] = {
            ast.Add: a.add,
            ast.Sub: a.sub,
            ast.Mult: a.mul,
            ast.Div: a.div,
        }
        return ops[type(node.op)](left, right)


def evaluate(tree: ast.expr, algebra: Algebra[T], src: str = "") -> T:
    """Fold a tree checked by `parse_tree` into the algebra's values.

    Raises
    ------
    ExpressionError
        On a division by an expression that is identically zero.
    """
    try:
        return _Fold(algebra, src)(tree)
    except ZeroDivisionError:
        raise ExpressionError(f"division by zero in {src!r}") from None


def exact_expression(text: str, allowed: Iterable[str] = STANDARD_SYMBOLS) -> RatFunc:
    """Parse ``text`` straight into an exact rational function (no sympy).

    The variables are ``s`` and the names that occur in ``text``; floats become
    the rationals they represent.  Each operation is size-checked first
    ([`seapass.model.rational`][seapass.model.rational]).

    Raises
    ------
    ExpressionError
        As `parse_tree`, and on division by zero.
    SymbolicLimitError
        When the expression is too large for exact analysis.

    Examples
    --------
    >>> exact_expression("kd + ki/s")
    RatFunc('(s*kd + ki)/(s)')
    """
    return _exact(_source(text), frozenset(allowed))


@functools.lru_cache(maxsize=1024)
def _exact(src: str, allowed: frozenset[str]) -> RatFunc:
    from .rational import RatFunc, context, variables

    tree = _checked_tree(src, allowed)
    delays = tree_delays(tree)
    ctx = context(variables(tree_names(tree) | {delay_variable(d) for d in delays}))

    class Exact:
        def number(self, value: Fraction) -> RatFunc:
            return RatFunc.constant(ctx, value)

        def laplace(self) -> RatFunc:
            return RatFunc.variable(ctx, "s")

        def parameter(self, name: str) -> RatFunc:
            return RatFunc.variable(ctx, name)

        add = staticmethod(RatFunc.__add__)
        sub = staticmethod(RatFunc.__sub__)
        mul = staticmethod(RatFunc.__mul__)
        div = staticmethod(RatFunc.__truediv__)
        neg = staticmethod(RatFunc.__neg__)
        power = staticmethod(RatFunc.__pow__)

        def delay(self, name: str, multiple: int) -> RatFunc:
            return RatFunc.variable(ctx, delay_variable(name)) ** multiple

    try:
        return evaluate(tree, Exact(), src)
    except SymbolicLimitError as exc:
        raise SymbolicLimitError(
            f"expression {src!r} is {exc}: simplify it or multiply out numeric factors"
        ) from None


def parse_expression(text: str, allowed: Iterable[str] = STANDARD_SYMBOLS) -> sp.Expr:
    """Parse ``text`` into a sympy expression, accepting only whitelisted input.

    Parameters
    ----------
    text : str
        Arithmetic in ``s`` and parameter names, e.g. ``"k1 + b1*s"`` or ``"kd + ki/s"``.
    allowed : iterable of str
        Parameter names that may appear (``s`` is always allowed).

    Returns
    -------
    sympy.Expr
        Parameters become positive real symbols, ``s`` is `S`.

    Raises
    ------
    ExpressionError
        On syntax errors, unknown names, function calls, attribute access,
        non-integer or huge powers, or over-long input.
    SymbolicLimitError
        When the expression exceeds the symbolic size budget.
    """
    from .symbolic import sympy_expression

    src = _source(text)
    return sympy_expression(_checked_tree(src, frozenset(allowed)), src)


def check_rational_in_s(expr: sp.Expr, allowed: Iterable[str], what: str) -> sp.Expr:
    """Validate a sympy expression given directly (not as text).

    Checks that its free symbols are ``s`` or allowed parameter names and that
    it is a rational function of ``s``; returns it with parameters mapped to
    the canonical positive symbols.
    """
    from .symbolic import check_sympy_input

    return check_sympy_input(expr, allowed, what)


def parse_assignment(text: str) -> tuple[str, float]:
    """Parse ``NAME=VALUE`` as given to ``--set``."""
    if "=" not in text:
        raise ParameterError(f"--set {text!r}: expected NAME=VALUE, e.g. --set kd=5000")
    name, _, raw = text.partition("=")
    name = name.strip()
    if not raw.strip():
        raise ParameterError(f"--set {text!r}: missing value after '=', e.g. --set {name}=1.5")
    try:
        check_name(name)
    except ExpressionError as exc:
        raise ParameterError(f"--set {text!r}: {exc}") from None
    return name, parse_value(raw.strip(), name)
