"""Core stages of :func:`seapass.reproduce.reproduce`: Tables I/II, stiffness responses, passive regions.

Each ``stage_*(quick)`` returns a :class:`~seapass.report.document.Section`; they need
only the core analysis modules (model, stiffness, passivity, region, tables).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import sympy as sp

from ...errors import ParameterError
from ..document import FigureData, Finding, Section, Table, figure_png, format_intervals, to_json

__all__ = ["PAPER_VALUES", "stage_regions", "stage_stiffness", "stage_tables"]

#: The paper's parameters for the passive regions (Sec. V: m, b, k1; b1, bd as in Fig. 4's setup).
PAPER_VALUES: dict[str, float] = {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 20.0, "bd": 25.0}


def _code(text: Any) -> str:
    return f"`{text}`"


# ----------------------------------------------------------------- tables


def stage_tables(quick: bool) -> Section:
    from ...paper.tablefmt import format_latex, format_markdown
    from ...paper.tables import build_tables

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
                findings.append(Finding(f"{p.title} ({p.name})", "differs", "; ".join(r.notes)))
            else:
                findings.append(
                    Finding(
                        f"{p.title} ({p.name})",
                        "agrees",
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
    n_bad = sum(1 for f in findings if f.verdict == "differs")
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


# ----------------------------------------------------------------- stiffness


def _paper_seas() -> list[tuple[Any, Any]]:
    from ...model.sea import SEA
    from ...paper.tables import PAPER_ROWS

    return [
        (row, SEA(D1=row.D1, D2=row.D2, CA=row.CA, CL=row.CL, name=row.name)) for row in PAPER_ROWS
    ]


def stage_stiffness(quick: bool) -> Section:
    import matplotlib.pyplot as plt

    from ...analysis.freqresp import stiffness_response
    from ...plot.analysis import plot_stiffness_response
    from ...paper.tables import REFERENCE_VALUES

    omega = np.logspace(-1, 4, 200 if quick else 400)
    results = []
    for row, sea in _paper_seas():
        vals = {k: REFERENCE_VALUES[k] for k in sea.parameters}
        results.append((row, vals, stiffness_response(sea, omega, values=vals, label=row.title)))
    figures = []
    for key, title in (("I", "Table I"), ("II", "Table II"), ("proposed", "Proposed design")):
        group = [r for r in results if r[0].table == key]
        ncol = min(3, len(group))
        nrow = math.ceil(len(group) / ncol)
        fig, axes = plt.subplots(
            nrow,
            ncol,
            figsize=(max(5.0 * ncol, 7.0), 3.9 * nrow + 0.4),
            squeeze=False,
            constrained_layout=True,
        )
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
                figure_png(fig),
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


# ----------------------------------------------------------------- regions


def _bound_set(bound_text: str, values: dict[str, float], lo: float, hi: float) -> Any:
    """The set of ``kd`` in ``[lo, hi]`` that the paper's bound admits (sympy set)."""
    from ...model.expr import symbol
    from ...paper.tables import _parse_bound

    bound = _parse_bound(bound_text)
    kd = symbol("kd")
    dom = sp.Interval(sp.Rational(lo), sp.Rational(hi))
    if bound in (sp.true, sp.false):
        return dom if bound == sp.true else sp.EmptySet
    subs = {symbol(k): sp.Rational(str(v)) for k, v in values.items() if k != "kd"}
    out: Any = dom
    for rel in sp.And.make_args(bound.xreplace(subs)):
        if rel in (sp.true, sp.false):
            out = out if rel == sp.true else sp.EmptySet
            continue
        out = sp.Intersection(out, sp.solveset(rel, kd, domain=dom))
    return out


def _intervals_of(s: Any) -> list[tuple[float, float]]:
    if s == sp.EmptySet:
        return []
    if isinstance(s, sp.Interval):
        return [(float(s.start), float(s.end))]
    if isinstance(s, sp.FiniteSet):
        return [(float(x), float(x)) for x in s]
    if isinstance(s, sp.Union):
        return [iv for a in s.args for iv in _intervals_of(a)]
    raise ParameterError(f"cannot convert {s} to intervals")


def _measure(ivs: Sequence[tuple[float, float]]) -> float:
    return float(sum(b - a for a, b in ivs))


def _compare(exact: list[tuple[float, float]], paper: Any, hi: float) -> str:
    ex = (
        sp.Union(*[sp.Interval(sp.Float(a), sp.Float(b)) for a, b in exact])
        if exact
        else sp.EmptySet
    )
    tol = 1e-9 * hi
    unsafe = _measure(_intervals_of(sp.Complement(paper, ex)))
    conservative = _measure(_intervals_of(sp.Complement(ex, paper)))
    if unsafe > tol:
        return "UNSAFE: admits non-passive kd"
    if conservative > tol:
        return "conservative (sufficient only)"
    return "matches"


