"""The exact (python-flint) discretization against the symbolic (sympy) one, coefficient for
coefficient: the fast path the deployed controller uses is the scheme the bounds use."""

from __future__ import annotations

import random
from fractions import Fraction

import pytest
import sympy as sp

from seapass.sampled.emulation import coeffs_in_q, discrete_paths, exact_paths, split_polynomial
from seapass.sampled.joint import DiscreteTF, q_reduce

S = sp.Symbol("s")


def _random_controller(rng: random.Random) -> sp.Expr:
    def r(lo: float, hi: float) -> sp.Rational:
        return sp.Rational(rng.randint(int(lo * 100), int(hi * 100)), 100)

    e = r(0.1, 5) + r(0, 30) / S + r(0, 2) * S / (1 + S / r(50, 500))
    e += rng.choice([0, r(0, 1) * S, r(1, 9) / (S**2 + r(1, 20) * S + r(100, 900))])
    return e * r(100, 3000)


@pytest.mark.parametrize("method", ["tustin", "backward"])
@pytest.mark.parametrize("vf", [None, 30.0])
def test_exact_paths_equal_the_symbolic_paths(method: str, vf: float | None) -> None:
    rng = random.Random(hash((method, vf)) % 1000)
    T = Fraction(1, 1000)
    for _ in range(12):
        e = _random_controller(rng)
        coeffs, proper = split_polynomial(e)
        err, meas = discrete_paths(coeffs, proper, T, method=method, velocity_filter=vf)  # type: ignore[arg-type]
        old = (
            DiscreteTF(*coeffs_in_q(sp.sympify(err)), T),
            DiscreteTF(*coeffs_in_q(sp.sympify(meas)), T),
        )
        assert exact_paths(e, T, method=method, velocity_filter=vf) == old, e  # type: ignore[arg-type]


def test_reduction_keeps_the_ratio_when_the_denominator_is_not_normalized() -> None:
    num, den = q_reduce((Fraction(6), Fraction(3)), (Fraction(4), Fraction(2), Fraction(0)))
    assert (num, den) == ((Fraction(3, 2),), (Fraction(1),))  # 3(2 + q) / 2(2 + q) = 3/2
