"""Results of seapass.ports: to_dict (strict JSON), short repr, escaped HTML, front-door names."""

from __future__ import annotations

import json

import seapass
from seapass.cli.output import json_text
from seapass.model.sea import SEA
from seapass.ports import TwoPort
from seapass.ports.axes import CoupledAxes
from seapass.ports.bound import port_intervals
from seapass.ports.check import check_two_port
from seapass.ports.friction import friction_certificate
from seapass.ports.mimo import NPort, mimo_is_passive

RIG = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)
HOSTILE = "<script>alert(1)</script>"


def test_front_door_names() -> None:
    for name in (
        "two_port",
        "TwoPort",
        "absolute_stability",
        "two_port_passivity",
        "mimo_is_passive",
    ):
        assert name in seapass.__all__ and callable(getattr(seapass, name))
    assert "ports" in dir(seapass)
    sea = seapass.SEA(D1="k1", CA="kd", values=dict(m=1, b=10, k1=1000, kd=500))
    assert seapass.absolute_stability(seapass.two_port(sea)).absolutely_stable
    assert seapass.two_port_passivity(sea).passive


def test_every_result_serializes_and_displays() -> None:
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": 5000.0}, name=HOSTILE)
    results = [
        check_two_port(sea),
        check_two_port(sea).stability,
        check_two_port(sea).passivity,
        mimo_is_passive([[1, 0], [0, 1]]),
        friction_certificate(sea),
        port_intervals(sea.with_values(kl=None), "kl", 0, 1e4),
    ]
    for r in results:
        d = r.to_dict()
        json.loads(json_text(d))  # strict JSON (inf and nan become null)
        text = repr(r)
        assert len(text) < 300 and "\n" not in text
        assert "<script>" not in r._repr_html_()
    for model in (
        TwoPort.from_matrix([[1, 0], [0, 1]], name=HOSTILE),
        NPort.from_matrix([[1]], name=HOSTILE),
        CoupledAxes(
            axes=({"D1": "k1"},),
            K=[["kd"]],
            B=[[0]],
            values={"m": 1, "b": 1, "k1": 1, "kd": 1},
            name=HOSTILE,
        ),
    ):
        assert "<script>" not in model._repr_html_() and len(repr(model)) < 300
        json.loads(json_text(model.to_dict()))
