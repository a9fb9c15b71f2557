"""Design stages about dynamics: stiffness response, step response, tuned gains.

Each ``stage_*`` returns a [`Section`][seapass.report.document.Section].
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ...analysis.freqresp import stiffness_response
from ...errors import ParameterError, TuningWarning
from ...model.design_file import Design
from ...plot.passivity import plot_bode
from ...plot.sim import plot_step_responses
from ...sampled.passivity import sampled_passivity
from ...sim.metrics import tracking_metrics
from ...sim.simulate import Step, simulate
from ...tuning.optimize import tune
from ...tuning.problem import QUICK_OPTIONS, TuningOptions
from ..document import FigureData, Finding, Section, Table, Verdict, to_json
from ..pipeline import stage_progress

__all__ = [
    "metrics_table",
    "stage_response",
    "stage_stiffness",
    "stage_tuning",
    "step_responses",
]


def stage_stiffness(design: Design, quick: bool) -> Section:

    sea = design.sea()
    r = stiffness_response(sea, np.logspace(-1, 4, 200 if quick else 400), label=design.name)
    k1 = design.values.get("k1")
    fig = plot_bode(
        r, title=f"{design.name}: rendered stiffness"
        + (" (dashed: spring stiffness k1)" if k1 is not None else ""), reference=k1,
        legend=False,
    )  # fmt: skip
    table = Table(
        name="stiffness_summary",
        title="Rendered stiffness",
        columns=("quantity", "value [N/m]"),
        rows=(
            ("static F_L/X_L(0)", r.static),
            ("high-frequency limit", r.high_frequency),
            ("peak over 0.1-1e4 rad/s", float(np.max(r.magnitude))),
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
            "(magnitude), and how far the force leads the motion (phase)."
        ),
        tables=(table,),
        figures=(
            FigureData.of(
                "stiffness", "Rendered stiffness of the design: magnitude and phase.", fig
            ),
        ),
        files={"stiffness_response.csv": "\n".join(lines) + "\n"},
    )


def step_responses(sea: Any, design: Design, dt: float) -> list[tuple[float, Any, Any]]:

    out = []
    for i, mass in enumerate(design.load_masses):
        stage_progress(i, len(design.load_masses), f"step response, m_L = {mass:g} kg")
        res = simulate(
            sea, load_mass=mass, scenario=Step(design.step), horizon=design.horizon, dt=dt
        )
        out.append((mass, res, tracking_metrics(res)))
    return out


def metrics_table(name: str, title: str, runs: list[tuple[float, Any, Any]]) -> Table:
    return Table(
        name=name,
        title=title,
        columns=(
            "load mass [kg]",
            "status",
            "settling time [s]",
            "final error [m]",
            "overshoot",
            "peak force [N]",
        ),
        rows=tuple(
            (m, met.status, met.settling_time, met.final_error, met.overshoot, met.peak_force)
            for m, _r, met in runs
        ),
    )


def stage_response(design: Design, quick: bool) -> Section:
    runs = step_responses(design.sea(), design, 2e-3 if quick else 1e-3)
    fig = FigureData.of(
        "step_response", "Load position after the step.",
        plot_step_responses(
            runs, step=design.step, title=f"{design.name}: {design.step:g} m reference step"
        ),
    )  # fmt: skip
    return Section(
        key="response",
        title="Step response at the given gains",
        text=(
            f"A {design.step:g} m step of both references from rest, simulated exactly "
            f"(matrix exponential) for {design.horizon:g} s with a load mass at the port. "
            "Settling: within 2 % of the step for the rest of the horizon."
        ),
        tables=(metrics_table("step_metrics", "Step-response metrics", runs),),
        figures=(fig,),
    )


def stage_tuning(design: Design, quick: bool) -> Section:
    """The best passive gains of the design's controller, in the boxes of its ``[ranges]``."""
    opts = QUICK_OPTIONS if quick else TuningOptions()
    title = "Tuned gains (fastest passive step response)"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TuningWarning)  # they go into the text
            tr = tune(design, options=opts, progress=False)
    except ParameterError as exc:  # e.g. a single gain passive nowhere in its box
        return Section(
            "tuning", title, text=f"Nothing to tune: {exc}.",
            findings=(Finding("Some gains in the box are passive", Verdict.DIFFERS, str(exc)),),
        )  # fmt: skip
    runs = step_responses(tr.sea, design, 2e-3 if quick else 1e-3)
    gains = ", ".join(f"{k} = {g:.5g}" for k, g in tr.gains.items())
    table = Table(
        name="tuned_gains",
        title="Tuned gains vs the file's gains",
        columns=("gain", "file value", "tuned", "search range", "at the edge"),
        rows=tuple(
            (
                g,
                design.values.get(g),
                tr.gains[g],
                f"[{tr.box[g][0]:g}, {tr.box[g][1]:g}]",
                tr.on_bound.get(g, ""),
            )
            for g in tr.gains
        ),
    )
    fig = FigureData.of(
        "tuned_response", "Step response with the tuned gains.",
        plot_step_responses(
            runs, step=design.step, title=f"{design.name} with tuned gains ({gains})"
        ),
    )  # fmt: skip
    findings = [Finding("The tuned gains are passive", _verdict(tr.passive), gains)]
    text = (
        f"The controller gains {', '.join(tr.gains)} were tuned by differential evolution "
        f"(seed {opts.seed}) for the fastest 2 % settling of a {tr.options.step:g} m step at "
        f"m_L = {tr.options.load_mass:g} kg, each in its box (the file's `[ranges]`, else "
        f"`[0, max(10·value, 1000)]`), every other parameter at its value, under the exact "
        f"passivity constraint and a {opts.force_limit:g} N force limit"
        + (" (reduced budget, --quick)" if quick else "")
        + f". Result: {gains} (passive: {'yes' if tr.passive else 'NO'})."
    )
    if tr.warnings:
        text += " " + " ".join(f"**Note:** {w}." for w in tr.warnings)
    sampled = _sampled_check(design, tr.sea)
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
        tables=(table, metrics_table("tuned_metrics", "Step response with the tuned gains", runs)),
        figures=(fig,),
        findings=tuple(findings),
        files={"tuning.json": to_json(tr.to_dict())},
    )


def _verdict(ok: bool) -> Verdict:
    return Verdict.AGREES if ok else Verdict.DIFFERS


def _sampled_check(design: Design, sea: Any) -> Any:
    """The sampled-data verdict of ``sea`` under the file's ``[control]``, or None."""
    if design.loop is None:
        return None
    return sampled_passivity(sea, loop=design.loop)
