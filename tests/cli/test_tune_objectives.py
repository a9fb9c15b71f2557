"""``seapass tune --objective rendering|force-bandwidth|zwidth`` end to end, as a user runs it."""

from __future__ import annotations

import contextlib
import io
import json
from typing import Any

import control
import numpy as np
import pytest

from seapass import SEA, is_passive
from seapass.cli import main
from seapass.model.loop import SampledLoop
from seapass.sampled.passivity import sampled_passivity

BUDGET = ["--maxiter", "2", "--popsize", "3", "--no-progress"]
CASCADED = "examples/cascaded_impedance.toml"
PLANT = {"m": 1.0, "b": 10.0, "k1": 1000.0}
ELEMENTS: dict[str, dict[str, Any]] = {
    "LP": {"D1": "k1", "CL": "kd"},
    "APD": {"D1": "k1", "CA": "kd + bd*s"},
    "ours": {"D1": "k1 + b1*s", "CA": "kd + bd*s"},
}


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def _json(argv: list[str]) -> dict:
    code, out, err = _cli([*argv, *BUDGET, "--json"])
    assert code == 0, err
    result = json.loads(out)
    assert isinstance(result, dict)
    result["_stderr"] = err
    return result


def _consistent(d: dict) -> None:
    c, u = d["objective"], d["unconstrained"]["value"]
    assert d["passivity_cost"] >= 0
    assert (c <= u) if d["maximize"] else (u <= c)
    assert d["passivity_cost"] == pytest.approx(abs(u - c), abs=1e-12)


@pytest.mark.parametrize("name", ["LP", "APD", "ours"])
def test_rendering_on_the_paper_designs(name: str) -> None:
    d = _json(["tune", name, "--objective", "rendering", "--target", "1500 + 40*s",
               "--band", "1:100"])  # fmt: skip
    sea = SEA(**ELEMENTS[name], values={**PLANT, **d["gains"]})
    assert d["passive"] and is_passive(sea).passive and d["feasible"]
    w = np.logspace(0, 2, 800)  # the verification grid (4 x 200 points)
    k = control.frequency_response(sea.to_control("stiffness"), w).complex.ravel()
    t = 1500 + 40j * w
    assert d["objective"] == pytest.approx(float(np.max(np.abs(k - t) / np.abs(t))), rel=1e-6)
    assert d["unconstrained"]["gains"].keys() == d["gains"].keys()
    _consistent(d)


def test_rendering_on_the_cascaded_file_checks_its_rate_too() -> None:
    d = _json(["tune", CASCADED, "--objective", "rendering", "--target", "kv + bv*s",
               "--band", "1:100", "--tune", "kp", "--tune", "ba"])  # fmt: skip
    assert d["passive"] and d["sampled_passive"] and d["period"] == pytest.approx(1e-3)
    assert d["load_masses"] == [0.5, 2.0, 5.0] and d["target"] == "kv + bv*s"
    assert "note: passivity also required at the design file's 1000 Hz" in d["_stderr"]
    _consistent(d)


@pytest.mark.parametrize("name", ["APD", CASCADED])
def test_force_bandwidth_text_and_json(name: str) -> None:
    argv = ["tune", name, "--objective", "force-bandwidth", "--band", "0.1:1000"]
    code, out, err = _cli([*argv, *BUDGET, *(["--continuous"] if name == CASCADED else [])])
    assert code == 0, err
    assert "force bandwidth (clamped load, -3 dB):" in out and "passivity cost:" in out
    assert "unconstrained optimum:" in out
    d = _json([*argv, *(["--continuous"] if name == CASCADED else [])])
    assert d["objective_unit"] == "rad/s" and d["maximize"] and 0 < d["objective"] <= 1000
    _consistent(d)


def test_zwidth_at_the_file_rate() -> None:
    d = _json(["tune", CASCADED, "--objective", "zwidth", "--tune", "ba", "--max-boxes", "300",
               "--maxiter", "1"])  # fmt: skip
    assert d["stiffness"] == "kv" and d["max_boxes"] == 300
    gains = d["gains"]
    assert gains["kv"] == d["objective"] > 0 and d["sampled_passive"]
    from seapass.model.design_file import load_design

    sea = load_design(CASCADED).sea().with_values(**gains)
    assert sampled_passivity(sea, loop=SampledLoop(period=1e-3)).passive
    _consistent(d)


@pytest.mark.parametrize(
    ("extra", "says"),
    [
        (
            ["--objective", "rendering", "--target", "1000", "--band", "100:1"],
            "--band: need 0 < lo < hi",
        ),
        (["--objective", "rendering", "--target", "1000 +", "--band", "1:10"], "--target: "),
        (["--objective", "rendering", "--target", "1000", "--band", "1-10"], "expected LO:HI"),
        (["--objective", "rendering", "--band", "1:10"], "needs a target"),
        (["--objective", "rendering", "--target", "1000"], "needs a band"),
        (["--objective", "zwidth"], "--objective zwidth needs the loop rate"),
        (["--objective", "force-bandwidth", "--target", "1"], "--target applies to"),
        (["--objective", "zwidth", "--period", "0.002", "--stiffness", "kx"], "--stiffness: "),
    ],
)
def test_bad_input_is_one_error_line(extra: list[str], says: str) -> None:
    code, out, err = _cli(["tune", "APD", *extra, *BUDGET])
    assert code == 2 and out == "" and err.count("\n") == 1 and err.startswith("error: "), err
    assert says in err, err


DELAYED = ["--D1", "k1 + b1*s", "--CA", "(kd + bd*s)*exp(-tau*s)", "--set", "m=1",
           "--set", "b=10", "--set", "k1=1000", "--set", "b1=30", "--set", "tau=0.001",
           "--tune", "kd=0:5000", "--tune", "bd=0:300"]  # fmt: skip


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (
            [*DELAYED, "--objective", "rendering", "--target", "1000", "--band", "1:50"],
            "the interaction objectives (rendering, force-bandwidth, zwidth) need a delay-free",
        ),
        (
            ["APD", "--objective", "force-bandwidth", "--uncertain", "m=1:2"],
            "--uncertain and --robust work with --objective settling or itae, not force-bandwidth",
        ),
    ],
)
def test_objectives_refuse_a_delay_or_a_box(argv: list[str], says: str) -> None:
    code, out, err = _cli(["tune", *argv, *BUDGET])
    assert code == 2 and out == "" and err.count("\n") == 1 and err.startswith("error: "), err
    assert says in err, err


def test_help_examples_are_one_command_per_line() -> None:
    # a lone backslash at a line's end inside the help text would join two lines
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
        main(["tune", "--help"])
    lines = out.getvalue().splitlines()
    assert any(line.strip().startswith("--target") for line in lines)


def test_help_shows_the_objectives_and_examples() -> None:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
        main(["tune", "--help"])
    text = out.getvalue()
    for piece in (
        "force-bandwidth",
        "zwidth",
        "--target EXPR",
        "--band LO:HI",
        "--objective rendering",
    ):
        assert piece in text
