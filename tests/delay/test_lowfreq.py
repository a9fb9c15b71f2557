"""Exact low-frequency bounds: L <= F <= U everywhere, Taylor coefficients, uniform cutoffs."""

from __future__ import annotations

import mpmath
import pytest
from flint import fmpq
from hypothesis import given
from hypothesis import strategies as st

from seapass.delay.lowfreq import (
    at_fixed_delay,
    bounds,
    dyadic_down,
    dyadic_up,
    limit_polynomial,
    lower_bound_on,
    uniform_cutoff,
)
from seapass.delay.structure import delayed_impedance
from seapass.delay.trig import real_part
from seapass.model.sea import SEA

mpmath.mp.dps = 60


def _f(b1=20.0, kd=500.0, bd=25.0, tau=None):
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
              values=dict(m=1.0, b=10.0, k1=1000.0, b1=b1, kd=kd, bd=bd, tau=tau))  # fmt: skip
    return real_part(delayed_impedance(sea, free_delay=tau is None))


def _exact_f(f, w, tau):
    """F at (ω, τ) in 60-digit arithmetic (mpmath), for comparisons."""
    w, tau = mpmath.mpf(w), mpmath.mpf(tau)
    total = mpmath.mpf(0)
    for m in range(len(f.cos)):
        a = sum(mpmath.mpf(int(c.p)) / int(c.q) * w**i for i, c in enumerate(f.cos[m].coeffs()))
        b = sum(mpmath.mpf(int(c.p)) / int(c.q) * w**i for i, c in enumerate(f.sin[m].coeffs()))
        total += a * mpmath.cos(m * w * tau) + b * mpmath.sin(m * w * tau)
    return total


@given(w=st.floats(1e-3, 300), tau=st.floats(0, 0.05), q=st.sampled_from([4, 8, 16]))
def test_polynomial_bounds_enclose_the_real_part(w, tau, q):
    f = _f()
    t = fmpq(int(tau * 10**6), 10**6)
    x = fmpq(int(w * 1000), 1000)
    lo, hi = bounds(f, t, q)
    val = _exact_f(f, mpmath.mpf(int(x.p)) / int(x.q), mpmath.mpf(int(t.p)) / int(t.q))
    tol = abs(val) * mpmath.mpf(10) ** -40

    def mp(v):
        return mpmath.mpf(int(v.p)) / int(v.q)

    assert mp(lo(x)) <= val + tol and val <= mp(hi(x)) + tol


def test_virtual_spring_limit_polynomial_and_decisions():
    f = real_part(
        delayed_impedance("m*s + b + K*exp(-tau*s)/s", values=dict(m=1, b=2, K=50), free_delay=True)
    )
    i0, poly = limit_polynomial(f)
    assert (i0, poly) == (2, poly.__class__([2, -50]))
    assert at_fixed_delay(f, fmpq(1, 100)).sign == 1
    assert at_fixed_delay(f, fmpq(1, 25)).order == 4  # b = K tau: the next term decides
    low = at_fixed_delay(f, fmpq(1, 20))
    assert low.sign == -1 and _exact_f(f, float(low.witness), 0.05) < 0


@pytest.mark.parametrize("tau_max", [fmpq(1, 100), fmpq(4, 100) * (1 - fmpq(1, 10**6))])
def test_uniform_cutoff_holds_for_every_delay_below(tau_max):
    f = real_part(
        delayed_impedance("m*s + b + K*exp(-tau*s)/s", values=dict(m=1, b=2, K=50), free_delay=True)
    )
    cut, everywhere = uniform_cutoff(f, 2, tau_max, target=fmpq(1))
    assert not everywhere and cut is not None and cut > 1
    for k in range(1, 21):
        tau = float(tau_max) * k / 20
        for j in range(1, 40):
            w = float(cut) * j / 40
            assert _exact_f(f, w, tau) > 0


def test_dyadic_rounding_and_polynomial_lower_bound():
    q = fmpq(10**40 + 1, 3**70)
    assert dyadic_down(q) <= q <= dyadic_up(q)
    p = _f().cos[0]  # any polynomial
    lb = lower_bound_on(p, fmpq(1), fmpq(50))
    assert all(lb <= p(fmpq(k, 10)) for k in range(10, 501))
