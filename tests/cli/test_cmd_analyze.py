"""``seapass analyze`` end to end: budgets, progress lines on a non-terminal, interrupts."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from long_jobs import hard_design
from seapass.cli import main
from seapass.report.analyze import ANALYSIS

SEAPASS = str(Path(sys.executable).with_name("seapass"))


def test_analyze_help_lists_every_stage_and_its_budget(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["analyze", "--help"])
    assert exit_.value.code == 0
    text = capsys.readouterr().out
    assert "--budget STAGE=N" in text
    for s in ANALYSIS:
        assert f"\n  {s.key} " in text, s.key
        if s.budget is not None:
            assert f"{s.budget.full} {s.budget.unit}" in text
    assert "zwidth" in text and "no budget" in text


def test_hard_design_stops_at_its_budget_with_one_line_per_stage(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "r"
    argv = ["analyze", str(hard_design(tmp_path)), "--out", str(out), "--jobs", "1",
            "--stages", "passivity,sampled", "--budget", "sampled=40", "--json"]  # fmt: skip
    assert main(argv) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert [s["status"] for s in summary["sections"]] == ["ok", "stopped_at_budget", "ok"]
    assert (
        summary["verdict"]
        == "passive in continuous time; passive under sampled-data control at 4000 Hz"
    )
    assert "report.html" in summary["files"] and summary["failed"] == []
    # stderr is not a terminal here: one progress line per stage, and the stage log
    lines = captured.err.splitlines()
    assert lines[:2] == ["analyze hard: 2 stages", "  [1/2] passivity: Passivity verdict"]
    assert lines[2].startswith("passivity: ok in ")
    assert lines[3] == "  [2/2] sampled: Sampled-data passivity"
    assert lines[4].startswith("sampled: stopped at budget in ")
    assert lines[-1].startswith("  stopped at budget (what it has is in the report")
    assert not any("%" in line for line in lines)  # no per-step chatter in a log
    assert (out / "report.html").is_file() and (out / "report.md").is_file()
    capsys.readouterr()
    assert main([*argv[:-1], "--no-progress"]) == 0
    assert not any(line.startswith("  [") for line in capsys.readouterr().err.splitlines())


@pytest.mark.parametrize(
    ("budget", "message"),
    [
        ("sampled=0", "--budget sampled must be a whole number of boxes per certified bound"),
        ("sampeld=3", "--budget: unknown stage 'sampeld'"),
        ("passivity=3", "exact decision and has no budget"),
        ("sampled=lots", "--budget sampled=lots: N must be a whole number"),
        ("sampled", "--budget 'sampled': expected STAGE=N"),
    ],
)
def test_bad_budgets_are_one_error_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], budget: str, message: str
) -> None:
    out = tmp_path / "r"
    rc = main(["analyze", str(hard_design(tmp_path)), "--out", str(out), "--budget", budget])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and err.startswith("error: ") and message in err, err
    assert not out.exists()  # refused before any work


def _wait_for(path: Path, proc: subprocess.Popen[str]) -> None:
    """Poll until ``path`` exists (the process must still be running)."""
    while not path.exists():
        if proc.poll() is not None:
            raise AssertionError(f"exited with {proc.returncode} first: {proc.communicate()}")
        time.sleep(0.05)


@pytest.mark.parametrize(
    ("sig", "code", "jobs"), [(signal.SIGINT, 130, "1"), (signal.SIGTERM, 143, "2")]
)
def test_an_interrupt_leaves_a_valid_partial_report(
    tmp_path: Path, sig: signal.Signals, code: int, jobs: str
) -> None:
    out = tmp_path / "r"
    cmd = [SEAPASS, "analyze", str(hard_design(tmp_path)),
           "--out", str(out), "--stages", "passivity,sampled", "--budget", "sampled=1000000",
           "--jobs", jobs]  # fmt: skip
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        _wait_for(out / "data" / "passivity.json", proc)  # the first stage is written
        proc.send_signal(sig)
        stdout, stderr = proc.communicate(timeout=600)  # a hang guard only: it exits at once
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == code, stderr
    assert "Traceback" not in stderr
    assert f"interrupted; the report of the finished stages is in {out}" in stderr
    assert stdout == ""
    sections = json.loads((out / "data/sections.json").read_text())
    assert [s["status"] for s in sections] == ["ok", "not_run", "ok"]
    assert json.loads((out / "data/passivity.json").read_text())["passive"] is True
    assert json.loads((out / "data/incomplete.json").read_text())["complete"] is False
    md = (out / "report.md").read_text()
    assert "> **Incomplete report:** interrupted: 1 of 2 analyses finished" in md
    assert "## Sampled-data passivity\n\n*not run*" in md
    html = (out / "report.html").read_text()
    assert 'id="incomplete"' in html and html.rstrip().endswith("</html>")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hard.toml", "r"]  # no leftovers
