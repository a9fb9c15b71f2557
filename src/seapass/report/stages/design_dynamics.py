"""Design stages about dynamics: stiffness response, step response, tuned gains.

Each ``stage_*`` returns a [`Section`][seapass.report.document.Section], split as
python-control splits ``*_response`` from ``*_plot``: ``*_data`` computes,
``*_figures`` draws, ``*_section`` writes the section.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ...analysis.freqresp import FrequencyResponse, PeakKind, stiffness_response
from ...errors import ParameterError, TuningWarning
from ...model.design_file import Design
from ...plot.sim import plot_step_responses
from ...progress import ProgressLike, as_progress, task
from ...sampled.passivity import SampledPassivityResult, sampled_passivity
from ...sim.metrics import overshoot_percent, tracking_metrics
from ...sim.simulate import Step, simulate
from ...tuning.optimize import TuningResult, tune
from ...tuning.problem import QUICK_OPTIONS, TuningOptions
from ..document import FigureData, Finding, Section, SectionStatus, Table, Verdict, to_json
from ..pipeline import StageContext

__all__ = [
    "TuningData",
    "metrics_table",
    "response_figures",
    "response_section",
    "stage_response",
    "stage_stiffness",
    "stage_tuning",
    "step_responses",
    "stiffness_data",
    "stiffness_figures",
    "stiffness_section",
    "tuning_data",
    "tuning_figures",
    "tuning_section",
]

#: The step response at each load mass: ``(mass, SimulationResult, TrackingMetrics)``.
Runs = Sequence[tuple[float, Any, Any]]


def stiffness_data(design: Design, quick: bool, *, points: int | None = None) -> FrequencyResponse:
    """``F_L/X_L(jω)`` of the design over 0.1–1e4 rad/s (``points``: default 400, 200 quick)."""
    points = points or (200 if quick else 400)
    return stiffness_response(design.sea(), np.logspace(-1, 4, points), label=design.name)


def stiffness_figures(design: Design, r: FrequencyResponse) -> tuple[FigureData, ...]:
    """No figure: the one Bode plot of ``F_L/X_L`` is the frequency stage's (with the bands)."""
    del design, r
    return ()


def stiffness_section(r: FrequencyResponse, figures: Sequence[FigureData]) -> Section:
    """The section of `stiffness_data` with the figures of `stiffness_figures`."""
    table = Table(
        name="stiffness_summary",
        title="Rendered stiffness",
        columns=("quantity", "value [N/m]"),
        rows=(
            ("static F_L/X_L(0)", r.static),
            ("high-frequency limit", r.high_frequency),
            (_peak_quantity(r), r.peak().magnitude),
        ),
    )
    lines = ["omega_rad_s,magnitude_N_per_m,phase_deg"] + [
        f"{w!r},{m!r},{p!r}"
        for w, m, p in zip(r.omega.tolist(), r.magnitude.tolist(), r.phase.tolist(), strict=True)
    ]
    return Section(
        key="stiffness",
        title="Stiffness frequency response",
        text=(
            "`F_L/X_L(jω)`: the stiffness a person feels when moving the load at frequency ω "
            "(magnitude), and how far the force leads the motion (phase); the Bode plot is "
            "in the section on passivity in the frequency domain."
        ),
        tables=(table,),
        figures=tuple(figures),
        files={"stiffness_response.csv": "\n".join(lines) + "\n"},
    )


def _peak_quantity(r: FrequencyResponse) -> str:
    """The table's name for the largest ``|F_L/X_L|``: a peak only when it is one."""
    peak = r.peak()
    if peak.kind is PeakKind.INTERIOR:
        return "peak over 0.1-1e4 rad/s"
    if peak.kind is PeakKind.UNBOUNDED_HIGH:
        return "largest over 0.1-1e4 rad/s, at 1e4 (no peak: grows without bound)"
    if peak.kind is PeakKind.UNBOUNDED_LOW:
        return "largest over 0.1-1e4 rad/s, at 0.1 (no peak: grows without bound as ω → 0)"
    edge = "1e4" if peak.kind is PeakKind.EDGE_HIGH else "0.1"
    return f"largest over 0.1-1e4 rad/s, at {edge} (no peak inside the range)"


def stage_stiffness(design: Design, context: StageContext) -> Section:
    """Budget: frequency points of the response (the grid; nothing is decided on it)."""
    r = stiffness_data(design, context.quick, points=context.budget)
    return stiffness_section(r, stiffness_figures(design, r))