def stage_regions(quick: bool) -> Section:

    from ...model.sea import SEA
    from ...plot.analysis import plot_passive_map
    from ...analysis.region import passive_intervals, passive_map
    from ...paper.tables import REFERENCE_VALUES

    hi = 1e4
    base = {**REFERENCE_VALUES, **PAPER_VALUES}
    rows, findings, flags, bars = [], [], set(), []
    unsafe: list[tuple[Any, Any, dict[str, float], list[tuple[float, float]]]] = []
    for i, (row, sea) in enumerate(_paper_seas()):
        vals = {k: base[k] for k in sea.parameters if k != "kd"}
        res = passive_intervals(sea, "kd", 0.0, hi, values=vals)
        paper = _bound_set(row.bound, vals, 0.0, hi)
        verdict = _compare(res.intervals, paper, hi)
        if verdict != "matches":
            flags.add((i, 4))
        if verdict.startswith("UNSAFE"):
            unsafe.append(
                (row, sea, vals, _intervals_of(sp.Complement(paper, _union(res.intervals))))
            )
        bars.append((row.name, res.intervals, _intervals_of(paper)))
        rows.append(
            (
                row.name,
                ", ".join(f"{k}={v:g}" for k, v in vals.items()),
                format_intervals(res.intervals, hi),
                format_intervals(_intervals_of(paper), hi),
                verdict,
            )
        )
    table = Table(
        name="passive_kd",
        title=f"Exact passive set of kd in [0, {hi:g}] N/m vs the paper's bound",
        columns=(
            "row",
            "other values",
            "exact passive kd",
            "paper's bound admits",
            "paper's bound",
        ),
        rows=tuple(rows),
        highlight=frozenset(flags),
    )
    fig_bars = _plot_kd_bars(bars, hi)
    # kd x b1 map of load-side P with a damped spring, the paper's Table I row 3
    lp = SEA(D1="k1 + b1*s", CL="kd", values={"m": 1.0, "b": 10.0, "k1": 1000.0}, name="LP")
    b1s = np.linspace(0.0, 60.0, 13 if quick else 31)
    pmap = passive_map(lp, "b1", b1s, "kd", (0.0, 1500.0), y_points=200 if quick else 400)
    m_, b_, k1_ = 1.0, 10.0, 1000.0
    fine = np.linspace(0.0, 60.0, 241)
    bound = np.minimum(k1_, (b_**2 + b_ * fine) / m_)
    fig_map = plot_passive_map(
        pmap,
        paper_bound=(fine, bound),
        title="Load-side P, D1 = k1 + b1 s (m = 1, b = 10, k1 = 1000)",
        units=("[N·s/m]", "[N/m]"),
    )
    fig_map.axes[0].set_xlabel("transmission damping b1 [N·s/m]")
    fig_map.axes[0].set_ylabel("load-side gain kd [N/m]")
    top = [max((b for _a, b in ivs), default=0.0) for ivs in pmap.intervals]
    gap = [t - min(k1_, (b_**2 + b_ * x) / m_) for x, t in zip(b1s, top, strict=True)]
    findings.append(
        Finding(
            "Load-side P with a damped spring: passive iff kd ≤ k1 and kd ≤ (b² + b·b1)/m (Table I, row 3)",
            "differs" if max(gap) > 1e-6 else "agrees",
            f"the paper's bound is sufficient only: the exact largest passive kd exceeds it by up "
            f"to {max(gap):.4g} N/m over b1 ∈ [0, 60] (e.g. b1 = {b1s[-1]:g}: exact "
            f"{top[-1]:.6g} N/m vs bound {min(k1_, (b_**2 + b_ * b1s[-1]) / m_):.6g} N/m)",
        )
    )
    ours = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=PAPER_VALUES, name="proposed")
    wide = passive_intervals(ours, "kd", 0.0, 1e6)
    findings.append(
        Finding(
            "The proposed design (damped spring + actuator-side PD) is passive for all kd",
            "agrees" if wide.passive_everywhere else "differs",
            f"exact passive set of kd in [0, 1e6] at m=1, b=10, k1=1000, b1=20, bd=25: "
            f"{format_intervals(wide.intervals, 1e6)}; the paper's printed bound for this row, "
            "kd ≤ ((b+bd)² + b·b1 + b1·bd)/(2m), is therefore not needed",
        )
    )
    witness_tables, witness_figures, witness_files = _unsafe_witnesses(unsafe, findings)
    map_lines = ["b1_Ns_per_m,kd_lo_N_per_m,kd_hi_N_per_m,paper_bound_N_per_m"]
    for x, ivs in zip(b1s.tolist(), pmap.intervals, strict=True):
        pb = min(k1_, (b_**2 + b_ * x) / m_)
        for a, b in ivs or [(math.nan, math.nan)]:
            map_lines.append(f"{x!r},{a!r},{b!r},{pb!r}")
    return Section(
        key="regions",
        title="Exact passive regions vs the paper's bounds",
        text=(
            "Each passive set is exact: the verdict can only change at a real root of a "
            "finite set of polynomials in the parameter (leading coefficients, resultants, "
            "discriminants of `Re N(jω)D(−jω)`), and one exact rational test per gap decides "
            "it (`seapass.analysis.region.passive_intervals`). Values: `m = 1, b = 10, k1 = 1000, "
            "b1 = 20, bd = 25` (paper, Sec. V) and `k2 = 1000, b2 = 20, ki = 100`. Where the "
            "paper's bound admits a gain that is not passive, seapass exhibits a passive "
            "mass-spring-damper environment that destabilizes it "
            "(`seapass.analysis.witness.find_destabilizing_environment`, verified exactly)."
        ),
        tables=(table, *witness_tables),
        figures=(
            FigureData(
                "passive_kd", "Exact passive kd of every row vs the paper's bound.", fig_bars
            ),
            FigureData(
                "passive_map_lp_b1",
                "Load-side P with a damped spring: exact passive region over (b1, kd) "
                "and the paper's sufficient bound.",
                figure_png(fig_map),
            ),
            *witness_figures,
        ),
        findings=tuple(findings),
        files={
            "passive_map_lp_b1.csv": "\n".join(map_lines) + "\n",
            "passive_proposed.json": to_json(wide.to_dict()),
            **witness_files,
        },
    )


