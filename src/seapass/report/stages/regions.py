"""Paper stage: the exact passive set of every row against the paper's bounds, with witnesses.

Split as python-control splits ``*_response`` from ``*_plot``: `regions_data`
computes (the exact sets, the paper's bounds judged as a
[`Discrepancy`][seapass.report.document.Discrepancy], the witnesses),
`regions_figures` draws and `regions_section` writes the
[`Section`][seapass.report.document.Section]; `stage_regions` runs the three.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from ...analysis.boundary import PassiveRegion, passive_region
from ...analysis.region import PassiveIntervals, PassiveMap, passive_intervals, passive_map
from ...analysis.witness import WitnessResult, find_destabilizing_environment
from ...errors import ParameterError
from ...exact.rounding import decimal_down
from ...model.catalog import PAPER_VALUES, REFERENCE_VALUES
from ...model.catalog import design as catalog_design
from ...model.sea import SEA
from ...paper.tables import PAPER_ROWS, PaperRow, paper_bound_set
from ...plot.region import plot_kd_bars, plot_passive_region
from ...plot.witness import plot_witness
from ...progress import Progress, ProgressLike, as_progress, task
from ..document import (
    Discrepancy,
    FigureData,
    Finding,
    Math,
    Section,
    Table,
    Verdict,
    format_intervals,
    formula,
    to_json,
)
from ..pipeline import StageContext

__all__ = [
    "REGION_VALUES",
    "KdRow",
    "RegionsData",
    "judge_bound",
    "regions_data",
    "regions_figures",
    "regions_section",
    "stage_regions",
]

REGION_VALUES: dict[str, float] = {**PAPER_VALUES, "b1": 20.0, "bd": 25.0}
"""The paper's parameters for the passive regions (Sec. V: m, b, k1; b1, bd as in Fig. 4's setup).
"""


Interval = tuple[float, float]

#: What the table says for each judgement of a paper's bound (None: it matches).
_JUDGEMENT_TEXT: Mapping[Discrepancy | None, str] = {
    None: "matches",
    Discrepancy.CONSERVATIVE: "conservative (sufficient only)",
    Discrepancy.UNSAFE: "UNSAFE: admits non-passive kd",
}
_KD_COLUMNS = ("row", "other values", "exact passive kd", "paper's bound admits", "paper's bound")
_B1_BOX, _KD_BOX = (0.0, 60.0), (0.0, 1500.0)


@dataclass(frozen=True, kw_only=True)
class KdRow:
    """One row of the paper: its exact passive set of ``kd`` against the set its bound admits.

    ``judgement`` is None when they match; ``admitted_not_passive`` is what the bound
    admits outside the exact set (empty unless the bound is unsafe).
    """

    row: PaperRow
    sea: SEA
    values: tuple[tuple[str, float], ...]
    exact: tuple[Interval, ...]
    admitted: tuple[Interval, ...]
    judgement: Discrepancy | None
    admitted_not_passive: tuple[Interval, ...]


@dataclass(frozen=True, kw_only=True)
class RegionsData:
    """Everything the regions stage computes (`regions_data`)."""

    hi: float
    kd_rows: tuple[KdRow, ...]
    lp_region: PassiveRegion
    lp_columns: PassiveMap
    proposed: PassiveIntervals
    witnesses: tuple[tuple[KdRow, float, WitnessResult], ...]


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


def _union(intervals: Sequence[tuple[float, float]]) -> Any:
    if not intervals:
        return sp.EmptySet
    return sp.Union(*[sp.Interval(sp.Float(a), sp.Float(b)) for a, b in intervals])


def judge_bound(exact: Sequence[Interval], paper: Any, hi: float) -> Discrepancy | None:
    """How the set a paper's bound admits (sympy set) differs from the exact passive set.

    ``UNSAFE`` when it admits non-passive values, ``CONSERVATIVE`` when it only rejects
    passive ones, None when they match (to ``1e-9·hi`` in measure).
    """
    ex = _union(exact)
    tol = 1e-9 * hi
    unsafe = _measure(_intervals_of(sp.Complement(paper, ex)))
    conservative = _measure(_intervals_of(sp.Complement(ex, paper)))
    if unsafe > tol:
        return Discrepancy.UNSAFE
    if conservative > tol:
        return Discrepancy.CONSERVATIVE
    return None


# ------------------------------------------------------------------ compute


def _kd_rows(hi: float, base: dict[str, float], progress: Progress) -> tuple[KdRow, ...]:
    """Every row's exact passive set of ``kd`` in ``[0, hi]`` against its bound."""
    out = []
    for row in PAPER_ROWS:
        progress.advance(1, note=f"passive kd of {row.name}")
        sea = row.design.sea()
        vals = {k: base[k] for k in sea.parameters if k != "kd"}
        res = passive_intervals(sea, "kd", 0.0, hi, values=vals)
        paper = paper_bound_set(row.bound, vals, 0.0, hi)
        judgement = judge_bound(res.intervals, paper, hi)
        bad: tuple[Interval, ...] = ()
        if judgement is Discrepancy.UNSAFE:
            bad = tuple(_intervals_of(sp.Complement(paper, _union(res.intervals))))
        out.append(
            KdRow(
                row=row, sea=sea, values=tuple(vals.items()), exact=res.intervals,
                admitted=tuple(_intervals_of(paper)), judgement=judgement,
                admitted_not_passive=bad,
            )
        )  # fmt: skip
    return tuple(out)


