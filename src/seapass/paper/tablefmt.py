"""Text, Markdown and LaTeX renderings of the derived Tables I and II (top layer)."""

from __future__ import annotations

import sympy as sp

from .tables import TableRow

__all__ = ["format_latex", "format_markdown", "format_text"]

_TITLES = {
    "I": "Table I: mechanical configurations, load-side P control (C_A = 0, C_L = kd)",
    "II": "Table II: controllers with a pure-spring transmission (D1 = k1, D2 = 0)",
    "proposed": "Proposed design: damped transmission with actuator-side PD control",
}


def _groups(rows: list[TableRow]) -> dict[str, list[TableRow]]:
    out: dict[str, list[TableRow]] = {}
    for r in rows:
        out.setdefault(r.paper.table, []).append(r)
    return out


def _cell(x: str) -> str:
    return x.replace("|", "\\|")


def format_markdown(rows: list[TableRow]) -> str:
    """One Markdown table per paper table, paper and derived side by side."""
    lines: list[str] = []
    for table, group in _groups(rows).items():
        lines += [f"### {_TITLES[table]}", ""]
        lines.append(
            "| row | D1 | D2 | C_A | C_L | F_L/X_L (derived) | paper TF ok | Re N(jw)D(-jw) (derived) "
            "| paper polynomial ok | paper bound | bound is | exact condition |"
        )
        lines.append("|" + "---|" * 12)
        for r in group:
            d = r.to_dict()
            lines.append(
                "| "
                + " | ".join(
                    _cell(str(v))
                    for v in (
                        d["name"], d["D1"], d["D2"], d["CA"], d["CL"], f"`{d['stiffness']}`",
                        "yes" if d["stiffness_agrees"] else "**no**", f"`{sp.factor(r.condition)}`",
                        "yes" if d["agrees"] else "**no**", f"`{d['paper_bound']}`",
                        d["paper_bound_status"], f"`{d['exact_condition']}`",
                    )
                )
                + " |"
            )  # fmt: skip
        lines.append("")
        for r in group:
            for note in r.notes:
                lines.append(f"- `{r.paper.name}`: {note}")
        lines.append("")
    return "\n".join(lines)


def format_latex(rows: list[TableRow]) -> str:
    """A ``tabular`` per paper table, with sympy's LaTeX for the expressions."""
    parts: list[str] = []
    for table, group in _groups(rows).items():
        parts.append(f"% {_TITLES[table]}")
        parts.append("\\begin{tabular}{lllll}")
        parts.append("\\toprule")
        parts.append(
            "Row & $F_L/X_L$ & $\\mathrm{Re}\\,N(j\\omega)D(-j\\omega)\\ge 0$ & Paper bound & Exact condition \\\\"
        )
        parts.append("\\midrule")
        for r in group:
            exact = r.exact_condition
            parts.append(
                f"{r.paper.name} & ${sp.latex(sp.factor(r.stiffness))}$ & ${sp.latex(r.condition)}$ & "
                f"{r.bound_status} & ${sp.latex(exact)}$ \\\\"
            )
        parts.append("\\bottomrule")
        parts.append("\\end{tabular}")
        parts.append("")
    return "\n".join(parts)


def format_text(rows: list[TableRow]) -> str:
    """Plain-text rendering for the terminal."""
    out: list[str] = []
    for table, group in _groups(rows).items():
        out.append(_TITLES[table])
        out.append("=" * len(_TITLES[table]))
        for r in group:
            d = r.to_dict()
            out.append(f"[{d['name']}]  D1={d['D1']}  D2={d['D2']}  C_A={d['CA']}  C_L={d['CL']}")
            out.append(f"  F_L/X_L (derived) : {d['stiffness']}")
            out.append(
                f"  F_L/X_L (paper)   : {d['paper_stiffness']}   agrees: {d['stiffness_agrees']}"
            )
            out.append(f"  condition (derived): {d['condition']}")
            out.append(f"  condition (paper)  : {d['paper_condition']}   agrees: {d['agrees']}")
            out.append(f"  paper's bound      : {d['paper_bound']}   -> {d['paper_bound_status']}")
            out.append(f"  exact condition    : {d['exact_condition']}")
            for note in d["notes"]:
                out.append(f"  note: {note}")
            out.append("")
    return "\n".join(out)
