"""The command line chooses the progress: a live bar on a terminal, lines otherwise, none."""

from __future__ import annotations

import io
import json
import sys
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.cli.progress import RichBar, choose_progress
from seapass.progress import NoProgress, Progress, TextProgress, task


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_the_cli_picks_by_the_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    with choose_progress(True) as lines:
        assert isinstance(lines, TextProgress)
        lines.start("a job")
        lines.close()
    assert sys.stderr.getvalue() == "a job\n"
    with choose_progress(False) as none:
        assert isinstance(none, NoProgress)
    monkeypatch.setattr(sys, "stderr", _Terminal())
    with choose_progress(True) as bar:
        assert isinstance(bar, RichBar) and isinstance(bar, Progress)


def test_the_live_bar_shows_nested_tasks_and_comes_down(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(sys, "stderr", _Terminal())
    bar = RichBar()
    with bar:
        with task(bar, "analyze x: 2 stages", 2):
            with task(bar, "[1/2] sampled"):
                with task(bar, "sampled bound of kd", 100):
                    bar.advance(40, note="40 % of the range decided")
                    rows = bar._bar.tasks
                    assert [t.description for t in rows] == [
                        "analyze x: 2 stages",
                        "  [1/2] sampled",
                        "    sampled bound of kd: 40 % of the range decided",
                    ]
                    assert rows[-1].completed == 40 and rows[-1].total == 100
            bar.advance()
        assert bar._bar is None  # the last task closed: the display is down
        with pytest.raises(KeyboardInterrupt), task(bar, "interrupted"):
            raise KeyboardInterrupt
        assert bar._bar is None
    bar.advance()  # nothing open: nothing happens
    bar.close()


def test_sampled_bound_budget_and_progress_on_the_command_line(
    capsys: pytest.CaptureFixture[str],
) -> None:
    model = ["--period", "0.00025", "--delay", "1", "--D1", "k1 + b1*s", "--CL", "kd",
             "--set", "m=1", "--set", "b=10", "--set", "k1=1000", "--set", "b1=30",
             "--range", "kd=0:5000"]  # fmt: skip
    assert main(["sampled", "bound", "kd", *model, "--max-boxes", "30", "--json"]) == 0
    captured = capsys.readouterr()
    res = json.loads(captured.out)
    assert res["budget_exhausted"] is True and res["undecided"] and res["intervals"][0][0] == 0.0
    assert captured.err == "sampled bound of kd in [0, 5000] (at most 30 boxes)\n"
    assert main(["sampled", "bound", "kd", *model, "--max-boxes", "30", "--no-progress"]) == 0
    captured = capsys.readouterr()
    assert "stopped at the budget of boxes" in captured.out and captured.err == ""
    assert main(["sampled", "bound", "kd", *model, "--max-boxes", "0"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--max-boxes must be a positive whole number" in err


def test_tune_writes_one_line_on_a_non_terminal(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["tune", "APD", "--quick", "--maxiter", "2", "--popsize", "2", "--json"]
    assert main(argv) in (0, 1)
    assert capsys.readouterr().err.splitlines()[0] == "tuning APD: 2 generations"
    assert main([*argv, "--no-progress"]) in (0, 1)
    assert "tuning" not in capsys.readouterr().err


_WALL = ["--D1", "k1 + b1*s", "--CL", "kd", "--set", "m=1", "--set", "b=10", "--set", "k1=1000"]


@pytest.mark.parametrize(
    ("argv", "first"),
    [
        (["sweep", *_WALL, "--set", "b1=20", "--grid", "kd=0:1000:500", "--no-metrics"],
         "sweep: 3 designs in 1 chunks"),
        (["rig", "sweep", "--design", "LP", "--load-mass", "10", "--kd-max", "100",
          "--kd-step", "100"], "kd sweeps on the twin of paper-rig"),
        (["sampled", "region", "kd", "b1", "--period", "0.002", *_WALL, "--range", "0:2000",
          "--range2", "0:40", "--rows", "2"], "Z-width map of kd against b1"),
        (["export", "c", "examples/ours.toml", "--set-gains", "--tunable", "kd"],
         "certifying 1 gain(s) at the sampled rate"),
    ],
)  # fmt: skip
def test_long_commands_write_lines_on_a_non_terminal_and_none_when_asked(
    argv: list[str], first: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """stderr is not a terminal under pytest: one line per task (no bar, no per-step
    chatter); ``--no-progress``: none."""
    out = ["--out", str(tmp_path / ("o.csv" if argv[0] == "sweep" else "o"))]
    assert main([*argv, *out]) == 0
    err = capsys.readouterr().err.splitlines()
    assert any(line.startswith(first) for line in err), err
    assert not any("\r" in line or "%" in line for line in err)
    assert main([*argv, "--out", str(tmp_path / ("p.csv" if argv[0] == "sweep" else "p")),
                 "--no-progress"]) == 0  # fmt: skip
    assert not any(line.lstrip().startswith(first) for line in capsys.readouterr().err.splitlines())