def _lp_bound(b1: Any) -> Any:
    """The paper's bound of load-side P with a damped spring: min(k1, (b² + b·b1)/m)."""
    m, b, k1 = PAPER_VALUES["m"], PAPER_VALUES["b"], PAPER_VALUES["k1"]
    return np.minimum(k1, (b**2 + b * np.asarray(b1, dtype=float)) / m)


def _witnesses(rows: Sequence[KdRow]) -> tuple[tuple[KdRow, float, WitnessResult], ...]:
    """For each bound that admits non-passive gains: a passive environment that destabilizes it."""
    out = []
    for r in rows:
        if not r.admitted_not_passive:
            continue
        a, b = r.admitted_not_passive[0]
        kd = float(f"{(a + b) / 2:.3g}")  # a round gain the paper's bound admits
        res = find_destabilizing_environment(r.sea.with_values(**dict(r.values), kd=kd))
        if res.found and res.environment is not None:
            out.append((r, kd, res))
    return tuple(out)


def regions_data(quick: bool, *, progress: ProgressLike = None) -> RegionsData:
    """The exact passive sets of every row, the load-side P region, the proposed design's
    passive set and the destabilizing environments of the unsafe bounds."""
    shown = as_progress(progress, where="regions_data")
    with task(shown, "exact passive regions", len(PAPER_ROWS) + 2):
        return _regions(quick, shown)


def _regions(quick: bool, progress: Progress) -> RegionsData:
    rows = _kd_rows(1e4, {**REFERENCE_VALUES, **REGION_VALUES}, progress)
    lp = catalog_design("mech/parallel-spring-damper").sea(PAPER_VALUES, b1=None)
    region = passive_region(lp, "b1", _B1_BOX, "kd", _KD_BOX, points=240 if quick else 480)
    progress.advance(1, note="kd × b1 region")
    # exact per column: the data file, and the largest passive kd the finding quotes
    b1s = np.linspace(*_B1_BOX, 13 if quick else 31)
    columns = passive_map(lp, "b1", b1s, "kd", _KD_BOX, y_points=2)
    ours = catalog_design("proposed").sea(REGION_VALUES)
    proposed = passive_intervals(ours, "kd", 0.0, 1e6)
    progress.advance(1, note="destabilizing environments")
    return RegionsData(
        hi=1e4, kd_rows=rows, lp_region=region, lp_columns=columns, proposed=proposed,
        witnesses=_witnesses(rows),
    )  # fmt: skip


