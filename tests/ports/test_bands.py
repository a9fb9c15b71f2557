"""Exact cells and bands on x >= 0, and the infimum of η, against known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from flint import fmpq, fmpq_poly
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar

from seapass.exact.halfline import half_line_cells
from seapass.ports.bands import failing_bands, half_line_points
from seapass.ports.eta import eta_infimum, sqrt_bounds

X = fmpq_poly([0, 1])
small = st.lists(st.integers(-6, 6), min_size=2, max_size=4).filter(lambda c: c[-1] != 0)


@settings(max_examples=40)
@given(st.lists(small, min_size=1, max_size=3))
def test_cells_agree_with_the_kernel(coeffs: list[list[int]]) -> None:
    polys = [fmpq_poly(c) for c in coeffs]
    polys.append(polys[0] * polys[-1])  # shared roots across the list
    ours, theirs = half_line_points(polys), half_line_cells(polys)
    assert len(ours) == len(theirs)
    for i, (a, b) in enumerate(zip(ours, theirs, strict=True)):
        assert [a.sign(p) for p in polys] == [b.sign(p) for p in polys]
        if i % 2 == 0:  # x = 0 and the roots (odd indices: any point inside a cell)
            assert float(a) == pytest.approx(float(b), rel=1e-12, abs=1e-300)


def test_bands_have_exact_edges_rounded_outward() -> None:
    p = (X - 2) * (X - 3)  # negative for 2 < x < 3: sqrt 2 < w < sqrt 3
    (band,) = failing_bands([p], lambda s: s[0] < 0)
    assert band.lo <= math.sqrt(2) and band.hi >= math.sqrt(3)
    assert band.lo == pytest.approx(math.sqrt(2), rel=1e-15) and band.hi == pytest.approx(
        math.sqrt(3), rel=1e-15
    )
    assert band.lo_x.lower < 2 <= band.lo_x.upper or band.lo_x.lower == 2
    assert failing_bands([X + 1], lambda s: s[0] < 0) == ()
    # two conditions, one band each, merged where they touch
    two = failing_bands([X - 4, (X - 1) * (X - 9)], lambda s: s[0] < 0 or s[1] < 0)
    assert len(two) == 1 and two[0].lo == 0.0 and round(two[0].hi, 9) == 3.0


def test_sqrt_bounds() -> None:
    for q in (fmpq(2), fmpq(1, 3), fmpq(10**40 + 7), fmpq(9, 4)):
        lo, hi = sqrt_bounds(q)
        assert lo * lo <= q <= hi * hi and float(hi - lo) < 1e-20 * max(1, float(hi))
    assert sqrt_bounds(fmpq(9, 4)) == (fmpq(3, 2), fmpq(3, 2))


@pytest.mark.parametrize(
    ("a", "q", "kind", "value", "omega"),
    [
        (X + 2, fmpq_poly([1]), "attained", 2.0, 0.0),
        ((X - 1) ** 2 + fmpq(1, 2), fmpq_poly([1]), "attained", 0.5, 1.0),
        (fmpq_poly([1]), X, "limit", 0.0, None),
        (X, X * X + 1, "attained", 0.0, 0.0),
    ],
)
def test_eta_known_infima(a, q, kind, value, omega) -> None:
    m = eta_infimum(a, q)
    assert m.kind == kind and m.value == pytest.approx(value, abs=1e-15)
    if omega is not None:
        assert m.omega == pytest.approx(omega, rel=1e-12)


def test_eta_unbounded_and_undefined() -> None:
    m = eta_infimum(fmpq_poly([-1]), X)  # −1/√x → −∞ as w → 0
    assert m.kind == "unbounded" and m.value == -math.inf and m.limit == 0.0
    assert eta_infimum(X, fmpq_poly([])).kind == "undefined"


def test_eta_irrational_minimum_against_scipy() -> None:
    a = X * X - 3 * X + 3
    q = (X + 1) ** 2 * (X + 2)
    m = eta_infimum(a, q)

    def f(t: float) -> float:
        x = math.exp(t)
        return (x * x - 3 * x + 3) / math.sqrt((x + 1) ** 2 * (x + 2))

    grid = np.linspace(-8, 8, 4001)
    t0 = grid[int(np.argmin([f(t) for t in grid]))]
    r = minimize_scalar(
        f, bounds=(t0 - 0.01, t0 + 0.01), method="bounded", options={"xatol": 1e-13}
    )
    assert m.kind == "attained"
    assert float(m.lower) <= r.fun + 1e-12 and r.fun <= float(m.upper) + 1e-9
    assert m.omega == pytest.approx(math.sqrt(math.exp(r.x)), rel=1e-5)
