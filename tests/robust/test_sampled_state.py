"""State-space alias sums over a box (issue 26, item 4): the point values against the pole
and residue route (`LocalPower`, itself checked against the exact per-plant pipeline), the
derivatives against central differences, every sampled plant's power inside the mean-value
enclosure, the exact Chebyshev-to-Bernstein table, and a box certified by the state-space
route checked plant by plant with the ordinary verdict."""

from __future__ import annotations

import itertools
import math
from fractions import Fraction as F

import pytest
from flint import acb, arb, fmpq, fmpq_poly
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.exact.poly import as_poly
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.robust.sampled_local import (
    LocalPower,
    _enclose,
    chebyshev_bernstein,
    chebyshev_t,
)
from seapass.robust.sampled_plant import ball_of
from seapass.robust.sampled_state import StatePower
from seapass.robust.sampled_verdict import Setup, box_outcome
from seapass.sampled.certified import precision
from seapass.sampled.passivity import sampled_passivity

OURS = dict(b=10, k1=1000, b1=300, kd=500, bd=300)
LOOP = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)


def _setup() -> Setup:
    return Setup(SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**OURS, "m": None}), LOOP, ("m",))


def _state(st: Setup, lo: F, hi: F, derive: bool = True) -> StatePower:
    sp = StatePower(st.state, {"m": ball_of(lo, hi)}, st.period, 1 / st.period, derive=derive)
    assert sp.ok
    return sp


def _value(x: object) -> acb:
    return acb(getattr(x, "v", x))


def _ka(st: Setup) -> tuple:
    return as_poly(st.ka.num), as_poly(st.ka.den)


@pytest.mark.parametrize("theta", [0.01, 0.4, 1.0, 2.5, 3.1])
def test_state_space_sums_equal_the_pole_residue_sums_at_a_point(theta: float) -> None:
    st = _setup()
    m = F(102, 100)
    with precision(128):
        z = acb(0, theta).exp()
        ss = _state(st, m, m, derive=False)
        pr = LocalPower(st.plant, {"m": ball_of(m, m)}, st.period, st.sums_names, derive=False)
        a, b = ss.sums_at(z), pr.sums_at(z)
        for name in st.sums_names:
            x, y = complex(_value(a[name]).mid()), complex(_value(b[name]).mid())
            assert abs(x - y) <= 1e-20 + 1e-12 * abs(y), name
        w1, w2 = (float(_value(loc.weight(z)).real.mid()) for loc in (ss, pr))
        assert abs(w1 - w2) <= 1e-12 * abs(w2)


@pytest.mark.parametrize("theta", [0.05, 1.0, 2.5])
def test_state_space_derivative_matches_a_central_difference(theta: float) -> None:
    st = _setup()
    m, h = F(102, 100), F(1, 10**8)
    with precision(256):
        z = acb(0, theta).exp()
        power, _ = _state(st, m, m).values(z, st.family, _ka(st))
        up, _ = _state(st, m + h, m + h, derive=False).values(z, st.family, _ka(st))
        down, _ = _state(st, m - h, m - h, derive=False).values(z, st.family, _ka(st))
        fd = (up.v - down.v) / (2 * arb(fmpq(h.numerator, h.denominator)))
        d = float(power.d[0].real.mid())
    assert abs(d - float(fd.real.mid())) <= 1e-6 * abs(d)


@pytest.mark.parametrize("x", [-0.95, -0.3, 0.4, 0.9, 0.999])
def test_every_sampled_plant_is_inside_the_mean_value_enclosure(x: float) -> None:
    st = _setup()
    c, r = F(1), F(1, 2000)
    with precision(128):
        z = acb(0, arb(x).acos()).exp()
        centre = _state(st, c, c, derive=False).values(z, st.family, _ka(st))
        box = _state(st, c - r, c + r).values(z, st.family, _ka(st))
        enc = [_enclose(centre[i], box[i], [ball_of(r, r)]) for i in range(2)]
        for k in range(-10, 11):
            m = c + r * F(k, 10)
            point = _state(st, m, m, derive=False).values(z, st.family, _ka(st))
            for i in range(2):
                assert enc[i].contains(point[i].v.real), (k, i)


@pytest.mark.parametrize("n", [3, 7, 12])
def test_the_chebyshev_bernstein_table_reconstructs_the_chebyshev_polynomials(n: int) -> None:
    table = chebyshev_bernstein(n)
    for k in range(n + 1):
        tk = fmpq_poly(chebyshev_t(k))
        for u in (fmpq(0), fmpq(1, 3), fmpq(1, 2), fmpq(5, 7), fmpq(1)):
            total = sum(
                (table[k][j] * fmpq(math.comb(n, j)) * u**j * (1 - u) ** (n - j)
                 for j in range(n + 1)),
                fmpq(0),
            )  # fmt: skip
            assert total == tk(2 * u - 1)


