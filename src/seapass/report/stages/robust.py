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
"""

from __future__ import annotations

from typing import Any

from ...exact.rounding import enclosure_text, exact_text, interval_text
from ...model.design_file import Design
from ...model.latency import LATENCY_PARAMETER
from ...outcome import Outcome
from ...robust.box import UncertainBox, uncertain_box
from ...robust.intervals import robust_passive_intervals
from ...robust.verdict import DEFAULT_BUDGET, Method, robust_check
from ..document import Finding, Section, SectionStatus, Table, Verdict, to_json
from ..pipeline import StageContext

__all__ = ["BUDGET_FULL", "BUDGET_QUICK", "COMPUTES", "robust_data", "stage_robust"]

COMPUTES = "with [uncertainty]: the verdict for every plant in the box, robust gain ranges"
"""What the stage computes (``analyze --help``)."""

BUDGET_FULL, BUDGET_QUICK = DEFAULT_BUDGET, 1000
"""Boxes of the certified branch and bound per verdict (full, ``--quick``)."""

TITLE = "Robust passivity over the [uncertainty] box"


def robust_data(design: Design, *, budget: int = DEFAULT_BUDGET) -> dict[str, Any]:
    """The box verdict and the robust passive set of every gain, as JSON-ready data.

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
    if design.delay_time:
        return _delayed_data(design, box, budget=budget)
    verdict = robust_check(sea, box=box, budget=budget)
    ranges = []
    for name, (lo, hi) in design.analysis_ranges().items():
        if name in box.intervals:
            continue
        free = sea.with_values(**{name: None})
        r = robust_passive_intervals(free, name, lo, hi, box=box, budget=budget)
        ranges.append(r.to_dict() | {"nominal": design.values.get(name)})
    return {"box": box.to_dict(), "verdict": verdict.to_dict(), "ranges": ranges}


def _delayed_data(design: Design, box: UncertainBox, *, budget: int) -> dict[str, Any]:
    """With a loop latency: the box verdict at ``delay_time`` and the robust delay margin
    (`seapass.robust.delayed`); the robust gain sets at the latency (`seapass bound`) are
    too slow for a report stage, so none are given (``ranges_note`` says why)."""
    from ...robust.delayed import DEFAULT_DELAY_BUDGET, robust_delay_margin

    cells = DEFAULT_DELAY_BUDGET if budget == DEFAULT_BUDGET else budget
    verdict = robust_check(design.delayed_sea(), box=box, budget=budget)
    margin = robust_delay_margin(design, LATENCY_PARAMETER, box=box, budget=cells)
    return {
        "box": box.to_dict(),
        "verdict": verdict.to_dict(),
        "delay_margin": margin.to_dict(),
        "ranges": [],
        "ranges_note": f"not computed here: at the loop latency ({design.delay_time:g} s) each "
        "robust gain set is a certified bisection over gain x box (8 s to over a minute of CPU "
        "per gain, measured in benchmarks/); run `seapass bound NAME DESIGN.toml` for the gain "
        "you need (it uses the file's [uncertainty] and delay_time)",
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
    data = robust_data(design, budget=budget)
    v = data["verdict"]
    span = ", ".join(
        f"`{k}` ∈ [{exact_text(a)}, {exact_text(b)}]" for k, (a, b) in data["box"].items()
    )
    rows = []
    for r in data["ranges"]:
        inner = ", ".join(interval_text(a, b, digits=8) for a, b in r["intervals"]) or "none"
        outer = ", ".join(enclosure_text(a, b, digits=8) for a, b in r["outer"]) or "none"
        rows.append((r["param"], r["nominal"], f"[{r['range'][0]:g}, {r['range'][1]:g}]",
                     inner, outer if r["method"] != Method.EXACT else "(exact)", r["method"]))  # fmt: skip
    table = Table(
        name="robust_ranges",
        title="Gain values passive for every plant in the box (the others at their values)",
        columns=("parameter", "value", "searched", "robust passive set", "outer set", "method"),
        rows=tuple(rows),
        note="Ends rounded inward: a printed end is itself robustly passive. With several "
        "uncertain parameters the set is a certified inner set; no value outside the outer "
        "set is robustly passive.",
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
        text += f" Gain ranges {data['ranges_note']}."
    if v["worst"] is not None:
        at = ", ".join(f"`{k}` = {x:.10g}" for k, x in v["worst"]["values"].items())
        text += f" Worst plant: {at} (verified not passive by the exact test)."
    claim = f"{design.name} is passive for every plant in the box"
    verdict = Verdict.AGREES if status is Outcome.PASSIVE else Verdict.INFO
    undecided = status is Outcome.UNDECIDED
    return Section(
        "robust", TITLE, text=text, tables=() if "delay_margin" in data else (table,),
        findings=(Finding(claim, verdict, v["detail"]),),
        files={"robust.json": to_json(data)},
        status=SectionStatus.STOPPED_AT_BUDGET if undecided else SectionStatus.OK,
    )  # fmt: skip