def step_responses(
    sea: Any,
    design: Design,
    dt: float,
    *,
    budget: int | None = None,
    progress: ProgressLike = None,
) -> list[tuple[float, Any, Any]]:
    """The step response at every load mass of the design, in order, while the simulated
    time steps (all masses together) stay within ``budget`` (default: no limit)."""
    shown = as_progress(progress, where="step_responses")
    steps = math.ceil(design.horizon / dt)
    masses = design.load_masses
    if budget is not None:
        masses = masses[: budget // steps]
    out = []
    with task(shown, f"step responses at {len(masses)} load mass(es)", len(masses)):
        for mass in masses:
            res = simulate(
                sea, load_mass=mass, scenario=Step(design.step), horizon=design.horizon, dt=dt
            )
            out.append((mass, res, tracking_metrics(res)))
            shown.advance(1, note=f"m_L = {mass:g} kg")
    return out


def metrics_table(name: str, title: str, runs: Runs) -> Table:
    return Table(
        name=name,
        title=title,
        columns=(
            "load mass [kg]",
            "status",
            "settling time [s]",
            "final error [m]",
            "overshoot [%]",
            "peak force [N]",
        ),
        rows=tuple(
            (
                m,
                met.status,
                met.settling_time,
                met.final_error,
                overshoot_percent(met.overshoot),
                met.peak_force,
            )
            for m, _r, met in runs
        ),
    )


def response_figures(design: Design, runs: Runs) -> tuple[FigureData, ...]:
    return (
        FigureData.of(
            "step_response", "Load position after the step.",
            plot_step_responses(
                list(runs), step=design.step,
                title=f"{design.name}: {design.step:g} m reference step",
            ),
        ),
    )  # fmt: skip


def response_section(design: Design, runs: Runs, figures: Sequence[FigureData]) -> Section:
    """The section of `step_responses` with the figures of `response_figures`."""
    return Section(
        key="response",
        title="Step response at the given gains",
        text=(
            f"A {design.step:g} m step of both references from rest, simulated exactly "
            f"(matrix exponential) for {design.horizon:g} s with a load mass at the port. "
            "Settling: within 2 % of the step for the rest of the horizon."
        ),
        tables=(metrics_table("step_metrics", "Step-response metrics", runs),),
        figures=tuple(figures),
    )


def stage_response(design: Design, context: StageContext) -> Section:
    """Budget: simulated time steps, all load masses together (masses beyond it are not
    simulated and the section is stopped at its budget)."""
    dt = 2e-3 if context.quick else 1e-3
    runs = step_responses(
        design.sea(), design, dt, budget=context.budget, progress=context.progress
    )
    sec = response_section(design, runs, response_figures(design, runs) if runs else ())
    left = design.load_masses[len(runs) :]
    if not left:
        return sec
    steps = math.ceil(design.horizon / dt)
    return replace(
        sec,
        status=SectionStatus.STOPPED_AT_BUDGET,
        text=sec.text
        + f" **Stopped at the budget of {context.budget} time steps** ({steps} per load "
        f"mass): m_L = {', '.join(f'{m:g}' for m in left)} kg not simulated (raise it with "
        "`--budget response=N`).",
    )


@dataclass(frozen=True, kw_only=True)
class TuningData:
    """The tuned gains (`tuning_data`): the result and its step responses, or why not."""

    options: TuningOptions
    quick: bool
    result: TuningResult | None
    refused: str
    runs: tuple[tuple[float, Any, Any], ...]
    sampled: SampledPassivityResult | None


def tuning_data(
    design: Design,
    quick: bool,
    *,
    generations: int | None = None,
    progress: ProgressLike = None,
) -> TuningData:
    """The best passive gains of the design's controller, in the boxes of its ``[ranges]``.

    ``generations`` replaces the search's ``maxiter`` (default: 60, 12 quick).
    """
    opts = (QUICK_OPTIONS if quick else TuningOptions()).replace(masses="tune")  # the tune_mass
    if generations is not None:
        opts = opts.replace(maxiter=generations)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TuningWarning)  # they go into the text
            tr = tune(design, options=opts, progress=progress)
    except ParameterError as exc:  # e.g. a single gain passive nowhere in its box
        return TuningData(
            options=opts, quick=quick, result=None, refused=str(exc), runs=(), sampled=None
        )
    runs = step_responses(tr.sea, design, 2e-3 if quick else 1e-3)
    return TuningData(
        options=opts, quick=quick, result=tr, refused="", runs=tuple(runs),
        sampled=_sampled_check(design, tr.sea),
    )  # fmt: skip


def _gains_text(tr: TuningResult, units: Mapping[str, str] | None = None) -> str:
    """``"kd = 1708 N/m, bd = 300 N*s/m"``: each gain with its declared (or default) unit."""
    units = units or {}
    return ", ".join(
        f"{k} = {g:.5g}" + (f" {units[k]}" if units.get(k) else "") for k, g in tr.gains.items()
    )


