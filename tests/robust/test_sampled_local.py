"""Mean-value enclosures of the sampled power (issue 26, item 4): the dual numbers' values
against the exact per-plant pipeline of seapass.sampled, their derivatives against
central finite differences, and the decision against sampled plants."""

from __future__ import annotations

from fractions import Fraction as F

import pytest
from flint import acb, arb

from seapass.exact.poly import as_poly
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.robust.sampled_local import Dual, LocalPower
from seapass.robust.sampled_plant import ball_of
from seapass.robust.sampled_verdict import Setup
from seapass.sampled.certified import precision
from seapass.sampled.plant import plant_key
from seapass.sampled.power import power_values
from seapass.sampled.verdict import cached_sums

OURS = dict(b=10, k1=1000, b1=300, kd=1708, bd=300)
LOOP = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)


def _setup() -> Setup:
    return Setup(SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**OURS, "m": None}), LOOP, ("m",))


def _power(st: Setup, m: F, theta: float, derive: bool = False) -> tuple[Dual, Dual, acb]:
    loc = LocalPower(st.plant, {"m": ball_of(m, m)}, st.period, st.sums_names, derive=derive)
    assert loc.ok
    z = acb(0, theta).exp()
    ka = (as_poly(st.ka.num), as_poly(st.ka.den))
    power, _chi = loc.values(z, st.family, ka)
    return power, loc.weight(z), z


@pytest.mark.parametrize("theta", [0.05, 1.0, 2.5])
def test_the_dual_value_is_the_power_of_the_exact_pipeline(theta: float) -> None:
    st = _setup()
    m = F(102, 100)
    with precision(128):
        power, weight, z = _power(st, m, theta)
        v0 = sum((c * (1 / z) ** k for k, c in enumerate(st.family[0][0].coeffs())), acb(0))
        n_local = power.v / (weight.v * (v0 * v0.conjugate()).real)
        sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**OURS, "m": float(m)})
        sums = cached_sums(plant_key(sea), st.period, st.sums_names, 128)
        (n_exact,) = power_values(sums, st.family, [theta])
    assert abs(float(n_local.mid()) - float(n_exact.mid())) <= 1e-12 * abs(float(n_exact.mid()))


@pytest.mark.parametrize("theta", [0.05, 1.0, 2.5])
def test_the_dual_derivative_matches_a_central_difference(theta: float) -> None:
    st = _setup()
    m, h = F(102, 100), F(1, 10**9)
    with precision(256):
        power, _w, _z = _power(st, m, theta, derive=True)
        up, _w, _z = _power(st, m + h, theta)
        down, _w, _z = _power(st, m - h, theta)
        fd = (up.v - down.v) / (2 * arb(float(h)))
    d = float(power.d[0].real.mid())
    assert abs(d - float(fd.real.mid())) <= 1e-6 * max(abs(d), 1e-30)


def test_the_box_enclosure_contains_the_power_of_sampled_plants() -> None:
    st = _setup()
    lo, hi = F(102, 100) - F(1, 10**6), F(102, 100) + F(1, 10**6)
    c = (lo + hi) / 2
    ka = (as_poly(st.ka.num), as_poly(st.ka.den))
    with precision(128):
        centre = LocalPower(st.plant, {"m": ball_of(c, c)}, st.period, st.sums_names, derive=False)
        box = LocalPower(st.plant, {"m": ball_of(lo, hi)}, st.period, st.sums_names)
        r = ball_of(hi - c, hi - c)
        for theta in (0.3, 1.0, 3.0):
            z = acb(0, theta).exp()
            pc, _ = centre.values(z, st.family, ka)
            pb, _ = box.values(z, st.family, ka)
            enclosure = arb(pc.v.real) + pb.d[0].real * (-r).union(r)
            for t in range(5):
                m = lo + (hi - lo) * t / 4
                point = LocalPower(st.plant, {"m": ball_of(m, m)}, st.period, st.sums_names,
                                   derive=False)  # fmt: skip
                pm, _ = point.values(z, st.family, ka)
                assert enclosure.contains(pm.v.real)
