"""CLI: seapass simulate / tune / figure sims."""

from __future__ import annotations

import json

import pytest

from helpers import LP_ARGV
from seapass.cli import main

OURS = [
    "--D1", "k1 + b1*s", "--CA", "kd + bd*s",
    "--set", "m=1", "--set", "b=10", "--set", "k1=1000",
    "--set", "b1=100", "--set", "kd=2000", "--set", "bd=60",
]  # fmt: skip
LP = list(LP_ARGV)  # the paper's load-side P on its plant (tests/helpers.py)


def _json(capsys) -> dict:
    return json.loads(capsys.readouterr().out)


def test_simulate_json(capsys, tmp_path):
    plot = tmp_path / "run.png"
    code = main(["simulate", *OURS, "--load-mass", "10", "--step", "0.5", "--horizon", "5",
                 "--json", "--plot", str(plot)])  # fmt: skip
    assert code == 0
    out = _json(capsys)
    for key in ("settling_time", "final_error", "overshoot", "passive", "stable",
                "peak_force", "energy"):  # fmt: skip
        assert key in out
    assert out["stable"] is True and out["passive"] is True
    assert out["settling_time"] == pytest.approx(1.5826126, abs=1e-6)
    assert out["peak_force"] == pytest.approx(1000.0)
    assert plot.stat().st_size > 1000


def test_simulate_text_and_scenarios(capsys, tmp_path):
    assert main(["simulate", *LP, "--set", "kd=500", "--load-mass", "1",
                 "--load-displaced", "0.02", "--horizon", "3"]) == 0  # fmt: skip
    assert "settling time" in capsys.readouterr().out
    traj = tmp_path / "ref.csv"
    traj.write_text("time,theta\n0,0\n1,0.2\n2,0.2\n")
    assert main(["simulate", *OURS, "--load-mass", "2", "--trajectory", str(traj),
                 "--interp", "zoh", "--horizon", "4", "--json"]) == 0  # fmt: skip
    out = _json(capsys)
    assert out["scenario"] == "Trajectory" and out["target"] == pytest.approx(0.2)
    assert main(["simulate", *OURS, "--load-mass", "2", "--force-step", "5", "--json"]) == 0
    assert _json(capsys)["scenario"] == "ForceStep"


def test_simulate_unstable_is_a_result(capsys):
    code = main(["simulate", *LP, "--set", "kd=5000", "--load-mass", "10", "--json"])
    assert code == 0
    out = _json(capsys)
    assert out["stable"] is False and out["passive"] is False
    assert out["settling_time"] is None and out["status"] == "unstable"


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--set", "kd=500", "--load-mass", "0"], "load mass"),
        (["--set", "kd=500", "--load-mass", "-3"], "load mass"),
        (["--set", "kd=500", "--load-mass", "1", "--horizon", "0.0001"], "shorter than"),
        (["--set", "kd=500", "--CA", "kd*s**2", "--load-mass", "1"], "improper"),
        (["--load-mass", "1"], "kd"),
    ],
)
def test_simulate_bad_input_exit_2(capsys, extra, needle):
    assert main(["simulate", *LP, *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err and "Traceback" not in err


def test_simulate_bad_trajectory_file(capsys, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("0,0\n1,abc\n")
    assert main(["simulate", *OURS, "--load-mass", "1", "--trajectory", str(bad)]) == 2
    assert "bad.csv:2" in capsys.readouterr().err
    assert main(["simulate", *OURS, "--load-mass", "1", "--trajectory", str(tmp_path / "no")]) == 2


def test_tune_json(capsys):
    code = main(["tune", "--design", "APD", "--quick", "--maxiter", "5", "--json",
                 "--no-progress"])  # fmt: skip
    assert code == 0
    out = _json(capsys)
    assert set(out["gains"]) == {"kd", "bd"} and out["passive"] is True
    assert out["settling_time"] is not None and out["peak_force"] <= 1000.0


@pytest.mark.parametrize(
    "args",
    [
        ["--design", "PID"],
        ["--design", "LP", "--load-mass", "0"],
        ["--design", "LP", "--bound", "kd=5:1"],
        ["--design", "LP", "--set", "kd=3"],
    ],
)
def test_tune_bad_input(capsys, args):
    assert main(["tune", *args, "--quick", "--no-progress"]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_figure_sims_quick(capsys, tmp_path):
    out = tmp_path / "figs"
    assert main(["figure", "sims", "--out", str(out), "--quick", "--no-progress",
                 "--horizon", "6"]) == 0  # fmt: skip
    names = {p.name for p in out.iterdir()}
    assert names == {"sims.png", "sims.pdf", "sims.csv", "sims_table.csv", "sims_table.json",
                     ".seapass-written"}  # fmt: skip
    table = json.loads((out / "sims_table.json").read_text())
    assert len(table["rows"]) == 9
    header = (out / "sims.csv").read_text().splitlines()[0]
    assert header == "design,load_mass_kg,time_s,x_A_m,x_L_m,f_A_N"
    assert "Ours is" in capsys.readouterr().out


def test_help_has_examples(capsys):
    for cmd in ("simulate", "tune", "figure"):
        with pytest.raises(SystemExit):
            main([cmd, "--help"])
        assert "example" in capsys.readouterr().out
