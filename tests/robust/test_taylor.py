"""Second-order Taylor enclosures of the sampled power over a box (issue 26): the jets'
Hessians against central differences of the plain point evaluation, every plant drawn
from a three-parameter box inside the Taylor enclosure, Jet arithmetic against exact
rational derivatives, and a box certified by the Taylor route checked with the ordinary
sampled verdict at 200 plants."""

from __future__ import annotations

import json
import random
from fractions import Fraction as F

import pytest
from flint import acb, arb, fmpq
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.exact.poly import as_poly
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.robust.sampled_local import LocalPower
from seapass.robust.sampled_plant import ball_of
from seapass.robust.sampled_state import StatePower
from seapass.robust.sampled_verdict import Setup, robust_sampled_check
from seapass.robust.taylor import Jet, pairs, taylor_enclose
from seapass.sampled.certified import precision
from seapass.sampled.passivity import sampled_passivity

LOOP = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
NAMES = ("m", "b", "b1")
CENTRE = {"m": F(1), "b": F(10), "b1": F(300)}


def _setup() -> Setup:
    sea = SEA(
        D1="k1 + b1*s", CA="kd + bd*s",
        values=dict(k1=1000, kd=500, bd=300, m=None, b=None, b1=None),
    )  # fmt: skip
    return Setup(sea, LOOP, NAMES)


def _power(setup: Setup, ball: dict, order: int) -> StatePower:
    sp = StatePower(setup.state, ball, setup.period, 1 / setup.period, order=order)
    assert sp.ok
    return sp


def _point(v: dict) -> dict:
    return {n: ball_of(v[n], v[n]) for n in NAMES}


def _ka(setup: Setup) -> tuple:
    return as_poly(setup.ka.num), as_poly(setup.ka.den)


@pytest.mark.parametrize("theta", [0.03, 1.0, 2.8])
def test_the_hessian_of_the_power_matches_central_differences(theta: float) -> None:
    setup = _setup()
    v = {"m": F(102, 100), "b": F(11), "b1": F(290)}
    with precision(256):
        z = acb(0, theta).exp()
        jet, _ = LocalPower.values(_power(setup, _point(v), 2), z, setup.family, _ka(setup))
        first, _ = LocalPower.values(_power(setup, _point(v), 1), z, setup.family, _ka(setup))

        def at(w: dict) -> arb:
            p, _ = LocalPower.values(_power(setup, _point(w), 0), z, setup.family, _ka(setup))
            return acb(getattr(p, "v", p)).real

        for q, (i, j) in enumerate(pairs(3)):
            a, b = NAMES[i], NAMES[j]
            ha, hb = v[a] / 10**9, v[b] / 10**9

            def shifted(sa: int, sb: int, a: str = a, b: str = b, ha: F = ha, hb: F = hb) -> arb:
                w = dict(v)
                w[a] += sa * ha
                w[b] += sb * hb
                return at(w)

            qa, qb = (
                arb(fmpq(ha.numerator, ha.denominator)),
                arb(fmpq(hb.numerator, hb.denominator)),
            )
            fd = (shifted(1, 1) - shifted(1, -1) - shifted(-1, 1) + shifted(-1, -1)) / (4 * qa * qb)
            if a == b:  # the same variable shifted twice: (f(+2h) − 2f + f(−2h))/(4h²)
                fd = (shifted(1, 1) - 2 * at(v) + shifted(-1, -1)) / (4 * qa * qa)
            got, want = float(acb(jet.h[q]).real.mid()), float(fd.mid())
            assert abs(got - want) <= 1e-8 * abs(want) + 1e-30, (a, b, got, want)
        for g1, g2 in zip(jet.d, first.d, strict=True):
            assert abs(complex(acb(g1).mid()) - complex(acb(g2).mid())) <= 1e-20 + 1e-12 * abs(
                complex(acb(g2).mid())
            )


def test_jet_arithmetic_gives_exact_rational_derivatives() -> None:
    # f(x, y) = (x² y + 3)/(x − y) at (2, 1): exact derivatives by hand (sympy-free)
    x = Jet(arb(2), [arb(1), arb(0)], [arb(0)] * 3)
    y = Jet(arb(1), [arb(0), arb(1)], [arb(0)] * 3)
    f = (x * x * y + 3) / (x - y)
    # f = 7; f_x = (2xy(x−y) − (x²y+3))/(x−y)² = (4 − 7) = −3; f_y = (x²(x−y) + (x²y+3))/(x−y)²
    # = 4 + 7 = 11; second derivatives from the quotient rule (checked against sympy offline)
    assert f.v == 7 and f.d[0] == -3 and f.d[1] == 11
    fxx, fxy, fyy = f.h
    # f_xx = 2y/(x−y) − 4xy/(x−y)² + 2(x²y+3)/(x−y)³ = 2 − 8 + 14 = 8
    # f_xy = 2x/(x−y) − (x² + 2xy... ) ; evaluate with a central difference instead
    h = 1e-5

    def g(a: float, b: float) -> float:
        return (a * a * b + 3) / (a - b)

    num_xy = (g(2 + h, 1 + h) - g(2 + h, 1 - h) - g(2 - h, 1 + h) + g(2 - h, 1 - h)) / (4 * h * h)
    num_yy = (g(2, 1 + h) - 2 * g(2, 1) + g(2, 1 - h)) / (h * h)
    assert fxx == 8
    assert abs(float(fxy.mid()) - num_xy) < 1e-3 and abs(float(fyy.mid()) - num_yy) < 1e-3


