"""The passivity delay margin: closed forms, properties, the verdicts at its ends, and a
time-domain simulation with energy bookkeeping (all written independently of the method)."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

import seapass as sp
from seapass.delay.balls import round_down, round_up
from seapass.delay.margin import MarginLoss, delay_margin
from seapass.delay.passivity import delayed_passivity
from seapass.errors import DelayError, ParameterError
from seapass.exact.poly import rational
from seapass.model.catalog import design
from seapass.model.sea import SEA
from seapass.outcome import Outcome

from .reference import simulate_ours

WALL = "m*s + b + (K + B*s)*exp(-tau*s)/s"
#: a certified width for the tests of properties that are not about the width: the search to
#: the default 1e-6 costs ~50x more (the closed-form tests keep the default)
COARSE = 1e-4
OURS = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


def _wall_margin(b, k, bb):
    """τ* of the delayed virtual wall from its closed form, independently: passive at τ iff
    φ(τ) = min_{θ>0} b + B cos θ − Kτ sin(θ)/θ ≥ 0; φ is found on a dense θ grid refined with
    scipy, and its first root by brentq."""

    def phi(tau):
        th = np.linspace(1e-6, 60, 60001)
        v = b + bb * np.cos(th) - k * tau * np.sinc(th / np.pi)
        i = int(np.argmin(v))
        r = minimize_scalar(lambda x: b + bb * math.cos(x) - k * tau * math.sin(x) / x,
                            bounds=(th[max(i - 2, 0)], th[min(i + 2, len(th) - 1)]),
                            method="bounded", options={"xatol": 1e-13})  # fmt: skip
        return min(float(v[i]), float(r.fun), b + bb - k * tau)  # θ → 0 included

    hi = (b + bb) / k
    grid = np.linspace(0, hi, 400)[1:]
    first = next((t for t in grid if phi(t) < 0), hi)
    return brentq(phi, first - hi / 399, first, xtol=1e-14) if phi(first) < 0 else hi


@pytest.mark.parametrize(("b", "k", "bb"), [(2.0, 50.0, 0.0), (2.0, 50.0, 1.0), (2.0, 50.0, 1.9),
                                            (10.0, 1000.0, 5.0), (1.0, 3.0, 0.5)])  # fmt: skip
def test_delayed_virtual_wall_matches_its_closed_form(b, k, bb):
    r = delay_margin(WALL, "tau", values=dict(m=1, b=b, K=k, B=bb))
    lo, hi = r.tau_star
    ref = _wall_margin(b, k, bb)
    assert lo <= ref * (1 + 1e-9) and ref <= hi * (1 + 1e-9), (lo, ref, hi)
    assert hi - lo <= 1e-6 * hi and r.certified
    if bb == 0:
        assert (
            r.loss is MarginLoss.LOW_FREQUENCY
            and r.frequency is None
            and hi == pytest.approx(b / k)
        )


def test_virtual_damper_above_the_physical_one_has_zero_margin():
    r = delay_margin(WALL, "tau", values=dict(m=1, b=2, K=50, B=3))
    assert (
        r.tau_star == (0.0, 0.0)
        and r.loss is MarginLoss.UNBOUNDED_BAND
        and r.outcome is Outcome.PASSIVE
    )


@pytest.mark.parametrize("key", ["LP", "APD", "ours"])
def test_paper_designs_with_a_controller_delay(key):
    values = {
        "LP": dict(kd=500),
        "APD": dict(kd=500, bd=25),
        "ours": dict(kd=500, bd=25, b1=20),
    }[key]
    r = sp.delay_margin(design(key).sea(dict(m=1, b=10, k1=1000, **values)), "tau")
    if key == "ours":
        lo, hi = r.tau_star
        assert r.loss is MarginLoss.INTERIOR and 0.0412 < lo < hi < 0.0413
        assert abs(r.frequency - 36.53) < 0.05
    else:  # undamped spring: every delay > 0 fails at high frequency
        assert r.tau_star == (0.0, 0.0) and r.loss is MarginLoss.UNBOUNDED_BAND


@pytest.mark.parametrize("values", [dict(kd=500, bd=25, b1=20), dict(kd=2000, bd=60, b1=100),
                                    dict(kd=100, bd=5, b1=40)])  # fmt: skip
def test_passive_just_below_lo_and_not_just_above_hi(values):
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
              values=dict(m=1.0, b=10.0, k1=1000.0, tau=None, **values))  # fmt: skip
    r = delay_margin(sea, "tau")
    lo, hi = r.tau_star
    below = delayed_passivity(sea, values=dict(tau=lo * (1 - 1e-6)))
    at_lo = delayed_passivity(sea, values=dict(tau=lo))
    above = delayed_passivity(sea, values=dict(tau=hi * (1 + 1e-6)))
    assert below.outcome is Outcome.PASSIVE and at_lo.outcome is Outcome.PASSIVE
    assert above.outcome is Outcome.NOT_PASSIVE


def test_more_physical_damping_never_lowers_the_margin_in_the_rigid_limit():
    for bb in (0.0, 0.5):  # COARSE: the margins differ by far more than 1e-4 relative
        margins = [delay_margin(WALL, "tau", values=dict(m=1, b=b, K=50, B=bb), rtol=COARSE)
                   .tau_star for b in (1.0, 1.5, 2.0, 4.0, 8.0)]  # fmt: skip
        for (lo1, _hi1), (_lo2, hi2) in itertools.pairwise(margins):
            assert lo1 <= hi2


@pytest.mark.parametrize("c", [1000.0, 0.125])
def test_unit_changes_scale_the_margin(c):
    """Z(s/c) is the same device with time in units of 1/c: m/c, K c, the same b and B; a
    force unit scales Z; τ* follows exactly (to the certified width ``COARSE``: a wrong
    scaling moves τ* by a factor, far more than 1e-4; the closed-form tests pin 1e-6)."""
    base = delay_margin(WALL, "tau", values=dict(m=1, b=2, K=50, B=1), rtol=COARSE)
    timed = delay_margin(WALL, "tau", values=dict(m=1 / c, b=2, K=50 * c, B=1), rtol=COARSE)
    force = delay_margin(WALL, "tau", values=dict(m=7, b=14, K=350, B=7), rtol=COARSE)
    assert max(base.tau_star[1] - base.tau_star[0], timed.tau_star[1] * c - timed.tau_star[0] * c,
               force.tau_star[1] - force.tau_star[0]) <= COARSE * base.tau_star[1] * 1.01  # fmt: skip
    lo, hi = base.tau_star
    assert timed.tau_star[0] <= hi / c * (1 + 1e-12) and lo / c <= timed.tau_star[1] * (1 + 1e-12)
    assert force.tau_star[0] <= hi and lo <= force.tau_star[1]


def test_delay_independent_and_not_passive_at_zero():
    r = delay_margin("m*s + b + B*exp(-tau*s)", "tau", values=dict(m=1, b=2, B=1.5))
    assert r.delay_independent and r.tau_star is None and r.outcome is Outcome.PASSIVE
    r = delay_margin(WALL, "tau", values=dict(m=1, b=-1, K=1, B=0))
    assert not r.passive_at_zero and r.tau_star is None and r.outcome is Outcome.NOT_PASSIVE


def test_result_api_and_rounding():
    r = delay_margin(WALL, "tau", values=dict(m=1, b=2, K=50, B=1), rtol=COARSE)
    d = r.to_dict()
    assert set(d) >= {
        "tau_star",
        "frequency",
        "loss",
        "delay_independent",
        "passive_at_zero",
    }
    json.dumps(d, allow_nan=False)
    assert "tau_star=" in repr(r) and "<table>" in r._repr_html_()
    lo, hi = r.exact
    assert rational(round_down(lo)) <= lo and rational(round_up(hi)) >= hi
    w, g = r.curve()
    assert w.size and np.nanmin(g) >= r.tau_star[0] * (1 - 1e-9)
    ax = r.plot()
    assert ax.get_ylabel().startswith("delay")
    import matplotlib.pyplot as plt

    plt.close("all")


def test_bad_arguments():
    with pytest.raises(ParameterError, match="rtol"):
        delay_margin(WALL, "tau", values=dict(m=1, b=2, K=50, B=1), rtol=0.5)
    with pytest.raises(ParameterError, match="not the delay"):
        delay_margin(WALL, "T", values=dict(m=1, b=2, K=50, B=1))
    with pytest.raises(DelayError, match="first power"):
        delay_margin("m*s + b + K*exp(-2*tau*s)/s", "tau", values=dict(m=1, b=2, K=5))


def test_time_domain_energy_just_above_and_below_the_margin():
    """A passive mass-spring-damper tuned to the loss frequency: below τ* the SEA port never
    returns more energy than it received; above τ* it pumps energy into the environment."""
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)", values={**OURS, "tau": None})
    r = delay_margin(sea, "tau")
    tau_star, w = r.tau_star[1], r.frequency
    from .reference import sea_impedance

    above = 1.15 * tau_star
    z = sea_impedance(SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)", values={**OURS, "tau": above}),
                      np.array([w]), above)[0]  # fmt: skip
    assert z.real < 0
    env = dict(M=1.0, B=0.2 * abs(z.real), K=w * (w + z.imag))  # resonant at w, lightly damped
    _t, port, stored = simulate_ours(OURS, 0.8 * tau_star, env, horizon=3.0, dt=2e-4)
    assert port.min() >= -1e-9 * stored[0] and stored[-1] < 1e-3 * stored[0]
    _t, port, stored = simulate_ours(OURS, above, env, horizon=3.0, dt=2e-4)
    assert port.min() < -10 * stored[0] and stored.max() > 5 * stored[0]
