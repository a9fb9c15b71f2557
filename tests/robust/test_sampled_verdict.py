"""Robust sampled-data verdict over a box of plants (issue 26, item 4), checked against the
ordinary certified sampled verdict at sampled plants of the box."""

from __future__ import annotations

import contextlib
import io
import json
from fractions import Fraction as F

import pytest

from seapass.cli import main
from seapass.errors import NotPassiveError, ParameterError
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.robust import robust_sampled_check, sampled_verdict
from seapass.robust.sampled_verdict import Setup, box_outcome, split
from seapass.sampled.passivity import sampled_passivity

OURS = dict(b=10, k1=1000, b1=300, kd=1708, bd=300)
LOOP = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)


def _ours(**values: float) -> SEA:
    return SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**OURS, **values})


def test_worst_case_plant_is_not_passive_by_the_plain_sampled_verdict() -> None:
    r = robust_sampled_check(_ours(), loop=LOOP, box={"m": (0.9, 1.1)})
    assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None
    plain = sampled_passivity(_ours(m=r.worst.values["m"]), loop=LOOP)
    assert plain.outcome is Outcome.NOT_PASSIVE
    d = r.to_dict()
    assert d["robust"] is True and d["status"] == "not_passive" and d["box"] == {"m": [0.9, 1.1]}
    assert d["worst"]["values"] == {"m": 0.9}
    with pytest.raises(NotPassiveError):
        robust_sampled_check(_ours(), loop=LOOP, box={"m": (0.9, 1.1)}, throw=True)


@pytest.mark.parametrize("box", [(0.95, 1.05), (0.97, 1.0)])
def test_a_box_that_straddles_the_boundary_is_never_passive(box: tuple) -> None:
    # m = 0.95 fails and m = 1.05 passes at 500 Hz with one sample of delay
    assert not sampled_passivity(_ours(m=0.95), loop=LOOP).passive
    assert sampled_passivity(_ours(m=1.05), loop=LOOP).passive
    r = robust_sampled_check(_ours(), loop=LOOP, box={"m": box}, budget=8)
    assert r.outcome is not Outcome.PASSIVE
    assert r.boxes <= 8
    if r.worst is not None:
        assert not sampled_passivity(_ours(m=r.worst.values["m"]), loop=LOOP).passive