# ------------------------------------------------------------------ figures


def _witness_stem(row: PaperRow) -> str:
    return f"witness_{row.name.replace('/', '_')}"


def regions_figures(data: RegionsData) -> tuple[FigureData, ...]:
    """The kd bars, the load-side P region and the growing response of every witness."""
    bars = [(r.row.name, r.exact, r.admitted) for r in data.kd_rows]
    figures = [
        FigureData.of(
            "passive_kd",
            "Exact passive kd of every row vs the paper's bound.",
            plot_kd_bars(bars, hi=data.hi, title="Passive kd at m=1, b=10, k1=1000, b1=20, bd=25"),
        )
    ]
    fine = np.linspace(*_B1_BOX, 241)
    figures.append(
        FigureData.of(
            "passive_map_lp_b1",
            "Load-side P with a damped spring: the exact passive region over (b1, kd), bounded "
            "by its exact boundary curves (zero sets of the critical polynomials), and the "
            "paper's sufficient bound.",
            plot_passive_region(
                data.lp_region,
                paper_bound=(fine, _lp_bound(fine)),
                title="Load-side P, D1 = k1 + b1 s (m = 1, b = 10, k1 = 1000)",
            ),
        )
    )
    for r, kd, res in data.witnesses:
        if res.simulation is not None:
            figures.append(
                FigureData.of(
                    _witness_stem(r.row),
                    f"{r.row.title} at kd = {kd:g} N/m, admitted by the paper's bound "
                    f"{formula(r.row.bound)}: coupled to a passive environment it grows without "
                    "bound.",
                    plot_witness(res),
                )
            )
    return tuple(figures)


# ------------------------------------------------------------------ section


def _kd_table(data: RegionsData) -> Table:
    rows = [
        (r.row.name, ", ".join(f"{k}={v:g}" for k, v in r.values),
         format_intervals(r.exact, data.hi), format_intervals(r.admitted, data.hi),
         _JUDGEMENT_TEXT[r.judgement])
        for r in data.kd_rows
    ]  # fmt: skip
    flags = {(i, "paper's bound") for i, r in enumerate(data.kd_rows) if r.judgement is not None}
    return Table(
        name="passive_kd",
        title=f"Exact passive set of kd in [0, {data.hi:g}] N/m vs the paper's bound",
        columns=_KD_COLUMNS,
        rows=tuple(rows),
        highlight=frozenset(flags),
    )


def _lp_finding(columns: PassiveMap) -> tuple[Finding, str]:
    """Load-side P with a damped spring (Table I, row 3) over (b1, kd): the finding and CSV."""
    b1s = columns.x
    top = [max((b for _a, b in ivs), default=0.0) for ivs in columns.intervals]
    gap = [t - float(_lp_bound(x)) for x, t in zip(b1s, top, strict=True)]
    finding = Finding(
        f"Load-side P with a damped spring: passive iff {formula('kd <= k1')} and "
        f"{formula('kd <= (b**2 + b*b1)/m')} (Table I, row 3)",
        Verdict.DIFFERS if max(gap) > 1e-6 else Verdict.AGREES,
        f"the paper's bound is sufficient only: the exact largest passive kd exceeds it by up "
        f"to {max(gap):.4g} N/m over b1 ∈ [0, 60] (e.g. b1 = {b1s[-1]:g}: exact "
        f"{decimal_down(top[-1], 6)} N/m vs bound {float(_lp_bound(b1s[-1])):.6g} N/m)",
        kind=Discrepancy.CONSERVATIVE if max(gap) > 1e-6 else None,
    )
    lines = ["b1_Ns_per_m,kd_lo_N_per_m,kd_hi_N_per_m,paper_bound_N_per_m"]
    for x, ivs in zip(b1s.tolist(), columns.intervals, strict=True):
        pb = float(_lp_bound(x))
        for a, b in ivs or [(math.nan, math.nan)]:
            lines.append(f"{x!r},{a!r},{b!r},{pb!r}")
    return finding, "\n".join(lines) + "\n"


