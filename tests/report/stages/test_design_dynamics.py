"""The analyze report's tuning table shows the units the design file declares (issue 23)."""

from __future__ import annotations

from pathlib import Path

from seapass.model.design_file import load_design
from seapass.report.stages.design_dynamics import tuning_data, tuning_section


def test_the_tuning_table_shows_declared_units(tmp_path: Path) -> None:
    path = tmp_path / "apd_mm.toml"
    path.write_text(Path("examples/apd.toml").read_text() + '\n[units]\nkd = "N/mm"\n')
    design = load_design(str(path))
    data = tuning_data(design, quick=True, generations=1)
    assert data.result is not None
    section = tuning_section(design, data, ())
    table = next(t for t in section.tables if t.name == "tuned_gains")
    assert table.columns[:2] == ("gain", "unit")
    units = {row[0]: row[1] for row in table.rows}
    assert units == {"kd": "N/mm", "bd": "N*s/m"}
    assert "N/mm" in section.text and "[SI units]" not in section.text
