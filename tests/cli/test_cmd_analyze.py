"""``seapass analyze`` end to end: budgets, progress lines on a non-terminal, interrupts."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from long_jobs import Recorder, hard_design
from seapass.cli import main
from seapass.cli.common import Terminated
from seapass.report.analyze import ANALYSIS


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


def test_every_stage_on_a_hard_design_delivers_a_complete_report(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """All stages of a design whose certified sampled search is hard (kd at 4 kHz with a
    delay: 500 boxes do not settle it): the budgets stop it, the report is complete and
    names the stopped stages."""
    from seapass.model.design_file import load_design
    from seapass.sampled.passivity import sampled_passivity

    path, out = hard_design(tmp_path), tmp_path / "r"
    argv = ["analyze", str(path), "--out", str(out), "--quick", "--jobs", "1",
            "--budget", "sampled=40", "--budget", "tuning=2", "--json"]  # fmt: skip
    assert main(argv) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    status = {s["key"]: s["status"] for s in summary["sections"]}
    assert list(status) == [*(s.key for s in ANALYSIS), "design-file"]  # every stage, in order
    stopped = {"tuning", "sampled"}
    # one gain: no witness needed (passive), no Z-width map (two gains), no [rig],
    # no [uncertainty] (the robust stage)
    skipped = {"witness", "zwidth", "rig", "robust"}
    assert {k for k, v in status.items() if v == "stopped_at_budget"} == stopped
    assert {k for k, v in status.items() if v == "skipped"} == skipped
    assert set(status.values()) == {"ok", "stopped_at_budget", "skipped"}
    assert summary["failed"] == [] and not (out / "data/incomplete.json").exists()
    assert summary["verdict"] == (
        "passive in continuous time; passive under sampled-data control at 4000 Hz"
    )
    # one progress line per stage on a non-terminal, and the stopped stages named at the end
    stage_lines = [line for line in captured.err.splitlines() if line.startswith("  [")]
    assert len(stage_lines) == len(ANALYSIS) and stage_lines[-1].startswith(
        f"  [{len(ANALYSIS)}/{len(ANALYSIS)}] rig"
    )
    assert captured.err.splitlines()[-1].endswith("--budget STAGE=N): tuning, sampled")
    md = (out / "report.md").read_text()
    assert "Incomplete report" not in md and "stopped at their budget: tuning, sampled" in md
    section = md[md.index("## Sampled-data passivity") :]
    assert section.split("\n\n")[1] == "*stopped at budget*"
    # the unsettled part of kd is undecided, never passive; a separate point decision
    # confirms the proven interval's ends
    bound = json.loads((out / "data/sampled.json").read_text())["bounds"]["kd"]
    assert bound["budget_exhausted"] is True and bound["undecided"]
    design = load_design(path)
    assert design.loop is not None
    for lo, hi in bound["intervals"]:
        for kd in (lo, hi):
            assert sampled_passivity(design.sea().with_values(kd=kd), loop=design.loop).passive


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


class _StopAtStage(Recorder):
    """The command's progress: raises ``interrupt`` when stage ``at`` (e.g. "[2/") starts."""

    def __init__(self, at: str, interrupt: BaseException) -> None:
        super().__init__()
        self.at, self.interrupt = at, interrupt

    def start(self, task: str, total: int | None = None) -> None:
        if task.startswith(self.at):
            raise self.interrupt  # a start that raises opens nothing
        super().start(task, total)

    def __enter__(self) -> _StopAtStage:
        return self

    def __exit__(self, *exc: object) -> None:
        pass


@pytest.mark.parametrize(
    ("interrupt", "code", "jobs", "finished"),
    [
        (KeyboardInterrupt(), 130, "1", ["ok", "not_run", "ok"]),  # Ctrl-C in the second stage
        (Terminated(), 143, "1", ["ok", "not_run", "ok"]),  # what SIGTERM raises
        # two workers: the costliest stage (sampled) is announced first, before any finished
        (KeyboardInterrupt(), 130, "2", ["not_run", "not_run", "ok"]),
    ],
)
def test_an_interrupt_leaves_a_valid_partial_report(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    interrupt: BaseException,
    code: int,
    jobs: str,
    finished: list[str],
) -> None:
    """Ctrl-C injected through the progress (no real signal): exit 130 and the report of
    the finished stages, marked incomplete, with no leftovers."""
    import seapass.cli.progress

    stopper = _StopAtStage("[2/" if jobs == "1" else "[", interrupt)
    monkeypatch.setattr(seapass.cli.progress, "choose_progress", lambda enabled: stopper)
    out = tmp_path / "r"
    argv = ["analyze", str(hard_design(tmp_path)), "--out", str(out),
            "--stages", "passivity,sampled", "--budget", "sampled=1000000", "--jobs", jobs]  # fmt: skip
    assert main(argv) == code
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err and captured.out == ""
    assert captured.err.splitlines()[-1] == (
        f"error: interrupted; the report of the finished stages is in {out} (marked incomplete)"
    )
    assert stopper.balanced  # every task closed however the run ended
    sections = json.loads((out / "data/sections.json").read_text())
    assert [s["status"] for s in sections] == finished
    assert json.loads((out / "data/incomplete.json").read_text())["complete"] is False
    md = (out / "report.md").read_text()
    done = finished.count("ok") - 1  # the design file's section is always there
    assert f"> **Incomplete report:** interrupted: {done} of 2 analyses finished" in md
    assert "## Sampled-data passivity\n\n*not run*" in md
    if done:
        assert json.loads((out / "data/passivity.json").read_text())["passive"] is True
    html = (out / "report.html").read_text()
    assert 'id="incomplete"' in html and html.rstrip().endswith("</html>")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hard.toml", "r"]  # no leftovers


def test_sigterm_stops_like_ctrl_c_without_sending_a_signal() -> None:
    """``main`` turns SIGTERM into `Terminated` (a KeyboardInterrupt) and restores the
    handler it found; the handler is called directly here, no signal is sent."""
    import signal

    import seapass.cli as cli

    before = signal.getsignal(signal.SIGTERM)
    seen: list[object] = []

    def during(argv: object) -> int:
        seen.append(signal.getsignal(signal.SIGTERM))
        return 0

    mp = pytest.MonkeyPatch()
    with mp.context() as m:
        m.setattr(cli, "_main", during)
        assert cli.main([]) == 0
    assert seen == [cli._terminate] and signal.getsignal(signal.SIGTERM) == before
    with pytest.raises(Terminated):
        cli._terminate(signal.SIGTERM, None)
    assert isinstance(Terminated(), KeyboardInterrupt)
