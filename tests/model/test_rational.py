"""Exact rational functions (``model.rational``): sympy's normal form, and a budget that holds.

The exact path parses an expression straight into ``num/den`` on flint polynomials.
Checked here against sympy (an independent implementation of the same algebra):
random expressions give the same function and the very same normal form as
``fraction(cancel(together(.)))``; and hostile inputs (huge exponents, nested
fractions, 1e300-scale numbers, many symbols) are refused with one clear error
before the work, never half-computed.
"""

from __future__ import annotations

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.cli import main
from seapass.errors import ExpressionError, SymbolicLimitError
from seapass.files.limits import (
    MAX_EXACT_BITS,
    MAX_EXACT_DEGREE,
    MAX_EXACT_TERMS,
    MAX_EXACT_WORK,
)
from seapass.model.expr import S, exact_expression, parse_expression, symbol
from seapass.model.rational import RatFunc, context, sympy_order, variables
from seapass.model.sea import SEA


def _to_sympy(p) -> sp.Expr:
    gens = [S if n == "s" else symbol(n) for n in p.context().names()]
    out = sp.Integer(0)
    for exps, c in zip(p.monoms(), p.coeffs(), strict=True):
        term = sp.Rational(int(c.p), int(c.q))
        for g, e in zip(gens, exps, strict=True):
            term *= g**e
        out += term
    return out


_atoms = st.sampled_from(
    ["s", "k1", "kd", "b1", "x", "p2", "0", "1", "2", "0.5", "-3", "1e-3", "7"]
)


@st.composite
def expressions(draw: st.DrawFn, depth: int = 3) -> str:
    if depth == 0 or draw(st.booleans()):
        return draw(_atoms)
    op = draw(st.sampled_from(["+", "-", "*", "/", "**"]))
    left = draw(expressions(depth - 1))
    if op == "**":
        return f"({left})**{draw(st.integers(-2, 3))}"
    return f"({left}) {op} ({draw(expressions(depth - 1))})"


@settings(max_examples=120, deadline=None)
@given(text=expressions())
def test_the_exact_algebra_is_sympys_algebra(text):
    """Both algebras fold the same checked tree; they agree, normal form included."""
    allowed = ("k1", "kd", "b1", "x", "p2")
    try:
        exact = exact_expression(text, allowed)
    except ExpressionError as exc:  # division by zero: sympy must refuse it too
        assert "division by zero" in str(exc)
        with pytest.raises(ExpressionError, match="division by zero"):
            parse_expression(text, allowed)
        return
    sym = parse_expression(text, allowed)
    num, den = exact.canonical()
    n_sym, d_sym = sp.fraction(sp.cancel(sp.together(sym)))
    assert sp.expand(_to_sympy(num) - n_sym) == 0
    assert sp.expand(_to_sympy(den) - d_sym) == 0
    assert exact.parameters() == {str(x) for x in (n_sym / d_sym).free_symbols} - {"s"}


def test_sympys_order_of_generators():
    """The sign of the normal form depends on it: x, y, z first, then p..w, then a..o."""
    assert sympy_order(["kd", "s", "b1", "k1", "x", "r", "zz"]) == (
        "x", "r", "s", "b1", "k1", "kd", "zz",
    )  # fmt: skip
    got = sp.polys.polyutils._sort_gens(
        [symbol(n) for n in ("kd", "b1", "k1", "x", "r", "zz")] + [S]
    )
    assert tuple(map(str, got)) == sympy_order(["kd", "s", "b1", "k1", "x", "r", "zz"])


def test_arithmetic_keeps_lowest_terms():
    ctx = context(variables(["kd", "ki"]))
    s, kd, ki = (RatFunc.variable(ctx, n) for n in ("s", "kd", "ki"))
    f = (kd + ki / s) * s / (s * kd + ki)
    assert f.is_one and f.num.gcd(f.den).is_one()
    assert (f - f).is_zero and ((s + kd) ** -2 * (s + kd) ** 2).is_one
    with pytest.raises(ZeroDivisionError):
        _ = s / (s - s)


# ---------------------------------------------------------------- hostile input, bounded

HOSTILE = {
    "many symbols": "(s + k1 + k2 + b1 + b2 + kd + bd + m + b)**12",
    "high degree": "*".join(f"(s + {i})**12" for i in range(1, 9)),
    "1e300 numbers": "(1e300*s + 1e-300)**12 * (1e300*s + 1)**12",
    "nested powers": "((s + k1 + kd)**12 + b1)**12",
}


@pytest.mark.parametrize("text", HOSTILE.values(), ids=HOSTILE.keys())
def test_hostile_expressions_are_refused_before_the_work(text):
    with pytest.raises(SymbolicLimitError, match="too large for exact analysis"):
        exact_expression(text)
    with pytest.raises(SymbolicLimitError, match="too large"):
        SEA(D1="k1", CA=text)


@pytest.mark.parametrize("text", list(HOSTILE.values())[:3])
def test_hostile_expressions_through_check_are_one_error_line(capsys, text):
    code = main(["check", "--D1", "k1", "--CA", text, "--set", "m=1", "--set", "b=1"])
    err = capsys.readouterr().err
    assert code == 2 and "too large" in err and err.count("\n") == 1


def test_the_limits_are_what_they_say():
    """Just inside each limit works, just outside is refused."""
    half = MAX_EXACT_DEGREE // 12
    exact_expression("*".join(f"(s + {i})**12" for i in range(1, half + 1)))
    with pytest.raises(SymbolicLimitError, match=f"limit {MAX_EXACT_DEGREE}"):
        exact_expression("*".join(f"(s + {i})**12" for i in range(1, half + 2)))
    with pytest.raises(SymbolicLimitError, match=f"{MAX_EXACT_BITS:,}"):
        exact_expression("(1e300*s + 1)**12 * (1e300*s + 3)**12")
    exact_expression("(1e300*s + 1)**12")  # about 12,000 bits: fine
    with pytest.raises(SymbolicLimitError, match=f"{MAX_EXACT_WORK:,} term products"):
        exact_expression("(s + k1 + k2 + b1 + b2 + kd + bd)**12")
    names = "abcdefghijklmnop"
    with pytest.raises(SymbolicLimitError, match=f"limit {MAX_EXACT_TERMS:,}"):
        exact_expression(f"({'+'.join(names[:8])})**4 * ({'+'.join(names[8:])})**4", names)


def test_deep_but_small_expressions_are_fine():
    """Nesting is bounded by the node limit, and reduction keeps nested fractions small."""
    assert exact_expression("1/(1 + " * 60 + "s" + ")" * 60).degrees_in_s() == (1, 1)
    assert str(exact_expression("-" * 190 + "s").num) == "s"
    with pytest.raises(ExpressionError, match="too large"):
        exact_expression("+".join(["s"] * 300))
    with pytest.raises(ExpressionError, match="exceeds the limit"):
        exact_expression("(s + 1)**13")


def test_numbers_are_the_rationals_floats_represent():
    f = exact_expression("0.1*s + 1e300")
    (c1, c0) = (f.num.coeffs()[i] for i in (0, 1)) if f.num.monoms()[0][0] else (None, None)
    assert sp.Rational(int(c1.p), int(c1.q)) == sp.Rational(0.1)
    assert int(c0.p) == int(1e300) and c0.q == 1
