"""``[control] delay_time``: the loop latency of a design file (model.latency, design_file, resolve)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import seapass
from seapass.errors import FileFormatError, ParameterError
from seapass.model.design_file import parse_design
from seapass.model.latency import LATENCY_PARAMETER, check_delay_time, latency_elements
from seapass.model.resolve import resolve_design
from seapass.model.sea import SEA

PARAMS = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


def doc(control: dict | None = None, **model: str) -> dict:
    out: dict = {
        "name": "ours",
        "model": model or {"D1": "k1 + b1*s", "CA": "kd + bd*s"},
        "parameters": dict(PARAMS),
    }
    if control is not None:
        out["control"] = control
    return out


def rez(w: np.ndarray, tau: float) -> np.ndarray:
    """Re Z_L(jw) of the damped-spring, actuator-PD design with C_A delayed, by hand."""
    s = 1j * w
    d1 = 1000 + 20 * s
    ca = (500 + 25 * s) * np.exp(-s * tau)
    return (d1 * (s * s + 10 * s + ca) / (s * s + 10 * s + d1 + ca) / s).real


def test_delay_time_alone_is_a_latency_without_a_sampled_loop():
    d = parse_design(doc({"delay_time": 0.002}))
    assert d.delay_time == 0.002 and d.loop is None
    sea = d.delayed_sea()
    assert sea.values[LATENCY_PARAMETER] == 0.002
    assert "exp(-delay_time*s)" in sea.describe()["CA"].replace(" ", "")
    assert d.sea().describe()["CA"] == "bd*s + kd"  # sea() stays the file's model
    assert d.to_dict()["control"]["delay_time"] == 0.002


def test_delay_time_with_a_rate_keeps_the_sampled_loop():
    d = parse_design(doc({"rate": 500.0, "delay": 1, "delay_time": 0.001}))
    assert d.loop is not None and d.loop.rate == 500.0 and d.delay_time == 0.001


def test_no_delay_time_means_no_key_and_no_change():
    d = parse_design(doc({"rate": 500.0}))
    assert d.delay_time is None and "delay_time" not in d.to_dict()["control"]
    assert d.delayed_sea().describe() == d.sea().describe()


def test_zero_latency_is_the_file_model_exactly():
    d = parse_design(doc({"delay_time": 0}))
    assert d.delay_time == 0.0
    assert d.delayed_sea().describe() == d.sea().describe()
    assert latency_elements({"CA": "kd", "CL": "0"}, 0.0) == {"CA": "kd", "CL": "0"}


def test_both_controllers_are_delayed_and_an_absent_one_stays_zero():
    out = latency_elements({"D1": "k1", "CA": "kd", "CL": "kp*k1", "D2": "0"}, 0.01)
    assert out == {"D1": "k1", "D2": "0", "CA": "(kd)*exp(-delay_time*s)",
                   "CL": "(kp*k1)*exp(-delay_time*s)"}  # fmt: skip
    assert latency_elements({"CA": "0", "CL": "kd"}, 0.01)["CA"] == "0"


def test_verdict_at_the_latency_matches_a_hand_written_delay_and_a_dense_grid():
    for tau in (0.01, 0.05):
        d = parse_design(doc({"delay_time": tau}))
        ours = seapass.is_passive(d.delayed_sea())
        hand = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)", values={**PARAMS, "tau": tau})
        assert ours.status == seapass.is_passive(hand).status
        w = np.geomspace(1e-2, 1e5, 200_001)
        grid_negative = bool(rez(w, tau).min() < 0)  # independent: numpy on the formula
        assert ours.passive == (not grid_negative)
        if not ours.passive:
            assert rez(np.array([ours.omega]), tau)[0] < 0  # the witness is a real one


@pytest.mark.parametrize(
    ("value", "says"),
    [
        (-0.001, "control.delay_time: must be a number of seconds in [0, 1000]"),
        (1001.0, "control.delay_time: must be a number of seconds in [0, 1000]"),
        (math.nan, "control.delay_time: must be finite"),  # the schema's own check
        (math.inf, "control.delay_time: must be finite"),
        ("1 ms", "control.delay_time"),
        (True, "control.delay_time"),
    ],
)
def test_bad_delay_time_names_the_key(value, says):
    with pytest.raises(FileFormatError) as info:
        parse_design(doc({"delay_time": value}))
    assert says in str(info.value)


def test_latency_refused_with_a_delay_in_the_model():
    bad = doc({"delay_time": 0.001}, D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)")
    bad["parameters"]["tau"] = 0.001
    with pytest.raises(FileFormatError, match=r"already has a delay exp\(-tau\*s\)"):
        parse_design(bad)


def test_latency_refused_without_a_controller_and_for_a_taken_name():
    no_controller = doc({"delay_time": 0.001}, D1="k1 + b1*s")
    for gain in ("kd", "bd"):
        del no_controller["parameters"][gain]
    with pytest.raises(FileFormatError, match="no controller"):
        parse_design(no_controller)
    taken = doc({"delay_time": 0.001}, D1="k1 + b1*s", CA="kd + bd*delay_time*s")
    taken["parameters"]["delay_time"] = 1.0
    with pytest.raises(FileFormatError, match=r"parameters\.delay_time: the name is taken"):
        parse_design(taken)


def test_check_delay_time_names_the_argument():
    assert check_delay_time(0) == 0.0
    with pytest.raises(ParameterError, match=r"^latency: ") as info:
        check_delay_time(-1, argument="latency")
    assert info.value.argument == "latency"


def test_resolve_design_uses_the_file_latency_and_the_given_one_wins():
    d = parse_design(doc({"delay_time": 0.002}))
    r = resolve_design(d)
    assert r.delay_time == 0.002 and r.sea.values[LATENCY_PARAMETER] == 0.002
    r0 = resolve_design(d, delay_time=0.0)
    assert r0.delay_time == 0.0 and LATENCY_PARAMETER not in r0.sea.parameters
    r5 = resolve_design(d, delay_time=0.005, values={"kd": 800.0})
    assert r5.sea.values[LATENCY_PARAMETER] == 0.005 and r5.sea.values["kd"] == 800.0
    assert r5.to_dict()["delay_time"] == 0.005
    r_none = resolve_design(parse_design(doc()), delay_time=0.001)  # no file latency
    assert r_none.sea.values[LATENCY_PARAMETER] == 0.001


def test_resolve_design_refuses_a_bad_latency_naming_delay_time():
    d = parse_design(doc())
    with pytest.raises(ParameterError, match=r"^delay_time: must be") as info:
        resolve_design(d, delay_time=-1.0)
    assert info.value.argument == "delay_time"
    with pytest.raises(ParameterError, match="already has a delay"):
        resolve_design(
            parse_design(doc({"delay_time": 0.001})),
            elements={"CA": "kd*exp(-tau*s)"},
            values={"tau": 0.001},
        )
