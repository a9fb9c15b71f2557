"""The exact polynomial kernel (python-flint), cross-checked against sympy's real roots over QQ.

sympy's ``Poly.count_roots`` and ``real_roots`` (Sturm sequences and exact
``CRootOf`` over QQ, no ball arithmetic) are the independent method; signs at
roots are also checked against mpmath at 120 digits.
"""

from __future__ import annotations

import itertools
import math
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp
from flint import acb, arb, fmpq, fmpq_poly, fmpz_poly
from hypothesis import given
from hypothesis import strategies as st

from seapass.exact import poly as ep

X = fmpq_poly([0, 1])
_x = sp.Symbol("x")


def from_roots(roots, lead=1) -> fmpq_poly:
    p = fmpq_poly([ep.rational(lead)])
    for r in roots:
        p *= X - ep.rational(r)
    return p


def sympy_poly(p: fmpq_poly) -> sp.Poly:
    return sp.Poly([sp.Rational(int(c.p), int(c.q)) for c in reversed(p.coeffs())], _x, domain="QQ")


def sympy_count(p: fmpq_poly, lo, hi) -> int:
    """Distinct real roots in ``(lo, hi]`` by sympy (Sturm over QQ), ``None`` for infinity."""
    sp_p = sympy_poly(p)
    lo_s = None if lo is None else sp.Rational(lo.numerator, lo.denominator)
    hi_s = None if hi is None else sp.Rational(hi.numerator, hi.denominator)
    n = sp_p.count_roots(lo_s, hi_s)
    return n - (1 if lo_s is not None and sp_p.eval(lo_s) == 0 else 0)


# ---------------------------------------------------------------- strategies

small = st.integers(-30, 30)
rationals = st.builds(Fraction, small, st.sampled_from([1, 2, 3, 7, 1000]))


@st.composite
def polys_with_structure(draw) -> fmpq_poly:
    """Products of rational roots (some repeated, some 10^-k apart), ±sqrt pairs and complex pairs."""
    roots = draw(st.lists(rationals, min_size=0, max_size=5))
    roots += draw(st.lists(st.sampled_from(roots), max_size=2)) if roots else []
    p = from_roots(roots, draw(st.sampled_from([1, -2, Fraction(1, 3)])))
    if roots and draw(st.booleans()):  # a close pair
        p *= X - ep.rational(roots[0] + Fraction(1, 10 ** draw(st.integers(3, 15))))
    for c in draw(st.lists(st.integers(1, 50), max_size=2)):  # ±sqrt(c) or ±j sqrt(c)
        p *= X**2 - c if draw(st.booleans()) else X**2 + c
    if draw(st.booleans()):  # two irrational roots 2^-k apart: x^2 - 2 and x^2 - (2 + 2^-k)
        k = draw(st.integers(10, 80))
        p *= (X**2 - 2) * (X**2 - (2 + fmpq(1, 2**k)))
    if p.degree() < 1:
        p *= X - 1
    return p


float_coeffs = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)


@st.composite
def polys_from_floats(draw) -> fmpq_poly:
    """Coefficients as SEA models produce them: floats converted exactly (big denominators)."""
    coeffs = draw(st.lists(float_coeffs, min_size=2, max_size=9))
    p = ep.as_poly(coeffs)
    return p if p.degree() >= 1 else X + 1


any_poly = st.one_of(polys_with_structure(), polys_from_floats())
ends = st.one_of(st.none(), rationals)


# ---------------------------------------------------------------- cross-checks


@given(any_poly, ends, ends)
def test_count_matches_sympy(p, lo, hi):
    if lo is not None and hi is not None and hi <= lo:
        lo, hi = hi, lo
    if lo is not None and hi is not None and hi == lo:
        hi = lo + 1
    assert ep.count_real_roots(p, lo, hi) == sympy_count(p, lo, hi)


