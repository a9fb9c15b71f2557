"""The report for a user's own design (``seapass analyze design.toml``).

`analyze` runs the stages of `ANALYSIS` on a [`Design`][seapass.model.design_file.Design]
and returns a [`Report`][seapass.report.document.Report]; `stages_text` lists them
with what each computes and its work budget (``seapass analyze --help`` shows it):

``passivity``
    The exact verdict at the given values (with the reason and a witness
    frequency when not passive), the derived stiffness ``F_L/X_L`` and the
    exact symbolic passivity condition.
``witness``
    For a design that is not passive: a passive environment that destabilizes it
    ([`find_destabilizing_environment`][seapass.analysis.witness.find_destabilizing_environment]).
``stiffness``
    Rendered-stiffness frequency response.
``frequency``
    Bode of ``F_L/X_L``, ``Re Z_L(jω)`` with its exact negative bands, and the Nyquist plot.
``ranges``
    The exact passive set of every controller gain (and of every parameter with
    a ``[ranges]`` entry), the others held at their values
    ([`seapass.analysis.region.passive_intervals`][seapass.analysis.region.passive_intervals]).
``twoport``
    The SEA as a two-port between the person and the rendered environment: absolute
    stability, two-port passivity, a destabilizing pair, friction ([`seapass.ports`][seapass.ports]).
``delay``
    The certified delay margin ``τ*`` with ``C_A``, ``C_L`` delayed and, with ``[control]
    delay_time``, the verdict up to that latency (``report.stages.design_delay``).
``robust``
    With ``[uncertainty]``: the verdict for every plant in the box and the robust gain
    ranges ([`seapass.report.stages.robust`][seapass.report.stages.robust]).
``response``
    Step response at every load mass, with 2 % settling time and final error.
``tuning``
    The fastest passive gains of the controller ([`seapass.tuning.tune`][seapass.tuning.optimize.tune]),
    each in its ``[ranges]`` box, the other parameters at their values; with ``[control]``,
    also the verdict of the tuned gains under the digital controller.
``sampled``
    Passivity under the digital controller and the certified passive set of every gain,
    when ``[control] rate`` is given ([`seapass.sampled.passivity`][seapass.sampled.passivity]).
``zwidth``
    The Z-width map at the control rate: hold, delay, velocity filter
    ([`sampled_region`][seapass.sampled.region.sampled_region]).
``rig``
    A gain sweep on the digital twin of the ``[rig]`` ([`seapass.rig`][seapass.rig]).

Every stage but ``passivity`` and ``twoport`` (exact decisions, bounded by the design
file's size limits and, for the two-port's witness, a fixed number of pairs) has a **work budget** in counted steps, never in seconds (`StageBudget`): the
boxes of a certified branch and bound, generations of the tuning search, twin runs,
simulated time steps, candidate environments, parameters, frequency points.  A stage
that reaches its budget returns what it has with status ``stopped_at_budget``; what a
certified search did not settle is undecided, never passive.

With ``out``, the report directory is written when the run starts and again as each
stage finishes (each write complete and atomic), so an interrupted or killed run
leaves a valid report of the finished stages, marked incomplete.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from functools import partial

from ..errors import ParameterError
from ..files.limits import MAX_FREQUENCY_POINTS
from ..model.design_file import Design
from ..progress import ProgressLike, as_progress
from ..sampled.boxes import MAX_BOXES
from ..tuning.problem import QUICK_OPTIONS, TuningOptions
from .document import (
    Math,
    Report,
    Section,
    SectionStatus,
    Table,
    Verdict,
    formula,
    literal,
    to_json,
)
from .output import check_output_dir, write_report
from .pipeline import Stage, StageContext, run_stages, select_stages
from .stages import (
    design_delay,
    design_dynamics,
    design_frequency,
    design_hardware,
    design_passivity,
    design_twoport,
    robust,
    zwidth,
)
from .stages.design_passivity import values_text

__all__ = [
    "ANALYSIS",
    "ANALYSIS_STAGES",
    "AnalysisStage",
    "StageBudget",
    "analyze",
    "check_budgets",
    "design_file_section",
    "stages_text",
    "verdict_line",
]


# ----------------------------------------------------------------- the stages


@dataclass(frozen=True, kw_only=True)
class StageBudget:
    """The work budget of a stage: how many ``unit`` it may spend.

    ``full`` by default, ``quick`` with ``quick=True``; a budget given to `analyze`
    must lie in ``[minimum, maximum]``.
    """

    unit: str
    full: int
    quick: int
    minimum: int = 1
    maximum: int = 10**9

    def default(self, quick: bool) -> int:
        return self.quick if quick else self.full


@dataclass(frozen=True, kw_only=True)
class AnalysisStage:
    """One stage of `analyze`: its key, title, what it computes and its budget (None: exact,
    no budget)."""

    key: str
    title: str
    computes: str
    run: Callable[[Design, StageContext], Section]
    budget: StageBudget | None
    core: bool = False
    cost: float = 1.0
    """Run time on examples/ours.toml relative to the others (the pool starts the costliest
    first, so two workers finish together)."""


ANALYSIS: tuple[AnalysisStage, ...] = (
    AnalysisStage(
        key="passivity", title="Passivity verdict",
        computes="the exact verdict, the derived stiffness F_L/X_L, the symbolic condition",
        run=design_passivity.stage_passivity, budget=None, core=True,
    ),
    AnalysisStage(
        key="witness", title="Destabilizing environment",
        computes="a passive environment that destabilizes a design that is not passive",
        run=design_passivity.stage_witness, cost=1.5,
        budget=StageBudget(unit="candidate environments", full=5000, quick=5000),
    ),
    AnalysisStage(
        key="stiffness", title="Stiffness frequency response",
        computes="the rendered stiffness over frequency, magnitude and phase",
        run=design_dynamics.stage_stiffness, core=True,
        budget=StageBudget(unit="frequency points", full=400, quick=200, minimum=2,
                           maximum=MAX_FREQUENCY_POINTS),
    ),
    AnalysisStage(
        key="frequency", title="Passivity in the frequency domain",
        computes="Bode, Re Z_L(jw) with the exact bands where it is negative, Nyquist",
        run=design_frequency.stage_frequency, cost=1.1,
        budget=StageBudget(unit="frequency points", full=600, quick=300, minimum=2,
                           maximum=MAX_FREQUENCY_POINTS),
    ),
    AnalysisStage(
        key="ranges", title="Exact passive ranges",
        computes="the exact passive set of every gain, the others fixed",
        run=design_passivity.stage_ranges, core=True, cost=1.1,
        budget=StageBudget(unit="parameters", full=64, quick=64),
    ),
    AnalysisStage(
        key="twoport", title="Two-port: any passive person, any passive virtual environment",
        computes="absolute stability with eta, two-port passivity, gain sets, friction",
        run=design_twoport.stage_twoport, budget=None, cost=1.2,
    ),
    AnalysisStage(
        key="delay", title="Delay margin and loop latency",
        computes="the certified delay margin tau* and the verdict at [control] delay_time",
        run=design_delay.stage_delay, cost=1.0,
        budget=StageBudget(unit="pieces per certified search", full=design_delay.FULL_BUDGET,
                           quick=design_delay.QUICK_BUDGET, minimum=100, maximum=10**7),
    ),
    AnalysisStage(
        key="robust", title=robust.TITLE, computes=robust.COMPUTES, run=robust.stage_robust,
        budget=StageBudget(unit="boxes per certified verdict", full=robust.BUDGET_FULL,
                           quick=robust.BUDGET_QUICK, maximum=10**6), cost=1.2,
    ),
    AnalysisStage(
        key="response", title="Step response",
        computes="the step response at every load mass: settling, error, overshoot, force",
        run=design_dynamics.stage_response,
        budget=StageBudget(unit="simulated time steps", full=2_000_000, quick=2_000_000),
    ),
    AnalysisStage(
        key="tuning", title="Tuned gains",
        computes="the fastest passive gains in the boxes of [ranges]",
        run=design_dynamics.stage_tuning, cost=4.8,
        budget=StageBudget(unit="generations", full=TuningOptions().maxiter,
                           quick=QUICK_OPTIONS.maxiter, maximum=10_000),
    ),
    AnalysisStage(
        key="sampled", title="Sampled-data passivity",
        computes="the verdict and every gain's certified passive set at [control] rate",
        run=design_hardware.stage_sampled,
        budget=StageBudget(unit="boxes per certified bound", full=2000, quick=500,
                           maximum=MAX_BOXES * 50),
    ),
    AnalysisStage(
        key="zwidth", title="Z-width map",
        computes="the certified passive region of the first two gains at the control rate",
        run=zwidth.stage_design_zwidth, cost=5.3,
        budget=StageBudget(unit="boxes per row", full=300, quick=150, maximum=MAX_BOXES * 50),
    ),
    AnalysisStage(
        key="rig", title="Digital twin of the rig",
        computes="a kd sweep on the digital twin of [rig]",
        run=design_hardware.stage_rig, cost=3.6,
        budget=StageBudget(unit="twin runs (gains x load masses)", full=2000, quick=500),
    ),
)  # fmt: skip
"""The stages of `analyze`, in order."""

ANALYSIS_STAGES: tuple[str, ...] = tuple(s.key for s in ANALYSIS)
"""Stage keys of `analyze`, in order."""


def stages_text() -> str:
    """Every stage: key, what it computes, its budget unit and defaults (``--help``)."""
    lines = []
    for s in ANALYSIS:
        if s.budget is None:
            budget = "exact; no budget (the design file's size limits bound it)"
        else:
            b = s.budget
            same = b.full == b.quick
            budget = f"{b.full} {b.unit}" + ("" if same else f" ({b.quick} with --quick)")
        lines.append(f"  {s.key:<10} {s.computes}\n  {'':<10} budget: {budget}")
    return "\n".join(lines)


def check_budgets(budgets: Mapping[str, int] | None) -> dict[str, int]:
    """``budgets`` checked: known stages with a budget, whole numbers within its range.

    Raises
    ------
    ParameterError
        Naming ``budgets[...]`` and what is allowed.
    """
    out: dict[str, int] = {}
    by = {s.key: s for s in ANALYSIS}
    for key, value in (budgets or {}).items():
        if key not in by:
            raise ParameterError(
                f"budgets: unknown stage {key!r}; choose from {', '.join(ANALYSIS_STAGES)}",
                argument="budgets",
            )
        b = by[key].budget
        if b is None:
            raise ParameterError(
                f"budgets[{key!r}]: the {key} stage is one exact decision and has no budget",
                argument=f"budgets[{key!r}]",
            )
        if (
            isinstance(value, bool)
            or not isinstance(value, int)
            or not (b.minimum <= value <= b.maximum)
        ):
            raise ParameterError(
                f"budgets[{key!r}] must be a whole number of {b.unit} in "
                f"[{b.minimum}, {b.maximum}], got {value!r}",
                argument=f"budgets[{key!r}]",
            )
        out[key] = value
    return out


# ----------------------------------------------------------------- entry point


def analyze(
    design: Design,
    *,
    quick: bool = False,
    stages: Sequence[str] | None = None,
    budgets: Mapping[str, int] | None = None,
    progress: ProgressLike = None,
    log: Callable[[str], None] | None = None,
    jobs: int = 1,
    out: str | os.PathLike[str] | None = None,
    force: bool = False,
) -> Report:
    """The analysis report of one design.

    Parameters
    ----------
    design : Design
        From [`seapass.model.design_file.load_design`][seapass.model.design_file.load_design].
    quick : bool
        Reduced budgets, coarser grids and scans.
    stages : sequence of str, optional
        Subset of `ANALYSIS_STAGES` (``"core"``: passivity, stiffness,
        ranges); default all.
    budgets : mapping of str to int, optional
        Work budget per stage key, in the stage's unit (`ANALYSIS`, `stages_text`);
        a stage not named keeps its default.
    progress : Progress, optional
        Where the run reports (a [`seapass.progress.Progress`][seapass.progress.Progress]):
        a task of one step per stage, each stage a task inside it.  Default: none;
        ``True``/``False`` still work for one release.
    log : callable, optional
        Receives one line per finished stage.
    jobs : int
        Worker processes for the independent stages; the report is the same for every ``jobs``.
    out : path-like, optional
        Write the report directory there: at the start (every stage *not run* yet), again
        as each stage finishes, and complete at the end (each write atomic, see
        [`write_report`][seapass.report.output.write_report]).  An interrupt
        (``KeyboardInterrupt``, re-raised) leaves the finished stages written and the
        report marked incomplete.
    force : bool
        Write ``out`` even over files seapass did not write in the names it owns (see
        [`check_output_dir`][seapass.report.output.check_output_dir]).

    Returns
    -------
    Report
        Without ``out``, write it with [`seapass.report.output.write_report`][seapass.report.output.write_report].

    Raises
    ------
    ParameterError
        For an unknown stage or a budget out of its range, before any work.
    OutputPathError
        When ``out`` cannot take a report, before any work.
    """
    chosen_budgets = check_budgets(budgets)
    shown = as_progress(progress, where="analyze")

    def _budget(s: AnalysisStage) -> int | None:
        return None if s.budget is None else chosen_budgets.get(s.key, s.budget.default(quick))

    all_stages = [
        Stage(s.key, s.title, partial(s.run, design), core=s.core, cost=s.cost, budget=_budget(s))
        for s in ANALYSIS
    ]
    chosen = select_stages(stages, all_stages)
    if out is not None:
        check_output_dir(out, force=force)
    done: dict[int, Section] = {}

    def assemble(state: _Run) -> Report:
        return _report(design, chosen, done, quick, state)

    def finished(i: int, section: Section) -> None:
        done[i] = section
        if out is not None:
            write_report(assemble(_Run.RUNNING), out, force=force)

    if out is not None:
        write_report(assemble(_Run.RUNNING), out, force=force)
    try:
        run_stages(
            chosen, quick=quick, progress=shown, log=log, jobs=jobs, on_section=finished,
            title=f"analyze {design.name}",
        )  # fmt: skip
    except KeyboardInterrupt:
        if out is not None:
            write_report(assemble(_Run.INTERRUPTED), out, force=force)
        raise
    report = assemble(_Run.COMPLETE)
    if out is not None:
        write_report(report, out, force=force)
    return report


class _Run(StrEnum):
    """Where the run is when the report is assembled."""

    RUNNING = "running"
    INTERRUPTED = "interrupted"
    COMPLETE = "complete"


_NOT_RUN = {
    _Run.RUNNING: "Not run yet: the analysis was still running when this report was written.",
    _Run.INTERRUPTED: "Not run: the analysis was interrupted before this stage finished.",
}


def _report(
    design: Design, chosen: Sequence[Stage], done: Mapping[int, Section], quick: bool, state: _Run
) -> Report:
    """The report of the finished sections; the others *not run* unless ``state`` is complete."""
    sections = tuple(
        done[i]
        if i in done
        else Section(st.key, st.title, status=SectionStatus.NOT_RUN, text=_NOT_RUN[state])
        for i, st in enumerate(chosen)
    )
    incomplete = ""
    if state is not _Run.COMPLETE:
        what = f"{len(done)} of {len(chosen)} analyses finished"
        incomplete = (
            f"{what}; the run was still going when this was written (if it is no longer "
            "running, it was stopped)."
            if state is _Run.RUNNING
            else f"interrupted: {what}. The finished analyses are complete; the others are "
            "marked *not run*. Run `seapass analyze` again for the whole report."
        )
    verdict = verdict_line(sections, design)
    title = design.title or design.name
    intro = (
        f"Analysis of the design `{design.name}`"
        + (f" ({literal(design.title)})" if design.title else "")
        + f": D1 = {formula(design.D1)}, D2 = {formula(design.D2)}, "
        f"C_A = {formula(design.CA)}, C_L = {formula(design.CL)}; "
        f"{values_text(dict(design.values), design.unit_map())}. Every number is in [`data/`](data/), "
        "every figure in [`figures/`](figures/) (PNG and SVG); verdicts are exact."
        + (" Reduced budgets (`--quick`)." if quick else "")
    )
    ok = sum(1 for s in sections if s.status == SectionStatus.OK)
    stopped = [s.key for s in sections if s.status == SectionStatus.STOPPED_AT_BUDGET]
    headline = (
        (f"**Verdict: {verdict}.** " if verdict else "")
        + f"{len(sections)} analyses run, {ok} completed"
        + (f", stopped at their budget: {', '.join(stopped)}" if stopped else "")
        + "."
    )
    return Report(
        title=f"seapass analysis: {title}",
        intro=intro,
        sections=(*sections, design_file_section(design)),
        headline=headline,
        incomplete=incomplete,
    )


def design_file_section(design: Design) -> Section:
    """The design as read and validated, defaults filled in, one row per key."""
    d = design.to_dict()
    rows: list[tuple[str, object, str]] = [("name", d["name"], ""), ("title", d["title"], "")]
    rows += [(f"model.{k}", Math(v), "") for k, v in d["model"].items()]
    units = design.unit_map()
    rows += [(f"parameters.{k}", v, units.get(k, "")) for k, v in d["parameters"].items()]
    searched = design.analysis_ranges()
    for k, (lo, hi) in searched.items():
        given = "" if k in d["ranges"] else " (default: [0, max(10·value, 1000)])"
        rows.append((f"ranges.{k}", f"[{lo:g}, {hi:g}]{given}", units.get(k, "")))
    sim_units = {"load_masses": "kg", "step": "m", "horizon": "s", "tune_mass": "kg"}
    for k, v in d["simulation"].items():
        shown = ", ".join(f"{x:g}" for x in v) if isinstance(v, list) else v
        rows.append((f"simulation.{k}", shown, sim_units.get(k, "")))
    control_units = {"rate": "Hz", "delay": "samples", "velocity_filter": "Hz", "delay_time": "s"}
    for k, v in d["control"].items():
        rows.append((f"control.{k}", "none" if v is None else v, control_units.get(k, "")))
    rows.append(("rig", d["rig"] or "none", ""))
    return Section(
        key="design-file",
        title="Design file (as validated)",
        text=(
            "The design as seapass read and validated it, defaults filled in; every analysis "
            "above used exactly these values. The same content is in "
            "[`data/design.json`](data/design.json)."
        ),
        tables=(
            Table(
                name="design_file",
                title="Validated design",
                columns=("key", "value", "unit"),
                rows=tuple(rows),
            ),
        ),
        files={"design.json": to_json(d)},
    )


def verdict_line(sections: Sequence[Section], design: Design) -> str:
    """One line: the continuous verdict and, when analysed, the sampled-data one."""
    # a section stopped at its budget still holds its decided verdict (its bounds are partial)
    done = (SectionStatus.OK, SectionStatus.STOPPED_AT_BUDGET)
    by = {s.key: s for s in sections if s.status in done and s.findings}
    parts = []
    if "passivity" in by:
        ok = by["passivity"].findings[0].verdict == Verdict.AGREES
        parts.append("passive" if ok else "NOT passive at the given values")
    if "sampled" in by:
        ok = by["sampled"].findings[0].verdict == Verdict.AGREES
        rate = f"{design.control_rate:g} Hz" if design.control_rate else "the control rate"
        parts.append(f"{'passive' if ok else 'NOT passive'} under sampled-data control at {rate}")
    if len(parts) == 2:
        parts[0] += " in continuous time"
    return "; ".join(parts)
