"""Design stages about passivity: the verdict, a destabilizing environment, passive ranges.

Each ``stage_*`` returns a [`Section`][seapass.report.document.Section]; one with
figures is split as python-control splits ``*_response`` from ``*_plot``
(``*_data`` computes, ``*_figures`` draws, ``*_section`` writes the section).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import sympy as sp

from ...analysis.conditions import exact_passivity_condition
from ...analysis.environment_box import EnvironmentBounds, bounds_from_mapping
from ...analysis.passivity import is_passive
from ...analysis.region import PassiveIntervals, passive_intervals
from ...analysis.witness import WitnessResult, find_destabilizing_environment
from ...errors import SeapassError
from ...model.controller import BLOCKS
from ...model.design_file import Design
from ...model.stiffness import derive_stiffness
from ...model.units import unit_label
from ...plot.region import plot_passive_intervals
from ...plot.style import axes_grid
from ...plot.witness import plot_witness
from ...progress import ProgressLike, as_progress, task
from ..document import (
    FigureData,
    Finding,
    Math,
    Section,
    SectionStatus,
    Table,
    Verdict,
    format_intervals,
    to_json,
)
from ..formula import decimal_rational
from ..pipeline import StageContext

__all__ = [
    "ranges_data",
    "ranges_figures",
    "ranges_section",
    "stage_passivity",
    "stage_ranges",
    "stage_witness",
    "values_text",
    "witness_figures",
    "witness_section",
]


def values_text(values: dict[str, float], units: Mapping[str, str] | None = None) -> str:
    """``"b = 10 N*s/m, kd = 500 N/m"``: each value with its unit, if it has one."""
    units = units or {}
    return ", ".join(
        f"{k} = {v:g}" + (f" {units[k]}" if units.get(k) else "") for k, v in sorted(values.items())
    )


def _elements_table(design: Design, k: sp.Expr, k_values: sp.Expr) -> Table:
    """The design's elements and its stiffness, symbolic and at the values (decimals)."""
    return Table(
        name="design",
        title="Design",
        columns=("element", "expression"),
        rows=(
            ("D1 (transmission)", Math(design.D1)),
            ("D2 (load to ground)", Math(design.D2)),
            ("C_A (actuator-side controller)", Math(design.CA)),
            ("C_L (load-side controller)", Math(design.CL)),
            ("parameter values", values_text(dict(design.values))),
            ("F_L/X_L (derived, symbolic)", Math(str(sp.factor(k)))),
            ("F_L/X_L at the values (6 digits)", Math(decimal_rational(k_values))),
        ),
    )


def _controller_table(design: Design) -> tuple[tuple[Table, ...], dict[str, str]]:
    """How ``C_A`` and ``C_L`` follow from the ``[controller]`` blocks, and its data file."""
    d = design.derivation()
    if d is None:
        return (), {}
    names = {sym: what for sym, what, _ in BLOCKS.values()}
    rows: list[tuple[str, Any]] = [
        ("kind", f"{d.controller.kind.value}: {d.controller.kind.description}")
    ]
    rows += [(f"{sym} ({names[sym]})", Math(text)) for sym, text in d.blocks.items()]
    rows.append(("force feed-forward", "yes" if d.controller.feedforward else "no"))
    rows += [(f"{sig} (block diagram)", Math(rhs)) for sig, rhs in d.diagram]
    rows += [
        ("C_A solved from the diagram", Math(d.general["CA"])),
        ("C_L solved from the diagram", Math(d.general["CL"])),
        ("C_A with the blocks", Math(d.CA)),
        ("C_L with the blocks", Math(d.CL)),
    ]
    table = Table(
        name="controller",
        title="Controller blocks → C_A, C_L (f_A = C_A (θ − x_A) + C_L (θ − x_L))",
        columns=("", "expression"),
        rows=tuple(rows),
    )
    return (table,), {"controller.json": to_json(d.to_dict())}


def _condition_text(sea: Any) -> tuple[str, dict[str, str]]:
    """The exact symbolic condition as math blocks, and its data file."""
    try:
        cond = exact_passivity_condition(sea)
    except SeapassError as exc:
        return f"The symbolic condition is not available: {exc}", {}
    if str(cond.condition) in ("True", "False"):
        always = str(cond.condition) == "True"
        head = (
            "The exact passivity condition is **always "
            + ("satisfied**: passive for every positive value of every parameter.\n\n"
               if always else "violated**: not passive for any positive parameter values.\n\n")
        )  # fmt: skip
    else:
        head = (
            "Exact passivity condition for positive parameters (symbolic):\n\n"
            f"```math\n{cond.condition}\n```\n\n"
        )
    text = head + (
        "Real-part polynomial `Re N(jω) D(−jω)`, which must be nonnegative for all ω:\n\n"
        f"```math\n{cond.real_part}\n```"
    )
    return text, {"condition.json": to_json(cond.to_dict())}