@given(any_poly, st.one_of(st.none(), rationals))
def test_isolating_intervals_hold_one_root_each(p, lo):
    ivs = ep.isolate_real_roots(p, lo)
    sf = ep.squarefree_part(p)
    assert len(ivs) == sympy_count(p, lo, None)
    assert ivs == sorted(ivs)
    for (_, b), (c, _) in itertools.pairwise(ivs):
        assert b <= c  # disjoint
    for a, b in ivs:
        fa, fb = ep.to_fraction(a), ep.to_fraction(b)
        if lo is not None:
            assert fa >= lo
        if a == b:
            assert sf(a) == 0
        else:
            assert sympy_count(p, fa, fb) == 1


@given(polys_with_structure())  # sympy's real_roots can take minutes on float-sized rationals
def test_refined_roots_and_values_match_sympy(p):
    ivs = ep.isolate_real_roots(p)
    exact = list(dict.fromkeys(sp.real_roots(sympy_poly(p))))  # ascending, distinct
    assert len(ivs) == len(exact)
    for k, (iv, r) in enumerate(zip(ivs, exact, strict=True)):
        a, b = ep.refine(p, iv, fmpq(1, 2**70))
        assert a == b or b - a <= fmpq(1, 2**70)
        fa, fb = ep.to_fraction(a), ep.to_fraction(b)
        if a == b:
            assert sympy_poly(p).eval(sp.Rational(fa.numerator, fa.denominator)) == 0
            assert sympy_count(p, None, fa) == k + 1
        else:  # the k-th root, alone in (a, b]
            assert sympy_count(p, fa, fb) == 1 and sympy_count(p, None, fa) == k
        assert ep.root_value(p, iv) == pytest.approx(float(sp.N(r, 30)), rel=2**-52, abs=0)


@given(polys_with_structure(), st.lists(small, min_size=1, max_size=4), st.booleans())
def test_sign_at_root_matches_high_precision(p, qc, share):
    """The exact sign against mpmath at 120 digits (cases built to be unambiguous there)."""
    q = ep.as_poly(qc)
    sf = ep.squarefree_part(p)
    if share:
        q *= sf  # vanishes at every root
    if q.is_zero():
        return
    ivs = ep.isolate_real_roots(p)
    exact = list(dict.fromkeys(sp.real_roots(sympy_poly(p))))  # ascending, distinct
    with mpmath.workdps(120):
        for iv, r in zip(ivs, exact, strict=True):
            s = ep.sign_at_root(q, p, iv)
            if share:
                assert s == 0
                continue
            val = mpmath.polyval(
                [mpmath.mpf(int(c.p)) / int(c.q) for c in reversed(q.coeffs())], sp.N(r, 130)
            )
            if abs(val) > mpmath.mpf(10) ** -80:
                assert s == (1 if val > 0 else -1)
            else:  # q(r) = 0 exactly iff r is a root of gcd(sf, q)
                g = sympy_poly(sf.gcd(q))
                assert (s == 0) == (g.degree() > 0 and g.eval(r) == 0)


@given(
    st.lists(
        st.tuples(rationals, st.integers(1, 4)), min_size=1, max_size=4, unique_by=lambda t: t[0]
    )
)
def test_odd_multiplicity_part(roots_mults):
    p = fmpq_poly([1])
    for r, m in roots_mults:
        p *= (X - ep.rational(r)) ** m
    odd = ep.positive_roots_odd_multiplicity(-3 * p)
    assert odd == from_roots(sorted(r for r, m in roots_mults if m % 2 == 1))
    assert ep.squarefree_part(p) == from_roots([r for r, _ in roots_mults])


# ---------------------------------------------------------------- known roots (ported from the Fraction kernel)

small_ints = st.integers(min_value=-20, max_value=20)


@given(st.lists(small_ints, min_size=1, max_size=6), st.lists(st.integers(1, 9), max_size=2))
def test_count_matches_known_roots(roots, complex_pairs):
    p = from_roots(roots)
    for c in complex_pairs:  # x^2 + c has no real roots
        p *= X**2 + c
    distinct = sorted(set(roots))
    assert ep.count_real_roots(p, -100, 100) == len(distinct)
    assert ep.count_real_roots(p, 0) == len([r for r in distinct if r > 0])
    ivs = ep.isolate_real_roots(p, -100, 100)
    assert len(ivs) == len(distinct)
    for (a, b), r in zip(ivs, distinct, strict=True):
        assert a < r <= b


