"""The trigonometric real part F = |D|² Re Z against an independent evaluation of Z(jω)."""

from __future__ import annotations

import numpy as np
import pytest
from flint import arb, fmpq
from hypothesis import given
from hypothesis import strategies as st

from seapass.analysis.impedance import exact_rational_function
from seapass.delay.balls import arb_of, precision
from seapass.delay.structure import delayed_impedance
from seapass.delay.trig import real_part
from seapass.exact.axis import real_part_polynomial
from seapass.model.sea import SEA

from .reference import sea_impedance


def _sea(b1, kd, bd, cl, tau):
    return SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)", CL="cl*exp(-tau*s)",
               values=dict(m=1.0, b=10.0, k1=1000.0, b1=b1, kd=kd, bd=bd, cl=cl, tau=tau))  # fmt: skip


@given(
    b1=st.floats(0.5, 80), kd=st.floats(1, 5000), bd=st.floats(0, 100),
    cl=st.floats(0.1, 500), tau=st.floats(1e-4, 0.05),
)  # fmt: skip
def test_real_part_has_the_sign_and_size_of_re_z(b1, kd, bd, cl, tau):
    sea = _sea(b1, kd, bd, cl, tau)
    z = delayed_impedance(sea)
    f = real_part(z)
    w = np.geomspace(0.5, 3e3, 25)
    ref = sea_impedance(sea, w, float(z.tau)).real
    s = 1j * w
    e = np.exp(-s * float(z.tau))
    den = sum(np.polyval([float(c) for c in reversed(p.coeffs())], s) * e**k
              for k, p in enumerate(z.den))  # fmt: skip
    with precision(128):
        form = f.balls()
        got = np.array([float(form.value(arb(float(x)), arb_of(z.tau)).mid()) for x in w])
    np.testing.assert_allclose(
        got / np.abs(den) ** 2, ref, rtol=1e-7, atol=1e-9 * np.abs(ref).max()
    )


def test_zero_delay_is_the_rational_real_part():
    sea = _sea(20, 500, 25, 3, 0.0)
    f = real_part(delayed_impedance(sea, values=dict(tau=0.01)))
    num, den = exact_rational_function(SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="cl",
                                           values={k: v for k, v in sea.values.items() if k != "tau"}))  # fmt: skip
    px = real_part_polynomial(num, den)
    x = f.in_x()[0]
    total = sum(x[1:], x[0])
    # same polynomial up to the positive factor the two derivations may differ by
    ratio = total.leading_coefficient() / px.leading_coefficient()
    assert ratio > 0 and total == px * ratio


def test_derivatives_match_finite_differences():
    f = real_part(delayed_impedance(_sea(20, 500, 25, 3, 0.004)))
    with precision(200):
        form = f.balls()
        w, t, h = arb(37.5), arb_of(fmpq(4, 1000)), arb("1e-20")
        dw = (form.value(w + h, t) - form.value(w - h, t)) / (2 * h)
        dt = (form.value(w, t + h) - form.value(w, t - h)) / (2 * h)
        assert abs(float((dw - form.d_omega(w, t)).mid())) <= 1e-12 * abs(float(dw.mid()))
        assert abs(float((dt - form.d_tau(w, t)).mid())) <= 1e-12 * abs(float(dt.mid()))


@pytest.mark.parametrize("power", [2, 3])
def test_higher_powers_of_the_delay_give_higher_harmonics(power):
    z = delayed_impedance(f"m*s + b + K*exp(-{power}*tau*s)/s", values=dict(m=1, b=2, K=5, tau=0.1))
    f = real_part(z)
    assert f.order == power
    w = 3.0
    ref = 2 - 5 * np.sin(power * w * 0.1) / w  # Re(K e^{-jkωτ}/(jω)) = -K sin(kωτ)/ω
    with precision(128):
        got = float(f.balls().value(arb(w), arb_of(z.tau)).mid())
    assert got == pytest.approx(ref * w**2, rel=1e-12)
