"""Safe parsing of rational expressions and parameter values.

User text is never given to `eval` or to a plain `sympy.sympify`.
It is parsed by `ast` in ``eval`` mode and every node is checked against a
whitelist: numeric literals, whitelisted names, ``+ - * /``, unary signs,
integer powers (``**`` or ``^``) and one delay factor ``exp(-NAME*s)`` (the only
call allowed; see [`seapass.model.delayatom`][seapass.model.delayatom]).  The sympy
expression is then built node by node, so no user string ever reaches a code path
that can execute code.
"""

from __future__ import annotations

import ast
import math
import re
import unicodedata
import warnings
from collections.abc import Iterable, Mapping
from fractions import Fraction
from types import MappingProxyType

import sympy as sp

from ..errors import ExpressionError, ParameterError, did_you_mean
from ..files.limits import MAX_EXPONENT, MAX_EXPRESSION_LENGTH, MAX_NODES
from .budget import check_symbolic_size
from .delayatom import check_one_delay, delay_factor

__all__ = [
    "STANDARD_SYMBOLS",
    "UNITS",
    "S",
    "W",
    "check_ascii",
    "check_name",
    "check_rational_in_s",
    "finite_number",
    "parse_assignment",
    "parse_expression",
    "parse_value",
    "symbol",
    "to_fraction",
    "underflows",
]

S = sp.Symbol("s")
"""Laplace variable and angular frequency."""
W = sp.Symbol("w", real=True)

STANDARD_SYMBOLS: tuple[str, ...] = ("m", "b", "k1", "k2", "b1", "b2", "kd", "bd", "ki")
"""Parameter names every model may use without declaring them."""

UNITS: Mapping[str, str] = MappingProxyType(
    {"m": "kg", "b": "N·s/m", "k1": "N/m", "k2": "N/m", "b1": "N·s/m", "b2": "N·s/m",
     "kd": "N/m", "bd": "N·s/m", "ki": "N/(m·s)", "m_L": "kg"}
)  # fmt: skip
"""SI units of the standard parameters (and of the load mass ``m_L``), for labels."""

# the size budgets live with every other limit, in seapass.files.limits
_RESERVED = {"s", "w", "I", "E", "pi", "oo", "nan", "zoo"}


def symbol(name: str) -> sp.Symbol:
    """Return the positive real sympy symbol used for parameter ``name``."""
    return sp.Symbol(name, positive=True)


def check_ascii(text: str, what: str) -> None:
    """Refuse non-ASCII input, saying what a lookalike character would have become.

    Python folds ``ｓ`` and ``𝑠`` into ``s`` and reads ``٣`` as 3; seapass does not
    guess: it names the character and its ASCII look-alike.

    >>> check_ascii("ｓ + 1", "CA")
    Traceback (most recent call last):
    ...
    seapass.errors.ExpressionError: CA: non-ASCII character 'ｓ' (U+FF53 FULLWIDTH LATIN SMALL LETTER S) in 'ｓ + 1'; write 's' instead
    """
    bad = next((ch for ch in text if ord(ch) > 127), None)
    if bad is None:
        return
    name = unicodedata.name(bad, "unnamed character")
    digit = unicodedata.digit(bad, None)
    folded = str(digit) if digit is not None else unicodedata.normalize("NFKC", bad)
    hint = (
        f"; write {folded!r} instead"
        if folded.isascii() and folded.strip()
        else "; use plain ASCII letters, digits and operators"
    )
    shown = bad if bad.isprintable() else ""
    where = f"{what}: " if what else ""
    raise ExpressionError(
        f"{where}non-ASCII character {shown!r} (U+{ord(bad):04X} {name}) in {text!r}{hint}"
    )