@given(st.lists(st.integers(-50, 50), min_size=2, max_size=7))
def test_count_matches_numpy_for_generic_polys(coeffs):
    p = ep.as_poly(coeffs)
    if p.degree() < 1:
        return
    sf = ep.squarefree_part(p)
    r = np.roots([float(c) for c in reversed(sf.coeffs())])
    real = r[np.abs(r.imag) < 1e-7].real
    # only compare when numpy is unambiguous (no nearly-real complex pairs)
    if np.any((np.abs(r.imag) >= 1e-7) & (np.abs(r.imag) < 1e-3)):
        return
    assert ep.count_real_roots(p) == len(real)


# ---------------------------------------------------------------- pinned cases


@pytest.mark.parametrize(
    ("p", "lo", "hi", "count"),
    [
        (from_roots([1, 2, 3]), 0, None, 3),
        (from_roots([1, 2, 3]), 1, 3, 2),  # (1, 3]: a root at each end, lo excluded
        (from_roots([0, 0, 5]), 0, None, 1),  # double root at the excluded end
        (from_roots([0, 0, 5]), None, 0, 1),
        ((X**2 - 2) * (X**2 - 2 - fmpq(1, 2**200)), 0, None, 2),  # roots 2^-201 apart
        (from_roots([fmpq(1, 10**40), fmpq(2, 10**40)]), 0, fmpq(3, 10**40), 2),  # tiny roots
        (from_roots([10**30, 10**30 + 1]), 0, None, 2),  # huge roots
        (X**2 + 1, None, None, 0),
        ((X - 1) ** 7 * (X + 1) ** 4, None, None, 2),  # high multiplicity
        (fmpq_poly([3]), None, None, 0),
        (fmpq_poly([fmpq(1, 3), 1]) ** 3 * (X**2 - 3), -1, 1, 1),  # root -1/3 (not dyadic)
    ],
)
def test_pinned_counts(p, lo, hi, count):
    assert ep.count_real_roots(p, lo, hi) == count
    assert len(ep.isolate_real_roots(p, lo, hi)) == count


def test_wilkinson_20_roots_isolated_exactly():
    p = from_roots(range(1, 21))
    ivs = ep.isolate_real_roots(p, 0)
    assert len(ivs) == 20
    assert [ep.root_value(p, iv) for iv in ivs] == [float(k) for k in range(1, 21)]
    # perturbed Wilkinson: famous for ill-conditioned roots, still exact here
    q = p - fmpq(1, 2**23) * X**19
    assert ep.count_real_roots(q) == sympy_count(q, None, None) == 10


def test_intervals_equal_classical_sturm_bisection():
    """Dyadic bisection intervals of (lo, hi], independent of how roots are found."""
    p = from_roots([1, 3]) * (X**2 - 2)
    assert ep.isolate_real_roots(p, 0) == [
        (fmpq(0), fmpq(9, 8)),
        (fmpq(9, 8), fmpq(9, 4)),
        (fmpq(9, 4), fmpq(9, 2)),
    ]
    # a root on a bisection point belongs to the left part, as (a, b]
    assert ep.isolate_real_roots(from_roots([1, 2]), 0, 4) == [
        (fmpq(0), fmpq(1)),
        (fmpq(1), fmpq(2)),
    ]


