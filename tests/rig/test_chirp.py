"""`seapass rig chirp`: the command to play on a bench, and the fit of a log of it (end to end)."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest

from seapass.cli import main
from seapass.errors import ParameterError
from seapass.rig.chirp import chirp_plan
from seapass.rig.log import twin_log
from seapass.rig.rigfile import paper_rig

RIG = paper_rig()


def _run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def test_the_plan_is_a_linear_chirp_within_the_limits() -> None:
    plan = chirp_plan(RIG, amplitude=40.0, band=(2.0, 30.0), duration=4.0)
    assert plan.force.size == 4 * 500 and plan.rate == RIG.control.rate
    assert np.max(np.abs(plan.force)) <= 40.0 and np.max(np.abs(plan.force)) > 39.0
    # independent check of the sweep: the zero crossings' spacing gives the instantaneous
    # frequency, rising linearly from 2 to 30 Hz
    t, u = plan.time, plan.force
    k = np.flatnonzero((u[:-1] < 0) != (u[1:] < 0))
    cross = t[k] + u[k] / (u[k] - u[k + 1]) * (t[k + 1] - t[k])  # linear interpolation
    f = 0.5 / np.diff(cross)
    mid = 0.5 * (cross[1:] + cross[:-1])
    expected = 2.0 + (30.0 - 2.0) * mid / 4.0
    inner = (mid > 0.5) & (mid < 3.5)
    assert np.allclose(f[inner], expected[inner], rtol=0.02)
    assert plan.to_dict()["samples"] == 2000 and "ChirpPlan(" in repr(plan)


@pytest.mark.parametrize(
    ("kwargs", "argument"),
    [
        ({"amplitude": 500.0}, "amplitude"),
        ({"band": (5.0, 300.0)}, "band"),
        ({"band": (25.0, 5.0)}, "band"),
        ({"duration": -1.0}, "duration"),
        ({"duration": 1e9}, "duration"),
        ({"rate": float("nan")}, "rate"),
    ],
)
def test_bad_plans_name_the_argument(kwargs: dict[str, object], argument: str) -> None:
    with pytest.raises(ParameterError) as info:
        chirp_plan(RIG, **kwargs)  # type: ignore[arg-type]
    assert info.value.argument == argument


def test_cli_writes_the_command_and_rig_fit_reads_a_log_of_it(tmp_path: Path) -> None:
    command = tmp_path / "command.csv"
    code, out, err = _run(["rig", "chirp", "--out", str(command), "--duration", "6"])
    assert code == 0 and err == f"wrote {command}\n" and "amplitude 60 N, band 5-25 Hz" in out
    lines = command.read_text().splitlines()
    header = [ln for ln in lines if ln.startswith("#")]
    assert any("500 Hz" in h for h in header) and any("duration 6 s" in h for h in header)
    rows = np.loadtxt(command, delimiter=",", comments="#", skiprows=len(header) + 1)
    assert rows.shape == (3000, 2) and np.allclose(np.diff(rows[:, 0]), 1 / 500)
    # play it on the twin as a bench would, log it, and fit the rig to the log
    log = twin_log(RIG, rows[:, 1], load_mass=0.1, seed=5)
    (tmp_path / "log.csv").write_text(log.to_csv())
    rig_file = tmp_path / "rig.toml"
    rig_file.write_text(RIG.to_toml())
    code, out, _ = _run(["rig", "fit", str(tmp_path / "log.csv"), "--rig", str(rig_file), "--json"])
    fit = json.loads(out)["parameters"]
    assert code == 0 and fit["b1"]["value"] == pytest.approx(RIG.damper.b1, rel=0.1)
    assert fit["m"]["value"] == pytest.approx(RIG.actuator_mass, rel=0.05)


def test_cli_owned_files_force_and_bad_input(tmp_path: Path) -> None:
    mine = tmp_path / "mine.csv"
    mine.write_text("my notes\n")
    code, _, err = _run(["rig", "chirp", "--out", str(mine)])
    assert code == 2 and err.startswith("error:") and "--force" in err
    assert mine.read_text() == "my notes\n"
    assert _run(["rig", "chirp", "--out", str(mine), "--force"])[0] == 0
    for argv, says in [
        (["--amplitude", "500"], "--amplitude"),
        (["--band", "5:300"], "--band"),
        (["--band", "x"], "--band"),
        (["--duration", "0"], "--duration"),
    ]:
        code, _, err = _run(["rig", "chirp", *argv])
        assert code == 2 and err.count("\n") == 1 and says in err, err
    code, out, _ = _run(["rig", "chirp", "--json", "--duration", "2"])
    assert json.loads(out)["samples"] == 1000
    code, out, _ = _run(["rig", "chirp", "--duration", "0.02"])
    assert code == 0 and out.count("\n") == 4 + 1 + 10