def check_name(name: str) -> None:
    check_ascii(name, "parameter name")
    if not name.isidentifier() or name.startswith("_") or name in _RESERVED:
        raise ExpressionError(
            f"invalid parameter name {name!r}: use a plain identifier other than "
            f"{', '.join(sorted(_RESERVED))}"
        )


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
    """
    if not isinstance(text, str):
        raise ExpressionError(f"expression must be a string, got {type(text).__name__}")
    src = text.strip()
    if not src:
        raise ExpressionError("empty expression: write e.g. 'k1 + b1*s', or '0'")
    if len(src) > MAX_EXPRESSION_LENGTH:
        raise ExpressionError(
            f"expression is {len(src)} characters long; the limit is {MAX_EXPRESSION_LENGTH}"
        )
    check_ascii(src, "")
    allowed_set = set(allowed)
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
    expr = _build(tree.body, allowed_set, src)
    check_one_delay(expr, src)
    check_symbolic_size(expr, repr(src))
    return expr


def _build(node: ast.AST, allowed: set[str], src: str) -> sp.Expr:
    if isinstance(node, ast.Constant):
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
        return sp.Rational(Fraction(val)) if isinstance(val, float) else sp.Integer(val)
    if isinstance(node, ast.Name):
        if node.id == "s":
            return S
        if node.id in allowed:
            return symbol(node.id)
        known = ", ".join(sorted(allowed)) or "none"
        raise ExpressionError(
            f"unknown symbol {node.id!r} in {src!r}{did_you_mean(node.id, allowed)}: known "
            f"symbols are s, {known}; a new parameter needs a value, "
            f"e.g. values={{{node.id!r}: 1.0}}"
        )
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.UAdd | ast.USub):
        inner = _build(node.operand, allowed, src)
        return -inner if isinstance(node.op, ast.USub) else inner
    if isinstance(node, ast.BinOp):
        op = node.op
        if isinstance(op, ast.Pow):
            base = _build(node.left, allowed, src)
            exponent = _integer_exponent(node.right, src)
            if exponent < 0 and base == 0:
                raise ExpressionError(f"division by zero in {src!r}")
            return base**exponent
        left = _build(node.left, allowed, src)
        right = _build(node.right, allowed, src)
        if isinstance(op, ast.Add):
            return left + right
        if isinstance(op, ast.Sub):
            return left - right
        if isinstance(op, ast.Mult):
            return left * right
        if isinstance(op, ast.Div):
            # bounded before expanding: sp.simplify here could run for minutes
            check_symbolic_size(right, repr(src))
            if right == 0 or sp.expand(sp.numer(sp.together(right))) == 0:
                raise ExpressionError(f"division by zero in {src!r}")
            return left / right
    if isinstance(node, ast.Call):  # the one extension point: a delay exp(-NAME*s)
        return delay_factor(node, allowed, src)
    what = type(node).__name__
    if isinstance(node, ast.Attribute):
        what = "attribute access"
    raise ExpressionError(
        f"{what} is not allowed in {src!r}: use numbers, parameter names, s, + - * / and integer powers"
    )


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


def check_rational_in_s(expr: sp.Expr, allowed: Iterable[str], what: str) -> sp.Expr:
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
    if not expr.is_rational_function(S):
        raise ExpressionError(f"{what}: {expr} is not a rational function of s")
    check_symbolic_size(expr, what)
    return expr


_NONZERO_MANTISSA = re.compile(r"^\s*[+-]?[0_.]*[1-9]")


def underflows(literal: str) -> bool:
    """True if the decimal ``literal`` is nonzero but rounds to 0.0 as a float.

    >>> underflows("1e-400"), underflows("0.0e5"), underflows("4.9e-324")
    (True, False, False)
    """
    mantissa = re.split("[eE]", literal, maxsplit=1)[0]
    try:
        zero = float(literal) == 0.0
    except ValueError:
        return False
    return zero and bool(_NONZERO_MANTISSA.match(mantissa))


def parse_value(text: str, name: str = "value") -> float:
    """Parse a finite real number, rejecting NaN, infinities, non-ASCII digits and underflow."""
    if isinstance(text, str):
        try:
            check_ascii(text, name)
        except ExpressionError as exc:
            raise ParameterError(str(exc)) from None
    try:
        val = float(text)
    except (TypeError, ValueError):
        raise ParameterError(f"{name}: {text!r} is not a number") from None
    if not math.isfinite(val):
        raise ParameterError(f"{name}: {text!r} is not finite; give a finite number")
    if isinstance(text, str) and underflows(text):
        raise ParameterError(
            f"{name}: {text.strip()} is too small for a float (it would become 0); "
            "give 0 or a value above 1e-308"
        )
    return val


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


def to_fraction(value: float | int | Fraction | sp.Rational, name: str = "value") -> Fraction:
    """Exact rational value of a finite number (floats convert exactly)."""
    if isinstance(value, Fraction):
        return value
    if isinstance(value, sp.Rational):
        return Fraction(int(value.p), int(value.q))
    if isinstance(value, sp.Float):
        value = float(value)
    if isinstance(value, bool):
        raise ParameterError(f"{name}: expected a number, got a boolean")
    if isinstance(value, int):
        return Fraction(value)
    try:
        f = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name}: {value!r} is not a number") from None
    if not math.isfinite(f):
        raise ParameterError(f"{name}: {value!r} is not finite")
    return Fraction(f)


def validate_values(values: Mapping[str, object]) -> dict[str, float]:
    """Check parameter names and values; return a plain ``{name: float}`` dict."""
    out: dict[str, float] = {}
    for name, val in values.items():
        check_name(name)
        out[name] = float(to_fraction(val, name))  # type: ignore[arg-type,unused-ignore]
    return out


def finite_number(
    value: float, name: str, *, positive: bool = False, nonzero: bool = False
) -> float:
    """``value`` as a finite float, or a `ParameterError` naming ``name``."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name}: expected a number, got {value!r}") from None
    if not math.isfinite(v):
        raise ParameterError(f"{name} must be finite, got {v}")
    if positive and v <= 0:
        raise ParameterError(f"{name} must be positive, got {v:g}")
    if nonzero and v == 0:
        raise ParameterError(f"{name} must be nonzero")
    return v
