"""Paper stages: Tables I and II derived and compared, and every row's rendered stiffness.

Each ``stage_*`` returns a [`Section`][seapass.report.document.Section]; one with
figures is split as python-control splits ``*_response`` from ``*_plot``
(``*_data`` computes, ``*_figures`` draws, ``*_section`` writes the section).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import sympy as sp

from ...analysis.freqresp import FrequencyResponse, stiffness_response
from ...model.catalog import REFERENCE_VALUES
from ...paper.tablefmt import format_latex, format_markdown
from ...paper.tables import PAPER_ROWS, BoundStatus, PaperRow, TableRow, build_tables
from ...plot.passivity import plot_bode
from ...plot.style import axes_grid, set_suptitle
from ...progress import ProgressLike, as_progress, task
from ..document import (
    Discrepancy,
    FigureData,
    Finding,
    Math,
    Section,
    Table,
    Verdict,
    formula,
    to_json,
)
from ..pipeline import StageContext

__all__ = [
    "stage_stiffness",
    "stage_tables",
    "stiffness_data",
    "stiffness_figures",
    "stiffness_section",
]

_GROUPS = (
    ("I", "table1", "Table I: mechanical configurations (load-side P, C_L = kd)"),
    ("II", "table2", "Table II: controllers (pure spring D1 = k1)"),
    ("proposed", "proposed", "Proposed design (damped spring, actuator-side PD)"),
)
_COLUMNS = (
    "row", "D1", "D2", "C_A", "C_L", "F_L/X_L (paper)", "F_L/X_L (derived)", "TF agrees",
    "Re condition (paper)", "Re condition (derived)", "condition agrees", "paper bound",
    "paper bound is", "exact condition (derived)", "counterexample",
)  # fmt: skip
_VIEWS = (
    ("Stiffness transfer function F_L/X_L", _COLUMNS[:8]),
    ("Passivity", (_COLUMNS[0], *_COLUMNS[8:])),
)


def _values_text(values: Mapping[str, float] | None) -> str:
    return ", ".join(f"{k}={v:.4g}" for k, v in values.items()) if values else ""


def _row_cells(r: TableRow) -> tuple[Any, ...]:
    """One table row: the paper's printed text and the derivation, formulas as `Math`."""
    p = r.paper
    return (
        p.name, Math(p.D1), Math(p.D2), Math(p.CA), Math(p.CL),
        Math(p.stiffness), Math(str(sp.factor(r.stiffness))), r.stiffness_agrees,
        Math(f"{p.condition} >= 0"), Math(f"{r.condition} >= 0"), r.agrees,
        Math(p.bound), r.bound_status, Math(str(r.exact_condition)),
        _values_text(r.counterexample),
    )  # fmt: skip


def _typos(r: TableRow) -> list[str]:
    """The printed formulas of a row that differ from the derivation."""
    out = []
    if not r.eq4_agrees:
        out.append(
            f"Eq. (4) as printed omits the {formula('D1*D2')} term: it should read "
            f"{formula('D2*(alpha + C_A + D1)')}"
        )
    if not r.stiffness_agrees:
        out.append("the printed transfer function differs from the first-principles derivation")
    if not r.agrees:
        extra = sp.factor(sp.expand(r.condition - r.paper_condition))
        out.append(
            "the printed passivity polynomial differs from the derived one "
            f"(derived - printed = {formula(extra)})"
        )
    return out


