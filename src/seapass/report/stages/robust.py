"""The ``robust`` stage of ``seapass analyze``: passive for every plant of ``[uncertainty]``.

When the design file has an ``[uncertainty]`` table (or ``analyze --robust``
gave a box), the stage decides the design over the whole box
([`robust_check`][seapass.robust.verdict.robust_check]) and gives the **robust
gain ranges**: for every gain of the ranges stage (``analysis_ranges``, the
uncertain names left out) the values for which the design is passive for every
plant in the box
([`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals]):
exact for one uncertain parameter, a certified inner set (and outer set) for
several.  Budget: boxes of the certified branch and bound per verdict (counted);
one that runs out leaves that verdict undecided, never passive.

With a loop latency (``[control] delay_time``) the verdict is the certified delayed one
at the latency, the stage adds the robust delay margin, and the gain ranges are the
certified robust delayed gain sets at the latency
([`seapass.robust.delayedgains`][seapass.robust.delayedgains]) at the coarse relative
tolerance `RANGE_RTOL`, each bounded by `RANGE_CELLS_FULL` (``--quick``:
`RANGE_CELLS_QUICK`) cells of its certificates together; a gain whose cells run out
reports what was certified until then (``exhausted``), possibly nothing.
"""

from __future__ import annotations

from typing import Any

from ...exact.rounding import enclosure_text, exact_text, interval_text
from ...model.design_file import Design
from ...model.latency import LATENCY_PARAMETER
from ...outcome import Outcome
from ...progress import ProgressLike, as_progress, task
from ...robust.box import UncertainBox, uncertain_box
from ...robust.intervals import robust_passive_intervals
from ...robust.verdict import DEFAULT_BUDGET, Method, robust_check
from ..document import Finding, Section, SectionStatus, Table, Verdict, to_json
from ..pipeline import StageContext

__all__ = [
    "BUDGET_FULL", "BUDGET_QUICK", "COMPUTES", "RANGE_CELLS_FULL", "RANGE_CELLS_QUICK",
    "RANGE_RTOL", "robust_data", "stage_robust",
]  # fmt: skip

COMPUTES = "with [uncertainty]: the verdict for every plant in the box, robust gain ranges"
"""What the stage computes (``analyze --help``)."""

BUDGET_FULL, BUDGET_QUICK = DEFAULT_BUDGET, 1000
"""Boxes of the certified branch and bound per verdict (full, ``--quick``)."""

RANGE_RTOL = 1e-2
"""Relative tolerance of the robust gain sets at a loop latency (``seapass bound`` uses 1e-3)."""

RANGE_CELLS_FULL, RANGE_CELLS_QUICK = 40_000, 20_000
"""Cells of all certificates of one robust gain set at a loop latency (full, ``--quick``)."""

TITLE = "Robust passivity over the [uncertainty] box"


def robust_data(
    design: Design, *, budget: int = DEFAULT_BUDGET, max_cells: int = RANGE_CELLS_FULL,
    progress: ProgressLike = None,
) -> dict[str, Any]:  # fmt: skip
    """The box verdict and the robust passive set of every gain, as JSON-ready data.

    With ``delay_time`` the sets are at the latency, at `RANGE_RTOL`, each bounded by
    ``max_cells`` cells; ``progress`` gets one task with a step per gain.

    Raises
    ------
    ParameterError
        When the design has no ``[uncertainty]`` table.
    """
    from ...errors import ParameterError

    if not design.uncertainty:
        raise ParameterError("the design has no [uncertainty] table")
    sea = design.sea()
    box = uncertain_box(sea, dict(design.uncertainty))
    shown = as_progress(progress, where="robust_data")
    if design.delay_time:
        return _delayed_data(design, box, budget=budget, max_cells=max_cells, shown=shown)
    verdict = robust_check(sea, box=box, budget=budget)
    return {"box": box.to_dict(), "verdict": verdict.to_dict(),
            "ranges": _ranges(design, sea, box, budget=budget, shown=shown)}  # fmt: skip


def _ranges(
    design: Design, sea: Any, box: UncertainBox, *, budget: int, shown: Any, **options: Any
) -> list[dict[str, Any]]:
    """The robust passive set of every gain of ``analysis_ranges`` not in the box."""
    todo = [(n, r) for n, r in design.analysis_ranges().items() if n not in box.intervals]
    out = []
    with task(shown, f"robust passive sets of {len(todo)} gain(s)", len(todo)):
        for name, (lo, hi) in todo:
            free = sea.with_values(**{name: None})
            r = robust_passive_intervals(free, name, lo, hi, box=box, budget=budget, **options)
            out.append(r.to_dict() | {"nominal": design.values.get(name)})
            shown.advance(1, note=name)
    return out