def test_sub_box_centres_are_examined_when_the_vertices_pass(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(sampled_verdict, "PIECES", 150)  # less work per sub-box: counted
    # both ends and the centre of [1.0, 1.2] pass; the search then examines sub-boxes (counted)
    for m in (1.0, 1.1, 1.2):
        assert sampled_passivity(_ours(m=m), loop=LOOP).passive
    r = robust_sampled_check(_ours(), loop=LOOP, box={"m": (1.0, 1.2)}, budget=1)
    assert r.boxes == 1 and r.outcome is Outcome.UNDECIDED and r.worst is None
    assert r.to_dict()["status"] == "undecided"


def test_passive_physics_is_certified_and_dense_sampling_agrees() -> None:
    sea = SEA(D1="k1 + b1*s", values=dict(m=None, b=10, k1=1000, b1=30))
    loop = SampledLoop(period=0.002)
    r = robust_sampled_check(sea, loop=loop, box={"m": (0.5, 2.0)}, budget=64)
    assert r.outcome is Outcome.PASSIVE and r.certified_share == 1.0
    for i in range(201):  # counted: 201 ordinary certified verdicts
        m = 0.5 + 1.5 * i / 200
        assert sampled_passivity(sea, loop=loop, values={"m": m}).passive


def test_a_narrow_box_of_a_controlled_design_is_certified_and_dense_sampling_agrees() -> None:
    # the mean-value enclosures certify narrow boxes (relative width 2e-6 here)
    lo, hi = 1.02 - 1e-6, 1.02 + 1e-6
    r = robust_sampled_check(_ours(), loop=LOOP, box={"m": (lo, hi)}, budget=2)
    assert r.outcome is Outcome.PASSIVE and r.certified_share == 1.0
    for i in range(201):  # counted: 201 ordinary certified verdicts inside the box
        m = lo + (hi - lo) * i / 200
        assert sampled_passivity(_ours(m=m), loop=LOOP).passive


def test_box_outcome_never_certifies_a_box_holding_a_failing_plant(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # [0.95, 1.0] holds failing plants and its centre passes: box_outcome spends its whole
    # piece budget on it; 300 pieces (not 1500) bound that work, counted (~4x less)
    monkeypatch.setattr(sampled_verdict, "PIECES", 300)
    st = Setup(_ours(m=None), LOOP, ("m",))
    boxes = [((F(9, 10), F(11, 10)),)]
    for _ in range(2):
        boxes = [h for b in boxes for h in split(b)]
    failing = 0
    for b in boxes[:2]:  # [0.9, 0.95] and [0.95, 1.0]: the ones holding failing plants
        out = box_outcome(st, b)
        plants = [float(b[0][0] + (b[0][1] - b[0][0]) * t / 4) for t in range(5)]
        verdicts = [sampled_passivity(_ours(m=m), loop=LOOP).outcome for m in plants]
        if Outcome.NOT_PASSIVE in verdicts:
            failing += 1
            assert out is not Outcome.PASSIVE
        if out is Outcome.NOT_PASSIVE:  # proven for every plant of the box
            assert all(v is not Outcome.PASSIVE for v in verdicts)
    assert failing >= 1  # the low end of the box fails (m = 0.9, 0.95)


def test_bad_input_is_refused() -> None:
    with pytest.raises(ParameterError, match="nonlinearly"):  # a gain is taken when affine
        sea = SEA(D1="k1 + b1*s", CA="kd*bd + bd*s", values=dict(m=1, b=10, k1=1000, b1=300))
        robust_sampled_check(sea, loop=LOOP, box={"kd": (1, 2), "bd": (1, 2)})
    with pytest.raises(ParameterError, match="budget"):
        robust_sampled_check(_ours(), loop=LOOP, box={"m": (0.9, 1.1)}, budget=0)
    with pytest.raises(ParameterError, match="positive"):
        robust_sampled_check(_ours(), loop=LOOP, box={"m": (0.0, 1.1)})


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


OURS_CLI = ["--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "b=10", "--set", "k1=1000",
            "--set", "b1=300", "--set", "kd=1708", "--set", "bd=300", "--period", "0.002",
            "--delay", "1", "--velocity-filter", "50"]  # fmt: skip


def test_cli_sampled_check_with_a_box_prints_the_robust_json() -> None:
    code, out, err = _cli(["sampled", "check", *OURS_CLI, "--uncertain", "m=0.9:1.1", "--json"])
    assert code == 1, err
    d = json.loads(out)
    assert d["robust"] is True and d["status"] == "not_passive"
    assert d["box"] == {"m": [0.9, 1.1]} and d["worst"]["values"] == {"m": 0.9}
    code, out, _ = _cli(["sampled", "check", *OURS_CLI, "--uncertain", "m=0.9:1.1"])
    assert code == 1 and "worst case: m=0.9" in out


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--uncertain", "kd=1:2"], "--set kd"),
        (["--uncertain", "m=2:1"], "LO must not exceed HI"),
        (["--uncertain", "q=1:2"], "not a parameter of the model"),
        (["--uncertain", "m=1:2", "--set", "m=1"], "--set m"),
        (["--uncertain", "m=1:2", "--budget", "0"], "--budget"),
        (["--uncertain", "m=-1:2"], "positive"),
    ],
)
def test_cli_bad_boxes_give_one_error_line_and_exit_2(extra: list, needle: str) -> None:
    code, out, err = _cli(["sampled", "check", *OURS_CLI, *extra])
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and needle in lines[0]


def test_a_controller_in_z_is_decided_over_the_box_without_a_continuous_gate() -> None:
    # a z-controller has no continuous twin: the deployment gate of robust_check must not
    # apply (it raised ContinuousOnlyError); the box verdict agrees with the plain sampled
    # verdict at its corners and centre
    from seapass.model.zcontroller import ZController

    zpd = ZController(CA="kd + bd*500*(1 - z^-1)", rate=500.0)
    sea = SEA(
        D1="k1 + b1*s",
        values={"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 2.0, "kd": 2000.0, "bd": 25.0},
        discrete=zpd,
    )
    loop = SampledLoop(rate=500.0, delay=1)
    result = robust_sampled_check(sea, loop=loop, box={"m": (1.0199, 1.0201)})
    plain = [
        sampled_passivity(sea, loop=loop, values={"m": m}).outcome for m in (1.0199, 1.02, 1.0201)
    ]
    assert result.outcome is Outcome.PASSIVE and plain == [Outcome.PASSIVE] * 3
    over = robust_sampled_check(sea.with_values(kd=30000.0), loop=loop, box={"m": (1.0199, 1.0201)})
    assert not sampled_passivity(sea.with_values(kd=30000.0), loop=loop).passive
    assert over.outcome is Outcome.NOT_PASSIVE and over.worst is not None
