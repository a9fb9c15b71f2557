"""Controllers given in z on the command line (issue 22, item 3), end to end.

A PD already running on a microcontroller at 500 Hz, ``K_A(z) = kd + bd (1 − z⁻¹)/T``,
given as a design file's ``[discrete]`` table or as ``--CA-z``/``--rate``: the sampled
analyses, ``simulate``, the twin and ``export c`` run it as is; the continuous analyses
refuse it with one ``error:`` line (``analyze`` reports those stages as not applicable).
Cross-check: its certified sampled bound equals that of the continuous design
``kd + bd s`` discretized by seapass (backward-difference derivative) at the same rate.
"""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.export import find_c_compiler

PLANT = ["--D1", "k1 + b1*s", "--set", "m=1.02", "--set", "b=10", "--set", "k1=1005",
         "--set", "b1=30", "--set", "bd=25"]  # fmt: skip
PD_Z = "kd + bd*500*(1 - z^-1)"
FILE = f"""
name = "zpd"
[model]
D1 = "k1 + b1*s"
[parameters]
m = 1.02
b = 10.0
k1 = 1005.0
b1 = 30.0
kd = 2000.0
bd = 25.0
[ranges]
kd = [0.0, 4000.0]
[discrete]
rate = 500.0
CA = "{PD_Z}"
[control]
delay = 1
[rig]
preset = "paper"
"""


def cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


@pytest.fixture
def zfile(tmp_path: Path) -> Path:
    p = tmp_path / "zpd.toml"
    p.write_text(FILE, encoding="utf-8")
    return p


def test_sampled_check_file_and_flags_agree(zfile: Path) -> None:
    code, out, err = cli(["sampled", "check", str(zfile), "--json"])
    assert code == 0, err
    from_file = json.loads(out)
    assert from_file["passive"] is True and from_file["delay"] == 1
    code, out, err = cli(["sampled", "check", *PLANT, "--set", "kd=2000", "--CA-z", PD_Z,
                          "--rate", "500", "--delay", "1", "--json"])  # fmt: skip
    assert code == 0, err
    assert json.loads(out)["status"] == from_file["status"]


def test_sampled_bound_equals_the_continuous_designs() -> None:
    common = ["sampled", "bound", "kd", *PLANT, "--range", "kd=0:1e5", "--json",
              "--no-progress", "--delay", "1"]  # fmt: skip
    code, out, err = cli([*common, "--CA-z", PD_Z, "--rate", "500"])
    assert code == 0, err
    z = json.loads(out)
    code, out, err = cli([*common, "--CA", "kd + bd*s", "--period", "0.002"])
    assert code == 0, err
    s = json.loads(out)
    assert z["intervals"] == s["intervals"] and z["intervals"][0][0] == 0.0
    assert z["period"] == s["period"] == 0.002


def test_simulate_runs_the_sampled_loop(zfile: Path) -> None:
    code, out, err = cli(["simulate", str(zfile), "--load-mass", "2", "--force-step", "20",
                          "--horizon", "4", "--json"])  # fmt: skip
    assert code == 0, err
    d = json.loads(out)
    assert d["kind"] == "sampled" and d["stable"] is True and d["samples"] == 2001
    # at rest: k1 (x_L − x_A) = 20 N and k1 (x_L − x_A) = K_A(1) x_A = kd x_A
    want = 20.0 / 1005.0 + 20.0 / 2000.0
    assert d["final_x_L"] == pytest.approx(want, rel=1e-4)
    assert d["metrics"]["target"] == pytest.approx(want, rel=1e-4)  # the statics of the loop
    assert d["metrics"]["status"] == "settled" and d["metrics"]["overshoot"] is None
    code, out, err = cli(["simulate", str(zfile), "--load-mass", "2", "--horizon", "1"])
    assert code == 0 and "sampled loop at 500 Hz (delay 1): stable" in out
    assert "settling time: " in out and "overshoot: " in out


@pytest.mark.parametrize(
    "argv",
    [["check"], ["bound", "kd"], ["region", "kd", "bd"], ["plot", "bode"], ["witness"],
     ["delay-margin", "tau"], ["twoport", "check"]],
    ids=lambda a: a[0],
)  # fmt: skip
def test_continuous_analyses_refuse_with_one_error_line(argv: list[str], zfile: Path) -> None:
    code, out, err = cli([*argv, str(zfile)])
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")
    assert "needs a continuous controller" in err and "given in z at 500 Hz" in err


def test_analyze_reports_continuous_stages_not_applicable(zfile: Path, tmp_path: Path) -> None:
    code, out, err = cli(["analyze", str(zfile), "--out", str(tmp_path / "rep"), "--quick",
                          "--stages", "passivity,sampled", "--no-progress", "--json"])  # fmt: skip
    assert code == 0, err
    sections = {s["key"]: s for s in json.loads(out)["sections"]}
    assert sections["sampled"]["status"] == "ok"
    assert sections["passivity"]["status"] == "skipped"
    text = (tmp_path / "rep" / "report.md").read_text(encoding="utf-8")
    assert "Not applicable: the continuous-time passivity analysis needs a continuous" in text


