"""Design stages about dynamics: stiffness response, step response, tuned gains.

Each ``stage_*`` returns a [`Section`][seapass.report.document.Section].
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import sympy as sp

from ...analysis.freqresp import stiffness_response
from ...model.catalog import SIMULATION_DESIGNS
from ...model.design_file import Design
from ...model.expr import STANDARD_SYMBOLS, parse_expression
from ...paper.simstudy import QUICK_OPTIONS
from ...plot.response import plot_stiffness_bode
from ...plot.sim import plot_step_responses
from ...sim.metrics import tracking_metrics
from ...sim.simulate import Step, simulate
from ...sim.tuning import TuningOptions, tune
from ..document import FigureData, Finding, Section, SectionStatus, Table, Verdict, to_json
from ..pipeline import stage_progress

__all__ = [
    "matching_tunable_design",
    "metrics_table",
    "stage_response",
    "stage_stiffness",
    "stage_tuning",
    "step_responses",
]


def stage_stiffness(design: Design, quick: bool) -> Section:
    """Magnitude and phase of the rendered stiffness ``F_L/X_L(jω)``."""
    sea = design.sea()
    r = stiffness_response(sea, np.logspace(-1, 4, 200 if quick else 400), label=design.name)
    k1 = design.values.get("k1")
    fig = plot_stiffness_bode(
        r, title=f"{design.name}: rendered stiffness"
        + (" (dashed: spring stiffness k1)" if k1 is not None else ""), reference=k1,
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


def matching_tunable_design(design: Design) -> str | None:
    """Name of the tunable design (``LP``, ``APD``, ``ours``) with the same structure, if any."""

    sea = design.sea()
    if sea.D2 != 0 or not {"m", "b", "k1"} <= set(design.values):
        return None
    allowed = (*STANDARD_SYMBOLS, *design.values)
    for spec in SIMULATION_DESIGNS:
        key = spec.key
        same = all(
            sp.simplify(getattr(sea, attr) - parse_expression(getattr(spec, attr), allowed)) == 0
            for attr in ("D1", "CA", "CL")
        )
        if same:
            return key
    return None


def stage_tuning(design: Design, quick: bool) -> Section:

    key = matching_tunable_design(design)
    if key is None:
        names = "; ".join(
            f"{s.key}: D1 = {s.D1}, C_A = {s.CA}, C_L = {s.CL}" for s in SIMULATION_DESIGNS
        )
        return Section(
            "tuning", "Tuned gains", status=SectionStatus.SKIPPED,
            text=f"Skipped: automatic tuning supports these structures only (D2 = 0, parameters named m, b, k1 and as shown): {names}.",
        )  # fmt: skip
    v = design.values
    opts = TuningOptions(
        load_mass=design.tuning_mass, step=design.step, horizon=design.horizon,
        m=v["m"], b=v["b"], k1=v["k1"],
    )  # fmt: skip
    if quick:
        opts = replace(
            opts, maxiter=QUICK_OPTIONS.maxiter, popsize=QUICK_OPTIONS.popsize,
            dt_search=QUICK_OPTIONS.dt_search,
        )  # fmt: skip
    tr = tune(key, options=opts, progress=False)
    runs = step_responses(tr.sea, design, 2e-3 if quick else 1e-3)
    gains = ", ".join(f"{k} = {g:.5g}" for k, g in tr.gains.items())
    table = Table(
        name="tuned_gains",
        title="Tuned gains vs the file's gains",
        columns=("gain", "file value", "tuned", "search range"),
        rows=tuple(
            (g, v.get(g), tr.gains[g], f"[{tr.bounds[g][0]:g}, {tr.bounds[g][1]:g}]")
            for g in tr.gains
        ),
    )
    fig = FigureData.of(
        "tuned_response", "Step response with the tuned gains.",
        plot_step_responses(
            runs, step=design.step, title=f"{design.name} with tuned gains ({gains})"
        ),
    )  # fmt: skip
    return Section(
        key="tuning",
        title="Tuned gains (fastest passive step response)",
        text=(
            f"The design has the structure of **{key}**, so its gains were tuned by "
            f"differential evolution (fixed seed) for the fastest 2 % settling at "
            f"m_L = {design.tuning_mass:g} kg, under the exact passivity constraint and a "
            f"{opts.force_limit:g} N force limit"
            + (" (reduced budget, --quick)" if quick else "")
            + f". Result: {gains} (passive: {'yes' if tr.passive else 'NO'})."
        ),
        tables=(table, metrics_table("tuned_metrics", "Step response with the tuned gains", runs)),
        figures=(fig,),
        findings=(
            Finding(
                "The tuned gains are passive",
                Verdict.AGREES if tr.passive else Verdict.DIFFERS,
                gains,
            ),
        ),
        files={"tuning.json": to_json(tr.to_dict())},
    )
