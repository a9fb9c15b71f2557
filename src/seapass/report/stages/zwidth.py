"""Z-width maps (Colgate & Brown) in the reports: the passive region of two gains, sampled.

Each ``stage_*`` returns a [`Section`][seapass.report.document.Section]:
``stage_zwidth(quick)`` for the paper's rig (Ours, ``kd`` against ``bd`` at 500 Hz) and
``stage_design_zwidth(design, quick)`` for a design file with a ``[control] rate``.
Each computes its map, draws it with `zwidth_figures` and writes the section with
`zwidth_section` (python-control's ``*_response`` / ``*_plot`` split).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from ...errors import ModelError
from ...exact.rounding import decimal_down
from ...model.design_file import Design
from ...model.loop import SampledLoop
from ...model.sea import SEA
from ...plot.sampled import plot_zwidth
from ...rig.predictions import rig_sea
from ...rig.rigfile import paper_rig
from ...sampled.region import ZWidthMap, sampled_region
from ..document import (
    FigureData,
    Finding,
    Section,
    SectionStatus,
    Table,
    UpperEnd,
    Verdict,
    to_json,
)
from ..pipeline import StageContext

__all__ = ["stage_design_zwidth", "stage_zwidth", "zwidth_figures", "zwidth_section"]

_TEXT = (
    "The Z-width (Colgate & Brown, 1994) is the range of impedances a haptic device renders "
    "passively. Here: for each value of {p2} the passive set of {p1} is certified by branch "
    "and bound (`seapass.sampled.region`), for the ideal zero-order hold, {d} sample(s) of "
    "computational delay, and the delay plus the {f:g} Hz velocity filter. Only the spacing "
    "of the {n} rows is a sampling; every row is exact to its edge enclosures."
)


def _with_filter(loop: SampledLoop) -> SampledLoop:
    """``loop``, given a comparison velocity filter (50 Hz, below Nyquist) if it has none."""
    if loop.velocity_filter is not None:
        return loop
    return loop.replace(velocity_filter=min(50.0, 0.4 * loop.nyquist))


def zwidth_figures(key: str, zmap: ZWidthMap) -> tuple[FigureData, ...]:
    return (
        FigureData.of(key, f"Z-width: passive {zmap.p1} against {zmap.p2}.", plot_zwidth(zmap)),
    )


def zwidth_section(
    key: str,
    title: str,
    zmap: ZWidthMap,
    text: str,
    findings: tuple[Finding, ...],
    figures: Sequence[FigureData],
) -> Section:
    """The section of a Z-width map with the figures of `zwidth_figures`."""
    bounds = [zmap.upper_boundary(s.label) for s in zmap.setups]
    rows = tuple(
        (v, *(None if math.isnan(b[i]) else UpperEnd(float(b[i])) for b in bounds))
        for i, v in enumerate(zmap.p2_values)
    )
    table = Table(
        name=f"{key}_boundary",
        title=f"Largest passive {zmap.p1} per {zmap.p2} (T = {zmap.period * 1e3:g} ms)",
        columns=(zmap.p2, *(s.label for s in zmap.setups)),
        rows=rows,
        note="Full passive sets (islands included) per row in the CSV and JSON files.",
    )
    return Section(
        key=key,
        title=title,
        text=text,
        tables=(table,),
        figures=tuple(figures),
        findings=findings,
        files={f"{key}.csv": zmap.to_csv(), f"{key}.json": to_json(zmap.to_dict())},
    )


def stage_zwidth(context: StageContext) -> Section:
    """Ours on the paper's rig: passive ``kd`` against ``bd`` at the rig's rate."""
    rig = paper_rig()
    sea = rig_sea(rig, "ours", bd=rig.experiment.bd_ours).with_values(bd=None, kd=None)
    n = 5 if context.quick else 21
    loop = _with_filter(rig.loop)
    zmap = sampled_region(
        sea, "kd", "bd", loop=loop, p1_range=(0.0, 1e5), p2_range=(0.0, 100.0), n=n, rtol=1e-6,
        progress=context.progress,
    )  # fmt: skip
    ideal, _delayed, real = (zmap.upper_boundary(s.label) for s in zmap.setups)

    def down(v: float) -> str:  # a largest passive value, printed rounded down
        return "none" if math.isnan(v) else decimal_down(float(v), 5)

    bd0 = rig.experiment.bd_ours
    i = int(np.argmin(np.abs(np.asarray(zmap.p2_values) - bd0)))
    finding = Finding(
        "Damping widens the sampled Z-width (Colgate & Schenkel: K ≤ 2(b + B)/T-like growth "
        "for the damped transmission)",
        Verdict.INFO,
        f"largest passive kd grows from {down(ideal[0])} to {down(ideal[-1])} N/m (ideal ZOH) "
        f"and from {down(real[0])} to {down(real[-1])} N/m (rig delay and filter) as bd goes "
        f"0 → {zmap.p2_values[-1]:g} N·s/m; at bd ≈ {zmap.p2_values[i]:g} the rig limit is "
        f"{down(real[i])} N/m",
    )
    text = _TEXT.format(p1="kd", p2="bd", d=max(loop.delay, 1), f=loop.velocity_filter, n=n)
    title = f"Z-width of Ours at {1 / rig.period:g} Hz (beyond the paper)"
    return zwidth_section("zwidth", title, zmap, text, (finding,), zwidth_figures("zwidth", zmap))


def _first(text: str, name: str) -> int:
    found = re.search(rf"\b{re.escape(name)}\b", text)
    return found.start() if found else len(text)


def stage_design_zwidth(design: Design, context: StageContext) -> Section:
    """The design's first two controller gains against each other at its control rate.

    Budget: boxes of each row's branch and bound (a row that reaches it keeps its
    unsettled part undecided, never passive, and the stage is stopped at its budget).
    """
    title = "Z-width map (sampled-data passive region of two gains)"
    if design.loop is None:
        return Section("zwidth", title, status=SectionStatus.SKIPPED,
                       text="Skipped: the design file has no `[control] rate`.")  # fmt: skip
    # the gains in the order they are written (``kd + bd*s``: stiffness over damping)
    written = f"{design.CA} {design.CL}"
    gains = sorted(
        (g for g in design.analysis_ranges() if g in design.gains), key=lambda g: _first(written, g)
    )
    if len(gains) < 2:
        return Section("zwidth", title, status=SectionStatus.SKIPPED,
                       text="Skipped: the controllers have fewer than two gains to map.")  # fmt: skip
    p1, p2 = gains[0], gains[1]
    ranges = design.analysis_ranges()
    sea: SEA = design.sea().with_values(**{p1: None, p2: None})
    loop = _with_filter(design.loop)
    n = 5 if context.quick else 15
    budget: dict[str, Any] = {} if context.budget is None else {"max_boxes": context.budget}
    try:
        zmap = sampled_region(
            sea, p1, p2, loop=loop, p1_range=ranges[p1], p2_range=ranges[p2], n=n, rtol=1e-6,
            progress=context.progress, **budget,
        )  # fmt: skip
    except ModelError as exc:
        return Section("zwidth", title, status=SectionStatus.SKIPPED,
                       text=f"Skipped: the sampled-data test does not apply to this plant: {exc}")  # fmt: skip
    text = _TEXT.format(p1=p1, p2=p2, d=max(loop.delay, 1), f=loop.velocity_filter, n=n)
    if design.velocity_filter is None:
        text += (
            f" (The design has no velocity filter; {loop.velocity_filter:g} Hz is shown for "
            "comparison.)"
        )
    if zmap.budget_exhausted:
        text += (
            f"\n\n**Stopped at the budget of {context.budget} boxes per row**: on the rows "
            "that reached it, the part of the range the branch and bound did not settle is "
            "undecided (never passive; the largest passive value shown is proven); raise it "
            "with `--budget zwidth=N`."
        )
    sec = zwidth_section("zwidth", title, zmap, text, (), zwidth_figures("zwidth", zmap))
    if zmap.budget_exhausted:
        sec = replace(sec, status=SectionStatus.STOPPED_AT_BUDGET)
    return sec