def _row_findings(r: TableRow) -> list[Finding]:
    """What the row shows: the printed formulas (typos) and the stated bound, classified."""
    p = r.paper
    name = f"{p.title} ({p.name})"
    typos = _typos(r)
    findings = []
    if typos:
        findings.append(
            Finding(f"{name}: printed formulas", Verdict.DIFFERS, "; ".join(typos),
                    kind=Discrepancy.PAPER_TYPO)
        )  # fmt: skip
    bound = formula(p.bound)
    example = _values_text(r.counterexample)
    if r.bound_status is BoundStatus.UNSAFE:
        findings.append(
            Finding(f"{name}: the stated bound {bound}", Verdict.DIFFERS,
                    f"admits designs that are NOT passive, e.g. {example}",
                    kind=Discrepancy.UNSAFE)
        )  # fmt: skip
    elif r.bound_status is BoundStatus.SUFFICIENT:
        findings.append(
            Finding(f"{name}: the stated bound {bound}", Verdict.DIFFERS,
                    f"is sufficient but not necessary: {example} violates it and is passive",
                    kind=Discrepancy.CONSERVATIVE)
        )  # fmt: skip
    if not findings:
        findings.append(
            Finding(name, Verdict.AGREES,
                    f"transfer function, passivity polynomial and bound agree: {r.bound_status.phrase}")
        )  # fmt: skip
    return findings


def _group_table(key: str, name: str, title: str, rows: Sequence[TableRow]) -> Table:
    group = [r for r in rows if r.paper.table == key]
    flags = {
        (i, "paper bound is")
        for i, r in enumerate(group)
        if r.bound_status in (BoundStatus.UNSAFE, BoundStatus.SUFFICIENT)
    }
    return Table(
        name=name,
        title=title,
        columns=_COLUMNS,
        rows=tuple(_row_cells(r) for r in group),
        highlight=frozenset(flags),
        views=_VIEWS,
    )


def stage_tables(context: StageContext) -> Section:
    """Tables I and II and the proposed design, derived and compared with the paper."""
    rows = build_tables(progress=context.progress)
    tables = tuple(_group_table(key, name, title, rows) for key, name, title in _GROUPS)
    findings = [f for r in rows for f in _row_findings(r)]
    n_bad = sum(1 for r in rows if r.notes)
    text = (
        "Every row is derived from the free-body model (actuator "
        f"{formula('m*s**2*X_A + b*s*X_A == F_A + D1*(X_L - X_A)')}, "
        f"massless port {formula('F_L == D1*(X_L - X_A) + D2*X_L')}) and compared with the "
        "paper's printed transfer function, passivity polynomial "
        "`Re N(jω) D(−jω) ≥ 0` and stated bound. The bound is classified against the exact "
        "condition: **exact**, **sufficient only** (a passive design violates it; "
        "counterexample given) or **unsafe** (a design satisfying it is not passive). Flagged "
        f"cells are discrepancies. {n_bad} of {len(rows)} rows have at least one discrepancy; "
        "see `docs/notes-on-the-paper.md` for the discussion of each."
    )
    return Section(
        key="tables",
        title="Tables I and II: paper vs first principles",
        text=text,
        tables=tables,
        findings=tuple(findings),
        files={
            "tables.json": to_json([r.to_dict() for r in rows]),
            "tables.md": format_markdown(rows),
            "tables.tex": format_latex(rows),
        },
    )


def _grid_shape(n: int) -> tuple[int, int]:
    """Rows and columns (at most 3) for ``n`` panels, with as few empty slots as possible."""
    ncol = min((c for c in (3, 2, 1) if c <= n), key=lambda c: (-(n % c == 0), -c))
    return math.ceil(n / ncol), ncol


#: One row of the stiffness stage: the paper's row, its reference values, its response.
StiffnessRow = tuple[PaperRow, dict[str, float], FrequencyResponse]


