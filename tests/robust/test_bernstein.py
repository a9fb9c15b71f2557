"""Exact Bernstein enclosures and the budgeted branch and bound, against plain evaluation."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
from flint import fmpq
from hypothesis import given
from hypothesis import strategies as st

from seapass.robust.bernstein import BoxSign, bernstein_coefficients, from_terms, positive_on_box


def _value(coeffs: np.ndarray, point: tuple[Fraction, ...]) -> Fraction:
    total = Fraction(0)
    for idx in itertools.product(*(range(n) for n in coeffs.shape)):
        term = Fraction(int(coeffs[idx].p), int(coeffs[idx].q))
        for v, e in zip(point, idx, strict=True):
            term *= v**e
        total += term
    return total


coefficient = st.integers(-5, 5)


@given(st.lists(coefficient, min_size=9, max_size=9), st.integers(-3, 2), st.integers(1, 3))
def test_bernstein_coefficients_enclose_the_range_and_hit_the_corners(
    cs: list[int], a: int, w: int
) -> None:
    coeffs = np.array([fmpq(c) for c in cs], dtype=object).reshape(3, 3)
    box = [(fmpq(a), fmpq(a + w)), (fmpq(0), fmpq(1))]
    bern = bernstein_coefficients(coeffs, box)
    lo = min(Fraction(int(c.p), int(c.q)) for c in bern.flat)
    hi = max(Fraction(int(c.p), int(c.q)) for c in bern.flat)
    for u, v in itertools.product(np.linspace(0, 1, 5), repeat=2):
        x = Fraction(a) + Fraction(w) * Fraction(u)
        val = _value(coeffs, (x, Fraction(v)))
        assert lo <= val <= hi
    corner = bern[-1, 0]
    assert Fraction(int(corner.p), int(corner.q)) == _value(coeffs, (Fraction(a + w), Fraction(0)))


def test_a_positive_polynomial_is_proven_and_a_negative_one_gives_an_exact_point() -> None:
    # f(x, y) = (x - 1/2)^2 + (y - 1/2)^2 - r: negative only inside a small disc
    def f(r: Fraction) -> np.ndarray:
        terms = {(2, 0): 1, (1, 0): -1, (0, 2): 1, (0, 1): -1, (0, 0): Fraction(1, 2) - r}
        return from_terms({k: fmpq(Fraction(v).numerator, Fraction(v).denominator)
                           for k, v in terms.items()}, 2)  # fmt: skip

    box = [(fmpq(0), fmpq(1)), (fmpq(0), fmpq(1))]
    assert positive_on_box(f(Fraction(-1, 100)), box, budget=1000).sign is BoxSign.PROVEN
    found = positive_on_box(f(Fraction(1, 100)), box, budget=1000)
    assert found.sign is BoxSign.POINT and found.point is not None
    x, y = (Fraction(int(q.p), int(q.q)) for q in found.point)
    assert (x - Fraction(1, 2)) ** 2 + (y - Fraction(1, 2)) ** 2 <= Fraction(1, 100)


def test_a_touching_zero_exhausts_the_budget_and_is_never_proven() -> None:
    # (x - 1/3)^2 >= 0 touches 0 at an irrational-free point that is never a dyadic corner
    coeffs = from_terms({(2,): fmpq(1), (1,): fmpq(-2, 3), (0,): fmpq(1, 9)}, 1)
    r = positive_on_box(coeffs, [(fmpq(0), fmpq(1))], budget=50)
    assert r.sign is BoxSign.BUDGET and r.boxes == 50
