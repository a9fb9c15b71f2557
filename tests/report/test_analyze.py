"""``analyze`` always delivers (issue 23 item 2): work budgets in counted steps, stages
stopped at their budget with what they have, the report written as stages finish."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from long_jobs import Recorder, hard_design
from seapass.errors import ParameterError
from seapass.model.design_file import load_design
from seapass.report.analyze import ANALYSIS, ANALYSIS_STAGES, analyze, check_budgets, stages_text
from seapass.report.document import Report, Section, SectionStatus
from seapass.report.output import write_report
from seapass.sampled.passivity import sampled_passivity

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_a_hard_sampled_search_stops_at_its_budget_with_a_complete_report(tmp_path: Path) -> None:
    design = load_design(hard_design(tmp_path))
    out = tmp_path / "report"
    rec = Recorder()
    report = analyze(
        design, stages=["passivity", "sampled"], budgets={"sampled": 40}, progress=rec, out=out
    )
    assert [s.status for s in report.sections[:2]] == ["ok", "stopped_at_budget"]
    assert report.incomplete == "" and rec.balanced
    sec = report.sections[1]
    assert "Stopped at the budget of 40 boxes per bound" in sec.text
    assert sec.findings[0].verdict == "agrees"  # the verdict at the design's kd is decided
    # the written report is the complete one, the stopped stage marked as such
    sections = json.loads((out / "data/sections.json").read_text())
    assert [s["status"] for s in sections] == ["ok", "stopped_at_budget", "ok"]
    assert not (out / "data/incomplete.json").exists()
    md = (out / "report.md").read_text()
    assert "*stopped at budget*" in md and "Incomplete report" not in md
    assert "stopped at their budget: sampled" in md
    # what the budget left is undecided, never passive; what is proven passive is
    bound = json.loads((out / "data/sampled.json").read_text())["bounds"]["kd"]
    assert bound["budget_exhausted"] is True and bound["undecided"]
    (lo, hi), *_ = bound["intervals"]
    assert lo == 0.0 and 500.0 < hi < 5000.0
    for a, b in bound["undecided"]:
        assert not any(x <= a and b <= y for x, y in bound["intervals"])
    sea, loop = design.sea(), design.loop
    assert loop is not None
    for kd in (0.0, hi / 2, hi):  # the point verdict, a separate certified path, agrees
        assert sampled_passivity(sea.with_values(kd=kd), loop=loop).passive
    above = max(b for _a, b in bound["undecided"]) * 1.01
    assert not sampled_passivity(sea.with_values(kd=above), loop=loop).passive


def test_every_stage_with_a_budget_stops_at_it_with_what_it_has() -> None:
    ours = load_design(EXAMPLES / "ours.toml")
    budgets = {"ranges": 1, "response": 5000, "tuning": 2, "zwidth": 3, "rig": 3}
    report = analyze(ours, quick=True, stages=list(budgets), budgets=budgets)
    secs = {s.key: s for s in report.sections}
    assert {k: secs[k].status for k in budgets} == dict.fromkeys(budgets, "stopped_at_budget")
    # ranges: the first parameter only; response: one load mass of 5000 steps
    assert [r[0] for r in secs["ranges"].tables[0].rows] == ["b1"]  # the ranges are sorted
    assert "`bd`, `kd` not analysed" in secs["ranges"].text
    assert [r[0] for r in secs["response"].tables[0].rows] == [1.0]
    assert "m_L = 10, 25 kg not simulated" in secs["response"].text
    # tuning: verified gains after 2 of 12 generations
    tuned = json.loads(secs["tuning"].files["tuning.json"])
    assert tuned["generations"] == 2 and tuned["passive"] is True
    # the Z-width rows keep their unsettled parts undecided; the rig sweeps one gain per mass
    zmap = json.loads(secs["zwidth"].files["zwidth.json"])
    rows = [r for per in zmap["rows"].values() for r in per]
    assert any(r["budget_exhausted"] for r in rows)
    assert all(r["budget_exhausted"] or not r["undecided"] for r in rows)
    rig = json.loads(secs["rig"].files["rig_sweeps.json"])
    assert [len(s["runs"]) for s in rig] == [1, 1]  # 3 runs: one gain per load mass
    assert "stopped at their budget: ranges, response, tuning, zwidth, rig" in report.headline


def test_budgets_are_checked_before_any_work() -> None:
    assert check_budgets({"sampled": 7, "tuning": 1}) == {"sampled": 7, "tuning": 1}
    bad = [
        ({"sampeld": 3}, "unknown stage 'sampeld'"),
        ({"passivity": 3}, "exact decision and has no budget"),
        ({"sampled": 0}, r"budgets\['sampled'\] must be a whole number of boxes"),
        ({"stiffness": 1}, r"in \[2, 100000\]"),
        ({"tuning": 2.5}, "whole number of generations"),
        ({"rig": True}, "whole number"),
    ]
    for budgets, message in bad:
        with pytest.raises(ParameterError, match=message):
            check_budgets(budgets)  # type: ignore[arg-type]
    design = load_design(EXAMPLES / "apd.toml")
    with pytest.raises(ParameterError, match="unknown stage"):
        analyze(design, budgets={"zwdith": 1})


def test_every_stage_is_listed_with_its_budget() -> None:
    text = stages_text()
    for s in ANALYSIS:
        assert f"  {s.key} " in text
        if s.budget is not None:
            assert f"{s.budget.full} {s.budget.unit}" in text
    assert ANALYSIS_STAGES == tuple(s.key for s in ANALYSIS)
    assert "zwidth" in ANALYSIS_STAGES and text.count("budget:") == len(ANALYSIS)


def test_the_report_is_written_when_the_run_starts_and_as_stages_finish(tmp_path: Path) -> None:
    design = load_design(EXAMPLES / "apd.toml")
    out = tmp_path / "r"
    seen: list[tuple[str, ...]] = []

    class Watch(Recorder):
        """Reads the written report each time a stage starts."""

        def start(self, task: str, total: int | None = None) -> None:
            super().start(task, total)
            if task.startswith("["):
                sections = json.loads((out / "data/sections.json").read_text())
                seen.append(tuple(s["status"] for s in sections))
                assert (out / "report.html").is_file()
                assert "Incomplete report" in (out / "report.md").read_text()

    analyze(design, stages=["passivity", "stiffness"], progress=Watch(), out=out)
    # before the first stage: both not run (and the design file); before the second: one done
    assert seen == [("not_run", "not_run", "ok"), ("ok", "not_run", "ok")]
    assert "Incomplete report" not in (out / "report.md").read_text()


def test_an_interrupted_run_leaves_a_valid_partial_report(tmp_path: Path) -> None:
    design = load_design(EXAMPLES / "apd.toml")
    out = tmp_path / "r"

    class StopInSecondStage(Recorder):
        def start(self, task: str, total: int | None = None) -> None:
            super().start(task, total)
            if task.startswith("[2/"):
                raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        analyze(design, stages=["passivity", "stiffness"], progress=StopInSecondStage(), out=out)
    sections = json.loads((out / "data/sections.json").read_text())
    assert [s["status"] for s in sections] == ["ok", "not_run", "ok"]
    assert json.loads((out / "data/passivity.json").read_text())["passive"] is True
    why = json.loads((out / "data/incomplete.json").read_text())
    assert why["complete"] is False and "interrupted: 1 of 2 analyses finished" in why["why"]
    md = (out / "report.md").read_text()
    assert "> **Incomplete report:** interrupted" in md and "*not run*" in md
    assert 'id="incomplete"' in (out / "report.html").read_text()
    # the library is usable at once: the same call completes and replaces the partial report
    analyze(design, stages=["passivity", "stiffness"], out=out)
    assert not (out / "data/incomplete.json").exists()


def test_unchanged_files_are_linked_not_written_again(tmp_path: Path) -> None:
    out = tmp_path / "r"
    first = Report("R", "i", (Section("a", "A", files={"a.json": "{}"}),), incomplete="running")
    write_report(first, out)
    before = (out / "data/a.json").stat().st_ino
    done = Report("R", "i", (*first.sections, Section("b", "B", status=SectionStatus.NOT_RUN)))
    write_report(done, out)
    assert (out / "data/a.json").stat().st_ino == before
    assert not (out / "data/incomplete.json").exists()
    assert "not run" in (out / "report.html").read_text()


def test_the_docs_list_every_stage_with_its_budget() -> None:
    text = (EXAMPLES.parent / "docs" / "index.md").read_text(encoding="utf-8")
    table = text[text.index("`seapass analyze` stages") :]
    for s in ANALYSIS:
        row = next(line for line in table.splitlines() if line.startswith(f"| `{s.key}` |"))
        assert (s.budget.unit.split(" (")[0] if s.budget else "none") in row, row
