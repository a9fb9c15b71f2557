from fractions import Fraction

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from seapass.exact import poly as ep


def poly_from_roots(roots):
    p = (Fraction(1),)
    for r in roots:
        p = ep.mul(p, (Fraction(-r), Fraction(1)))
    return p


small_ints = st.integers(min_value=-20, max_value=20)


@given(st.lists(small_ints, min_size=1, max_size=6), st.lists(st.integers(1, 9), max_size=2))
def test_count_matches_known_roots(roots, complex_pairs):
    p = poly_from_roots(roots)
    for c in complex_pairs:  # x^2 + c has no real roots
        p = ep.mul(p, (Fraction(c), Fraction(0), Fraction(1)))
    distinct = sorted(set(roots))
    assert ep.count_real_roots(p, Fraction(-100), Fraction(100)) == len(distinct)
    assert ep.count_real_roots(p, Fraction(0), None) == len([r for r in distinct if r > 0])
    ivs = ep.isolate_real_roots(p, Fraction(-100), Fraction(100))
    assert len(ivs) == len(distinct)
    for (a, b), r in zip(ivs, distinct, strict=True):
        assert a < r <= b


@given(st.lists(st.integers(-50, 50), min_size=2, max_size=7))
def test_count_matches_numpy_for_generic_polys(coeffs):
    p = ep.normalize([Fraction(c) for c in coeffs])
    if ep.degree(p) < 1:
        return
    sf = ep.squarefree_part(p)
    r = np.roots([float(c) for c in reversed(sf)])
    real = r[np.abs(r.imag) < 1e-7].real
    # only compare when numpy is unambiguous (no nearly-real complex pairs)
    if np.any((np.abs(r.imag) >= 1e-7) & (np.abs(r.imag) < 1e-3)):
        return
    assert ep.count_real_roots(p, -ep.cauchy_bound(sf), None) == len(real)


def test_sign_at_root_exact():
    # p = x^2 - 2, root sqrt(2); q = x - 1.41421356 is positive at sqrt(2)
    p = (Fraction(-2), Fraction(0), Fraction(1))
    ((a, b),) = ep.isolate_real_roots(p, Fraction(0), None)
    assert ep.sign_at_root((Fraction(-141421356, 10**8), Fraction(1)), p, a, b) == 1
    assert ep.sign_at_root((Fraction(-141421357, 10**8), Fraction(1)), p, a, b) == -1
    assert ep.sign_at_root(ep.mul(p, (Fraction(3), Fraction(1))), p, a, b) == 0


def test_gcd_and_division():
    a = poly_from_roots([1, 2, 3])
    b = poly_from_roots([2, 3, 7])
    assert ep.pgcd(a, b) == poly_from_roots([2, 3])
    q, r = ep.pdivmod(a, poly_from_roots([1]))
    assert r == () and q == poly_from_roots([2, 3])


def test_odd_multiplicity_part():
    p = ep.mul(poly_from_roots([1, 1, 2]), poly_from_roots([3, 3, 3]))
    odd = ep.positive_roots_odd_multiplicity(p)
    assert odd == poly_from_roots([2, 3])