def _proposed_finding(wide: PassiveIntervals) -> Finding:
    return Finding(
        "The proposed design (damped spring + actuator-side PD) is passive for all kd",
        Verdict.AGREES if wide.passive_everywhere else Verdict.DIFFERS,
        f"exact passive set of kd in [0, 1e6] at m=1, b=10, k1=1000, b1=20, bd=25: "
        f"{format_intervals(wide.intervals, 1e6)}; the paper's printed bound for this row, "
        f"{formula('kd <= ((b + bd)**2 + b*b1 + b1*bd)/(2*m)')}, is therefore not needed",
    )


def _witness_parts(data: RegionsData) -> tuple[tuple[Table, ...], list[Finding], dict[str, str]]:
    """The table, findings and files of the destabilizing environments."""
    rows, findings, files = [], [], {}
    for r, kd, res in data.witnesses:
        env = res.environment
        assert env is not None
        rate = res.coupled.max_real_part if res.coupled is not None else math.nan
        row = r.row
        rows.append((row.name, Math(row.bound), kd, env.mass, env.damping, env.stiffness, rate))
        files[f"{_witness_stem(row)}.json"] = to_json(res.to_dict())
        findings.append(
            Finding(
                f"{row.title}: every kd the paper's bound {formula(row.bound)} admits is safe",
                Verdict.DIFFERS,
                f"kd = {kd:g} N/m satisfies the bound but the design is not passive; the passive "
                f"environment m_e = {env.mass:.4g} kg, b_e = {env.damping:.4g} N·s/m, "
                f"k_e = {env.stiffness:.4g} N/m makes the coupled system unstable "
                f"(growth rate {rate:.4g} 1/s)",
                kind=Discrepancy.UNSAFE,
            )
        )
    if not rows:
        return (), findings, files
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
    return (table,), findings, files


def regions_section(data: RegionsData, figures: Sequence[FigureData]) -> Section:
    """The section of `regions_data` with the figures of `regions_figures`."""
    region_finding, map_csv = _lp_finding(data.lp_columns)
    witness_tables, witness_findings, witness_files = _witness_parts(data)
    return Section(
        key="regions",
        title="Exact passive regions vs the paper's bounds",
        text=(
            "Each passive set is exact: the verdict can only change at a real root of a "
            "finite set of polynomials in the parameter (leading coefficients, resultants, "
            "discriminants of `Re N(jω)D(−jω)`), and one exact rational test per gap decides "
            "it (`seapass.analysis.region.passive_intervals`). Over two parameters the same "
            "polynomials, in both, are curves that carry the boundary; the map is a "
            "cylindrical decomposition along them, one exact test per cell "
            "(`seapass.analysis.boundary.passive_region`). Values: `m = 1, b = 10, k1 = 1000, "
            "b1 = 20, bd = 25` (paper, Sec. V) and `k2 = 1000, b2 = 20, ki = 100`. Where the "
            "paper's bound admits a gain that is not passive, seapass exhibits a passive "
            "mass-spring-damper environment that destabilizes it "
            "(`seapass.analysis.witness.find_destabilizing_environment`, verified exactly)."
        ),
        tables=(_kd_table(data), *witness_tables),
        figures=tuple(figures),
        findings=(region_finding, _proposed_finding(data.proposed), *witness_findings),
        files={
            "passive_map_lp_b1.csv": map_csv,
            "passive_proposed.json": to_json(data.proposed.to_dict()),
            **witness_files,
        },
    )


def stage_regions(context: StageContext) -> Section:
    """The exact passive set of ``kd`` of every row against the paper's bound, and 2-D maps."""
    data = regions_data(context.quick, progress=context.progress)
    return regions_section(data, regions_figures(data))