def _plot_kd_bars(
    bars: list[tuple[str, list[tuple[float, float]], list[tuple[float, float]]]], hi: float
) -> bytes:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.5, 0.45 * len(bars) + 1.6), constrained_layout=True)
    for i, (_name, exact, paper) in enumerate(bars):
        y = len(bars) - 1 - i
        for a, b in exact:
            ax.barh(y + 0.15, max(b - a, hi * 2e-3), left=a, height=0.3, color="#2e7d32")
        for a, b in paper:
            ax.barh(y - 0.15, max(b - a, hi * 2e-3), left=a, height=0.3, color="0.55", hatch="//")
    from matplotlib.patches import Patch

    handles = [
        Patch(color="#2e7d32", label="exact passive set"),
        Patch(facecolor="0.55", hatch="//", label="paper's bound admits"),
    ]
    ax.set_yticks(range(len(bars)), [b[0] for b in reversed(bars)])
    ax.set_xscale("symlog", linthresh=100.0)
    ax.set_xlim(0, hi)
    ax.set_xlabel("controller stiffness kd [N/m] (symlog scale)")
    ax.set_title("Passive kd at m=1, b=10, k1=1000, b1=20, bd=25")
    ax.grid(True, axis="x", alpha=0.3)
    # rows 6-7 (load-side PD/PI) are never passive: the legend sits in their empty band
    ax.legend(handles=handles, loc="center right", bbox_to_anchor=(1.0, 0.45), fontsize=9)
    return figure_png(fig)


def _union(intervals: Sequence[tuple[float, float]]) -> Any:
    if not intervals:
        return sp.EmptySet
    return sp.Union(*[sp.Interval(sp.Float(a), sp.Float(b)) for a, b in intervals])


def _unsafe_witnesses(
    unsafe: list[tuple[Any, Any, dict[str, float], list[tuple[float, float]]]],
    findings: list[Finding],
) -> tuple[tuple[Table, ...], tuple[FigureData, ...], dict[str, str]]:
    """For each bound that admits non-passive gains: a passive environment that destabilizes it."""
    try:
        from ...plot.witness import plot_witness
        from ...analysis.witness import find_destabilizing_environment
    except ImportError:
        return (), (), {}
    rows, figures, files = [], [], {}
    for row, sea, vals, bad in unsafe:
        if not bad:
            continue
        a, b = bad[0]
        kd = float(f"{(a + b) / 2:.3g}")  # a round gain the paper's bound admits
        res = find_destabilizing_environment(sea.with_values(**vals, kd=kd))
        if not res.found or res.environment is None:
            continue
        env = res.environment
        rate = res.coupled.max_real_part if res.coupled is not None else math.nan
        stem = f"witness_{row.name.replace('/', '_')}"
        rows.append((row.name, row.bound, kd, env.mass, env.damping, env.stiffness, rate))
        files[f"{stem}.json"] = to_json(res.to_dict())
        if res.simulation is not None:
            figures.append(
                FigureData(
                    stem,
                    f"{row.title} at kd = {kd:g} N/m, admitted by the paper's bound "
                    f"{row.bound}: coupled to a passive environment it grows without bound.",
                    figure_png(plot_witness(res)),
                )
            )
        findings.append(
            Finding(
                f"{row.title}: every kd the paper's bound {row.bound} admits is safe",
                "differs",
                f"kd = {kd:g} N/m satisfies the bound but the design is not passive; the passive "
                f"environment m_e = {env.mass:.4g} kg, b_e = {env.damping:.4g} N·s/m, "
                f"k_e = {env.stiffness:.4g} N/m makes the coupled system unstable "
                f"(growth rate {rate:.4g} 1/s)",
            )
        )
    if not rows:
        return (), tuple(figures), files
    table = Table(
        name="unsafe_bounds",
        title="Gains the paper's bound admits, destabilized by a passive environment",
        columns=(
            "row",
            "paper's bound",
            "kd [N/m]",
            "environment mass [kg]",
            "environment damping [N·s/m]",
            "environment stiffness [N/m]",
            "growth rate [1/s]",
        ),
        rows=tuple(rows),
    )
    return (table,), tuple(figures), files