def tuning_figures(design: Design, data: TuningData) -> tuple[FigureData, ...]:
    if data.result is None:
        return ()
    return (
        FigureData.of(
            "tuned_response", "Step response with the tuned gains.",
            plot_step_responses(
                list(data.runs), step=design.step,
                title=f"{design.name} with tuned gains ({_gains_text(data.result)})",
            ),
        ),
    )  # fmt: skip


def tuning_section(design: Design, data: TuningData, figures: Sequence[FigureData]) -> Section:
    """The section of `tuning_data` with the figures of `tuning_figures`."""
    title = "Tuned gains (fastest passive step response)"
    tr, opts = data.result, data.options
    if tr is None:
        return Section(
            "tuning", title, text=f"Nothing to tune: {data.refused}.",
            findings=(Finding("Some gains in the box are passive", Verdict.DIFFERS, data.refused),),
        )  # fmt: skip
    units = design.unit_map()
    gains = _gains_text(tr, units)
    table = Table(
        name="tuned_gains",
        title="Tuned gains vs the file's gains",
        columns=("gain", "unit", "file value", "tuned", "search range", "at the edge"),
        rows=tuple(
            (
                g,
                units.get(g, "") or "-",
                design.values.get(g),
                tr.gains[g],
                f"[{tr.box[g][0]:g}, {tr.box[g][1]:g}]",
                tr.on_bound.get(g, ""),
            )
            for g in tr.gains
        ),
    )
    findings = [Finding("The tuned gains are passive", _verdict(tr.passive), gains)]
    text = (
        f"The controller gains {', '.join(tr.gains)} were tuned by differential evolution "
        f"(seed {opts.seed}) for the fastest 2 % settling of a {tr.options.step:g} m step at "
        f"m_L = {tr.options.load_mass:g} kg, each in its box (the file's `[ranges]`, else "
        f"`[0, max(10·value, 1000)]`), every other parameter at its value, under the exact "
        f"passivity constraint and a {opts.force_limit:g} N force limit"
        + (" (reduced budget, --quick)" if data.quick else "")
        + f". Result: {gains} (passive: {'yes' if tr.passive else 'NO'})."
    )
    if tr.warnings:
        text += " " + " ".join(f"**Note:** {w}." for w in tr.warnings)
    sampled = data.sampled
    if sampled is not None:
        findings.append(
            Finding(
                f"The tuned gains are passive under the {design.control_rate:g} Hz controller",
                _verdict(sampled.passive),
                sampled.detail or sampled.reason or "passive",
            )
        )
        text += (
            f" Under the file's digital controller ({design.control_rate:g} Hz, "
            f"{design.control_delay} sample(s) of delay) the tuned gains are "
            f"{'passive' if sampled.passive else '**not** passive'}; "
            f"`seapass tune {design.name}.toml --period {design.period:g}` tunes under it."
        )
    return Section(
        key="tuning",
        title=title,
        text=text,
        tables=(
            table,
            metrics_table("tuned_metrics", "Step response with the tuned gains", data.runs),
        ),
        figures=tuple(figures),
        findings=tuple(findings),
        files={"tuning.json": to_json(tr.to_dict())},
    )


def stage_tuning(design: Design, context: StageContext) -> Section:
    """The best passive gains of the design's controller, in the boxes of its ``[ranges]``.

    Budget: generations of the search.  A budget below the default (60, 12 quick) that
    the search uses up stops the stage at its budget, with the best gains found.
    """
    data = tuning_data(design, context.quick, generations=context.budget, progress=context.progress)
    sec = tuning_section(design, data, tuning_figures(design, data))
    planned = (QUICK_OPTIONS if context.quick else TuningOptions()).maxiter
    tr = data.result
    if tr is None or context.budget is None or not (tr.generations >= context.budget < planned):
        return sec
    return replace(
        sec,
        status=SectionStatus.STOPPED_AT_BUDGET,
        text=sec.text
        + f" **Stopped at the budget of {context.budget} generations** (of {planned}): "
        "the best gains found so far, verified as above (raise it with "
        "`--budget tuning=N`).",
    )


def _verdict(ok: bool) -> Verdict:
    return Verdict.AGREES if ok else Verdict.DIFFERS


def _sampled_check(design: Design, sea: Any) -> SampledPassivityResult | None:
    """The sampled-data verdict of ``sea`` under the file's ``[control]``, or None."""
    if design.loop is None:
        return None
    return sampled_passivity(sea, loop=design.loop)
