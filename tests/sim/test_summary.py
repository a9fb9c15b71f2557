"""``seapass simulate`` is one library call: simulation_summary, and read_trajectory for files."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest

from seapass.cli import main
from seapass.errors import FileFormatError
from seapass.files import limits
from seapass.model.sea import SEA, Impedance
from seapass.sim import Trajectory, read_trajectory, simulate, simulation_summary, tracking_metrics

OURS = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1000, b1=20, kd=1000, bd=25))
ARGS = ["--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "m=1", "--set", "b=10",
        "--set", "k1=1000", "--set", "b1=20", "--set", "kd=1000", "--set", "bd=25"]  # fmt: skip


def test_the_cli_prints_the_summary_dict() -> None:
    summary = simulation_summary(OURS, load_mass=10, horizon=2)
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        assert main(["simulate", *ARGS, "--load-mass", "10", "--horizon", "2", "--json"]) == 0
    assert json.loads(out.getvalue()) == json.loads(json.dumps(summary.to_dict()))


def test_summary_agrees_with_the_parts() -> None:
    s = simulation_summary(OURS, load_mass=10, horizon=2, dt=2e-3, tolerance=0.05)
    res = simulate(OURS, load_mass=10, horizon=2, dt=2e-3)
    met = tracking_metrics(res, tolerance=0.05)
    assert s.metrics == met and np.array_equal(s.result.x_L, res.x_L)
    assert s.passive is True and s.passive_error is None and s.dt == pytest.approx(2e-3)
    d = s.to_dict()
    assert "passive_error" not in d and d["scenario"] == "Step" and d["band"] == met.band
    assert "SimulationSummary(" in repr(s) and "<" in s._repr_html_()


def test_an_undecidable_passivity_is_data(monkeypatch: pytest.MonkeyPatch) -> None:
    from seapass.errors import SymbolicLimitError
    from seapass.sim import summary

    def too_big(sea: SEA | Impedance) -> None:
        raise SymbolicLimitError("too big to decide")

    monkeypatch.setattr(summary, "is_passive", too_big)
    s = simulation_summary(OURS, load_mass=10, horizon=1)
    assert s.passive is None and s.to_dict()["passive_error"] == "too big to decide"


def test_read_trajectory(tmp_path: Path) -> None:
    f = tmp_path / "ref.csv"
    f.write_text("time,ref\n# a comment\n0;0\n\n0.5\t0.1\n1.0,0.2\n")
    t = read_trajectory(f, interpolation="zoh", apply_to="load")
    assert t == Trajectory((0.0, 0.5, 1.0), (0.0, 0.1, 0.2), interpolation="zoh", apply_to="load")
    for text, says in (
        ("0,0\n1,x\n", r"ref\.csv:2: expected two numbers"),
        ("0,0\n1,nan\n", r"ref\.csv:2: expected two finite numbers"),
        ("0,0,1\n", r"ref\.csv:1: expected two finite numbers"),
        ("# nothing\n", "no samples found"),
    ):
        f.write_text(text)
        with pytest.raises(FileFormatError, match=says):
            read_trajectory(f)


def test_read_trajectory_is_bounded(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from seapass.sim import scenarios

    monkeypatch.setattr(scenarios, "MAX_TRAJECTORY_SAMPLES", 3)
    f = tmp_path / "long.csv"
    f.write_text("".join(f"{i},0\n" for i in range(5)))
    with pytest.raises(FileFormatError, match="more than 3 samples"):
        read_trajectory(f)
    assert limits.MAX_TRAJECTORY_SAMPLES == 1_000_000
    with pytest.raises((FileFormatError, OSError), match="trajectory file"):
        read_trajectory(tmp_path)  # a directory: refused before reading
