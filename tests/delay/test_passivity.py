"""Certified passivity at a given delay, cross-checked with a dense sweep with local refinement."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import seapass as sp
from seapass.analysis.passivity import PassivityResult
from seapass.delay.passivity import DelayPassivityResult, delayed_passivity, is_passive
from seapass.errors import DelayError, NotPassiveError
from seapass.model.sea import SEA
from seapass.outcome import Outcome

from .reference import expression_impedance, min_real_part, sea_impedance

OURS = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


def _ours(**v):
    vals = {**OURS, "tau": 0.001}
    vals.update(v)
    return SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)", values=vals)


@given(
    b1=st.floats(1, 60), kd=st.floats(10, 4000), bd=st.floats(0, 80),
    tau=st.floats(1e-4, 0.06),
)  # fmt: skip
def test_verdict_agrees_with_a_dense_sweep(b1, kd, bd, tau):
    sea = _ours(b1=b1, kd=kd, bd=bd, tau=tau)
    r = delayed_passivity(sea)
    t = float(sea.values["tau"])
    low, _w = min_real_part(lambda w: sea_impedance(sea, w, t).real, 1e-2, 1e5, 6000)
    if r.outcome is Outcome.PASSIVE:
        assert low >= -1e-9, (b1, kd, bd, tau, low)
    elif r.outcome is Outcome.NOT_PASSIVE and r.reason == "negative_real_part":
        assert sea_impedance(sea, np.array([r.omega]), t).real[0] < 0
    # undecided is allowed (never passive); it must not happen for these well-scaled designs
    assert r.outcome is not Outcome.UNDECIDED, r.detail


def test_virtual_spring_limit_is_exact():
    text, vals = "m*s + b + K*exp(-tau*s)/s", dict(m=1, b=2, K=50)
    assert is_passive(text, values={**vals, "tau": 0.04}).passive  # b = K tau: still passive
    r = is_passive(text, values={**vals, "tau": 0.0400001})
    assert r.outcome is Outcome.NOT_PASSIVE and r.reason == "negative_real_part"
    ref = expression_impedance(text, vals, np.array([r.omega]), 0.0400001).real[0]
    assert ref < 0


@pytest.mark.parametrize(
    ("text", "values", "reason"),
    [
        ("m*s + b + K*exp(-tau*s)/s**2", dict(m=1, b=1, K=1, tau=0.1), "repeated_axis_pole"),
        ("(s + 1)/(s - 1 + exp(-tau*s)/10)", dict(tau=0.1), "rhp_pole"),
        ("-m*s + b*exp(-tau*s)", dict(m=1, b=1, tau=0.1), "infinity_residue"),
        ("m*s**2 + exp(-tau*s)", dict(m=1, tau=0.1), "relative_degree"),
        ("b - K*exp(-tau*s)/s", dict(b=1, K=1, tau=0.1), "axis_residue"),
    ],
)
def test_structural_failures_are_exact(text, values, reason):
    r = is_passive(text, values=values)
    assert r.outcome is Outcome.NOT_PASSIVE and r.reason == reason, r


def test_zero_delay_is_the_exact_rational_verdict():
    r = delayed_passivity(_ours(tau=0.0))
    assert r.outcome is Outcome.PASSIVE and r.tau == 0.0
    assert is_passive(_ours(tau=0.0)).passive


def test_front_door_dispatch():
    from seapass.robust.api import is_passive as front_door

    assert sp.is_passive is front_door  # no box: sent on to delay.passivity.is_passive
    plain = sp.is_passive(SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500)))
    assert isinstance(plain, PassivityResult)
    delayed = sp.is_passive(_ours())
    assert isinstance(delayed, DelayPassivityResult) and delayed.passive
    with pytest.raises(DelayError, match="rational analysis does not apply"):
        from seapass.analysis.passivity import is_passive as rational

        rational(_ours())


def test_result_api():
    r = is_passive(_ours(tau=0.05))
    assert r.outcome is Outcome.NOT_PASSIVE and not r.passive and r.status == "not passive"
    d = r.to_dict()
    assert {"passive", "outcome", "reason", "witness_frequency", "detail", "delay"} <= set(d)
    assert d["witness_frequency"] == r.omega and d["delay"] == {"name": "tau", "tau": 0.05}
    json.dumps(d, allow_nan=False)
    assert "witness_frequency=" in repr(r) and "<table>" in r._repr_html_()
    with pytest.raises(NotPassiveError):
        delayed_passivity(_ours(tau=0.05), throw=True)
    resp = r.response()
    assert resp.negative_bands and all(a < r.omega < b or True for a, b in resp.negative_bands)
    inside = [(a, b) for a, b in resp.negative_bands if a <= r.omega <= b]
    assert inside, (resp.negative_bands, r.omega)
    ax = r.plot()
    assert ax.get_xlabel().startswith("frequency")
    ax = r.plot("nyquist")
    import matplotlib.pyplot as plt

    plt.close("all")


def test_budget_exhaustion_is_undecided_never_passive():
    sea = _ours(tau=0.04125)  # just below tau*: Re Z nearly touches 0 at 36.5 rad/s
    r = delayed_passivity(sea, budget=3)
    assert r.outcome in (Outcome.UNDECIDED, Outcome.PASSIVE)
    if r.outcome is Outcome.UNDECIDED:
        assert not r.passive and r.reason == "undecided"


def test_neutral_and_advanced_loops():
    # a neutral loop with |q_n/p_n| > 1 is unstable for every delay > 0
    r = is_passive("(s + 1)/(s + 1 + 2*s*exp(-tau*s))", values=dict(tau=0.1))
    assert r.outcome is Outcome.NOT_PASSIVE and r.reason == "rhp_pole"
    r = is_passive("(s + 2)/(s + 1 + s*exp(-tau*s))", values=dict(tau=0.1))
    assert r.outcome is Outcome.UNDECIDED


@pytest.mark.parametrize("tau", [900.0, 999.0])
def test_long_delays_are_decided_or_refused_in_bounded_work(tau):
    r = is_passive("m*s + b + K*exp(-tau*s)/s", values=dict(m=1, b=1, K=1, tau=tau))
    assert r.outcome is Outcome.NOT_PASSIVE
    assert is_passive("m*s + b + B*exp(-tau*s)", values=dict(m=1, b=2, B=1.9, tau=tau)).passive


def test_work_bound_refuses_a_scan_beyond_the_limit():
    from flint import fmpq

    from seapass.delay.sign import MAX_PIECES, scan_pieces

    with pytest.raises(DelayError, match="oscillate"):
        scan_pieces([(fmpq(1), fmpq(10**4))], fmpq(100))
    assert len(scan_pieces([(fmpq(1), fmpq(100))], fmpq(1, 100))) < MAX_PIECES
