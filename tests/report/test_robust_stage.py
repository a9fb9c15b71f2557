"""``analyze``'s robust stage: the box verdict and the robust gain ranges of ``[uncertainty]``."""

from __future__ import annotations

import contextlib
import io
import json
import tomllib
from pathlib import Path
from typing import Any

import pytest

from seapass.cli import main
from seapass.delay.passivity import delayed_passivity
from seapass.model.design_file import Design, parse_design
from seapass.outcome import Outcome
from seapass.report.analyze import ANALYSIS_STAGES, analyze, stages_text
from seapass.report.document import SectionStatus
from seapass.report.pipeline import StageContext
from seapass.report.stages import robust as robust_stage
from seapass.report.stages.robust import BUDGET_QUICK, robust_data, stage_robust
from seapass.robust.box import uncertain_box
from seapass.robust.intervals import robust_passive_intervals

VALUES = {"m": 1.0, "b": 10.0, "k1": 1000.0, "kd": 500.0}
BOXED = Design(name="lpbox", D1="k1", CL="kd", values=VALUES, ranges={"kd": (0.0, 2000.0)},
               uncertainty={"k1": (800.0, 1200.0)})  # fmt: skip


def test_the_stage_is_listed_with_its_budget() -> None:
    assert "robust" in ANALYSIS_STAGES
    assert "robust" in stages_text() and "boxes per certified verdict" in stages_text()


def test_the_ranges_are_robust_passive_intervals_of_the_library() -> None:
    data = robust_data(BOXED)
    sea = BOXED.sea().with_values(kd=None)
    lib = robust_passive_intervals(
        sea, "kd", 0.0, 2000.0, box=uncertain_box(sea, {"k1": (800, 1200)})
    )
    (kd,) = data["ranges"]
    assert kd["intervals"] == [list(iv) for iv in lib.intervals] == [[0.0, 800.0]]
    assert kd["method"] == "exact" and kd["nominal"] == 500.0
    assert data["verdict"]["status"] == "passive"


def test_a_section_with_the_verdict_and_table_or_skipped_without_a_box() -> None:
    sec = stage_robust(BOXED, StageContext(quick=True, budget=BUDGET_QUICK))
    assert sec.status == SectionStatus.OK and "passive" in sec.text
    assert sec.tables[0].rows[0][0] == "kd" and "robust.json" in sec.files
    plain = Design(name="lp", D1="k1", CL="kd", values=VALUES)
    assert stage_robust(plain, StageContext()).status == SectionStatus.SKIPPED


def test_a_worst_plant_is_reported(tmp_path: Path) -> None:
    hot = Design(name="hot", D1="k1", CL="kd", values={**VALUES, "kd": 1100.0},
                 uncertainty={"k1": (800.0, 1200.0)})  # fmt: skip
    sec = stage_robust(hot, StageContext(quick=True))
    assert "not passive" in sec.text and "Worst plant" in sec.text


def test_analyze_runs_the_stage_from_the_file_and_refuses_robust_without_a_box(
    tmp_path: Path,
) -> None:
    report = analyze(BOXED, stages=["robust"], quick=True)
    assert [s.key for s in report.sections] == ["robust", "design-file"]
    assert report.sections[0].status == SectionStatus.OK
    design = tmp_path / "d.toml"
    design.write_text('name = "x"\n[model]\nD1 = "k1"\nCL = "kd"\n[parameters]\nm = 1.0\nb = 10.0\n'
                      'k1 = 1000.0\nkd = 500.0\n[uncertainty]\nk1 = [800.0, 1200.0]\n')  # fmt: skip
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["analyze", str(design), "--out", str(tmp_path / "r"), "--stages", "robust",
                     "--quick", "--no-progress", "--json"])  # fmt: skip
    assert code == 0 and json.loads(out.getvalue())["sections"]
    data = json.loads((tmp_path / "r" / "data" / "robust.json").read_text())
    assert data["box"] == {"k1": [800.0, 1200.0]} and data["verdict"]["status"] == "passive"
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        plain = tmp_path / "plain.toml"
        plain.write_text(design.read_text().split("[uncertainty]")[0])
        code = main(["analyze", str(plain), "--out", str(tmp_path / "r2"), "--robust"])
    assert code == 2 and err.getvalue().startswith("error: ") and "[uncertainty]" in err.getvalue()


