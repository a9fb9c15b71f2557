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


def _containers(value: object, depth: int = 0) -> list[str]:
    """Mutable containers held by a value (tuples and read-only mappings looked into)."""
    from types import MappingProxyType

    if isinstance(value, list | dict | set):
        return [type(value).__name__]
    if isinstance(value, tuple) and depth < 3:
        return [c for v in value for c in _containers(v, depth + 1)]
    if isinstance(value, MappingProxyType) and depth < 3:
        return [c for v in value.values() for c in _containers(v, depth + 1)]
    return []


def test_every_verdict_speaks_outcome_and_holds_no_mutable_container() -> None:
    """One vocabulary (seapass.outcome): booleans are read off ``outcome``; results are immutable."""
    import dataclasses

    from seapass.outcome import Outcome
    from seapass.ports.bound import port_region

    stable = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG)
    unstable = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": 5000.0})
    checks = [check_two_port(stable), check_two_port(unstable)]
    assert [c.stability.outcome for c in checks] == [Outcome.PASSIVE, Outcome.NOT_PASSIVE]
    witness = checks[1].stability.witness
    assert witness is not None and witness.found and witness.outcome is Outcome.NOT_PASSIVE
    assert witness.closed_loop is not None and witness.closed_loop.outcome is Outcome.NOT_PASSIVE
    friction = [friction_certificate(stable), friction_certificate(unstable)]
    verdicts = [
        *checks,
        *(c.stability for c in checks),
        *(c.passivity for c in checks),
        *friction,
        witness,
        mimo_is_passive([["b + k/s", "c/s"], ["-c/s", "b + k/s"]], values={"b": 1, "k": 1, "c": 1}),
    ]
    for r in verdicts:
        assert isinstance(r.outcome, Outcome), type(r).__name__
        if hasattr(r, "passive"):
            assert r.passive is r.outcome.passive, type(r).__name__
    for c in checks:
        assert c.absolutely_stable is c.stability.outcome.passive
    for f in friction:
        assert f.certified is f.outcome.passive
    for cond in checks[1].stability.conditions:
        assert cond.holds is (None if cond.outcome is Outcome.UNDECIDED else cond.outcome.passive)
    built = [
        *verdicts,
        port_intervals(unstable.with_values(kl=None), "kl", 0, 1e4),
        port_region(unstable.with_values(kl=None, kd=None), "kd", [400, 500], "kl", (0, 1e4)),
        CoupledAxes(axes=({"D1": "k1"},), K=[["kd"]], B=[[0]], values={"k1": 1, "kd": 1}),
    ]
    for r in built:
        for f in dataclasses.fields(r):
            found = _containers(getattr(r, f.name))
            assert not found, f"{type(r).__name__}.{f.name} holds a {found[0]}"
