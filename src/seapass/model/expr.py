"""Safe parsing of rational expressions and parameter values.

User text is never given to `eval` or to a plain `sympy.sympify`.
It is parsed by `ast` in ``eval`` mode and every node is checked against a
whitelist: numeric literals, whitelisted names, ``+ - * /``, unary signs and
integer powers (``**`` or ``^``).  The sympy expression is then built node by
node, so no user string ever reaches a code path that can execute code.
"""

from __future__ import annotations

import ast
import math
import re
import signal
import threading
import unicodedata
import warnings
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from fractions import Fraction
from types import MappingProxyType
from typing import NamedTuple

import sympy as sp

from ..errors import ExpressionError, ParameterError, SymbolicLimitError, did_you_mean
from ..files.limits import (
    MAX_EXPONENT,
    MAX_EXPRESSION_LENGTH,
    MAX_NODES,
    MAX_S_DEGREE,
    MAX_TERMS,
    SYMBOLIC_TIME_LIMIT,
)

__all__ = [
    "STANDARD_SYMBOLS",
    "UNITS",
    "FractionSize",
    "S",
    "W",
    "check_ascii",
    "check_name",
    "check_rational_in_s",
    "check_symbolic_size",
    "finite_number",
    "fraction_size",
    "parse_assignment",
    "parse_expression",
    "parse_value",
    "symbol",
    "symbolic_time_limit",
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
    what = type(node).__name__
    if isinstance(node, ast.Call):
        what = "function call"
    elif isinstance(node, ast.Attribute):
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


def _multinomial(terms: int, n: int) -> int:
    """Number of monomials of ``(t_1 + ... + t_terms)**n``, capped to stay small."""
    return min(math.comb(terms + n - 1, n), TERM_CAP)


class FractionSize(NamedTuple):
    """Upper bounds of ``N`` and ``D`` when an expression is brought to one fraction ``N/D``.

    Degrees are in ``s``; terms count monomials in ``s`` and every parameter.
    """

    num_degree: int
    den_degree: int
    num_terms: int
    den_terms: int

    @property
    def degree(self) -> int:
        """``deg N + deg D``."""
        return self.num_degree + self.den_degree

    @property
    def terms(self) -> int:
        """``terms(N) + terms(D)``."""
        return self.num_terms + self.den_terms


TERM_CAP = 10**12
"""Term counts are capped here (beyond every budget, so capping never hides a refusal)."""


def fraction_size(expr: sp.Expr) -> FractionSize:
    """Upper bounds of ``N`` and ``D`` of ``expr`` brought to one fraction ``N/D``.

    Computed from the expression tree without expanding anything (linear in
    the tree size): sums of fractions multiply denominators, products add
    degrees, powers use the multinomial count.

    Examples
    --------
    >>> fraction_size(parse_expression("kd + ki/s"))
    FractionSize(num_degree=1, den_degree=1, num_terms=2, den_terms=1)
    """

    def walk(e: sp.Basic) -> tuple[int, int, int, int]:  # deg N, deg D, terms N, terms D
        if e == S:
            return 1, 0, 1, 1
        if e.is_Atom:
            return 0, 0, 1, 1
        if isinstance(e, sp.Add):
            dn, dd, tn, td = walk(e.args[0])
            for a in e.args[1:]:
                an, ad, atn, atd = walk(a)
                dn, dd = max(dn + ad, an + dd), dd + ad
                tn, td = min(tn * atd + atn * td, TERM_CAP), min(td * atd, TERM_CAP)
            return dn, dd, tn, td
        if isinstance(e, sp.Mul):
            dn = dd = 0
            tn = td = 1
            for a in e.args:
                an, ad, atn, atd = walk(a)
                dn, dd = dn + an, dd + ad
                tn, td = min(tn * atn, TERM_CAP), min(td * atd, TERM_CAP)
            return dn, dd, tn, td
        if isinstance(e, sp.Pow) and e.exp.is_Integer:
            n = int(e.exp)
            bn, bd, btn, btd = walk(e.base)
            if n < 0:
                bn, bd, btn, btd, n = bd, bn, btd, btn, -n
            return bn * n, bd * n, _multinomial(btn, n), _multinomial(btd, n)
        # anything else (not produced by the parser): count its atoms
        atoms = sum(1 for _ in sp.preorder_traversal(e))
        return atoms, atoms, atoms, atoms

    return FractionSize(*walk(sp.sympify(expr)))


def symbolic_size(expr: sp.Expr) -> tuple[int, int]:
    """Upper bounds ``(deg N + deg D, terms(N) + terms(D))`` of ``expr`` as one fraction ``N/D``.

    See `fraction_size`, which keeps the numerator and denominator apart.
    """
    size = fraction_size(expr)
    return size.degree, size.terms


def check_symbolic_size(expr: sp.Expr, what: str = "expression") -> None:
    """Raise `SymbolicLimitError` when ``expr`` exceeds the symbolic size budget.

    The budget (`MAX_S_DEGREE`, `MAX_TERMS`) bounds the size of the
    single fraction sympy will form, so that derivations stay fast instead of
    hanging on adversarial input such as ``1/(s + k1 + k2 + kd + bd + m + b)**12``.
    """
    deg, terms = symbolic_size(expr)
    if deg > MAX_S_DEGREE or terms > MAX_TERMS:
        raise SymbolicLimitError(
            f"{what} is too large for symbolic analysis (as one fraction up to degree "
            f"{deg} in s and {terms} terms; limits {MAX_S_DEGREE} and {MAX_TERMS}): "
            "simplify it or multiply out numeric factors"
        )


@contextmanager
def symbolic_time_limit(
    seconds: float = SYMBOLIC_TIME_LIMIT, what: str = "symbolic derivation"
) -> Iterator[None]:
    """Raise `SymbolicLimitError` if the block runs longer than ``seconds``.

    Uses ``SIGALRM`` and is therefore active only in the main thread of a
    process whose real-time interval timer is unused; elsewhere (worker
    threads, dask workers) the size budget of `check_symbolic_size`
    is the only guard.
    """
    usable = (
        hasattr(signal, "setitimer")
        and threading.current_thread() is threading.main_thread()
        and signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)
        and signal.getsignal(signal.SIGALRM) in (signal.SIG_DFL, None)
    )
    if not usable:
        yield
        return

    def _expired(signum: int, frame: object) -> None:
        raise SymbolicLimitError(
            f"{what} exceeded its time budget of {seconds:g} s: simplify the model"
        )

    old = signal.signal(signal.SIGALRM, _expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old)


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
