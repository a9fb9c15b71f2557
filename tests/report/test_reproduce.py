"""``seapass reproduce``: stages, outputs, determinism, atomic replacement."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from long_jobs import Recorder
from seapass.cli import main
from seapass.errors import MissingExtraError, OutputPathError
from seapass.plot.style import figure_bytes
from seapass.progress import task
from seapass.report.document import FigureData, Finding, Report, Section, Table
from seapass.report.output import write_report
from seapass.report.pipeline import Stage, StageContext, run_stages, select_stages
from seapass.report.reproduce import STAGES, reproduce, stage_keys


@pytest.fixture(scope="module")
def core(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("rep") / "out"
    rc = main(["reproduce", "--out", str(out), "--quick", "--stages", "core", "--no-progress"])
    assert rc == 0
    return out


def _csv(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as fh:
        return list(csv.DictReader(fh))


def test_core_outputs_exist(core: Path) -> None:
    for rel in ("report.html", "report.md", "data/table1.csv", "data/table2.csv",
                "data/proposed.csv", "data/tables.json", "data/passive_kd.csv",
                "data/passive_map_lp_b1.csv", "data/stiffness_response.csv",
                "figures/stiffness_table1.png", "figures/passive_map_lp_b1.png"):  # fmt: skip
        assert (core / rel).is_file(), rel
    assert not [p for p in core.parent.iterdir() if p.name.startswith(".out.")]
    md = (core / "report.md").read_text()
    html = (core / "report.html").read_text()
    for fig in (core / "figures").glob("*.png"):
        assert f"figures/{fig.name}" in md
        # every figure also as SVG, linked from both reports
        assert fig.with_suffix(".svg").read_bytes().lstrip().startswith(b"<?xml")
        assert f'href="figures/{fig.stem}.svg"' in html and f"(figures/{fig.stem}.svg)" in md
    for data in (core / "data").iterdir():
        assert f'href="data/{data.name}"' in html, data.name


def test_summary_classifies_every_difference(core: Path) -> None:
    html = (core / "report.html").read_text()
    summary = html.index('<section id="summary">')
    assert summary < html.index("<table")
    block = html[summary : html.index("</section>", summary)]
    for label in ("Typos in the paper", "only conservative", "Unsafe bounds"):
        assert label in block
    findings = json.loads((core / "data/findings.json").read_text())
    kinds = {f["kind"] for f in findings if f["verdict"] == "differs"}
    assert kinds == {"paper typo", "conservative bound", "unsafe bound"}
    assert all(f["kind"] is None for f in findings if f["verdict"] != "differs")
    # the rows' findings: spring-spring has a typo and an unsafe bound, pure spring agrees
    rows = {(f["claim"].split(":")[0], f["kind"]) for f in findings if f["section"] == "tables"}
    assert ("Disjointed spring-spring (mech/spring-spring)", "paper typo") in rows
    assert ("Disjointed spring-spring (mech/spring-spring)", "unsafe bound") in rows
    assert ("Pure spring (mech/pure-spring)", None) in rows
    # formulas are MathML in the page and plain text in data/
    assert html.count("<math") > 100
    assert "`" not in (core / "data/table1.csv").read_text()


def test_tables_flag_the_papers_discrepancies(core: Path) -> None:
    rows = {r["row"]: r for r in _csv(core / "data/table1.csv")}
    assert rows["mech/pure-spring"]["paper bound is"] == "exact"
    assert rows["mech/spring-spring"]["TF agrees"] == "False"
    assert rows["mech/spring-spring"]["paper bound is"] == "unsafe"
    assert rows["mech/parallel-spring-damper"]["paper bound is"] == "sufficient only"
    html = (core / "report.html").read_text()
    assert 'class="flag"' in html
    doc = json.loads((core / "data/tables.json").read_text())
    assert len(doc) == 11


def test_regions_against_the_paper(core: Path) -> None:
    rows = {r["row"]: r for r in _csv(core / "data/passive_kd.csv")}
    # load-side P with a damped spring at m=1, b=10, k1=1000, b1=20: exact kd <= 849.19 N/m
    assert "849.19" in rows["mech/parallel-spring-damper"]["exact passive kd"]
    assert rows["mech/parallel-spring-damper"]["paper's bound"].startswith("conservative")
    assert rows["mech/spring-spring"]["paper's bound"].startswith("UNSAFE")
    assert rows["mech/pure-spring"]["paper's bound"] == "matches"
    assert "search limit" in rows["proposed"]["exact passive kd"]
    assert rows["ctrl/load-PD"]["exact passive kd"] == "none"
    prop = json.loads((core / "data/passive_proposed.json").read_text())
    assert prop["intervals"] == [[0.0, 1e6]]
    # the unsafe bound, made physical: a passive environment destabilizes an admitted gain
    (unsafe,) = _csv(core / "data/unsafe_bounds.csv")
    assert unsafe["row"] == "mech/spring-spring"
    assert 1000.0 < float(unsafe["kd [N/m]"]) <= 2000.0
    assert float(unsafe["growth rate [1/s]"]) > 0
    pmap = _csv(core / "data/passive_map_lp_b1.csv")
    # the paper's sufficient bound never exceeds the exact edge
    assert all(float(r["kd_hi_N_per_m"]) >= float(r["paper_bound_N_per_m"]) for r in pmap)


def test_figures_are_byte_stable() -> None:
    import matplotlib.pyplot as plt

    def draw() -> bytes:
        fig, ax = plt.subplots()
        ax.plot([0, 1], [1, 0], label="x")
        ax.legend()
        return figure_bytes(fig)

    assert draw() == draw()


def test_same_outputs_every_run(core: Path, tmp_path: Path) -> None:
    out = tmp_path / "again"
    assert main(["reproduce", "--out", str(out), "--quick", "--stages", "regions",
                 "--no-progress"]) == 0  # fmt: skip
    for rel in ("data/passive_kd.csv", "data/passive_map_lp_b1.csv", "data/unsafe_bounds.csv",
                "figures/passive_kd.png", "figures/passive_map_lp_b1.png",
                "figures/witness_mech_spring-spring.png"):  # fmt: skip
        assert (out / rel).read_bytes() == (core / rel).read_bytes(), rel


def _tiny(key: str = "a") -> Section:
    fig = __import__("matplotlib.pyplot").pyplot.figure(figsize=(1, 1))
    return Section(
        key=key, title=key.upper(), text="hello `x` **y**\n\n- one\n- two",
        tables=(Table("t_" + key, "T", ("a", "b"), ((1.5, True), (None, False))),),
        figures=(FigureData.of("f_" + key, "cap", fig),),
        findings=(Finding("c", "agrees", "d"),),
        files={"x.json": "{}\n"},
    )  # fmt: skip


def test_interrupt_leaves_previous_output(tmp_path: Path) -> None:
    out = tmp_path / "out"
    write_report(Report("R", "intro", (_tiny(),)), out)
    before = {p.name: p.read_bytes() for p in out.rglob("*") if p.is_file()}

    def boom(quick: bool) -> Section:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_stages([Stage("a", "A", lambda q: _tiny()), Stage("b", "B", boom)])
    after = {p.name: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    assert after == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_write_replaces_own_output_only(tmp_path: Path) -> None:
    out = tmp_path / "out"
    write_report(Report("R", "i", (_tiny("a"),)), out)
    write_report(Report("R", "i", (_tiny("b"),)), out)
    assert (out / "data/t_b.csv").exists() and not (out / "data/t_a.csv").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    foreign = tmp_path / "mine"
    foreign.mkdir()
    (foreign / "thesis.tex").write_text("keep me")
    with pytest.raises(OutputPathError, match="did not write"):
        write_report(Report("R", "i", (_tiny(),)), foreign)
    assert (foreign / "thesis.tex").read_text() == "keep me"
    (tmp_path / "file").write_text("x")
    with pytest.raises(OutputPathError, match="not a directory"):
        write_report(Report("R", "i", (_tiny(),)), tmp_path / "file")


def test_failed_and_skipped_stages_are_reported() -> None:
    def bad(quick: bool) -> Section:
        raise ValueError("broken input")

    def broken_import(quick: bool) -> Section:
        raise ImportError("No module named 'seapass.nothing'", name="seapass.nothing")

    def no_mujoco(quick: bool) -> Section:
        raise MissingExtraError("MuJoCo is not installed; pip install 'seapass[mujoco]'")

    secs = run_stages(
        [Stage("a", "A", bad), Stage("b", "B", broken_import), Stage("m", "M", no_mujoco),
         Stage("c", "C", lambda q: _tiny("c"))],
    )  # fmt: skip
    # a broken import is a bug and fails loudly; only a named optional extra is skipped
    assert [s.status for s in secs] == ["failed", "failed", "skipped", "ok"]
    assert "broken input" in secs[0].text and "seapass.nothing" in secs[1].text
    assert "seapass[mujoco]" in secs[2].text
    report = Report("R", "i", secs)
    assert report.failed == ["a", "b"]


def test_stage_selection(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    assert stage_keys()[:3] == ("tables", "stiffness", "regions")
    assert [s.key for s in select_stages(["core"], STAGES)] == ["tables", "stiffness", "regions"]
    assert [s.key for s in select_stages(["regions", "tables"], STAGES)] == ["tables", "regions"]
    assert main(["reproduce", "--out", str(tmp_path / "x"), "--stages", "tabels"]) == 2
    err = capsys.readouterr().err
    assert "unknown stage 'tabels'" in err and err.count("\n") == 1
    assert not (tmp_path / "x").exists()


def test_report_text_rendering(tmp_path: Path) -> None:
    report = reproduce(stages=[])
    assert report.sections == ()
    out = tmp_path / "o"
    write_report(Report("R & D", "intro <b>", (_tiny(),)), out)
    html = (out / "report.html").read_text()
    assert "R &amp; D" in html and "intro &lt;b&gt;" in html
    assert "<code>x</code>" in html and "<strong>y</strong>" in html and "<li>one</li>" in html
    assert (out / "data/t_a.csv").read_text() == "a,b\n1.5,True\n,False\n"
    md = (out / "report.md").read_text()
    assert "| 1.5 | yes |" in md and "| – | **NO** |" in md


def _stage_ok(quick: bool) -> Section:
    return _tiny("p")


def _stage_bad(quick: bool) -> Section:
    raise RuntimeError("stage exploded")


def _stage_with_progress(context: StageContext) -> Section:
    with task(context.progress, "halves", 2):
        context.progress.advance(1, note="first half")
        context.progress.advance(1, note="done")
    return _tiny("g")


@pytest.mark.parametrize("jobs", [1, 2])
def test_progress_within_stages_reaches_the_caller(jobs: int) -> None:
    rec = Recorder()
    stages = [Stage("g", "G", _stage_with_progress), Stage("p", "P", _stage_ok)]
    run_stages(stages, jobs=jobs, progress=rec)
    notes = [c[2] for c in rec.calls if c[0] == "advance" and c[1] == (1 if jobs == 1 else 0)]
    # in this process the stage's own task nests; from a worker its notes name the stage
    want = ["first half", "done"] if jobs == 1 else ["g: first half", "g: done"]
    assert [n for n in notes if n.endswith(("first half", "done"))] == want
    assert rec.balanced


def test_parallel_stages_match_sequential() -> None:
    stages = [Stage("p", "P", _stage_ok), Stage("q", "Q", _stage_bad)]
    seq = run_stages(stages, jobs=1)
    par = run_stages(stages, jobs=2)
    assert [s.status for s in par] == ["ok", "failed"]
    assert par[0].figures[0].png == seq[0].figures[0].png
    assert par[0].files == seq[0].files and par[1].text == seq[1].text
    with pytest.raises(ValueError, match="jobs"):
        run_stages(stages, jobs=0)


def test_foreign_output_dir_is_refused_before_any_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    foreign = tmp_path / "thesis"
    foreign.mkdir()
    (foreign / "chapter1.tex").write_text("keep me")
    assert main(["reproduce", "--out", str(foreign), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "did not write" in err
    assert [p.name for p in foreign.iterdir()] == ["chapter1.tex"]
