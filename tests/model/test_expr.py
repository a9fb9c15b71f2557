import math

import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from seapass.errors import ExpressionError, ParameterError
from seapass.model.expr import S, parse_assignment, parse_expression, parse_value, symbol


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("k1 + b1*s", symbol("k1") + symbol("b1") * S),
        ("kd + ki/s", symbol("kd") + symbol("ki") / S),
        ("2*s^2 + 1", 2 * S**2 + 1),
        ("-(s + 1)**-1", -1 / (S + 1)),
        ("1e-9", sp.Rational(1e-9)),
        ("0", sp.Integer(0)),
    ],
)
def test_parses_rational_expressions(text, expected):
    assert sp.simplify(parse_expression(text) - expected) == 0


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("__import__('os').system('echo hacked')", "function call"),
        ("sin(s)", "function call"),
        ("s.__class__", "attribute access"),
        ("k1 + foo", "unknown symbol 'foo'"),
        ("s**s", "integer constant powers"),
        ("s**0.5", "integer constant powers"),
        ("s**100", "exceeds the limit"),
        ("[1, 2]", "not allowed"),
        ("lambda: 1", "not allowed"),
        ("1/0", "division by zero"),
        ("k1 +", "cannot parse"),
        ("", "empty expression"),
        ("True", "only numbers"),
        ("'abc'", "only numbers"),
        ("1 if s else 2", "not allowed"),
        ("s" + "+s" * 2000, "characters long"),
    ],
)
def test_rejects_unsafe_or_invalid(text, fragment):
    with pytest.raises(ExpressionError, match=fragment):
        parse_expression(text)


def test_injection_does_nothing(tmp_path):
    marker = tmp_path / "pwned"
    with pytest.raises(ExpressionError):
        parse_expression(f"__import__('pathlib').Path('{marker}').touch()")
    assert not marker.exists()


def test_declared_symbols_are_allowed():
    assert parse_expression("kp*s", allowed={"kp"}) == symbol("kp") * S


@pytest.mark.parametrize("bad", ["nan", "inf", "-inf", "abc", ""])
def test_parse_value_rejects(bad):
    with pytest.raises(ParameterError):
        parse_value(bad)


@pytest.mark.parametrize("bad", ["m", "m=", "=1", "s=1", "_x=1", "1x=2"])
def test_parse_assignment_rejects(bad):
    with pytest.raises(ParameterError):
        parse_assignment(bad)


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_parse_value_roundtrip(x):
    assert parse_value(repr(x)) == x
    assert math.isfinite(parse_value(repr(x)))
