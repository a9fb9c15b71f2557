"""Where the theory links a continuous delay with whole-sample delays at period T.

A zero-order hold delays a slow signal by half a sample, and ``d`` samples of computation
add ``d T``: to first order in ``s`` a sampled controller ``C`` acts like ``C e^{-sτ}`` with
``τ = (d + ½) T`` (``seapass.sampled.lowfreq``).  So:

* the low-frequency resistance of the sampled loop (``seapass.sampled.lowfreq``) equals
  ``Re Z(0)`` of the continuously delayed loop at ``τ = (d + ½) T``, exactly;
* where that condition is the binding one, the certified sampled bound and the certified
  continuous delay margin describe the same boundary: for the actuator-side virtual
  spring (Colgate–Schenkel's wall, ``kd ≤ 2b/((2d + 1)T)``) the continuous margin at the
  sampled limit is ``τ* = (d + ½) T``.
"""

from __future__ import annotations

from fractions import Fraction

import pytest
import sympy as sp
from flint import fmpq

from seapass.delay.lowfreq import limit_polynomial
from seapass.delay.margin import MarginLoss, delay_margin
from seapass.delay.structure import delayed_impedance
from seapass.delay.trig import real_part
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.lowfreq import closed_form_expr

T = 0.002


@pytest.mark.parametrize("d", [0, 1, 3])
@pytest.mark.parametrize(
    ("elements", "values"),
    [
        (dict(D1="k1 + b1*s", CA="kd + bd*s"), dict(b1=20, kd=500, bd=25)),
        (dict(D1="k1", CA="kd"), dict(kd=700)),
        (dict(D1="k1 + b1*s", CL="kd"), dict(b1=30, kd=400)),
    ],
)
def test_low_frequency_resistance_equals_the_continuous_delay(d, elements, values):
    vals = dict(m=1, b=10, k1=1000, **values)
    sea = SEA(values=vals, **elements)
    expr = closed_form_expr(sea, d)
    subs = {sp.Symbol(k, positive=True): sp.Rational(Fraction(v)) for k, v in vals.items()}
    subs[sp.Symbol("T", positive=True)] = sp.Rational(1, 500)
    sampled = sp.Rational(expr.xreplace(subs))
    delayed = SEA(
        values={**vals, "tau": None},
        **{k: (f"({v})*exp(-tau*s)" if k in ("CA", "CL") else v) for k, v in elements.items()},
    )
    z = delayed_impedance(delayed, free_delay=True)
    i0, fp = limit_polynomial(real_part(z))
    tau = fmpq(2 * d + 1, 2) * fmpq(1, 500)
    # D = s·D̃(s, E) (the port's pole at s = 0), so |D(jω)|² = ω² D̃(0, 1)² + O(ω⁴) and
    # Re Z(0) = f_2(τ)/D̃(0, 1)², with D̃(0, 1) the sum of the s-coefficients of the D_k
    assert all(p[0] == 0 for p in z.den) and i0 == 2
    d0 = sum((p[1] for p in z.den), fmpq(0))
    value = fp(tau) / (d0 * d0)
    assert sp.Rational(int(value.p), int(value.q)) == sampled


@pytest.mark.parametrize("d", [0, 1])
def test_colgate_schenkel_wall_limit_and_the_continuous_margin(d):
    sea = SEA(D1="k1", CA="kd", values=dict(m=1, b=10, k1=1000, kd=None))
    loop = SampledLoop(period=T, delay=d)
    bound = sampled_passive_bound(sea, "kd", loop=loop, lo=0, hi=3e4, rtol=1e-9)
    kd = bound.max_passive
    assert kd == pytest.approx(2 * 10 / ((2 * d + 1) * T), rel=1e-8)
    delayed = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=10, k1=1000, kd=kd, tau=None))
    r = delay_margin(delayed, "tau", rtol=1e-9)
    lo, hi = r.tau_star
    assert r.loss is MarginLoss.LOW_FREQUENCY
    assert lo <= (d + 0.5) * T * (1 + 1e-7) and (d + 0.5) * T * (1 - 1e-7) <= hi