def _stiffness_figure(title: str, group: Sequence[StiffnessRow]) -> Any:
    """Magnitude and phase of every row of one table, one Bode pair per row, no empty slot."""
    nrow, ncol = _grid_shape(len(group))
    axes = axes_grid(
        None, 2 * nrow, ncol, figsize=(4.3 * ncol + 0.6, 4.4 * nrow + 0.6),
        sharex=True, gridspec_kw={"height_ratios": [2, 1] * nrow},
    )  # fmt: skip
    for k, (row, vals, resp) in enumerate(group):
        i, j = divmod(k, ncol)
        shown = ", ".join(f"{n}={v:g}" for n, v in vals.items() if n not in ("m", "b"))
        plot_bode(
            resp, title=f"{row.title}\n{shown}", reference=vals.get("k1"), legend=False,
            axes=axes[2 * i : 2 * i + 2, j],
        )  # fmt: skip
    for k in range(len(group) - ncol):  # one frequency label per column, at the bottom
        i, j = divmod(k, ncol)
        axes[2 * i + 1, j].set_xlabel("")
    for k in range(len(group), nrow * ncol):
        i, j = divmod(k, ncol)
        axes[2 * i, j].set_visible(False)
        axes[2 * i + 1, j].set_visible(False)
    fig = axes[0, 0].figure
    set_suptitle(
        fig,
        f"{title}: rendered stiffness F_L/X_L(jω), magnitude and phase "
        "(m = 1 kg, b = 10 N·s/m; dashed: spring stiffness k1)",
        fontsize=11,
    )
    return fig


def stiffness_data(quick: bool, *, progress: ProgressLike = None) -> tuple[StiffnessRow, ...]:
    """The rendered stiffness of every table row at the reference values (computed)."""
    shown = as_progress(progress, where="stiffness_data")
    omega = np.logspace(-1, 4, 200 if quick else 400)
    results = []
    with task(shown, f"stiffness of {len(PAPER_ROWS)} rows", len(PAPER_ROWS)):
        for row in PAPER_ROWS:
            sea = row.design.sea()
            vals = {n: REFERENCE_VALUES[n] for n in sea.parameters}
            resp = stiffness_response(sea, omega, values=vals, label=row.title)
            results.append((row, vals, resp))
            shown.advance(1, note=row.name)
    return tuple(results)


def stiffness_figures(results: Sequence[StiffnessRow]) -> tuple[FigureData, ...]:
    """One figure per table: the Bode pair of each of its rows."""
    figures = []
    for key, name, _title in _GROUPS:
        title = {"I": "Table I", "II": "Table II"}.get(key, "Proposed design")
        group = [r for r in results if r[0].table == key]
        figures.append(
            FigureData.of(
                f"stiffness_{name}",
                f"{title}: stiffness frequency response (magnitude and phase) of every row at "
                "the reference values.",
                _stiffness_figure(title, group),
            )
        )
    return tuple(figures)


def stiffness_section(results: Sequence[StiffnessRow], figures: Sequence[FigureData]) -> Section:
    """The section of `stiffness_data` with the figures of `stiffness_figures`."""
    summary = Table(
        name="stiffness_summary",
        title="Static and high-frequency stiffness at the reference values",
        columns=("row", "values", "static F_L/X_L(0) [N/m]", "high-frequency limit [N/m]"),
        rows=tuple(
            (row.name, ", ".join(f"{k}={v:g}" for k, v in vals.items()), r.static, r.high_frequency)
            for row, vals, r in results
        ),
    )
    lines = ["row,omega_rad_s,magnitude_N_per_m,phase_deg"]
    for row, _vals, r in results:
        lines += [
            f"{row.name},{w!r},{m!r},{p!r}"
            for w, m, p in zip(
                r.omega.tolist(), r.magnitude.tolist(), r.phase.tolist(), strict=True
            )
        ]
    return Section(
        key="stiffness",
        title="Stiffness frequency responses",
        text=(
            "The paper's *Frequency Response* column, recomputed from the derived transfer "
            "functions, with the phase the paper does not show. Reference values: `m = 1, "
            "b = 10, k1 = k2 = 1000, b1 = b2 = 20, kd = 500, bd = 25, ki = 100` (SI units). A "
            "damper in the transmission makes the stiffness grow with frequency (the "
            "*perceived stiffness* under impacts)."
        ),
        tables=(summary,),
        figures=tuple(figures),
        files={"stiffness_response.csv": "\n".join(lines) + "\n"},
    )


def stage_stiffness(context: StageContext) -> Section:
    """The rendered stiffness of every table row at the reference values."""
    results = stiffness_data(context.quick, progress=context.progress)
    return stiffness_section(results, stiffness_figures(results))
