"""Rendered stiffness frequency response, cross-checked with python-control and scipy."""

import json

import numpy as np
import pytest
from scipy import signal

from seapass import SEA, stiffness_response
from seapass.cli import main
from seapass.errors import ParameterError

OURS = {"m": 1.0, "b": 10.0, "k1": 1005.0, "b1": 20.0, "bd": 25.0, "kd": 1000.0}


def test_matches_closed_form_eq10():
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=OURS)
    w = np.logspace(-1, 4, 50)
    r = stiffness_response(sea, w)
    s = 1j * w
    m, b, k1, b1, bd, kd = (OURS[k] for k in ("m", "b", "k1", "b1", "bd", "kd"))
    expected = (
        (k1 + b1 * s) * (m * s**2 + b * s + bd * s + kd) / (m * s**2 + (b + b1 + bd) * s + k1 + kd)
    )
    np.testing.assert_allclose(r.magnitude, np.abs(expected), rtol=1e-12)
    assert r.static == pytest.approx(k1 * kd / (k1 + kd))
    assert r.high_frequency == np.inf  # grows like b1*s: the damper is felt at high frequency


def test_matches_python_control_and_scipy():
    control = pytest.importorskip("control")
    sea = SEA(D1="k1", CL="kd", values={"m": 1.0, "b": 10.0, "k1": 1000.0, "kd": 500.0})
    w = np.logspace(-1, 3, 80)
    r = stiffness_response(sea, w)
    sys = control.tf([1000.0, 10000.0, 500000.0], [1.0, 10.0, 1000.0])
    mag = np.abs(sys(1j * w))
    np.testing.assert_allclose(r.magnitude, mag, rtol=1e-10)
    _, h = signal.freqs([1000.0, 10000.0, 500000.0], [1.0, 10.0, 1000.0], worN=w)
    np.testing.assert_allclose(r.magnitude, np.abs(h), rtol=1e-10)
    assert r.high_frequency == pytest.approx(1000.0)  # tends to k1, as the paper says


def test_bad_frequencies():
    sea = SEA(D1="k1", CL="kd", values={"m": 1.0, "b": 10.0, "k1": 1000.0, "kd": 500.0})
    with pytest.raises(ParameterError, match="shape"):
        stiffness_response(sea, np.array([[1.0]]))
    with pytest.raises(ParameterError, match="non-negative"):
        stiffness_response(sea, np.array([-1.0]))


def test_cli_response(capsys, tmp_path):
    args = ["response", "--D1", "k1 + b1*s", "--CA", "kd + bd*s"] + [
        x for k, v in OURS.items() for x in ("--set", f"{k}={v}")
    ]
    assert main([*args, "--json", "--points", "10"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert len(d["magnitude"]) == 10
    out = tmp_path / "r.png"
    assert main([*args, "--out", str(out)]) == 0
    assert out.stat().st_size > 1000
    assert main([*args, "--omega", "0:10"]) == 2
    assert "positive" in capsys.readouterr().err