@pytest.mark.skipif(find_c_compiler() is None, reason="no C compiler on PATH (install gcc)")
def test_export_c_runs_the_z_controller_as_is(zfile: Path, tmp_path: Path) -> None:
    code, out, err = cli(["export", "c", str(zfile), "--out", str(tmp_path / "c"), "--verify",
                          "--set-gains", "--json"])  # fmt: skip
    assert code == 0, err
    d = json.loads(out)
    assert d["verify"]["ok"] is True and d["deployment"]["certified"] is True
    assert sorted(d["deployment"]["gains"]) == ["bd", "kd"]


def test_rig_sweep_runs_the_z_design(zfile: Path) -> None:
    code, out, err = cli(["rig", "sweep", "--design", str(zfile), "--gain", "kd", "--load-mass",
                          "0.1", "--kd-step", "2000", "--no-progress", "--json"])  # fmt: skip
    assert code == 0, err
    (sweep,) = json.loads(out)["sweeps"]
    assert sweep["design"] == "zpd" and [r["kd"] for r in sweep["runs"]] == [0, 2000, 4000]
    assert sweep["unstable_gain_continuous"] is None  # no continuous prediction for z


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["--CA-z", PD_Z, "--rate", "500", "--period", "0.001"],
         "the controller in z runs at 500 Hz but the sampled loop at 1000 Hz"),
        (["--CA-z", "kd*z", "--rate", "500"], "--CA-z: not causal"),
        (["--CA-z", "kd*s", "--rate", "500"], "--CA-z: 'kd*s' uses s"),
        (["--CA-z", "kd", "--CA", "kd", "--rate", "500"], "not both"),
        (["--CA-z", "kd"], "needs its rate: give --rate HZ"),
        (["--rate", "500", "--CA", "kd"], "--rate is the rate of a controller in z"),
        (["--CA-z", "kd", "--rate", "1e7"], "--rate: 10000000.0 Hz is outside"),
        (["--CA-z", "kd/((z - 1/2)^12*(z + 1/2)^12*(z - 1/4))", "--rate", "500"],
         "order 25 in z exceeds the limit of 24"),
    ],
)  # fmt: skip
def test_bad_input_one_error_line(argv: list[str], words: str) -> None:
    base = ["--D1", "k1 + b1*s", "--set", "m=1.02", "--set", "b=10", "--set", "k1=1005",
            "--set", "b1=30", "--set", "kd=2000"]  # fmt: skip
    if "bd" in " ".join(argv):
        base += ["--set", "bd=25"]
    code, out, err = cli(["sampled", "check", *base, *argv])
    assert code == 2 and out == "", err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and words in err, err


def test_file_at_another_rate_than_its_control(tmp_path: Path) -> None:
    p = tmp_path / "bad.toml"
    p.write_text(FILE.replace("[control]\n", "[control]\nrate = 1000.0\n"), encoding="utf-8")
    code, out, err = cli(["sampled", "check", str(p)])
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "runs at 500 Hz but the sampled loop at 1000 Hz" in err


def test_sweep_refuses_a_z_design(zfile: Path, tmp_path: Path) -> None:
    code, _out, err = cli(["sweep", str(zfile), "--grid", "kd=0:4000:5", "--out",
                          str(tmp_path / "sw")])  # fmt: skip
    assert (
        code == 2 and "error: the batch sweep (continuous-time kernels) needs a continuous" in err
    )
    assert err.count("error:") == 1


def test_tune_a_z_design_end_to_end(zfile: Path) -> None:
    # kd over the file's [ranges]; every candidate certified in the 500 Hz loop (delay 1)
    code, out, err = cli(["tune", str(zfile), "--tune", "kd", "--maxiter", "3", "--popsize", "4",
                          "--load-mass", "1", "--mass-policy", "tune", "--horizon", "2",
                          "--step", "0.05", "--seed", "1", "--no-progress", "--json"])  # fmt: skip
    assert code == 0, err
    d = json.loads(out)
    assert d["sampled_passive"] is True and d["feasible"] is True
    kd = d["gains"]["kd"]
    code, out, err = cli(["sampled", "check", str(zfile), "--set", f"kd={kd!r}", "--json"])
    assert code == 0, err
    assert json.loads(out)["passive"] is True and json.loads(out)["delay"] == 1
    code, out, err = cli(["simulate", str(zfile), "--set", f"kd={kd!r}", "--load-mass", "1",
                          "--step", "0.05", "--horizon", "2", "--json"])  # fmt: skip
    assert code == 0, err
    assert json.loads(out)["metrics"]["settling_time"] == pytest.approx(d["objective"], rel=1e-9)
    code, out, err = cli(["tune", str(zfile), "--tune", "kd", "--maxiter", "2", "--popsize", "3",
                          "--load-mass", "1", "--mass-policy", "tune", "--horizon", "1",
                          "--step", "0.05", "--no-progress"])  # fmt: skip
    assert code == 0, err
    assert "passive in the sampled loop at T = 0.002 s (delay 1, controller in z" in out
    assert "--continuous drops it" not in err


@pytest.mark.parametrize(
    ("argv", "words"),
    [([], "--tune bd: a controller in z has no default box"),
     (["--tune", "b1=0:50", "--allow-plant"], "b1 is not a gain of the controller in z")],
)  # fmt: skip
def test_tune_a_z_design_bad_input(zfile: Path, argv: list[str], words: str) -> None:
    code, out, err = cli(["tune", str(zfile), *argv, "--no-progress"])
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and words in lines[0]
