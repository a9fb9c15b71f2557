"""``seapass tune`` with a delay in the model and with ``--uncertain`` boxes (end to end)."""

from __future__ import annotations

import contextlib
import io
import json
import re

import numpy as np
import pytest

from seapass.analysis.passivity import is_passive
from seapass.cli import main
from seapass.delay.passivity import delayed_passivity
from seapass.model.sea import SEA
from seapass.outcome import Outcome

PLANT = ["--set", "m=1", "--set", "b=10", "--set", "k1=1000", "--set", "b1=30"]
BUDGET = ["--quick", "--maxiter", "8", "--popsize", "5", "--no-progress"]  # counted work
DELAYED = ["--D1", "k1 + b1*s", "--CA", "(kd + bd*s)*exp(-tau*s)", *PLANT]
GAINS = ["--tune", "kd=0:5000", "--tune", "bd=0:300"]


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def test_tune_with_a_delay_json_is_certified_at_tau() -> None:
    code, out, err = _cli(["tune", *DELAYED, "--set", "tau=0.01", *GAINS, *BUDGET, "--json"])
    d = json.loads(out)
    assert code == 0, err
    assert d["constraint"] == {"kind": "delay", "delay": "tau", "tau": 0.01, "box": None}
    assert d["passive"] is True and d["certified"] == "passive" and d["feasible"] is True
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
              values={"m": 1, "b": 10, "k1": 1000, "b1": 30, "tau": 0.01, **d["gains"]})  # fmt: skip
    assert delayed_passivity(sea).outcome is Outcome.PASSIVE  # the printed gains, re-checked


def test_tune_with_a_delay_text_prints_the_verified_gains_and_verdict() -> None:
    code, out, err = _cli(["tune", *DELAYED, "--set", "tau=0.01", *GAINS, *BUDGET])
    assert code == 0, err
    assert "passive (certified at tau = 0.01 s): yes [passive]" in out
    gains = dict(re.findall(r"(\w+) = ([-+.\deE]+)", out.splitlines()[0]))
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
              values={"m": 1, "b": 10, "k1": 1000, "b1": 30, "tau": 0.01,
                      **{k: float(v) for k, v in gains.items()}})  # fmt: skip
    assert delayed_passivity(sea).outcome is Outcome.PASSIVE


def test_tune_uncertain_reports_the_robustness_cost() -> None:
    argv = ["tune", "--D1", "k1 + b1*s", "--CL", "kd + bd*s", "--set", "k1=1000",
            "--set", "b1=20", "--set", "m=1", "--uncertain", "b=0:10", *GAINS, *BUDGET]  # fmt: skip
    code, out, err = _cli([*argv, "--json"])
    d = json.loads(out)
    assert code == 0, err
    assert d["constraint"]["kind"] == "box" and d["constraint"]["box"] == {"b": [0.0, 10.0]}
    assert d["certified"] == "passive"
    assert d["robustness_cost"] >= 0
    assert d["robustness_cost"] == pytest.approx(d["robust"] - d["nominal"])
    # the printed gains pass the exact test across the box (b from 0 to 10, 200 plants)
    for b in np.linspace(0.0, 10.0, 200):
        sea = SEA(D1="k1 + b1*s", CL="kd + bd*s",
                  values={"m": 1, "b": float(b), "k1": 1000, "b1": 20, **d["gains"]})  # fmt: skip
        assert is_passive(sea).passive, b
    code, text, err = _cli(argv)
    assert code == 0, err
    assert "passive (certified for every plant with b in [0, 10]): yes" in text
    assert "robustness cost:" in text and "nominal tune:" in text


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["ours", "--uncertain", "q=0:1"], "--uncertain q: not a parameter"),
        (["ours", "--uncertain", "m=1.2:0.8"], "--uncertain m: empty interval"),
        (["ours", "--uncertain", "m=0.8"], "--uncertain 'm=0.8': expected NAME=LO:HI"),
        (["ours", "--uncertain", "kd=1:2"], "--uncertain kd: kd is tuned"),
        (["ours", "--uncertain", "m=0:1"], "m must be positive"),
        (["ours", "--uncertain", "m=0.9:1.1", "--set", "m=1"], "--set m: m is uncertain"),
        (["ours", "--uncertain", "m=0.9:1.1", "--budget", "0"], "--budget must be a positive"),
        (["ours", "--uncertain", "m=0.9:1.1", "--period", "0.002"], "--continuous"),
        ([*DELAYED, "--set", "tau=-0.001", *GAINS], "--set tau: a delay must be >= 0"),
        (
            [*DELAYED, "--set", "tau=0.001", *GAINS, "--tune", "tau=0:1"],
            "--tune tau: tau is the delay",
        ),
        ([*DELAYED, "--set", "tau=0.001", *GAINS, "--period", "0.001"], "sampled-data loop"),
        (
            [
                "--D1",
                "k1 + b1*s",
                "--CA",
                "(kd + bd*s)*exp(-tau*s)",
                *PLANT[2:],
                "--set",
                "tau=0.001",
                *GAINS,
                "--uncertain",
                "m=0.9:1.1",
            ],
            "delayed design",
        ),
    ],
)
def test_bad_input_is_one_error_line(argv: list[str], words: str) -> None:
    code, out, err = _cli(["tune", *argv, *BUDGET])
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and words in lines[0], err
