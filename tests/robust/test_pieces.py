"""The set algebra of `seapass.robust.pieces`, checked point by point (hypothesis)."""

from __future__ import annotations

from fractions import Fraction

from hypothesis import given
from hypothesis import strategies as st

from seapass.robust.pieces import as_floats, intersect, merge, minus, widen

ends = st.integers(min_value=0, max_value=40).map(lambda n: Fraction(n, 4))
piece = st.tuples(ends, ends).map(lambda p: (min(p), max(p)))
pieces = st.lists(piece, max_size=5)
points = [Fraction(n, 8) for n in range(-2, 84)]


def _in(x: Fraction, ps: list[tuple[Fraction, Fraction]]) -> bool:
    return any(a <= x <= b for a, b in ps)


@given(pieces, pieces)
def test_merge_intersect_and_minus_agree_with_membership(xs, ys) -> None:
    m, i, d = merge(xs), intersect(xs, ys), minus(merge(xs), merge(ys))
    assert all(a <= b for a, b in m) and all(m[k][1] < m[k + 1][0] for k in range(len(m) - 1))
    for x in points:
        assert _in(x, m) == _in(x, xs)
        assert _in(x, i) == (_in(x, xs) and _in(x, ys))
        # the closure of xs minus ys: every point of xs outside ys is in it, nothing outside xs
        if _in(x, xs) and not _in(x, ys):
            assert _in(x, d)
        if _in(x, d):
            assert _in(x, xs)


@given(pieces)
def test_rounding_goes_the_promised_way(xs) -> None:
    third = [(a / 3, b / 3) for a, b in merge(xs)]
    for (a, b), (lo, hi) in zip(third, as_floats(third, inward=False), strict=True):
        assert Fraction(lo) <= a and b <= Fraction(hi)
    for lo, hi in as_floats(third, inward=True):
        assert any(a <= Fraction(lo) and Fraction(hi) <= b for a, b in third)
    wide = widen(third, Fraction(0), Fraction(40))
    assert all(_in(x, wide) for x in points if _in(x, third))
