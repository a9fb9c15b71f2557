"""One overshoot format for people: percent of the step (JSON and results keep the fraction)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from seapass.sim.metrics import TrackingMetrics, overshoot_percent, overshoot_text

SRC = Path(__file__).resolve().parents[2] / "src" / "seapass"


def test_percent_text() -> None:
    assert overshoot_text(0.8715) == "87.15 %" and overshoot_text(0.68) == "68 %"
    assert overshoot_text(None) == "-" and overshoot_percent(0.5) == 50.0


def test_no_other_overshoot_format_in_the_sources() -> None:
    # every text field that formats an overshoot goes through overshoot_text
    field = re.compile(r"\{[^{}]*(?<!max_)overshoot\b[^{}]*[:*][^{}]*\}")
    assert field.search('f"{100 * m.overshoot:.3g} %"') and field.search('f"{met.overshoot:.4g}"')
    bad = [
        f"{p.relative_to(SRC)}: {line.strip()}"
        for p in SRC.rglob("*.py")
        for line in p.read_text().splitlines()
        if field.search(line)
    ]
    assert bad == []


def test_report_table_shows_percent() -> None:
    from seapass.report.stages.design_dynamics import metrics_table

    met = TrackingMetrics(
        status="settled", settling_time=1.0, final_error=0.0, overshoot=0.25,
        peak_force=1.0, energy=0.0, positive_work=0.0, band=0.02, target=0.5,
    )  # fmt: skip
    table = metrics_table("m", "t", [(1.0, None, met)])
    assert "overshoot [%]" in table.columns
    assert table.rows[0][table.columns.index("overshoot [%]")] == pytest.approx(25.0)