def _verdict_text(res: Any) -> str:
    if res.passive:
        return f"**The design is passive** at the given values ({res.status})."
    w = (
        f" A witness: `Re Z(jω) < 0` at ω = {res.omega:.6g} rad/s."
        if res.omega and "w =" not in res.detail
        else ""
    )
    return (
        f"**The design is NOT passive** at the given values: {res.detail or res.reason.description}.{w} "
        "Coupled to some passive environment (a person, a spring, a mass) it can become "
        "unstable. See the passive ranges below for values that are safe."
    )


def stage_passivity(design: Design, context: StageContext) -> Section:
    """The exact verdict at the file's values, the stiffness and the symbolic condition
    (exact; no budget: the design file's size limits bound the work)."""
    sea = design.sea()
    res = is_passive(sea)
    k = derive_stiffness(sea).stiffness
    k_values = sp.factor(sp.cancel(sea.numeric(k)))
    cond_text, files = _condition_text(sea)
    controller, controller_files = _controller_table(design)
    finding = Finding(
        f"{design.name} is passive at {values_text(dict(design.values))}",
        Verdict.AGREES if res.passive else Verdict.DIFFERS,
        res.status + (f": {res.detail}" if res.detail else ""),
    )
    stiffness = {
        "symbolic": str(sp.factor(k)),
        "at_values_exact": str(k_values),
        "at_values_decimal": decimal_rational(k_values),
    }
    return Section(
        key="passivity",
        title="Passivity verdict",
        text=_verdict_text(res) + "\n\n" + cond_text,
        tables=(_elements_table(design, k, k_values), *controller),
        findings=(finding,),
        files={
            "passivity.json": to_json(res.to_dict()),
            "stiffness.json": to_json(stiffness),
            **files,
            **controller_files,
        },
    )


#: The exact passive set of each ranged parameter, by name.
RangesData = tuple[tuple[str, PassiveIntervals], ...]


def ranges_data(
    design: Design, quick: bool, *, budget: int | None = None, progress: ProgressLike = None
) -> RangesData:
    """The exact passive set of every gain (and ranged parameter), the others at their values.

    At most ``budget`` parameters (in the order of the design's ranges; default all);
    ``progress`` gets one task with a step per parameter.
    """
    shown = as_progress(progress, where="ranges_data")
    sea = design.sea()
    ranges = list(design.analysis_ranges().items())[:budget]
    results = []
    with task(shown, f"exact passive sets of {len(ranges)} parameter(s)", len(ranges)):
        for name, (lo, hi) in ranges:
            others = {k: v for k, v in design.values.items() if k != name}
            results.append((name, passive_intervals(sea, name, lo, hi, values=others)))
            shown.advance(1, note=name)
    return tuple(results)


def ranges_figures(design: Design, results: RangesData) -> tuple[FigureData, ...]:
    """One bar per parameter: its exact passive set and the design's value."""
    if not results:
        return ()
    axes = axes_grid(None, len(results), 1, figsize=(7, 1.6 * len(results) + 0.6))
    fig = axes[0, 0].figure
    for ax, (name, res) in zip(axes[:, 0], results, strict=True):
        plot_passive_intervals(res, ax=ax)
        value = design.values[name]
        unit = design.unit_map().get(name, "")
        for a, b in res.intervals:
            if a == b:  # an isolated passive value has no width: draw it
                ax.axvline(a, color="#2e7d32", lw=3, clip_on=False)
        # unclipped: a design value at the end of the range stays visible
        ax.axvline(
            value,
            color="tab:blue",
            lw=2.5,
            clip_on=False,
            label=f"design: {value:g} {unit}".rstrip(),
        )
        ax.set_xlabel(unit_label(name, {name: unit}))
        ax.legend(loc="upper right", ncol=3, fontsize=8)
    fig.suptitle(f"{design.name}: exact passive sets")
    return (FigureData.of("passive_ranges", "Exact passive set of every gain.", fig),)


def ranges_section(design: Design, results: RangesData, figures: Sequence[FigureData]) -> Section:
    """The section of `ranges_data` with the figures of `ranges_figures`."""
    rows, flags, findings = [], set(), []
    for i, (name, res) in enumerate(results):
        value = design.values[name]
        inside = res.contains(value) if res.lo <= value <= res.hi else None
        if inside is False:
            flags.add((i, "value is passive"))
        rows.append(
            (
                name,
                value,
                f"[{res.lo:g}, {res.hi:g}]",
                inside,
                format_intervals(res.intervals, res.hi),
            )
        )
        findings.append(
            Finding(
                f"{name} = {value:g} lies in its passive set",
                Verdict.INFO if inside is None else (Verdict.AGREES if inside else Verdict.DIFFERS),
                f"exact passive {name} in [{res.lo:g}, {res.hi:g}] (others fixed): "
                f"{format_intervals(res.intervals, res.hi)}",
            )
        )
    table = Table(
        name="passive_ranges",
        title="Exact passive set of each gain (the other parameters at their values)",
        columns=("parameter", "value", "search range", "value is passive", "exact passive set"),
        rows=tuple(rows),
        highlight=frozenset(flags),
    )
    return Section(
        key="ranges",
        title="Exact passive ranges",
        text=(
            "For each gain, the exact set of values for which the design is passive, all other "
            "parameters held at the file's values. Gains without a `[ranges]` entry are searched "
            "in `[0, max(10·value, 1000)]`."
        ),
        tables=(table,),
        figures=tuple(figures),
        findings=tuple(findings),
        files={"passive_ranges.json": to_json({n: r.to_dict() for n, r in results})},
    )


