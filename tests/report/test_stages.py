"""Report stages return enums, not prose, and split compute → section → figure (issue 21, item 8)."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from seapass.analysis.region import PassiveIntervals, PassiveMap
from seapass.errors import ParameterError
from seapass.paper.tables import PAPER_ROWS
from seapass.report.document import Discrepancy, Table, Verdict
from seapass.report.stages import regions

STAGES = Path(regions.__file__).parent
#: Calls that draw: only ``*_figures`` (and their ``*_figure`` helpers) may make them.
DRAWING = ("FigureData.of", "figure_bytes", "axes_grid")


def _draws(call: ast.Call) -> bool:
    name = ast.unparse(call.func)
    return name.split(".")[-1].startswith("plot_") or name in DRAWING


def drawing_outside_figures(source: str) -> list[str]:
    """``function: call`` for every drawing call outside a ``*_figures``/``*_figure`` function."""
    out = []
    for fn in ast.walk(ast.parse(source)):
        if not isinstance(fn, ast.FunctionDef) or fn.name.endswith(("_figures", "_figure")):
            continue
        nested = {n for d in ast.walk(fn) if isinstance(d, ast.FunctionDef) and d is not fn
                  for n in ast.walk(d)}  # fmt: skip
        for node in ast.walk(fn):
            if isinstance(node, ast.Call) and node not in nested and _draws(node):
                out.append(f"{fn.name}: {ast.unparse(node.func)}")
    return out


def test_the_check_sees_a_plot_in_a_stage() -> None:
    mixed = "def stage_x(q):\n    r = compute(q)\n    return Section(figures=(FigureData.of('a', 'b', plot_x(r)),))\n"
    assert drawing_outside_figures(mixed) == ["stage_x: FigureData.of", "stage_x: plot_x"]
    split = "def x_figures(r):\n    return (FigureData.of('a', 'b', plot_x(r)),)\n"
    assert drawing_outside_figures(split) == []


@pytest.mark.parametrize("path", sorted(STAGES.glob("*.py")), ids=lambda p: p.name)
def test_stages_draw_only_in_their_figure_functions(path: Path) -> None:
    """Computing is separate from plotting: ``*_data`` computes, ``*_figures`` draws,
    ``*_section`` writes the section (python-control's ``*_response`` / ``*_plot``)."""
    assert drawing_outside_figures(path.read_text(encoding="utf-8")) == []


def test_a_paper_bound_is_judged_with_an_enum() -> None:
    exact = [(0.0, 1000.0)]
    assert regions.judge_bound(exact, sp.Interval(0, 2000), 1e4) is Discrepancy.UNSAFE
    assert regions.judge_bound(exact, sp.Interval(0, 500), 1e4) is Discrepancy.CONSERVATIVE
    assert regions.judge_bound(exact, sp.Interval(0, 1000), 1e4) is None
    assert regions.judge_bound([], sp.EmptySet, 1e4) is None


def _data(judgement: Discrepancy | None) -> regions.RegionsData:
    row = PAPER_ROWS[0]
    kd_row = regions.KdRow(
        row=row, sea=row.design.sea(), values=(("k1", 1000.0),), exact=((0.0, 1000.0),),
        admitted=((0.0, 2000.0),), judgement=judgement,
        admitted_not_passive=((1000.0, 2000.0),) if judgement is Discrepancy.UNSAFE else (),
    )  # fmt: skip
    columns = PassiveMap(
        param_x="b1", param_y="kd", x=np.array([0.0, 60.0]), y=np.array([0.0, 1500.0]),
        intervals=(((0.0, 1000.0),), ((0.0, 1600.0),)), mask=np.zeros((2, 2), dtype=bool),
    )  # fmt: skip
    proposed = PassiveIntervals(param="kd", lo=0.0, hi=1e6, intervals=((0.0, 1e6),))
    return regions.RegionsData(
        hi=1e4, kd_rows=(kd_row,), lp_region=None, lp_columns=columns,  # type: ignore[arg-type]
        proposed=proposed, witnesses=(),
    )  # fmt: skip


@pytest.mark.parametrize(
    ("judgement", "text", "flagged"),
    [
        (Discrepancy.UNSAFE, "UNSAFE: admits non-passive kd", True),
        (Discrepancy.CONSERVATIVE, "conservative (sufficient only)", True),
        (None, "matches", False),
    ],
)
def test_the_regions_section_shows_the_judgement_and_flags_by_column_name(
    judgement: Discrepancy | None, text: str, flagged: bool
) -> None:
    section = regions.regions_section(_data(judgement), ())
    (table,) = section.tables
    assert table.rows[0][-1] == text
    assert table.flagged(0, table.columns.index("paper's bound")) is flagged
    assert table.highlight == ({(0, "paper's bound")} if flagged else set())
    assert not section.figures  # the section takes its figures, it does not draw them
    lp, proposed = section.findings
    assert lp.verdict is Verdict.DIFFERS and lp.kind is Discrepancy.CONSERVATIVE
    assert proposed.verdict is Verdict.AGREES


def test_tables_highlight_and_split_by_column_name() -> None:
    t = Table(
        name="t", title="T", columns=("a", "b", "c"), rows=((1, 2, 3), (4, False, 6)),
        highlight=frozenset({(0, "c")}), views=(("left", ("a", "b")), ("right", ("a", "c"))),
    )  # fmt: skip
    assert t.flagged(0, 2) and not t.flagged(0, 1) and t.flagged(1, 1)
    assert t.view_indices() == [("left", (0, 1)), ("right", (0, 2))]
    with pytest.raises(ParameterError, match="no column 'd'"):
        Table(name="t", title="T", columns=("a",), rows=((1,),), highlight=frozenset({(0, "d")}))
    with pytest.raises(ParameterError, match="unknown columns"):
        Table(name="t", title="T", columns=("a",), rows=((1,),), views=(("v", ("z",)),))


def test_analyze_draws_one_bode_figure() -> None:
    from seapass.model.design_file import load_design
    from seapass.report.analyze import analyze

    examples = Path(__file__).resolve().parents[2] / "examples"
    design = load_design(examples / "lp.toml")
    report = analyze(design, quick=True, stages=["stiffness", "frequency"])
    names = [f.name for s in report.sections for f in s.figures]
    assert names == ["bode", "real_part", "nyquist"]
    bode = next(f for s in report.sections for f in s.figures if f.name == "bode")
    assert "whole turns removed" in bode.caption
    (table,) = next(s for s in report.sections if s.key == "stiffness").tables
    assert [r[0] for r in table.rows][-1] == "peak over 0.1-1e4 rad/s"
