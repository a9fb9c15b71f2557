"""The delay atom in expressions and the exact structure N(s, E)/D(s, E)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from flint import fmpq

from seapass.delay.structure import controller_delay, delayed_impedance, has_model_delay
from seapass.errors import DelayError, ExpressionError, ParameterError
from seapass.model.expr import parse_expression
from seapass.model.sea import SEA, Impedance
from seapass.model.symbolic import Delay, delay_names, symbol

from .reference import sea_impedance

OURS = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


@pytest.mark.parametrize(
    ("text", "power"),
    [("exp(-tau*s)", 1), ("exp(-s*tau)", 1), ("exp(-(tau*s))", 1), ("exp(-2*tau*s)", 2),
     ("exp(-tau*s)*exp(-tau*s)", 2), ("exp(-1*tau*s)", 1), ("exp(-tau*s)^2", 2)],
)  # fmt: skip
def test_accepted_spellings_are_one_delay_atom(text, power):
    expr = parse_expression(text, ["tau"])
    assert expr == Delay(symbol("tau")) ** power
    assert delay_names(expr) == ("tau",)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("exp(s)", "function call is not allowed"),
        ("exp(-tau)", "function call is not allowed"),
        ("exp(-tau*s*s)", "function call is not allowed"),
        ("exp(-tau*kd*s)", "function call is not allowed"),
        ("exp(-tau*s, 1)", "function call is not allowed"),
        ("sin(s)", "function call is not allowed"),
        ("exp(tau*s)", "prediction"),
        ("exp(-0.5*tau*s)", "positive whole number"),
        ("exp(-9*tau*s)", "limit of 4"),
        ("exp(-tau*s)*exp(-t2*s)", "two different delays"),
        ("exp(-x*s)", "unknown symbol 'x'"),
    ],
)
def test_refused_spellings_say_what_is_supported(text, words):
    with pytest.raises(ExpressionError, match=words) as info:
        parse_expression(text, ["tau", "t2", "kd"])
    assert "\n" not in str(info.value)
    if "function call" in words:
        assert "exp(-NAME*s)" in str(info.value)


def test_delay_prints_back_as_text_that_parses_again():
    expr = parse_expression("(kd + bd*s)*exp(-tau*s)", ["kd", "bd", "tau"])
    assert parse_expression(str(expr), ["kd", "bd", "tau"]) == expr


def test_structure_of_ours_matches_the_free_body_formula():
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)", values={**OURS, "tau": 0.003})
    z = delayed_impedance(sea)
    assert z.name == "tau" and z.tau == fmpq(3, 1000) and z.order == 1
    w = np.geomspace(0.1, 1e4, 50)
    s = 1j * w
    e = np.exp(-s * 0.003)

    def value(parts):
        return sum(np.polyval([float(c) for c in reversed(p.coeffs())], s) * e**k
                   for k, p in enumerate(parts))  # fmt: skip

    np.testing.assert_allclose(value(z.num) / value(z.den), sea_impedance(sea, w, 0.003), rtol=1e-9)


def test_delay_is_the_decimal_it_was_written_as():
    z = delayed_impedance("m*s + K*exp(-tau*s)/s", values=dict(m=1, K=2, tau=0.001))
    assert z.tau == fmpq(1, 1000)
    z = delayed_impedance("m*s + K*exp(-tau*s)/s", values=dict(m=1, K=2, tau=Fraction(1, 3)))
    assert z.tau == fmpq(1, 3)


@pytest.mark.parametrize(
    ("values", "error", "words"),
    [
        (dict(m=1, K=2, tau=-0.001), ParameterError, ">= 0 s"),
        (dict(m=1, K=2, tau=1e9), ParameterError, "beyond the limit"),
        (dict(m=1, K=2, tau=float("nan")), ParameterError, "not finite"),
        (dict(m=1, K=2), ParameterError, "no value for the delay tau"),
        (dict(m=1, tau=0.1), ParameterError, "no value for parameter"),
    ],
)
def test_bad_delay_values(values, error, words):
    with pytest.raises(error, match=words):
        delayed_impedance("m*s + K*exp(-tau*s)/s", values=values)


def test_two_delays_in_two_elements_are_refused():
    sea = SEA(D1="k1", CA="kd*exp(-tau*s)", CL="kd*exp(-t2*s)",
              values=dict(m=1, b=1, k1=1, kd=1, tau=0.1, t2=0.2))  # fmt: skip
    with pytest.raises(DelayError, match="two different delays"):
        delayed_impedance(sea)


def test_a_prediction_in_a_denominator_is_refused():
    with pytest.raises(DelayError, match="prediction"):
        delayed_impedance("1/(exp(-tau*s)*(s + 1))", values=dict(tau=0.1))


def test_the_delay_used_outside_the_exponential_is_refused():
    with pytest.raises(DelayError, match="also appears outside"):
        delayed_impedance("tau*s + exp(-tau*s)", values=dict(tau=0.1))


def test_no_delay_is_reported():
    assert not has_model_delay(SEA(D1="k1", values=dict(m=1, b=1, k1=1)))
    with pytest.raises(DelayError, match="no delay"):
        delayed_impedance(Impedance(expr="s + 1"))


def test_controller_delay_on_catalog_and_model():
    lp = controller_delay("LP", "tau", dict(kd=500))
    assert str(lp.CL) == "kd*exp(-tau*s)" and lp.values["tau"] is None
    sea = SEA(D1="k1", CA="kd + bd*s", values=dict(m=1, b=10, k1=1000, kd=1, bd=1))
    assert str(controller_delay(sea, "T").CA) == "(bd*s + kd)*exp(-T*s)"
    with pytest.raises(ParameterError, match="already a parameter"):
        controller_delay(sea, "kd")
    with pytest.raises(DelayError, match="no controller"):
        controller_delay(SEA(D1="k1", values=dict(m=1, b=1, k1=1)), "tau")
    delayed = SEA(D1="k1", CA="kd*exp(-t*s)", values=dict(m=1, b=1, k1=1, kd=1, t=None))
    assert controller_delay(delayed, "t") is delayed
    with pytest.raises(DelayError, match="not exp"):
        controller_delay(delayed, "tau")
