"""Exact high-frequency classification and the delay-independent bound omega1."""

from __future__ import annotations

import mpmath
import pytest
from flint import fmpq

from seapass.delay.balls import precision
from seapass.delay.highfreq import chebyshev, high_frequency
from seapass.delay.structure import delayed_impedance
from seapass.delay.trig import real_part
from seapass.model.sea import SEA

from .test_lowfreq import _exact_f


def _f(**v):
    vals = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0, tau=None)
    vals.update(v)
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)", values=vals)
    return real_part(delayed_impedance(sea, free_delay=True))


def test_damped_transmission_is_positive_with_a_finite_omega1():
    hf = high_frequency(_f())
    assert hf.kind == "positive" and hf.omega1 is not None
    for tau in (1e-4, 3e-3, 0.05, 0.7):
        for k in range(1, 60):
            w = float(hf.omega1) * (1 + k / 7)
            assert _exact_f(_f(), w, tau) > 0


@pytest.mark.parametrize(
    ("b", "bd", "kind"), [(10, 25, "unbounded"), (10, 5, "positive"), (10, 10, "tangent")]
)
def test_apd_high_frequency_compares_b_and_bd(b, bd, kind):
    assert high_frequency(_f(b1=0.0, b=b, bd=bd)).kind == kind


def test_unbounded_angle_is_a_negative_direction():
    hf = high_frequency(_f(b1=0.0))
    with precision(64):
        theta = float(hf.theta.mid())
    # h(θ) = b + bd cos θ with b = 10 < bd = 25
    assert 10 + 25 * mpmath.cos(theta) < 0


def test_chebyshev_expansion():
    # 1 + 2 T_1 + 3 T_2 = 1 + 2x + 3(2x^2 - 1)
    assert chebyshev([fmpq(1), fmpq(2), fmpq(3)]) == chebyshev([fmpq(1)]).__class__([-2, 2, 6])


def test_odd_leading_degree_is_unbounded():
    # Z = m s + B e^{-sτ}·s/(s + a)... leading Re term ω·B sin(ωτ)-like: use Z = s + e^{-sτ} s
    f = real_part(delayed_impedance("m*s + c*s*exp(-tau*s)", values=dict(m=1, c=1, tau=0.1)))
    assert high_frequency(f).kind == "unbounded"
