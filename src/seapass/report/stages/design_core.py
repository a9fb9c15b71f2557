"""Stages of :func:`seapass.analyze.analyze` that need only the core analysis modules:
the passivity verdict, the stiffness response, the exact passive ranges and step responses.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp

from ...model.design_file import Design
from ...errors import SeapassError
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
    "UNITS",
    "metrics_table",
    "response_figure",
    "stage_passivity",
    "stage_ranges",
    "stage_response",
    "stage_stiffness",
    "step_responses",
    "values_text",
]

#: SI units of the standard parameter names (for labels).
UNITS: dict[str, str] = {
    "m": "kg", "b": "N·s/m", "k1": "N/m", "k2": "N/m", "b1": "N·s/m", "b2": "N·s/m",
    "kd": "N/m", "bd": "N·s/m", "ki": "N/(m·s)",
}  # fmt: skip


def values_text(values: dict[str, float]) -> str:
    return ", ".join(f"{k} = {v:g}" for k, v in sorted(values.items()))


# ----------------------------------------------------------------- passivity


def stage_passivity(design: Design, quick: bool) -> Section:
    from ...analysis.conditions import exact_passivity_condition
    from ...analysis.passivity import is_passive
    from ...model.stiffness import derive_stiffness

    sea = design.sea()
    res = is_passive(sea)
    k = derive_stiffness(sea).stiffness
    k_num = sp.factor(sp.cancel(sea.numeric(k)))
    elements = Table(
        name="design",
        title="Design",
        columns=("element", "expression"),
        rows=(
            ("D1 (transmission)", f"`{design.D1}`"),
            ("D2 (load to ground)", f"`{design.D2}`"),
            ("C_A (actuator-side controller)", f"`{design.CA}`"),
            ("C_L (load-side controller)", f"`{design.CL}`"),
            ("parameter values", values_text(dict(design.values))),
            ("F_L/X_L (derived, symbolic)", f"`{sp.factor(k)}`"),
            ("F_L/X_L at the values", f"`{k_num}`"),
        ),
    )
    try:
        cond = exact_passivity_condition(sea)
        cond_text = (
            f"Exact passivity condition for positive parameters (symbolic):\n\n"
            f"```\n{cond.condition}\n```\n\n"
            f"Real-part polynomial `Re N(jω) D(−jω)`:\n\n```\n{cond.real_part}\n```"
        )
        files = {"condition.json": to_json(cond.to_dict())}
    except SeapassError as exc:
        cond_text = f"The symbolic condition is not available: {exc}"
        files = {}
    if res.passive:
        verdict = f"**The design is passive** at the given values ({res.status})."
    else:
        w = (
            f" A witness: `Re Z(jω) < 0` at ω = {res.omega:.6g} rad/s."
            if res.omega and "w =" not in res.detail
            else ""
        )
        verdict = (
            f"**The design is NOT passive** at the given values: {res.detail or res.reason}.{w} "
            "Coupled to some passive environment (a person, a spring, a mass) it can become "
            "unstable. See the passive ranges below for values that are safe."
        )
    finding = Finding(
        f"{design.name} is passive at {values_text(dict(design.values))}",
        "agrees" if res.passive else "differs",
        res.status + (f": {res.detail}" if res.detail else ""),
    )
    return Section(
        key="passivity",
        title="Passivity verdict",
        text=verdict + "\n\n" + cond_text,
        tables=(elements,),
        findings=(finding,),
        files={"passivity.json": to_json(res.to_dict()), **files},
    )


# ----------------------------------------------------------------- stiffness


def stage_stiffness(design: Design, quick: bool) -> Section:
    from ...analysis.freqresp import stiffness_response
    from ...plot.analysis import plot_stiffness_response

    sea = design.sea()
    r = stiffness_response(sea, np.logspace(-1, 4, 200 if quick else 400), label=design.name)
    k1 = design.values.get("k1")
    fig = plot_stiffness_response(r, title=f"{design.name}: rendered stiffness", reference=k1)
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
        text="`|F_L/X_L(jω)|`: the stiffness a person feels when moving the load at frequency ω.",
        tables=(table,),
        figures=(FigureData("stiffness", "Rendered stiffness of the design.", figure_png(fig)),),
        files={"stiffness_response.csv": "\n".join(lines) + "\n"},
    )


# ----------------------------------------------------------------- ranges


def stage_ranges(design: Design, quick: bool) -> Section:
    import matplotlib.pyplot as plt

    from ...plot.analysis import plot_passive_intervals
    from ...analysis.region import passive_intervals

    sea = design.sea()
    ranges = design.analysis_ranges()
    results = []
    for name, (lo, hi) in ranges.items():
        others = {k: v for k, v in design.values.items() if k != name}
        results.append((name, passive_intervals(sea, name, lo, hi, values=others)))
    rows, flags, findings = [], set(), []
    for i, (name, res) in enumerate(results):
        value = design.values[name]
        inside = res.contains(value) if res.lo <= value <= res.hi else None
        if inside is False:
            flags.add((i, 3))
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
                "info" if inside is None else ("agrees" if inside else "differs"),
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
    figures = []
    if results:
        fig, axes = plt.subplots(
            len(results), 1, figsize=(7, 1.6 * len(results) + 0.6), squeeze=False,
            constrained_layout=True,
        )  # fmt: skip
        for ax, (name, res) in zip(axes[:, 0], results, strict=True):
            plot_passive_intervals(res, ax=ax)
            value = design.values[name]
            unit = UNITS.get(name, "SI units")
            for a, b in res.intervals:
                if a == b:  # an isolated passive value has no width: draw it
                    ax.axvline(a, color="#2e7d32", lw=3, clip_on=False)
            # unclipped: a design value at the end of the range stays visible
            ax.axvline(
                value, color="tab:blue", lw=2.5, clip_on=False, label=f"design: {value:g} {unit}"
            )
            ax.set_xlabel(f"{name} [{unit}]")
            ax.legend(loc="upper right", ncol=3, fontsize=8)
        fig.suptitle(f"{design.name}: exact passive sets")
        figures.append(
            FigureData("passive_ranges", "Exact passive set of every gain.", figure_png(fig))
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


# ----------------------------------------------------------------- response


def step_responses(sea: Any, design: Design, dt: float) -> list[tuple[float, Any, Any]]:
    from ...sim.metrics import tracking_metrics
    from ...sim.simulate import Step, simulate

    out = []
    for mass in design.load_masses:
        res = simulate(
            sea, load_mass=mass, scenario=Step(design.step), horizon=design.horizon, dt=dt
        )
        out.append((mass, res, tracking_metrics(res)))
    return out


def response_figure(runs: list[tuple[float, Any, Any]], design: Design, title: str) -> bytes:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 3.8), constrained_layout=True)
    for mass, res, met in runs:
        ts = f"settles in {met.settling_time:.3g} s" if met.settled else met.status
        # an unstable run is drawn until it leaves ±10 steps (the axes stay readable)
        limit = 10 * abs(design.step)
        out = np.flatnonzero(np.abs(res.x_L) > limit)
        x = np.array(res.x_L, dtype=float)
        if out.size:
            x[out[0] :] = np.nan
            ts += f", |x_L| > {limit:g} m at {res.time[out[0]]:.3g} s"
        ax.plot(res.time, x, lw=1.5, label=f"m_L = {mass:g} kg ({ts})")
    ax.axhline(design.step, color="0.3", lw=0.8, ls="--", label=f"target {design.step:g} m")
    ax.axhspan(design.step * 0.98, design.step * 1.02, color="0.88", zorder=0)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("load position x_L [m]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    return figure_png(fig)


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
    fig = response_figure(runs, design, f"{design.name}: {design.step:g} m reference step")
    return Section(
        key="response",
        title="Step response at the given gains",
        text=(
            f"A {design.step:g} m step of both references from rest, simulated exactly "
            f"(matrix exponential) for {design.horizon:g} s with a load mass at the port. "
            "Settling: within 2 % of the step for the rest of the horizon."
        ),
        tables=(metrics_table("step_metrics", "Step-response metrics", runs),),
        figures=(FigureData("step_response", "Load position after the step.", fig),),
    )
