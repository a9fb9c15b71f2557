"""Controller gains in a sampled box: certified boxes checked by the plain verdict."""

from __future__ import annotations

import json

import pytest

from seapass.cli import main
from seapass.errors import ParameterError
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.robust import robust_sampled_check
from seapass.robust.sampled_control import check_gain_structure
from seapass.sampled.passivity import sampled_passivity

LOOP = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
VALUES = dict(m=1.0, b=10.0, k1=1000.0, b1=300.0, kd=1708.0, bd=300.0)
# the plain certified verdict: Ours at 500 Hz is passive for kd up to about 3108.07
EDGE = 3108.07


def _ours() -> SEA:
    return SEA(D1="k1 + b1*s", CA="kd + bd*s", values=VALUES)


def test_a_gain_interval_times_a_plant_box_is_certified_and_every_sample_is_passive() -> None:
    box = {"kd": (400.0, 500.0), "m": (1.0, 1.0001)}
    r = robust_sampled_check(_ours(), loop=LOOP, box=box, budget=8)
    assert r.outcome is Outcome.PASSIVE
    # independent: the ordinary certified verdict at 225 (gain, plant) points of the box
    n = 15
    for i in range(n):
        for j in range(n):
            kd = 400.0 + 100.0 * i / (n - 1)
            m = 1.0 + 0.0001 * j / (n - 1)
            v = sampled_passivity(_ours(), loop=LOOP, values={"kd": kd, "m": m})
            assert v.outcome is Outcome.PASSIVE, (kd, m)


@pytest.mark.parametrize(
    "box",
    [
        {"kd": (3000.0, 3108.1)},  # the edge inside, at the top end
        {"kd": (3100.0, 3120.0), "m": (1.0, 1.0001)},  # straddles the edge
    ],
)
def test_a_box_straddling_the_gain_edge_is_never_passive(box: dict) -> None:
    r = robust_sampled_check(_ours(), loop=LOOP, box=box, budget=4)
    assert r.outcome is not Outcome.PASSIVE
    assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None
    worst = dict(r.worst.values)
    assert worst["kd"] > EDGE
    plain = sampled_passivity(_ours(), loop=LOOP, values=worst)
    assert plain.outcome is Outcome.NOT_PASSIVE


def test_the_gain_structure_is_checked() -> None:
    plant = dict(m=1.0, b=10.0, k1=1000.0)
    check_gain_structure(SEA(D1="k1", CA="kd*bd + bd*s", values=plant), ["kd"])  # affine in kd
    with pytest.raises(ParameterError, match="nonlinearly"):
        check_gain_structure(SEA(D1="k1", CA="kd*bd + bd*s", values=plant), ["kd", "bd"])
    with pytest.raises(ParameterError, match="denominator"):
        check_gain_structure(SEA(D1="k1", CA="kd/(1 + bd*s)", values=plant), ["bd"])
    with pytest.raises(ParameterError, match="denominator"):
        sea = SEA(D1="k1", CA="kd/(1 + bd*s)", values={**plant, "kd": 100.0})
        robust_sampled_check(sea, loop=LOOP, box={"bd": (0.001, 0.002)})


def test_cli_sampled_check_with_a_gain_interval(capsys) -> None:
    from helpers import EXAMPLES

    ours = str(EXAMPLES / "ours.toml")
    code = main(["sampled", "check", ours, "--uncertain", "kd=400:500", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["status"] == "passive" and out["box"] == {"kd": [400.0, 500.0]}
    for kd in (400.0, 433.0, 466.0, 500.0):  # the plain verdict agrees at points of the box
        v = sampled_passivity(_ours(), loop=LOOP, values={"kd": kd})
        assert v.outcome is Outcome.PASSIVE
    code = main(["sampled", "check", ours, "--uncertain", "kd=3100:3120", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "not_passive" and out["worst"]["values"]["kd"] > EDGE


def test_cli_sampled_bound_of_a_gain_over_a_plant_box_has_a_certified_inner_set(capsys) -> None:
    from helpers import EXAMPLES

    argv = ["sampled", "bound", "kd", str(EXAMPLES / "ours.toml"), "--range", "kd=400:500"]
    argv += ["--uncertain", "m=1:1.0001", "--budget", "6", "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["intervals"] == [[400.0, 500.0]] and out["outer"] == [[400.0, 500.0]]
    for kd in (400.0, 450.0, 500.0):  # the inner set is passive by the plain verdict
        for m in (1.0, 1.00005, 1.0001):
            v = sampled_passivity(_ours(), loop=LOOP, values={"kd": kd, "m": m})
            assert v.outcome is Outcome.PASSIVE


def test_two_gains_in_the_box_are_certified_and_the_plain_verdict_agrees() -> None:
    box = {"kd": (400.0, 450.0), "bd": (299.0, 300.0)}
    r = robust_sampled_check(_ours(), loop=LOOP, box=box, budget=4)
    assert r.outcome is Outcome.PASSIVE
    for i in range(5):
        for j in range(5):
            values = {"kd": 400.0 + 12.5 * i, "bd": 299.0 + 0.25 * j}
            assert sampled_passivity(_ours(), loop=LOOP, values=values).passive, values