def test_with_a_loop_latency_the_box_is_decided_at_the_latency_with_its_delay_margin(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """``[control] delay_time`` with ``[uncertainty]``: the verdict is the certified delayed
    one over the box (not the delay-free one), with the robust delay margin, and a robust
    gain set at the latency for every gain (here with no cells: nothing certified)."""
    from seapass.robust.delayed import robust_delay_margin

    values = {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 20.0, "kd": 500.0, "bd": 25.0}
    box = {"m": (0.9, 1.1)}

    def ours(tau: float) -> Design:
        return Design(name="ours-latency", D1="k1 + b1*s", CA="kd + bd*s", values=values,
                      ranges={"kd": (0.0, 2000.0)}, uncertainty=box, delay_time=tau)  # fmt: skip

    inside = robust_data(ours(0.01), max_cells=0)  # the full budget: 20,000 cells for the margin
    margin = robust_delay_margin(ours(0.01), "delay_time", box=box)
    lo, hi = inside["delay_margin"]["tau_star"]
    assert [lo, hi] == list(margin.tau_star) and 0.01 < lo <= hi < 0.0414  # nominal 41.26 ms
    assert inside["verdict"]["status"] == "passive" and inside["verdict"]["delay"]["tau"] == 0.01
    # every gain of the ranges (bd by its default range), at the latency; no cells: none certified
    assert [r["param"] for r in inside["ranges"]] == ["bd", "kd"]
    for r in inside["ranges"]:
        assert r["delay_time"] == 0.01 and r["exhausted"] is True and r["cells"] == 0
        assert r["intervals"] == [] and r["outer"]  # never more than what is certified
    assert "loop latency" in inside["ranges_note"] and "--rtol" in inside["ranges_note"]
    monkeypatch.setattr(robust_stage, "RANGE_CELLS_QUICK", 0)
    sec = stage_robust(ours(0.045), StageContext(quick=True, budget=BUDGET_QUICK))
    beyond = json.loads(sec.files["robust.json"])  # above every plant's margin
    assert beyond["verdict"]["status"] == "not_passive" and beyond["ranges_max_cells"] == 0
    assert "at the loop latency 0.045 s" in sec.text and "Robust delay margin" in sec.text
    assert [row[0] for row in sec.tables[0].rows] == ["bd", "kd"]
    assert all("cells ran out" in row[-1] and row[3] == "none" for row in sec.tables[0].rows)
    assert sec.status == SectionStatus.STOPPED_AT_BUDGET


# a virtual wall behind the loop latency: robustly passive exactly for kd <= min b / tau = 4500
WALL_TOML = """name = "wall"
[model]
D1 = "k1"
CA = "kd"
[parameters]
m = 1.0
b = 10.0
k1 = 1000.0
kd = 2000.0
[ranges]
kd = [0, 6000]
[control]
delay_time = 0.002
[uncertainty]
b = [9, 11]
"""


@pytest.fixture(scope="module")
def wall_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, Any]]:
    """``analyze WALL --stages robust --quick`` (the quick budget: 1,000 cells per segment)."""
    tmp = tmp_path_factory.mktemp("wall")
    (tmp / "wall.toml").write_text(WALL_TOML)
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["analyze", str(tmp / "wall.toml"), "--out", str(tmp / "r"), "--stages",
                     "robust", "--quick", "--no-progress"])  # fmt: skip
    assert code == 0
    return tmp, json.loads((tmp / "r" / "data" / "robust.json").read_text())


def test_at_a_latency_the_ranges_enclose_the_exact_robust_set(
    wall_run: tuple[Path, dict[str, Any]],
) -> None:
    tmp, data = wall_run
    (kd,) = data["ranges"]
    assert kd["param"] == "kd" and kd["delay_time"] == 0.002 and kd["method"] == "certified"
    assert kd["exhausted"] is False and 0 < kd["cells"] <= robust_stage.RANGE_CELLS_QUICK
    assert data["ranges_rtol"] == robust_stage.RANGE_RTOL == 1e-2
    ((a, b),) = kd["intervals"]
    assert 0 <= a < 100 and 4400 < b <= 4500  # inside [0, min b / tau], within rtol of its end
    assert any(c <= a and b <= d for c, d in kd["outer"])  # the outer set holds the inner one
    assert any(c <= 0 and 4500 <= d < 4501 for c, d in kd["outer"])  # and the exact set
    # independent check: the plain certified delayed verdict at the box's corners
    sea = parse_design(tomllib.loads(WALL_TOML)).delayed_sea()
    for bv in (9.0, 11.0):
        for g in (a, b):
            got = delayed_passivity(sea, values={"b": bv, "kd": g})
            assert got.outcome is Outcome.PASSIVE
    beyond = delayed_passivity(sea, values={"b": 9.0, "kd": 4600.0})  # 4600 > 9 / 0.002
    assert beyond.outcome is Outcome.NOT_PASSIVE
    md = (tmp / "r" / "report.md").read_text()
    assert "coarse relative tolerance 0.01" in md and "--rtol 1e-3" in md


def test_at_a_latency_the_ranges_are_what_bound_gives_at_the_same_rtol(
    wall_run: tuple[Path, dict[str, Any]],
) -> None:
    tmp, data = wall_run
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["bound", "kd", str(tmp / "wall.toml"), "--rtol", "1e-2",
                     "--budget", str(BUDGET_QUICK), "--json"])  # fmt: skip
    assert code == 0
    (kd,) = data["ranges"]
    assert {k: v for k, v in kd.items() if k != "nominal"} == json.loads(out.getvalue())
    assert kd["nominal"] == 2000.0
