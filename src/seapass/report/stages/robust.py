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
from ...outcome import Outcome
from ...robust.box import uncertain_box
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
    verdict = robust_check(sea, box=box, budget=budget)
    ranges = []
    for name, (lo, hi) in design.analysis_ranges().items():
        if name in box.intervals:
            continue
        free = sea.with_values(**{name: None})
        r = robust_passive_intervals(free, name, lo, hi, box=box, budget=budget)
        ranges.append(r.to_dict() | {"nominal": design.values.get(name)})
    return {"box": box.to_dict(), "verdict": verdict.to_dict(), "ranges": ranges}


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
    text = (
        f"Over the box {span}: **{status.replace('_', ' ')}** for every plant "
        f"({v['method']}; {v['detail']})."
    )
    if v["worst"] is not None:
        at = ", ".join(f"`{k}` = {x:.10g}" for k, x in v["worst"]["values"].items())
        text += f" Worst plant: {at} (verified not passive by the exact test)."
    claim = f"{design.name} is passive for every plant in the box"
    verdict = Verdict.AGREES if status is Outcome.PASSIVE else Verdict.INFO
    undecided = status is Outcome.UNDECIDED
    return Section(
        "robust", TITLE, text=text, tables=(table,),
        findings=(Finding(claim, verdict, v["detail"]),),
        files={"robust.json": to_json(data)},
        status=SectionStatus.STOPPED_AT_BUDGET if undecided else SectionStatus.OK,
    )  # fmt: skip
