"""``seapass analyze``: the report for a user's design file."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import pytest

from cpu_budget import limit_child_cpu
from seapass.cli import main
from seapass.model.design_file import load_design
from seapass.report.analyze import ANALYSIS_STAGES, analyze

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _csv(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as fh:
        return list(csv.DictReader(fh))


def test_not_passive_design_report(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "lpd"
    rc = main(["analyze", str(EXAMPLES / "load_pd_not_passive.toml"), "--out", str(out),
               "--quick", "--stages", "core,response,tuning,witness", "--no-progress"])  # fmt: skip
    assert rc == 0
    assert "NOT passive" in capsys.readouterr().out
    md = (out / "report.md").read_text()
    assert "**Verdict: NOT passive at the given values.**" in md
    verdict = json.loads((out / "data/passivity.json").read_text())
    assert verdict["passive"] is False and verdict["omega"] > 0
    ranges = {r["parameter"]: r for r in _csv(out / "data/passive_ranges.csv")}
    # load-side derivative: only bd = 0 can be passive; with bd = 25 no kd is
    assert ranges["bd"]["exact passive set"] == "{0}"
    assert ranges["kd"]["exact passive set"] == "none"
    assert ranges["kd"]["value is passive"] == "False"
    # tuning runs for any design: here no gains with bd > 0 are passive, and it says so
    tuning = json.loads((out / "data/tuning.json").read_text())
    assert tuning["passive"] is False and "passivity" in tuning["violations"]
    assert "no passive gains found" in md
    env = _csv(out / "data/witness.csv")[0]
    assert float(env["growth rate [1/s]"]) > 0
    assert min(float(env[k]) for k in ("mass [kg]", "damping [N·s/m]", "stiffness [N/m]")) >= 0
    assert (out / "figures/step_response.png").is_file()
    design = json.loads((out / "data/design.json").read_text())
    assert design["model"]["CL"] == "kd + bd*s"
    # the design file as validated: one row per key, defaults filled in
    rows = {r["key"]: r for r in _csv(out / "data/design_file.csv")}
    assert rows["model.CL"]["value"] == "kd + bd*s" and rows["parameters.kd"]["unit"] == "N/m"
    assert rows["control.rate"]["value"] == "none" and "simulation.horizon" in rows
    html = (out / "report.html").read_text()
    sec = html[html.index('id="sec-design-file"') :]
    assert "<table>" in sec[: sec.index("</section>")] and "parameters.kd" in sec
    # the stiffness at the values: decimal coefficients, not exact-rational noise
    stiffness = {r["element"]: r["expression"] for r in _csv(out / "data/design.csv")}
    at_values = stiffness["F_L/X_L at the values (6 digits)"]
    assert not re.search(r"\d{8}", at_values), at_values
    assert json.loads((out / "data/stiffness.json").read_text())["at_values_decimal"] == at_values
    # the summary names the failed check first, the condition is MathML
    summary = html[html.index('id="summary"') :]
    assert summary.index("NOT passive") < summary.index("</section>")
    assert "Checks of seapass" in summary[: summary.index("</section>")]
    assert '<div class="math-block"><math' in html


def test_ours_with_sampled_control() -> None:
    design = load_design(EXAMPLES / "ours.toml")
    report = analyze(design, quick=True, stages=["passivity", "ranges", "sampled", "zwidth"])
    secs = {s.key: s for s in report.sections}
    assert secs["passivity"].findings[0].verdict == "agrees"
    kd = next(r for r in secs["ranges"].tables[0].rows if r[0] == "kd")
    assert kd[3] is True and "search limit" in kd[4]
    sampled = secs["sampled"]
    assert sampled.status == "ok"
    assert "Passive under sampled-data control" in sampled.text
    rows = {r[0]: r for r in sampled.tables[0].rows}
    # continuous: every kd; at 500 Hz with one sample of delay and a 50 Hz velocity
    # filter: a finite limit above the file's kd = 1708 N/m
    assert "search limit" not in rows["kd"][3]
    upper = float(rows["kd"][3].strip("[]").split(",")[1])
    assert 1708.0 < upper < 1e5
    assert rows["kd"][5] == "yes" and "[" in rows["kd"][4]  # the design's own value, an edge
    zw = secs["zwidth"]
    assert zw.status == "ok" and zw.figures and "zwidth.csv" in zw.files
    assert zw.tables[0].columns[0] == "bd" and len(zw.tables[0].rows) == 5


def test_tuning_lp_quick() -> None:
    design = load_design(EXAMPLES / "lp.toml")
    report = analyze(design, quick=True, stages=["tuning"])
    (sec,) = report.sections[:1]
    assert sec.status == "ok"
    (row,) = sec.tables[0].rows
    gain = dict(zip(sec.tables[0].columns, row, strict=True))
    assert gain["gain"] == "kd" and gain["unit"] == "N/m"
    assert 0.0 <= gain["tuned"] <= 1000.0  # LP is passive only for kd <= k1
    assert gain["search range"] == "[0, 5000]"  # the box of the file's [ranges]
    continuous, sampled = sec.findings
    assert continuous.verdict == "agrees"
    # the file's 500 Hz controller: sampled load feedback on an undamped spring is never passive
    assert "500 Hz" in sampled.claim and sampled.verdict == "differs"


def test_no_control_rate_skips_sampled() -> None:
    design = load_design(EXAMPLES / "apd.toml")
    report = analyze(design, stages=["sampled"])
    assert report.sections[0].status == "skipped"
    assert "[control] rate" in report.sections[0].text
    assert ANALYSIS_STAGES == (
        "passivity", "witness", "stiffness", "frequency", "ranges", "twoport", "delay", "robust",
        "response", "tuning", "sampled", "zwidth", "rig",
    )  # fmt: skip
    rig = analyze(design, stages=["rig"]).sections[0]
    assert rig.status == "skipped" and "[rig]" in rig.text


def test_rig_stage_on_the_twin() -> None:
    design = load_design(EXAMPLES / "ours.toml")
    assert design.rig_file == "paper"
    sec = analyze(design, quick=True, stages=["rig"]).sections[0]
    assert sec.status == "ok"
    rows = sec.tables[0].rows
    assert [r[0] for r in rows] == [0.1, 0.6]  # the rig's load masses
    assert all(r[2] == "settled" for r in rows)


def _doc_blocks(lang: str) -> list[str]:
    import re

    text = (EXAMPLES.parent / "docs" / "tutorial.md").read_text(encoding="utf-8")
    return re.findall(rf"```{lang}\n(.*?)```", text, re.S)


def test_tutorial_python_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(EXAMPLES.parent)
    ns: dict[str, object] = {}
    blocks = _doc_blocks("python")
    assert len(blocks) >= 8
    for i, block in enumerate(blocks):
        exec(compile(block, f"docs/tutorial.md python block {i}", "exec"), ns)
    assert ns["result"].passive  # type: ignore[attr-defined]
    assert not ns["bad"].passive  # type: ignore[attr-defined]
    assert ns["tuned"].passive  # type: ignore[attr-defined]
    assert ns["record"].stop_reason == ""  # type: ignore[attr-defined]


def test_tutorial_commands_parse() -> None:
    import shlex

    from seapass.cli import build_parser

    parser = build_parser()
    commands = []
    for block in _doc_blocks("bash"):
        for cmd in block.replace("\\\n", " ").splitlines():
            cmd = cmd.split("#")[0].strip()
            if cmd.startswith(".venv/bin/seapass "):
                commands.append(shlex.split(cmd)[1:])
    assert len(commands) >= 6
    for argv in commands:
        args = parser.parse_args(argv)
        assert callable(args.func)


def test_lp_with_control_rate_is_not_passive_when_sampled(
    capsys: pytest.CaptureFixture[str],
) -> None:
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        rc = main(["analyze", str(EXAMPLES / "lp.toml"), "--out", tmp + "/o", "--quick",
                   "--stages", "passivity,sampled", "--no-progress"])  # fmt: skip
        assert rc == 0
    out = capsys.readouterr().out
    assert "LP: passive in continuous time; NOT passive under sampled-data control at 500 Hz" in out


def test_docs_build_strict_and_offline(tmp_path: Path) -> None:
    import re
    import shutil
    import subprocess
    import sys

    mkdocs = Path(sys.executable).with_name("mkdocs")
    if not mkdocs.exists() and shutil.which("mkdocs") is None:
        pytest.skip("mkdocs is not installed (pip install -e '.[docs]')")
    exe = str(mkdocs) if mkdocs.exists() else "mkdocs"
    site = tmp_path / "site"
    proc = subprocess.run(
        [exe, "build", "--strict", "--site-dir", str(site)],
        cwd=EXAMPLES.parent, capture_output=True, text=True,
        preexec_fn=limit_child_cpu(600),  # CPU time, not wall-clock time
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr[-3000:]
    for page in ("index.html", "tutorial/index.html", "api/index.html"):
        text = (site / page).read_text(encoding="utf-8")
        assert not re.search(r"""<(script|link|img)[^>]+(src|href)=["']https?:""", text), page
    api = (site / "api/index.html").read_text(encoding="utf-8")
    assert (
        'id="seapass.analysis.passivity.is_passive"' in api and 'id="seapass.model.sea.SEA"' in api
    )
    # no Sphinx role is left to be rendered literally
    assert not re.search(r":(func|class|mod|data|meth|attr):`", api)