def test_a_box_certified_by_the_state_space_route_is_passive_plant_by_plant() -> None:
    st = _setup()
    lo, hi = F(9999, 10000), F(10001, 10000)
    assert box_outcome(st, ((lo, hi),)) is Outcome.PASSIVE
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**OURS, "m": 1.0})
    for k in range(41):
        m = float(lo + (hi - lo) * F(k, 40))
        r = sampled_passivity(sea, loop=LOOP, values={"m": m}, continuous_gate=False)
        assert r.outcome is Outcome.PASSIVE, m


def test_a_one_per_mille_box_is_certified_and_every_sampled_plant_agrees() -> None:
    from seapass.robust.sampled_verdict import robust_sampled_check

    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**OURS, "m": 1.0})
    r = robust_sampled_check(sea, loop=LOOP, box={"m": (0.999, 1.001)}, budget=4)
    assert r.outcome is Outcome.PASSIVE and r.boxes <= 4
    for k in range(401):
        m = 0.999 + 0.002 * k / 400
        v = sampled_passivity(sea, loop=LOOP, values={"m": m}, continuous_gate=False)
        assert v.outcome is Outcome.PASSIVE, m


@settings(max_examples=15, deadline=None)
@given(
    u=st.fractions(min_value=-1, max_value=1, max_denominator=1000),
    x=st.floats(min_value=-0.999, max_value=0.9999),
    b1=st.sampled_from([F(1), F(2)]),
)
def test_property_the_enclosure_of_a_two_parameter_box_holds_every_plant(
    u: F, x: float, b1: F
) -> None:
    """m and b uncertain: the plant at (m, b) = centre + u·radius (each axis) is inside."""
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**OURS, "m": None, "b": None})
    stp = Setup(sea, LOOP, ("m", "b"))
    c, r = (F(1), F(10)), (F(1, 1000) * b1, F(1, 100) * b1)
    with precision(128):
        z = acb(0, arb(x).acos()).exp()
        ka = _ka(stp)

        def power(lo: tuple, hi: tuple, derive: bool) -> tuple:
            ball = {n: ball_of(a, b) for n, a, b in zip(("m", "b"), lo, hi, strict=True)}
            sp = StatePower(stp.state, ball, stp.period, 1 / stp.period, derive=derive)
            assert sp.ok
            return sp.values(z, stp.family, ka)

        centre = power(c, c, False)
        box = power(
            tuple(a - d for a, d in zip(c, r, strict=True)),
            tuple(a + d for a, d in zip(c, r, strict=True)),
            True,
        )
        radii = [ball_of(d, d) for d in r]
        point = tuple(a + u * d for a, d in zip(c, r, strict=True))
        at = power(point, point, False)
        for i in range(2):
            assert _enclose(centre[i], box[i], radii).contains(at[i].v.real)


def test_a_three_parameter_box_is_certified_and_a_grid_of_its_plants_agrees() -> None:
    from seapass.robust.sampled_verdict import robust_sampled_check

    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**OURS, "m": 1.0})
    e = 1e-4
    box = {
        "m": (1 - e, 1 + e),
        "b": (10 * (1 - e), 10 * (1 + e)),
        "b1": (300 * (1 - e), 300 * (1 + e)),
    }
    r = robust_sampled_check(sea, loop=LOOP, box=box, budget=4)
    assert r.outcome is Outcome.PASSIVE
    grid = [-1.0, -0.5, 0.0, 0.5, 1.0]
    for i, j, k in itertools.product(grid, grid, grid):
        values = {"m": 1 + e * i, "b": 10 * (1 + e * j), "b1": 300 * (1 + e * k)}
        v = sampled_passivity(sea, loop=LOOP, values=values, continuous_gate=False)
        assert v.outcome is Outcome.PASSIVE, values


def test_apd_a_ten_percent_mass_box_is_certified_and_its_plants_agree() -> None:
    """A design without load feedback (D1 = k1, actuator-side PD): the sums it does not
    need are not required to converge."""
    from seapass.robust.sampled_verdict import robust_sampled_check

    apd = SEA(D1="k1", CA="kd + bd*s", values=dict(m=1.0, b=10, k1=1000, kd=100, bd=5))
    r = robust_sampled_check(apd, loop=LOOP, box={"m": (0.9, 1.1)}, budget=4)
    assert r.outcome is Outcome.PASSIVE
    for k in range(201):
        m = 0.9 + 0.2 * k / 200
        v = sampled_passivity(apd, loop=LOOP, values={"m": m}, continuous_gate=False)
        assert v.outcome is Outcome.PASSIVE, m
