"""Hostile text through the expression parser and `--set`: never a crash, never code execution,
non-ASCII look-alikes and underflowing values refused in one line."""

from __future__ import annotations

import math
import warnings

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers import LP_ARGV, one_error, run_main
from hostile import (
    MARKER,
    grammar,
    no_marker,  # noqa: F401 (a fixture)
    payload_id,
    payloads,
)
from seapass.errors import (
    ExpressionError,
    ParameterError,
    SymbolicLimitError,
)
from seapass.model.expr import parse_assignment, parse_expression

# ------------------------- hostile text (moved from test_fuzz): never a crash, never code execution


@pytest.mark.usefixtures("no_marker")
@pytest.mark.parametrize("text", payloads(), ids=payload_id)
def test_injection_through_the_parser_does_nothing(text):
    try:
        expr = parse_expression(text)
    except (ExpressionError, SymbolicLimitError):
        pass
    else:  # a few payloads are harmless valid arithmetic, e.g. 0x10*s
        assert isinstance(expr, sp.Expr)
        assert expr.free_symbols <= {sp.Symbol("s")}
    assert not MARKER.exists()


ALPHABET = "sk1bdmi0123456789.eE+-*/^() _,'\"[]{}:;=<>!@#$%&|~`\\\t\n" + "ωé\u200b"


texts = st.one_of(
    st.text(alphabet=ALPHABET, max_size=80),
    st.text(max_size=40),
)


@pytest.mark.usefixtures("no_marker")
@settings(max_examples=400, deadline=2000)
@given(text=texts)
def test_parser_never_crashes(text):
    try:
        expr = parse_expression(text)
    except (ExpressionError, SymbolicLimitError):
        return
    assert isinstance(expr, sp.Expr)


@pytest.mark.usefixtures("no_marker")
@settings(max_examples=300, deadline=3000)
@given(text=grammar())
def test_grammar_expressions_parse_or_fail_cleanly(text):
    try:
        expr = parse_expression(text)
    except (ExpressionError, SymbolicLimitError):
        return
    assert expr.is_rational_function(sp.Symbol("s"))
    assert not expr.has(sp.zoo, sp.nan, sp.oo)


@pytest.mark.usefixtures("no_marker")
@settings(max_examples=300, deadline=1000)
@given(text=st.text(max_size=40))
def test_set_assignments_never_crash(text):
    try:
        name, val = parse_assignment(text)
    except ParameterError:
        return
    assert name.isidentifier() and math.isfinite(val)


# -------------------------------------- input hygiene (moved from test_hardening, issue 12 item 10)


def test_syntax_warning_does_not_add_a_line() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        err = one_error(["check", "--Z", "(40)**1inf"], "cannot parse")
    assert "SyntaxWarning" not in err


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ("ｓ + 1", "write 's'"),
        ("𝑠 + 1", "write 's'"),
        ("٣*s + 1", "write '3'"),
        ("s\u200b+1", "U+200B"),
    ],
)
def test_unicode_lookalikes_are_refused_naming_the_character(text: str, shown: str) -> None:
    one_error(["check", "--Z", text], "non-ASCII", shown)


def test_arabic_indic_digits_in_values_are_refused() -> None:
    one_error(["check", *LP_ARGV, "--set", "kd=٣"], "non-ASCII", "write '3'")


def test_values_that_underflow_are_refused() -> None:
    one_error(["check", *LP_ARGV, "--set", "kd=1e-400"], "too small for a float")
    one_error(["check", "--Z", "1e-400*s + 1"], "too small for a float")
    code, _, _ = run_main(["check", *LP_ARGV, "--set", "kd=4.9e-324"])  # denormal, but not zero
    assert code == 0
