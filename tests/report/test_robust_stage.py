"""``analyze``'s robust stage: the box verdict and the robust gain ranges of ``[uncertainty]``."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

from seapass.cli import main
from seapass.model.design_file import Design
from seapass.report.analyze import ANALYSIS_STAGES, analyze, stages_text
from seapass.report.document import SectionStatus
from seapass.report.pipeline import StageContext
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