def _delayed_data(
    design: Design, box: UncertainBox, *, budget: int, max_cells: int, shown: Any
) -> dict[str, Any]:
    """With a loop latency: the box verdict at ``delay_time``, the robust delay margin
    (`seapass.robust.delayed`) and the robust gain sets at the latency (`seapass bound`'s,
    at `RANGE_RTOL` and at most ``max_cells`` cells per gain)."""
    from ...robust.delayed import DEFAULT_DELAY_BUDGET, robust_delay_margin

    cells = DEFAULT_DELAY_BUDGET if budget == DEFAULT_BUDGET else budget
    delayed = design.delayed_sea()
    verdict = robust_check(delayed, box=box, budget=budget)
    margin = robust_delay_margin(design, LATENCY_PARAMETER, box=box, budget=cells)
    ranges = _ranges(design, delayed, box, budget=budget, shown=shown, rtol=RANGE_RTOL,
                     max_cells=max_cells)  # fmt: skip
    return {
        "box": box.to_dict(),
        "verdict": verdict.to_dict(),
        "delay_margin": margin.to_dict(),
        "ranges": ranges,
        "ranges_rtol": RANGE_RTOL,
        "ranges_max_cells": max_cells,
        "ranges_note": f"certified at the loop latency ({design.delay_time:g} s) and at the "
        f"coarse relative tolerance {RANGE_RTOL:g} (at most {max_cells:,} cells per gain; a gain "
        "that runs out keeps what was certified); for tighter sets run `seapass bound NAME "
        "DESIGN.toml --rtol 1e-3` (it uses the file's [uncertainty] and delay_time)",
    }


def stage_robust(design: Design, context: StageContext) -> Section:
    """The robust verdict and gain ranges (skipped without ``[uncertainty]``)."""
    if not design.uncertainty:
        return Section(
            "robust", TITLE, status=SectionStatus.SKIPPED,
            text="Skipped: the design file has no `[uncertainty]` table (e.g. `m = [0.9, 1.1]`); "
            "add one, or run `seapass analyze FILE --robust FITTED_RIG.toml`.",
        )  # fmt: skip
    budget = context.budget_or(BUDGET_QUICK if context.quick else BUDGET_FULL)
    cells = RANGE_CELLS_QUICK if context.quick else RANGE_CELLS_FULL
    data = robust_data(design, budget=budget, max_cells=cells, progress=context.progress)
    v = data["verdict"]
    span = ", ".join(
        f"`{k}` ∈ [{exact_text(a)}, {exact_text(b)}]" for k, (a, b) in data["box"].items()
    )
    rows = []
    for r in data["ranges"]:
        inner = ", ".join(interval_text(a, b, digits=8) for a, b in r["intervals"]) or "none"
        outer = ", ".join(enclosure_text(a, b, digits=8) for a, b in r["outer"]) or "none"
        method = r["method"] + (" (cells ran out)" if r.get("exhausted") else "")
        rows.append((r["param"], r["nominal"], f"[{r['range'][0]:g}, {r['range'][1]:g}]",
                     inner, outer if r["method"] != Method.EXACT else "(exact)", method))  # fmt: skip
    latency = (
        f" At the loop latency {design.delay_time:g} s the sets are certified at that latency, "
        f"at the coarse relative tolerance {data['ranges_rtol']:g} (`seapass bound NAME FILE "
        "--rtol 1e-3` gives tighter ones); a gain whose cells ran out shows only what was "
        "certified."
        if "delay_margin" in data
        else ""
    )
    table = Table(
        name="robust_ranges",
        title="Gain values passive for every plant in the box (the others at their values)",
        columns=("parameter", "value", "searched", "robust passive set", "outer set", "method"),
        rows=tuple(rows),
        note="Ends rounded inward: a printed end is itself robustly passive. "
        + (
            "At the latency every set is a certified inner set"
            if "delay_margin" in data
            else "With several uncertain parameters the set is a certified inner set"
        )
        + "; no value outside the outer set is robustly passive."
        + latency,
    )
    status = Outcome(v["status"])
    at_latency = f" at the loop latency {design.delay_time:g} s" if design.delay_time else ""
    text = (
        f"Over the box {span}: **{status.replace('_', ' ')}** for every plant{at_latency} "
        f"({v['method']}; {v['detail']})."
    )
    if "delay_margin" in data:
        dm = data["delay_margin"]
        lo, hi = dm["tau_star"] if dm.get("tau_star") else (None, None)
        text += (
            f" Robust delay margin over the box: τ* ∈ [{lo:.6g}, {hi:.6g}] s "
            f"({dm['status'].replace('_', ' ')}; the lower end holds for every plant)."
            if lo is not None and hi is not None
            else f" Robust delay margin over the box: {dm['status'].replace('_', ' ')}."
        )
        text += f" Robust gain ranges (table) {data['ranges_note']}."
    if v["worst"] is not None:
        at = ", ".join(f"`{k}` = {x:.10g}" for k, x in v["worst"]["values"].items())
        text += f" Worst plant: {at} (verified not passive by the exact test)."
    claim = f"{design.name} is passive for every plant in the box"
    verdict = Verdict.AGREES if status is Outcome.PASSIVE else Verdict.INFO
    undecided = status is Outcome.UNDECIDED or any(r.get("exhausted") for r in data["ranges"])
    return Section(
        "robust", TITLE, text=text, tables=(table,),
        findings=(Finding(claim, verdict, v["detail"]),),
        files={"robust.json": to_json(data)},
        status=SectionStatus.STOPPED_AT_BUDGET if undecided else SectionStatus.OK,
    )  # fmt: skip
