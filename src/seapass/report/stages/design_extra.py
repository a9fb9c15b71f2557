"""Stages of :func:`seapass.analyze.analyze` built on the witness, tuning, sampled-data and
rig modules (each imported only when its stage runs).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import sympy as sp

from .design_core import metrics_table, response_figure, step_responses
from ...model.design_file import Design
from ...errors import ModelError
from ..document import (
    FigureData,
    Finding,
    Section,
    Table,
    figure_png,
    format_intervals,
    to_json,
)

__all__ = [
    "matching_experiment_design",
    "matching_tunable_design",
    "stage_rig",
    "stage_sampled",
    "stage_tuning",
    "stage_witness",
]


# ----------------------------------------------------------------- witness


def stage_witness(design: Design, quick: bool) -> Section:
    from ...plot.witness import plot_witness
    from ...analysis.witness import find_destabilizing_environment

    title = "What can go wrong: a destabilizing passive environment"
    res = find_destabilizing_environment(design.sea())
    if res.passive:
        return Section(
            "witness", title, status="skipped",
            text="Skipped: the design is passive, so no passive environment (person, spring, "
            "mass, damper) can destabilize it (passivity theorem).",
        )  # fmt: skip
    if not res.found or res.environment is None:
        return Section("witness", title, text=f"No destabilizing environment found: {res.detail}.")
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
    figures: tuple[FigureData, ...] = ()
    if res.simulation is not None:
        figures = (
            FigureData(
                "witness", "Growing response of the design coupled to the environment.",
                figure_png(plot_witness(res)),
            ),
        )  # fmt: skip
    return Section(
        key="witness",
        title=title,
        text=(
            "Not passive means that *some* passive environment makes the coupled system "
            "unstable. seapass finds one (Colgate–Hogan construction plus a search, each "
            f"candidate verified exactly): {res.detail}."
        ),
        tables=(table,),
        figures=figures,
        findings=(
            Finding(
                f"{design.name} is safe to couple to any passive environment",
                "differs",
                res.detail,
            ),
        ),
        files={"witness.json": to_json(res.to_dict())},
    )


# ----------------------------------------------------------------- tuning


def matching_tunable_design(design: Design) -> str | None:
    """Name of the tunable design (``LP``, ``APD``, ``ours``) with the same structure, if any."""
    from ...model.expr import STANDARD_SYMBOLS, parse_expression
    from ...sim.tuning import DESIGNS

    sea = design.sea()
    if sea.D2 != 0 or not {"m", "b", "k1"} <= set(design.values):
        return None
    allowed = (*STANDARD_SYMBOLS, *design.values)
    for key, spec in DESIGNS.items():
        same = all(
            sp.simplify(getattr(sea, attr) - parse_expression(getattr(spec, attr), allowed)) == 0
            for attr in ("D1", "CA", "CL")
        )
        if same:
            return key
    return None


def stage_tuning(design: Design, quick: bool) -> Section:
    from dataclasses import replace

    from ...paper.simstudy import QUICK_OPTIONS
    from ...sim.tuning import DESIGNS, TuningOptions, tune

    key = matching_tunable_design(design)
    if key is None:
        names = "; ".join(
            f"{k}: D1 = {s.D1}, C_A = {s.CA}, C_L = {s.CL}" for k, s in DESIGNS.items()
        )
        return Section(
            "tuning", "Tuned gains", status="skipped",
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
    fig = response_figure(runs, design, f"{design.name} with tuned gains ({gains})")
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
        figures=(FigureData("tuned_response", "Step response with the tuned gains.", fig),),
        findings=(
            Finding("The tuned gains are passive", "agrees" if tr.passive else "differs", gains),
        ),
        files={"tuning.json": to_json(tr.to_dict())},
    )


# ----------------------------------------------------------------- sampled


def stage_sampled(design: Design, quick: bool) -> Section:
    from ...sampled.passivity import sampled_passive_bound, sampled_passivity

    period = design.period
    if period is None:
        return Section(
            "sampled", "Sampled-data passivity", status="skipped",
            text="Skipped: the design file has no `[control] rate`; the controller is "
            "analysed in continuous time only.",
        )  # fmt: skip
    sea = design.sea()
    kw: dict[str, Any] = {
        "period": period,
        "delay": design.control_delay,
        "velocity_filter": design.velocity_filter,
    }
    try:
        res = sampled_passivity(sea, **kw)
    except ModelError as exc:
        return Section(
            "sampled", "Sampled-data passivity", status="skipped",
            text=f"Skipped: the sampled-data test does not apply to this plant: {exc}",
        )  # fmt: skip
    samples, rtol = (9, 1e-3) if quick else (17, 1e-5)
    rows, bounds = [], {}
    for name, (lo, hi) in design.analysis_ranges().items():
        if name not in design.gains:
            continue
        b = sampled_passive_bound(
            sea.with_values(**{name: None}), name, lo=lo, hi=hi, samples=samples, rtol=rtol, **kw
        )
        bounds[name] = b.to_dict()
        rows.append(
            (name, design.values[name], f"[{lo:g}, {hi:g}]", format_intervals(b.intervals, hi))
        )
    setup = (
        f"T = {period * 1e3:.4g} ms ({design.control_rate:g} Hz), delay {design.control_delay} "
        f"sample(s), velocity filter "
        + ("none" if design.velocity_filter is None else f"{design.velocity_filter:g} Hz")
    )
    if res.passive:
        verdict = f"**Passive under sampled-data control** ({setup})."
    else:
        w = f" Witness ω = {res.omega:.6g} rad/s." if res.omega else ""
        verdict = f"**NOT passive under sampled-data control** ({setup}): {res.detail}.{w}"
    return Section(
        key="sampled",
        title="Sampled-data passivity",
        text=verdict
        + "\n\nDecided exactly with the Colgate–Schenkel alias argument generalised to the SEA "
        "(`seapass.sampled.passivity`). Each gain's passive set is located by a scan of exact verdicts "
        f"refined by bisection ({samples} scan points; islands narrower than a scan step can be "
        "missed).",
        tables=(
            Table(
                name="sampled_ranges",
                title=f"Passive gains under sampling ({setup})",
                columns=("gain", "value", "search range", "passive set (sampled)"),
                rows=tuple(rows),
            ),
        ),
        findings=(
            Finding(
                f"{design.name} stays passive at {design.control_rate:g} Hz",
                "agrees" if res.passive else "differs",
                res.detail,
            ),
        ),
        files={"sampled.json": to_json({"verdict": res.to_dict(), "bounds": bounds})},
    )


# ----------------------------------------------------------------- rig


def matching_experiment_design(design: Design) -> str | None:
    """``"LP"`` (``C_L = kd``) or ``"ours"`` (``C_A = kd + bd*s``) for the rig experiment, else None."""
    from ...model.expr import S, symbol

    sea = design.sea()
    kd, bd, s = symbol("kd"), symbol("bd"), S
    if sea.CA == 0 and sp.expand(sea.CL - kd) == 0:
        return "LP"
    if sea.CL == 0 and sp.expand(sea.CA - (kd + bd * s)) == 0:
        return "ours"
    return None


def stage_rig(design: Design, quick: bool) -> Section:
    from ...rig.experiment import ExperimentResult, run_sweep
    from ...plot.rig import plot_sweep
    from ...rig.rigfile import load_rig, paper_rig

    title = "On the digital twin of a rig"
    if design.rig_file is None:
        return Section(
            "rig", title, status="skipped", text="Skipped: the design file has no `[rig]` section."
        )
    rig = paper_rig() if design.rig_file == "paper" else load_rig(design.rig_file)
    key = matching_experiment_design(design)
    if key is None:
        return Section(
            "rig", title, status="skipped",
            text="Skipped: the twin's experiment runs load-side P (`C_L = kd`) or "
            "actuator-side PD (`C_A = kd + bd*s`) controllers only.",
        )  # fmt: skip
    ex = rig.experiment
    bd = design.values.get("bd") if key == "ours" else None
    step = ex.kd_step * (4 if quick else 1)
    sweeps = tuple(
        run_sweep(rig, design=key, load_mass=float(ml), kd_step=step, bd=bd)
        for ml in ex.load_masses
    )
    kd = design.values["kd"]
    rows = []
    for s in sweeps:
        i = int(np.argmin(np.abs(s.kd - kd)))
        rows.append(
            (s.load_mass, float(s.kd[i]), s.status[i], float(s.settling_time[i]),
             float(s.steady_state_error[i]) * 1e3, s.unstable_gain_twin)
        )  # fmt: skip
    fig = plot_sweep(ExperimentResult(rig.name, sweeps, ()))
    return Section(
        key="rig",
        title=title,
        text=(
            f"The controller runs on the twin of `{rig.name}` ({rig.control.rate:g} Hz, "
            f"{rig.control.delay_samples} sample delay, friction, quantization, saturation) "
            f"with the **rig's** plant (m = {rig.actuator_mass:.4g} kg, b = "
            f"{rig.actuator_damping:g} N·s/m, k1 = {rig.damper.k1:g} N/m, b1 = "
            f"{rig.damper.b1:g} N·s/m), not the file's: the load starts "
            f"{ex.initial_position * 1e3:g} mm from the reference; kd is swept from 0 to "
            f"{ex.kd_max:g} N/m."
        ),
        tables=(
            Table(
                name="rig_at_design_kd",
                title="At the gain nearest to the design's kd",
                columns=(
                    "load mass [kg]",
                    "kd [N/m]",
                    "status",
                    "settling time [s]",
                    "steady-state error [mm]",
                    "unstable from kd (twin) [N/m]",
                ),
                rows=tuple(rows),
            ),
        ),
        figures=(FigureData("rig_sweep", "kd sweep on the twin.", figure_png(fig)),),
        files={"rig_sweeps.json": to_json([s.to_dict() for s in sweeps])},
    )
