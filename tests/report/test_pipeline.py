"""The stage pipeline reports to one Progress, hands each section over as it finishes, and
keeps what finished when it is interrupted (issues 21 item 6, 23 item 2)."""

from __future__ import annotations

from typing import Any

import pytest

from long_jobs import Recorder
from seapass.errors import SeapassDeprecationWarning
from seapass.progress import task
from seapass.report.document import Section, SectionStatus
from seapass.report.pipeline import Stage, StageContext, run_stages


def _ok(key: str) -> Any:
    def run(context: StageContext) -> Section:
        return Section(key, key.upper(), text=f"budget {context.budget}, quick {context.quick}")

    return run


def _with_parts(context: StageContext) -> Section:
    with task(context.progress, "two parts", 2):
        context.progress.advance(1, note="first")
        context.progress.advance(1, note="second")
    return Section("g", "G", status=SectionStatus.STOPPED_AT_BUDGET, text="half of it")


def _interrupt(context: StageContext) -> Section:
    raise KeyboardInterrupt


def test_stages_nest_inside_the_run_and_get_their_budget() -> None:
    rec = Recorder()
    got: list[tuple[int, str]] = []
    stages = [Stage("g", "G", _with_parts), Stage("p", "P", _ok("p"), budget=7)]
    secs = run_stages(
        stages, quick=True, progress=rec, on_section=lambda i, s: got.append((i, s.key)),
        title="test",
    )  # fmt: skip
    assert [s.status for s in secs] == ["stopped_at_budget", "ok"]
    assert secs[1].text == "budget 7, quick True"
    assert got == [(0, "g"), (1, "p")]
    assert rec.calls == [
        ("start", "test: 2 stages", 2),
        ("start", "[1/2] g: G", None),
        ("start", "two parts", 2),
        ("advance", 1, "first"),
        ("advance", 1, "second"),
        ("close",),
        ("close",),
        ("advance", 1, "g stopped at budget"),
        ("start", "[2/2] p: P", None),
        ("close",),
        ("advance", 1, "p ok"),
        ("close",),
    ]


def test_parallel_stages_announce_each_stage_once() -> None:
    rec = Recorder()
    got: list[str] = []
    stages = [Stage("g", "G", _with_parts), Stage("p", "P", _ok("p"), budget=3)]
    secs = run_stages(
        stages, progress=rec, jobs=2, on_section=lambda i, s: got.append(s.key), title="t"
    )
    assert [s.key for s in secs] == ["g", "p"] and secs[1].text == "budget 3, quick False"
    assert sorted(got) == ["g", "p"] and rec.balanced
    starts = [c[1] for c in rec.calls if c[0] == "start"]
    assert starts[0] == "t: 2 stages on 2 processes"
    assert sorted(starts[1:]) == ["[1/2] g: G", "[2/2] p: P"]  # the stages' own parts: notes
    assert sum(c[1] for c in rec.calls if c[0] == "advance") == 2
    assert any(c[0] == "advance" and c[2] == "g: second" for c in rec.calls)


def test_an_interrupt_keeps_the_finished_sections() -> None:
    """(With workers, which ignore SIGINT, the interrupt reaches the parent: tested end to
    end with a signal in tests/report/test_analyze_budgets.py.)"""
    rec = Recorder()
    got: list[str] = []
    stages = [Stage("p", "P", _ok("p")), Stage("x", "X", _interrupt), Stage("q", "Q", _ok("q"))]
    with pytest.raises(KeyboardInterrupt):
        run_stages(stages, progress=rec, on_section=lambda i, s: got.append(s.key))
    assert got == ["p"] and rec.balanced


def test_old_progress_spelling_of_the_pipeline() -> None:
    with pytest.warns(SeapassDeprecationWarning, match=r"run_stages\(progress=False\)"):
        secs = run_stages([Stage("g", "G", _with_parts)], progress=False)
    assert [s.key for s in secs] == ["g"]
    with pytest.raises(TypeError):
        run_stages([], on_progress=print)  # type: ignore[call-arg]  # removed: one protocol
