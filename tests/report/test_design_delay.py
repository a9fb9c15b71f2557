"""The ``delay`` stage of ``analyze``: τ* of every design, the verdict at ``[control] delay_time``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import seapass
from seapass.cli import main
from seapass.exact.rounding import decimal_down, decimal_up
from seapass.model.design_file import load_design, parse_design
from seapass.report.analyze import ANALYSIS, analyze, check_budgets, stages_text
from seapass.report.stages.design_delay import FULL_BUDGET, QUICK_BUDGET

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
PARAMS = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


def ours(delay_time: float | None = None, **model: str):
    control = {} if delay_time is None else {"control": {"delay_time": delay_time}}
    return parse_design({"name": "ours", "model": model or {"D1": "k1 + b1*s", "CA": "kd + bd*s"},
                         "parameters": dict(PARAMS), **control})  # fmt: skip


def rows(section) -> dict[str, object]:
    return dict(section.tables[0].rows)


def test_tau_star_in_the_report_is_delay_margins(tmp_path: Path) -> None:
    design = ours(0.01)
    sec = analyze(design, stages=["delay"]).sections[0]
    assert sec.key == "delay" and sec.status == "ok"
    m = seapass.delay_margin(design, "delay_time")
    lo, hi = m.tau_star
    r = rows(sec)
    assert r["τ* lower end (certified, rounded down) [s]"] == decimal_down(lo, 12)
    assert r["τ* upper end (rounded up) [s]"] == decimal_up(hi, 12)
    assert float(r["τ* lower end (certified, rounded down) [s]"]) <= lo
    assert r["kind of loss"] == "interior" and r["delay-independent"] == "no"
    assert r["frequency of the loss [rad/s]"] == m.frequency
    assert r["stated latency [s]"] == 0.01 and r["verdict up to the latency"] == "passive"
    (finding,) = sec.findings
    assert finding.verdict == "agrees" and "delay_time = 0.01 s" in finding.claim
    assert [f.name for f in sec.figures] == ["delay_margin", "real_part_at_latency"]
    data = json.loads(sec.files["delay_margin.json"])
    assert data["margin"]["tau_star"] == [lo, hi] and data["latency"] == 0.01
    assert decimal_down(lo, 6) in sec.text  # the printed passive end rounds down


def test_the_stage_agrees_with_a_dense_grid_of_the_delayed_design() -> None:
    """Independent check: numpy on Re Z_L(jw) of the delayed design, written by hand."""
    sec = analyze(ours(), stages=["delay"]).sections[0]
    lo = float(rows(sec)["τ* lower end (certified, rounded down) [s]"])
    hi = float(rows(sec)["τ* upper end (rounded up) [s]"])
    w = np.geomspace(1e-2, 1e5, 200_001)

    def rez(tau: float) -> np.ndarray:
        s = 1j * w
        d1, ca = 1000 + 20 * s, (500 + 25 * s) * np.exp(-s * tau)
        return (d1 * (s * s + 10 * s + ca) / (s * s + 10 * s + d1 + ca) / s).real

    for tau in np.linspace(0.0, lo, 6):
        assert rez(float(tau)).min() >= 0.0
    bad = rez(hi * 1.001)
    assert (
        bad.min() < 0
        and abs(w[np.argmin(bad)] / rows(sec)["frequency of the loss [rad/s]"] - 1) < 0.01
    )


def test_a_latency_beyond_tau_star_differs_and_none_is_info() -> None:
    sec = analyze(ours(0.05), stages=["delay"]).sections[0]
    assert sec.findings[0].verdict == "differs" and "not passive" in sec.text
    assert rows(sec)["verdict up to the latency"] == "not passive"
    plain = analyze(ours(), stages=["delay"]).sections[0]
    assert plain.findings == () and "No latency is stated" in plain.text
    assert [f.name for f in plain.figures] == ["delay_margin"]


@pytest.mark.parametrize(
    ("file", "words"),
    [
        ("lp.toml", "τ* = 0"),  # load-side P behind a spring: every delay breaks it
        ("load_pd_not_passive.toml", "Not passive even without delay"),
        ("cascaded_impedance.toml", "passive for every loop latency up to"),
    ],
)
def test_every_example_design_gets_tau_star(file: str, words: str) -> None:
    design = load_design(EXAMPLES / file)
    sec = analyze(design, stages=["delay"], quick=True).sections[0]
    assert sec.status == "ok" and words in sec.text
    m = seapass.delay_margin(design, "delay_time", budget=QUICK_BUDGET)
    star = rows(sec)["τ* upper end (rounded up) [s]"]
    assert star == ("none" if m.tau_star is None else decimal_up(m.tau_star[1], 12))


def test_no_controller_says_so() -> None:
    d = parse_design({"name": "spring", "model": {"D1": "k1 + b1*s"},
                      "parameters": {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 20.0}})  # fmt: skip
    sec = analyze(d, stages=["delay"]).sections[0]
    assert sec.status == "ok" and "no controller" in sec.text


def test_the_budget_stops_the_search_and_the_answer_is_undecided() -> None:
    sec = analyze(ours(0.01), stages=["delay"], budgets={"delay": 100}).sections[0]
    assert sec.status == "stopped_at_budget"
    assert "--budget delay=N" in sec.text
    assert rows(sec)["margin"] == "undecided"
    assert rows(sec)["verdict up to the latency"] == "undecided"  # never passive
    assert sec.findings[0].verdict == "info"


def test_the_stage_is_listed_with_its_budget() -> None:
    (stage,) = [s for s in ANALYSIS if s.key == "delay"]
    assert stage.budget is not None and stage.budget.full == FULL_BUDGET
    assert stage.budget.quick == QUICK_BUDGET and FULL_BUDGET >= 50_000  # delay_margin's default
    assert (
        "delay " in stages_text() and f"{FULL_BUDGET} pieces per certified search" in stages_text()
    )
    assert check_budgets({"delay": 500}) == {"delay": 500}
    with pytest.raises(ValueError, match=r"budgets\['delay'\]"):
        check_budgets({"delay": 10})


def test_analyze_cli_writes_the_delay_stage(tmp_path: Path, capsys) -> None:
    path = tmp_path / "ours.toml"
    text = (EXAMPLES / "ours.toml").read_text(encoding="utf-8")
    path.write_text(
        text.replace("rate = 500.0", "rate = 500.0\ndelay_time = 0.002"), encoding="utf-8"
    )
    out = tmp_path / "r"
    assert main(["analyze", str(path), "--stages", "delay", "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert [s["key"] for s in summary["sections"]] == ["delay", "design-file"]
    data = json.loads((out / "data/delay_margin.json").read_text())
    m = seapass.delay_margin(load_design(path), "delay_time")
    assert data["margin"]["tau_star"] == list(m.tau_star) and data["outcome"] == "passive"
    assert (out / "figures/real_part_at_latency.svg").is_file()
    md = (out / "report.md").read_text()
    assert "Delay margin and loop latency" in md and "delay_time" in md
    design_json = json.loads((out / "data/design.json").read_text())
    assert design_json["control"]["delay_time"] == 0.002
    with pytest.raises(SystemExit) as info:
        main(["analyze", "--help"])
    assert info.value.code == 0
    assert "  delay      the certified delay margin tau*" in capsys.readouterr().out


def test_analyze_delay_time_flag_replaces_the_file_latency(tmp_path: Path, capsys) -> None:
    out = tmp_path / "r"
    argv = ["analyze", str(EXAMPLES / "ours.toml"), "--stages", "delay", "--out", str(out),
            "--delay-time", "0.003", "--no-progress", "--json"]  # fmt: skip
    assert main(argv) == 0
    capsys.readouterr()
    data = json.loads((out / "data/delay_margin.json").read_text())
    assert data["latency"] == 0.003 and data["outcome"] == "passive"
    bad = [
        "analyze",
        str(EXAMPLES / "ours.toml"),
        "--out",
        str(tmp_path / "r2"),
        "--delay-time",
        "-2",
    ]
    assert main(bad) == 2
    err = capsys.readouterr().err
    assert err == "error: --delay-time: must be a number of seconds in [0, 1000], got -2.0\n"
    assert not (tmp_path / "r2").exists()