def test_a_jet_refuses_a_first_order_dual() -> None:
    from seapass.robust.sampled_local import Dual

    with pytest.raises(TypeError):
        _ = Jet(arb(1), [arb(0)], [arb(0)]) * Dual(arb(1), [arb(1)])


@settings(max_examples=4, deadline=None)
@given(
    x=st.floats(min_value=-0.95, max_value=0.999999),
    seed=st.integers(min_value=0, max_value=10**6),
)
def test_property_every_plant_of_a_three_parameter_box_is_inside_the_taylor_enclosure(
    x: float, seed: int
) -> None:
    setup = _setup()
    w = F(2, 100)
    box = {n: (c * (1 - w), c * (1 + w)) for n, c in CENTRE.items()}
    radii = [ball_of(c * w, c * w) for c in CENTRE.values()]
    rng = random.Random(seed)
    with precision(128):
        z = acb(0, arb(x).acos()).exp()
        ka = _ka(setup)
        pc, mc = LocalPower.values(_power(setup, _point(CENTRE), 1), z, setup.family, ka)
        pb, mb = LocalPower.values(
            _power(setup, {n: ball_of(*box[n]) for n in NAMES}, 2), z, setup.family, ka
        )
        enc_p = taylor_enclose(pc.v, pc.d, pb, radii)
        enc_m = taylor_enclose(mc.v, mc.d, mb, radii)
        for _ in range(3):
            v = {n: lo + (hi - lo) * F(rng.randint(0, 1000), 1000) for n, (lo, hi) in box.items()}
            p, m = LocalPower.values(_power(setup, _point(v), 0), z, setup.family, ka)
            assert enc_p.contains(acb(getattr(p, "v", p)).real)
            assert enc_m.contains(acb(getattr(m, "v", m)).real)


def test_a_three_parameter_box_certified_by_taylor_agrees_with_200_plants() -> None:
    sea = SEA(
        D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1.0, b=10, k1=1000, b1=300, kd=500, bd=300)
    )
    box = {"m": (0.999, 1.001), "b": (9.99, 10.01), "b1": (299.7, 300.3)}
    r = robust_sampled_check(sea, loop=LOOP, box=box, budget=2, continuous_gate=False)
    assert r.outcome is Outcome.PASSIVE
    rng = random.Random(26)
    for _ in range(200):
        values = {n: rng.uniform(lo, hi) for n, (lo, hi) in box.items()}
        assert sampled_passivity(sea, loop=LOOP, values=values, continuous_gate=False).passive


def test_the_cli_certifies_a_three_parameter_sampled_box_and_refuses_bad_input() -> None:
    from helpers import run_main

    argv = ["sampled", "check", "examples/ours.toml", "--set", "kd=500", "--budget", "2"]
    box = ["--uncertain", "m=0.999:1.001", "--uncertain", "b=9.99:10.01",
           "--uncertain", "b1=299.7:300.3"]  # fmt: skip
    code, out, err = run_main([*argv, *box, "--json"])
    assert code == 0, err
    d = json.loads(out)
    assert d["status"] == "passive" and d["robust"] and d["sampled"] and d["boxes"] == 1
    assert "Taylor" in d["method"]
    code, out, err = run_main([*argv, "--uncertain", "m=1.001:0.999"])  # LO > HI
    assert code == 2 and err.count("\n") == 1 and err.startswith("error:")


@pytest.mark.parametrize("theta", [0.001, 0.05, 1.0, 3.0])
def test_the_split_and_the_plain_realization_give_the_same_jets_at_a_point(theta: float) -> None:
    setup = _setup()
    v = {"m": F(98, 100), "b": F(9), "b1": F(310)}
    with precision(256):
        sp = _power(setup, _point(v), 2)
        assert [r.split for r in sp.reals] == [0, setup.state.m0] and setup.state.m0 > 0
        z = acb(0, theta).exp()
        (s0, w0), (s1, w1) = (r.at(z, setup.state.m0) for r in sp.reals)
        for a, b in [*((s0[k], s1[k]) for k in s0), (w0, w1)]:
            for x, y in zip((a.v, *a.d, *a.h), (b.v, *b.d, *b.h), strict=True):
                x, y = complex(acb(x).mid()), complex(acb(y).mid())
                assert abs(x - y) <= 1e-25 + 1e-15 * max(abs(x), abs(y)), (theta, x, y)
