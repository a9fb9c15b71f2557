"""Paper stages: Tables I and II derived and compared, and every row's rendered stiffness.

Each ``stage_*`` returns a [`Section`][seapass.report.document.Section].
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import sympy as sp

from ...analysis.freqresp import stiffness_response
from ...model.catalog import REFERENCE_VALUES
from ...paper.tablefmt import format_latex, format_markdown
from ...paper.tables import PAPER_ROWS, build_tables
from ...plot.response import plot_stiffness_response
from ...plot.style import axes_grid, figure_bytes
from ..document import FigureData, Finding, Section, Table, Verdict, to_json

__all__ = [
    "stage_stiffness",
    "stage_tables",
]


def _code(text: Any) -> str:
    return f"`{text}`"


def stage_tables(quick: bool) -> Section:
    """Tables I and II and the proposed design, derived and compared with the paper."""

    rows = build_tables()
    tables = []
    findings = []
    titles = {
        "I": "Table I: mechanical configurations (load-side P, C_L = kd)",
        "II": "Table II: controllers (pure spring D1 = k1)",
        "proposed": "Proposed design (damped spring, actuator-side PD)",
    }
    columns = (
        "row", "D1", "D2", "C_A", "C_L", "F_L/X_L (paper)", "F_L/X_L (derived)", "TF agrees",
        "Re condition (paper)", "Re condition (derived)", "condition agrees", "paper bound",
        "paper bound is", "exact condition (derived)", "counterexample",
    )  # fmt: skip
    for key, title in titles.items():
        group = [r for r in rows if r.paper.table == key]
        cells, flags = [], set()
        for i, r in enumerate(group):
            p = r.paper
            ce = r.counterexample
            cells.append(
                (
                    p.name, _code(p.D1), _code(p.D2), _code(p.CA), _code(p.CL),
                    _code(p.stiffness), _code(sp.factor(r.stiffness)), r.stiffness_agrees,
                    _code(f"{p.condition} >= 0"), _code(f"{r.condition} >= 0"), r.agrees,
                    _code(p.bound), r.bound_status, _code(r.exact_condition),
                    ", ".join(f"{k}={v:.4g}" for k, v in ce.items()) if ce else "",
                )
            )  # fmt: skip
            if r.bound_status in ("unsafe", "sufficient only"):
                flags.add((i, 12))
            if r.notes:
                findings.append(
                    Finding(f"{p.title} ({p.name})", Verdict.DIFFERS, "; ".join(r.notes))
                )
            else:
                findings.append(
                    Finding(
                        f"{p.title} ({p.name})",
                        Verdict.AGREES,
                        f"transfer function, passivity polynomial and bound ({r.bound_status}) agree",
                    )
                )
        tables.append(
            Table(
                name={"I": "table1", "II": "table2"}.get(key, "proposed"),
                title=title,
                columns=columns,
                rows=tuple(cells),
                highlight=frozenset(flags),
                views=(
                    ("Stiffness transfer function F_L/X_L", (0, 1, 2, 3, 4, 5, 6, 7)),
                    ("Passivity", (0, 8, 9, 10, 11, 12, 13, 14)),
                ),
            )
        )
    n_bad = sum(1 for f in findings if f.verdict == Verdict.DIFFERS)
    text = (
        "Every row is derived from the free-body model (actuator `m s² X_A + b s X_A = F_A + "
        "D1 (X_L − X_A)`, massless port `F_L = D1 (X_L − X_A) + D2 X_L`) and compared with the "
        "paper's printed transfer function, passivity polynomial `Re N(jω) D(−jω) ≥ 0` and "
        "stated bound. The bound is classified against the exact condition: **exact**, "
        "**sufficient only** (a passive design violates it; counterexample given) or "
        "**unsafe** (a design satisfying it is not passive). Flagged cells are discrepancies. "
        f"{n_bad} of {len(rows)} rows have at least one discrepancy; see "
        "`docs/notes-on-the-paper.md` for the discussion of each."
    )
    return Section(
        key="tables",
        title="Tables I and II: paper vs first principles",
        text=text,
        tables=tuple(tables),
        findings=tuple(findings),
        files={
            "tables.json": to_json([r.to_dict() for r in rows]),
            "tables.md": format_markdown(rows),
            "tables.tex": format_latex(rows),
        },
    )


def stage_stiffness(quick: bool) -> Section:
    """The rendered stiffness of every table row at the reference values."""
    omega = np.logspace(-1, 4, 200 if quick else 400)
    results = []
    for row in PAPER_ROWS:
        sea = row.design.sea()
        vals = {k: REFERENCE_VALUES[k] for k in sea.parameters}
        results.append((row, vals, stiffness_response(sea, omega, values=vals, label=row.title)))
    figures = []
    for key, title in (("I", "Table I"), ("II", "Table II"), ("proposed", "Proposed design")):
        group = [r for r in results if r[0].table == key]
        ncol = min(3, len(group))
        nrow = math.ceil(len(group) / ncol)
        axes = axes_grid(None, nrow, ncol, figsize=(max(5.0 * ncol, 7.0), 3.9 * nrow + 0.4))
        fig = axes[0, 0].figure
        for ax, (row, vals, resp) in zip(axes.flat, group, strict=False):
            shown = ", ".join(f"{k}={v:g}" for k, v in vals.items() if k not in ("m", "b"))
            plot_stiffness_response(resp, reference=vals.get("k1"), ax=ax)
            ax.set_title(f"{row.title}\n{shown}", fontsize=10)
        for ax in list(axes.flat)[len(group) :]:
            ax.set_visible(False)
        fig.suptitle(
            f"{title}: rendered stiffness |F_L/X_L(jω)|\n(m = 1 kg, b = 10 N·s/m)", fontsize=11
        )
        figures.append(
            FigureData(
                f"stiffness_{'table1' if key == 'I' else 'table2' if key == 'II' else 'proposed'}",
                f"{title}: stiffness frequency response of every row at the reference values.",
                figure_bytes(fig),
            )
        )
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
            "functions. Reference values: `m = 1, b = 10, k1 = k2 = 1000, b1 = b2 = 20, "
            "kd = 500, bd = 25, ki = 100` (SI units). A damper in the transmission makes the "
            "stiffness grow with frequency (the *perceived stiffness* under impacts)."
        ),
        tables=(summary,),
        figures=tuple(figures),
        files={"stiffness_response.csv": "\n".join(lines) + "\n"},
    )