def stage_ranges(design: Design, context: StageContext) -> Section:
    """The exact passive set of every gain (and ranged parameter), the others at their values.

    Budget: parameters (each one exact passive set); the others are listed as not
    analysed and the section is stopped at its budget.
    """
    results = ranges_data(design, context.quick, budget=context.budget, progress=context.progress)
    sec = ranges_section(design, results, ranges_figures(design, results))
    left = [k for k in design.analysis_ranges() if k not in dict(results)]
    if not left:
        return sec
    return replace(
        sec,
        status=SectionStatus.STOPPED_AT_BUDGET,
        text=sec.text
        + f" **Stopped at the budget of {len(results)} parameter(s)**: "
        + ", ".join(f"`{k}`" for k in left)
        + " not analysed (raise it with `--budget ranges=N`).",
    )


def witness_figures(res: WitnessResult) -> tuple[FigureData, ...]:
    """The growing coupled response, when a destabilizing environment was simulated."""
    if not res.found or res.simulation is None:
        return ()
    return (
        FigureData.of(
            "witness", "Growing response of the design coupled to the environment.",
            plot_witness(res),
        ),
    )  # fmt: skip


def witness_section(
    design: Design,
    bounds: EnvironmentBounds,
    res: WitnessResult,
    figures: Sequence[FigureData],
) -> Section:
    """The section of a witness search with the figures of `witness_figures`."""
    title = "What can go wrong: a destabilizing passive environment"
    if res.passive:
        return Section(
            "witness", title, status=SectionStatus.SKIPPED,
            text="Skipped: the design is passive, so no passive environment (person, spring, "
            "mass, damper) can destabilize it (passivity theorem).",
        )  # fmt: skip
    if not res.found or res.environment is None:
        claim = f"{design.name} is safe to couple to any passive environment within the bounds"
        verdict = Verdict.AGREES if res.certified else Verdict.INFO
        return Section(
            "witness", title,
            text=(
                f"The design is not passive, but within the environments of the design file "
                f"(`[environment]`, default a human limb: {bounds.describe()}) "
                + ("none can destabilize it, **proven exactly**: " if res.certified
                   else "none was found (a search, **not a proof**): ")
                + f"{res.detail}"
            ),
            findings=(Finding(claim, verdict, res.detail),),
            files={"witness.json": to_json(res.to_dict())},
        )  # fmt: skip
    env = res.environment
    rate = res.coupled.max_real_part if res.coupled is not None else math.nan
    table = Table(
        name="witness",
        title="A passive environment that destabilizes the design",
        columns=(
            "mass [kg]",
            "damping [N·s/m]",
            "stiffness [N/m]",
            "growth rate [1/s]",
            "found by",
        ),
        rows=((env.mass, env.damping, env.stiffness, rate, res.method),),
    )
    return Section(
        key="witness",
        title=title,
        text=(
            "Not passive means that *some* passive environment makes the coupled system "
            "unstable. seapass finds one within the environments of the design file "
            f"(`[environment]`, default a human limb: {bounds.describe()}; Colgate–Hogan "
            f"construction plus a search, each candidate verified exactly): {res.detail}."
        ),
        tables=(table,),
        figures=tuple(figures),
        findings=(
            Finding(
                f"{design.name} is safe to couple to any passive environment",
                Verdict.DIFFERS,
                res.detail,
            ),
        ),
        files={"witness.json": to_json(res.to_dict())},
    )


def stage_witness(design: Design, context: StageContext) -> Section:
    """For a design that is not passive: a passive environment that destabilizes it.

    Budget: candidate environments scored exactly (the search stops there, nothing found
    among those tried; the exact certificate is still tried).
    """
    bounds = bounds_from_mapping(dict(design.environment))
    res = find_destabilizing_environment(design.sea(), bounds=bounds, max_candidates=context.budget)
    sec = witness_section(design, bounds, res, witness_figures(res))
    if not res.budget_exhausted or res.certified:
        return sec
    return replace(
        sec,
        status=SectionStatus.STOPPED_AT_BUDGET,
        text=sec.text
        + f"\n\n**Stopped at the budget of {context.budget} candidate environments** before "
        "the search was finished (raise it with `--budget witness=N`).",
    )
