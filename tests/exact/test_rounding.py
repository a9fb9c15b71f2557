"""Directed rounding of exact numbers to doubles and decimal text (issue 20, item 2)."""

from __future__ import annotations

import math
from fractions import Fraction

import pytest
import sympy as sp
from flint import fmpq_poly
from hypothesis import given
from hypothesis import strategies as st

from seapass.exact.rounding import (
    decimal_down,
    decimal_up,
    enclosure_text,
    exact_text,
    float_above_root,
    float_below_root,
    float_down,
    float_up,
    interval_text,
    inward_text,
)

rationals = st.fractions(
    min_value=Fraction(-(10**30)), max_value=Fraction(10**30), max_denominator=10**25
)


@given(rationals)
def test_float_down_and_up_are_the_nearest_doubles_on_each_side(x):
    lo, hi = float_down(x), float_up(x)
    assert Fraction(lo) <= x <= Fraction(hi)
    assert Fraction(math.nextafter(lo, math.inf)) > x or Fraction(lo) == x
    assert Fraction(math.nextafter(hi, -math.inf)) < x or Fraction(hi) == x


@given(rationals, st.integers(1, 17))
def test_decimal_text_lands_on_its_side_as_a_number_and_as_a_double(x, digits):
    down, up = decimal_down(x, digits), decimal_up(x, digits)
    assert Fraction(down) <= x <= Fraction(up)
    assert Fraction(float(down)) <= Fraction(float_up(x))
    assert Fraction(float(up)) >= Fraction(float_down(x))
    for text in (down, up):  # at most `digits` significant digits
        mantissa = text.split("e")[0].replace("-", "").replace(".", "").lstrip("0")
        assert len(mantissa) <= digits


@pytest.mark.parametrize("x", [0.0, 1.0, 1234.5, 1e6, 0.0625, 0.25, 0.375, 1e16, 123456.0, -2.5])
@pytest.mark.parametrize("digits", [6, 10])
def test_decimal_text_is_percent_g_for_short_values(x, digits):
    assert decimal_down(x, digits) == decimal_up(x, digits) == f"{x:.{digits}g}"


@given(rationals, rationals, st.integers(1, 12))
def test_inward_text_stays_inside(a, b, digits):
    lo, hi = min(a, b), max(a, b)
    ta, tb = inward_text(lo, hi, digits)
    assert lo <= Fraction(ta) <= Fraction(tb) <= hi
    if lo < hi:
        assert Fraction(ta) < Fraction(tb)


def test_interval_and_enclosure_text():
    assert interval_text(0.0, 118.46721557324219, digits=10) == "[0, 118.4672155]"
    assert interval_text(2.0, 2.0) == "{2}" and interval_text(0.1, 0.1) == "{0.1}"
    assert (
        enclosure_text(118.46721557324217, 118.46721557324219) == "[118.467215573, 118.467215574]"
    )
    assert exact_text(30.0) == "30" and float(exact_text(0.1 + 0.2)) == 0.1 + 0.2


@pytest.mark.parametrize("n", [2, 3, 5, 10**6 + 3, 2**53 + 1])
def test_doubles_next_to_a_square_root_are_placed_exactly(n):
    """Cross-check with sympy's exact comparison of rationals with sqrt(n)."""
    p = fmpq_poly([-n, 0, 1])
    r = math.isqrt(n)
    iv = (Fraction(r), Fraction(r + 1))
    above, below = float_above_root(p, iv), float_below_root(p, iv)
    root = sp.sqrt(n)
    assert sp.Rational(Fraction(above)) > root > sp.Rational(Fraction(below))
    assert sp.Rational(Fraction(math.nextafter(above, -math.inf))) < root
    assert sp.Rational(Fraction(math.nextafter(below, math.inf))) > root


def test_a_rational_root_is_refused():
    with pytest.raises(ArithmeticError):
        float_above_root(fmpq_poly([-4, 0, 1]), (Fraction(1), Fraction(2)))
