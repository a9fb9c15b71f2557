"""Corners where a condition vanishes: the blow-up charts (seapass.robust.corners)."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
from flint import fmpq
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.robust.bernstein import from_terms
from seapass.robust.corners import CornerSign, positive_off_faces
from seapass.robust.faces import blow_axis, divide_out, evaluate, shift_axis


def _q(x: Fraction) -> fmpq:
    return fmpq(x.numerator, x.denominator)


_small = st.fractions(min_value=-3, max_value=3, max_denominator=5)
_unit = st.fractions(min_value=0, max_value=1, max_denominator=9)
_width = st.fractions(min_value=Fraction(1, 4), max_value=4, max_denominator=4)
_coeffs = st.lists(st.integers(min_value=-4, max_value=4), min_size=9, max_size=9).map(
    lambda xs: np.array([fmpq(x) for x in xs], dtype=object).reshape(3, 3)
)


@given(_coeffs, _small, _small, _width, _width, st.booleans(), st.booleans(), _unit, _unit)
def test_a_chart_reproduces_the_polynomial_exactly(
    f: np.ndarray,
    lo0: Fraction,
    lo1: Fraction,
    w0: Fraction,
    w1: Fraction,
    up0: bool,
    up1: bool,
    a: Fraction,
    s: Fraction,
) -> None:
    """The chart of axis 0 at a corner of [lo0, lo0 + w0] × [lo1, lo1 + w1]: with
    x0 = q0 ± y0, x1 = q1 ± (w1/w0)·y0·σ, f(x) = y0^r·g(y0, σ) at every chart point, and the
    chart point lies in the box (the charts cover it: y1/w1 ≤ y0/w0 here)."""
    box = [(_q(lo0), _q(lo0 + w0)), (_q(lo1), _q(lo1 + w1))]
    q = [box[0][1] if up0 else box[0][0], box[1][1] if up1 else box[1][0]]
    d = [-1 if up0 else 1, -1 if up1 else 1]
    local = shift_axis(shift_axis(f, 0, q[0], d[0]), 1, q[1], d[1])
    g = blow_axis(local, 0, 1, _q(w1) / _q(w0))
    y0, sigma = _q(a) * _q(w0), _q(s)
    x = (q[0] + d[0] * y0, q[1] + d[1] * (_q(w1) / _q(w0)) * y0 * sigma)
    assert all(lo <= v <= hi for v, (lo, hi) in zip(x, box, strict=True))
    assert evaluate(g, (y0, sigma)) == evaluate(f, x)
    assert evaluate(local, (y0, (_q(w1) / _q(w0)) * y0 * sigma)) == evaluate(f, x)
    quotient = divide_out(g, 0, fmpq(0), upper=False)
    if quotient is not None:
        r = g.shape[0] - quotient.shape[0]
        assert y0**r * evaluate(quotient, (y0, sigma)) == evaluate(f, x)


_terms = st.dictionaries(
    st.tuples(st.integers(0, 2), st.integers(0, 2)),
    st.integers(min_value=-3, max_value=5),
    min_size=1,
    max_size=5,
)


@settings(max_examples=40)
@given(_terms, st.sets(st.tuples(st.integers(0, 1), st.booleans()), max_size=2))
def test_the_blow_up_never_proves_a_polynomial_negative_off_the_excused_faces(
    terms: dict[tuple[int, int], int], excused: set[tuple[int, bool]]
) -> None:
    """Soundness: PROVEN means positive at every grid point on no excused face; POINT
    is an exact point with f < 0 on no excused face; STUCK is a point with f ≤ 0."""
    f = from_terms({e: fmpq(c) for e, c in terms.items()}, 2)
    box = [(fmpq(0), fmpq(1)), (fmpq(0), fmpq(2))]
    r = positive_off_faces(f, box, excused, budget=300, max_depth=4)

    def on_excused(x: tuple[fmpq, ...]) -> bool:
        return any(x[a] == box[a][1 if up else 0] for a, up in excused)

    if r.sign is CornerSign.PROVEN:
        for u, v in itertools.product(range(9), range(9)):
            x = (fmpq(u, 8), fmpq(v, 4))
            assert on_excused(x) or evaluate(f, x) > 0
    elif r.sign is CornerSign.POINT:
        assert r.point is not None and not on_excused(r.point) and evaluate(f, r.point) < 0
    elif r.sign is CornerSign.STUCK:
        assert r.point is not None and evaluate(f, r.point) <= 0


def test_two_faces_meeting_at_a_zero_corner_are_proven_off_the_corner() -> None:
    """u + v² on [0, 1]²: zero only at the corner; proven when a face through it is
    excused, never otherwise (the corner itself is not positive)."""
    f = from_terms({(1, 0): fmpq(1), (0, 2): fmpq(1)}, 2)
    box = [(fmpq(0), fmpq(1))] * 2
    proven = positive_off_faces(f, box, {(0, False)}, budget=100)
    assert proven.sign is CornerSign.PROVEN and proven.charts > 1
    stuck = positive_off_faces(f, box, set(), budget=100)
    assert stuck.sign is CornerSign.STUCK and stuck.point == (fmpq(0), fmpq(0))


def test_a_weighted_corner_needs_two_blow_ups() -> None:
    """The real part of LP near t = 1, b1 = 0 in local form: p·m² + p·c·v + K·v² with
    c < 0 (p = b1, v = 1 − t).  Positive off p = 0 for small p, zero at the corner; the
    chart p = v·σ leaves v·(σ + …) and a second blow-up resolves it."""
    k, c = fmpq(50), fmpq(-9)
    # p + c·p·v + K·v² on v ∈ [0, 1/8], p ∈ [0, 1]
    f = from_terms({(0, 1): fmpq(1), (1, 1): c, (2, 0): k}, 2)
    box = [(fmpq(0), fmpq(1, 8)), (fmpq(0), fmpq(1))]
    r = positive_off_faces(f, box, {(1, False)}, budget=400)
    assert r.sign is CornerSign.PROVEN and r.charts >= 3
    # independently: f = p·(1 + c·v) + K·v²; for v ≤ 1/9 both terms are ≥ 0 and not both
    # zero off the corner; for v in (1/9, 1/8], K·v² ≥ 50/81 > 1/8 ≥ −p·(1 + c·v).  A grid:
    for v, p in itertools.product(np.linspace(0, 0.125, 17)[1:], np.linspace(0, 1, 17)[1:]):
        assert p + float(c) * p * v + float(k) * v * v > 0


def test_a_negative_point_next_to_an_excused_face_is_moved_off_it() -> None:
    """u − v on [0, 1]² with u = 0 excused: negative at (0, v), and also at points off the
    face; the point returned lies off the excused face."""
    f = from_terms({(1, 0): fmpq(1), (0, 1): fmpq(-1)}, 2)
    box = [(fmpq(0), fmpq(1))] * 2
    r = positive_off_faces(f, box, {(0, False)}, budget=50)
    assert r.sign is CornerSign.POINT and r.point is not None
    assert r.point[0] > 0 and evaluate(f, r.point) < 0