def test_sign_at_root_exact_cases():
    p = X**2 - 2
    ((iv),) = ep.isolate_real_roots(p, 0)
    assert ep.sign_at_root(X - fmpq(141421356, 10**8), p, iv) == 1
    assert ep.sign_at_root(X - fmpq(141421357, 10**8), p, iv) == -1
    assert ep.sign_at_root(p * (X + 3), p, iv) == 0
    # q with a root within 2^-100 of sqrt(2), on either side: separated exactly
    below = fmpq(math.isqrt(2 * 4**100), 2**100)  # floor(sqrt(2) 2^100) / 2^100
    assert ep.sign_at_root(X - below, p, iv) == 1
    assert ep.sign_at_root(X - below - fmpq(1, 2**100), p, iv) == -1
    # an exact rational root (a == b) and a root at the right end of its interval
    assert ep.sign_at_root(X - 5, from_roots([2]), (fmpq(2), fmpq(2))) == -1
    assert ep.sign_at_root(X, from_roots([2]), (fmpq(1), fmpq(2))) == 1


def test_root_value_overflow_and_exact():
    assert ep.root_value(X - fmpq(1, 3), (fmpq(0), fmpq(1))) == 1 / 3
    big = from_roots([10**400])
    (iv,) = ep.isolate_real_roots(big, 0)
    with pytest.raises(OverflowError):
        ep.root_value(big, iv)


def test_conversions():
    assert ep.rational(0.1) == fmpq(3602879701896397, 36028797018963968)  # exact float value
    assert ep.rational(Fraction(-2, 6)) == fmpq(-1, 3)
    assert ep.as_poly([Fraction(1, 2), 0.25, 3]) == fmpq_poly([fmpq(1, 2), fmpq(1, 4), 3])
    assert ep.as_poly(fmpz_poly([1, 2])) == fmpq_poly([1, 2])
    assert ep.to_fractions(fmpq_poly([fmpq(1, 2), 0, 3])) == (
        Fraction(1, 2),
        Fraction(0),
        Fraction(3),
    )
    assert ep.to_fractions(fmpq_poly([])) == ()
    assert ep.degree(fmpq_poly([])) == -1
    for bad in (True, "1", 1j):
        with pytest.raises(TypeError):
            ep.rational(bad)
    for bad in (math.nan, math.inf):
        with pytest.raises((ValueError, OverflowError)):
            ep.rational(bad)
    with pytest.raises(ValueError, match="zero polynomial"):
        ep.count_real_roots(fmpq_poly([]))


def test_gcd_division_via_flint():
    a, b = from_roots([1, 2, 3]), from_roots([2, 3, 7])
    assert a.gcd(b) == from_roots([2, 3])
    q, r = divmod(a, from_roots([1]))
    assert r.is_zero() and q == from_roots([2, 3])


# ---------------------------------------------------------------- certification guard


def test_a_wrong_enclosure_is_an_error_not_a_guess(monkeypatch):
    """If the certified enclosure fails the exact sign check, nothing is decided."""
    p = X**2 - 2

    def wrong(z):  # claims a real root in [1.9, 2.1]: no sign change of x^2 - 2 there
        return [(acb(arb(2, fmpq(1, 10))), 1), (acb(arb(-2, fmpq(1, 10))), 1)]

    monkeypatch.setattr(ep, "_complex_roots", wrong)
    with pytest.raises(ArithmeticError, match="refusing to guess"):
        ep.count_real_roots(p, 0)


def test_missing_roots_are_an_error(monkeypatch):
    monkeypatch.setattr(ep, "_complex_roots", lambda z: [])
    with pytest.raises(ArithmeticError, match="every simple root"):
        ep.count_real_roots(X**2 - 2)


def test_overlapping_enclosures_are_an_error(monkeypatch):
    p = (X - 1) * (X - fmpq(11, 10))
    balls = [(acb(arb(fmpq(21, 20), fmpq(1, 5))), 1), (acb(arb(fmpq(21, 20), fmpq(1, 5))), 1)]
    monkeypatch.setattr(ep, "_complex_roots", lambda z: balls)
    with pytest.raises(ArithmeticError):
        ep.count_real_roots(p)


def test_kernel_leaves_flint_precision_alone():
    from flint import ctx

    before = ctx.prec
    ep.isolate_real_roots((X**2 - 2) * (X**2 - 2 - fmpq(1, 2**300)))
    assert ctx.prec == before
