"""`seapass.delay.latency.latency_check`: τ* against a stated loop latency."""

from __future__ import annotations

import pytest

import seapass
from seapass.delay.latency import latency_check
from seapass.errors import ParameterError
from seapass.model.design_file import parse_design
from seapass.model.sea import SEA
from seapass.outcome import Outcome

PARAMS = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


def ours(delay_time: float | None = None):
    control = {} if delay_time is None else {"control": {"delay_time": delay_time}}
    return parse_design({"name": "ours", "model": {"D1": "k1 + b1*s", "CA": "kd + bd*s"},
                         "parameters": dict(PARAMS), **control})  # fmt: skip


def test_without_a_latency_only_tau_star() -> None:
    c = latency_check(ours())
    assert c.latency is None and c.at_latency is None and c.outcome is Outcome.PASSIVE
    assert c.tau_star == seapass.delay_margin(ours(), "delay_time").tau_star
    assert c.to_dict()["at_latency"] is None and "tau_star" in repr(c)
    with pytest.raises(ValueError, match="no latency"):
        c.plot()


def test_the_file_latency_and_a_given_one() -> None:
    c = latency_check(ours(0.01))
    assert c.latency == 0.01 and c.certified and c.at_latency is not None
    assert c.at_latency.passive and c.at_latency.tau == 0.01
    far = latency_check(ours(0.01), latency=0.2)
    assert far.outcome is Outcome.NOT_PASSIVE and not far.certified
    assert "exceeds tau*" in far.detail or "not passive at the latency" in far.detail
    assert "Loop latency against" in c._repr_html_()
    ax = c.plot()
    assert ax.get_xlabel()


def test_a_model_with_its_own_delay_uses_it() -> None:
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)", values={**PARAMS, "tau": 0.01})
    c = latency_check(sea)
    assert c.delay == "tau" and c.latency == 0.01 and c.certified
    assert c.tau_star == latency_check(ours()).tau_star  # the same delay on the same controller


def test_not_passive_at_zero_and_delay_independent() -> None:
    bad = SEA(
        D1="k1", CL="kd + bd*s", values={"m": 1.0, "b": 10.0, "k1": 1e3, "kd": 5e3, "bd": 25.0}
    )
    c = latency_check(bad, latency=0.001)
    assert c.outcome is Outcome.NOT_PASSIVE and "without delay" in c.detail
    # a small velocity feedback on the actuator behind a damped spring: passive for every delay
    di = latency_check(
        SEA(
            D1="k1 + b1*s",
            CA="bd*s",
            values={"m": 1.0, "b": 10.0, "k1": 1e3, "b1": 20.0, "bd": 2.0},
        ),
        latency=5.0,
    )
    assert di.margin.delay_independent and di.tau_star is None
    assert di.certified and "every delay" in di.detail


def test_bad_latency() -> None:
    with pytest.raises(ParameterError, match=r"^latency: must be"):
        latency_check(ours(), latency=-1.0)
    with pytest.raises(ParameterError, match=r"^latency: must be"):
        latency_check(ours(), latency=2000.0)
