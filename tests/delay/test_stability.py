"""Right-half-plane roots of P + Q e^{-sτ}: exact counts against the argument principle."""

from __future__ import annotations

import random

import pytest
from flint import fmpq, fmpq_poly

from seapass.delay.stability import (
    characteristic,
    crossings,
    delay_independent_stability,
    first_crossing,
    rhp_count,
    stability_at,
)

from .reference import rhp_roots_quasi


def test_rhp_count_on_random_products():
    rng = random.Random(7)
    for _ in range(300):
        p, expected, axis = fmpq_poly([rng.choice([1, -2, 3])]), 0, False
        while p.degree() < rng.randint(1, 8):
            if rng.random() < 0.4:
                re, im = (
                    fmpq(rng.randint(-5, 5), rng.randint(1, 3)),
                    fmpq(rng.randint(1, 5), rng.randint(1, 4)),
                )
                p *= fmpq_poly([re * re + im * im, -2 * re, 1])
                expected += 2 if re > 0 else 0
                axis |= re == 0
            else:
                r = fmpq(rng.randint(-4, 4), rng.randint(1, 3))
                p *= fmpq_poly([-r, 1])
                expected += r > 0
                axis |= r == 0
        assert rhp_count(p) == (None if axis else expected)


def _ch(p, q):
    return characteristic((fmpq_poly(p), fmpq_poly(q)))


def test_first_order_crossing_in_closed_form():
    # s + a + c e^{-sτ}: ω = sqrt(c² - a²), τ0 = (π - atan(ω/a))/ω
    import math

    a, c = 0.5, 2.0
    (cr,) = crossings(_ch([fmpq(1, 2), 1], [2]))
    w = math.sqrt(c * c - a * a)
    assert float(cr.omega.mid()) == pytest.approx(w, rel=1e-15)
    assert float(cr.delay.mid()) == pytest.approx((math.pi - math.atan(w / a)) / w, rel=1e-14)
    assert cr.direction == 1


@pytest.mark.parametrize("seed", range(12))
def test_stability_agrees_with_the_argument_principle(seed):
    rng = random.Random(seed)
    deg = rng.randint(1, 3)
    p = [fmpq(rng.randint(1, 9), rng.randint(1, 3)) for _ in range(deg)] + [fmpq(1)]
    q = [fmpq(rng.randint(-9, 9), rng.randint(1, 3)) for _ in range(rng.randint(1, deg))]
    ch = _ch(p, q)
    assert ch.kind == "retarded"
    radius = 2 + float(sum(abs(c) for c in p) + sum(abs(c) for c in q))
    for tau in (fmpq(1, 10), fmpq(1, 2), fmpq(3, 2), fmpq(4)):
        st = stability_at(ch, tau)
        if st.stable is None:
            continue
        n = rhp_roots_quasi([float(c) for c in p], [float(c) for c in q], float(tau), radius)
        assert abs(n - round(n)) < 1e-3
        assert st.rhp_roots == round(n), (p, q, tau)


def test_kinds_and_delay_independence():
    assert _ch([2, 1], [1]).kind == "retarded"
    assert delay_independent_stability(_ch([2, 1], [1]))  # |s + 2| > 1 on the axis
    assert not delay_independent_stability(_ch([fmpq(1, 2), 1], [2]))
    neutral = _ch([1, 1], [0, fmpq(1, 2)])
    assert neutral.kind == "neutral" and neutral.neutral_ratio == fmpq(1, 2)
    assert stability_at(_ch([1, 1], [0, 2]), fmpq(1)).stable is False  # |q_n/p_n| > 1
    assert stability_at(_ch([1, 1], [0, 1]), fmpq(1)).stable is None  # = 1: undecided
    assert stability_at(_ch([1], [0, 1]), fmpq(1)).stable is False  # advanced
    assert (
        stability_at(
            characteristic((fmpq_poly([1, 1]), fmpq_poly([1]), fmpq_poly([1]))), fmpq(1)
        ).stable
        is None
    )


def test_first_crossing_and_counting_many_crossings():
    ch = _ch([fmpq(1, 2), 1], [2])
    cr = first_crossing(ch)
    assert (
        cr is not None
        and cr.count_below(fmpq(100))
        == int((100 * float(cr.omega.mid()) - float(cr.phase.mid())) // (2 * 3.141592653589793)) + 1
    )
    assert stability_at(ch, fmpq(100)).rhp_roots == 2 * cr.count_below(fmpq(100))
