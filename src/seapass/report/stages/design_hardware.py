"""Design stages about the hardware: sampled-data passivity and the digital twin of the rig.

Each ``stage_*`` returns a [`Section`][seapass.report.document.Section]; one with
figures is split as python-control splits ``*_response`` from ``*_plot``
(``*_data`` computes, ``*_figures`` draws, ``*_section`` writes the section).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import sympy as sp

from ...errors import ModelError
from ...exact.rounding import enclosure_text
from ...model.design_file import Design
from ...model.expr import S, symbol
from ...outcome import Outcome
from ...plot.rig import plot_rig_sweep
from ...progress import ProgressLike, as_progress, task
from ...rig.design_sweep import design_gain, run_design_sweeps
from ...rig.experiment import ExperimentResult, RigSweepResult, run_rig_sweeps
from ...rig.rigfile import Rig, load_rig, paper_rig
from ...sampled.bound import intervals_text, sampled_passive_bound
from ...sampled.passivity import sampled_passivity
from ..document import (
    FigureData,
    Finding,
    Section,
    SectionStatus,
    Table,
    Verdict,
    format_intervals,
    to_json,
)
from ..pipeline import StageContext

__all__ = [
    "DesignRigData",
    "matching_experiment_design",
    "rig_data",
    "rig_figures",
    "rig_section",
    "stage_rig",
    "stage_sampled",
]


def stage_sampled(design: Design, context: StageContext) -> Section:
    """The sampled-data verdict and the certified passive set of every gain.

    Budget: boxes of each gain's branch and bound (what a bound leaves is reported
    undecided, never passive, and the stage is stopped at its budget).
    """
    loop = design.loop
    if loop is None:
        return Section(
            "sampled", "Sampled-data passivity", status=SectionStatus.SKIPPED,
            text="Skipped: the design file has no `[control] rate`; the controller is "
            "analysed in continuous time only.",
        )  # fmt: skip
    sea = design.sea()
    try:
        res = sampled_passivity(sea, loop=loop)
    except ModelError as exc:
        return Section(
            "sampled", "Sampled-data passivity", status=SectionStatus.SKIPPED,
            text=f"Skipped: the sampled-data test does not apply to this plant: {exc}",
        )  # fmt: skip
    rtol = 1e-6 if context.quick else 1e-9
    rows, bounds, stopped = [], {}, []
    budget: dict[str, Any] = {} if context.budget is None else {"max_boxes": context.budget}
    for name, (lo, hi) in design.analysis_ranges().items():
        if name not in design.gains:
            continue
        value = design.values[name]
        b = sampled_passive_bound(
            sea.with_values(**{name: None}), name, loop=loop, lo=lo, hi=hi, rtol=rtol,
            design_value=value, progress=context.progress, **budget,
        )  # fmt: skip
        bounds[name] = b.to_dict()
        if b.budget_exhausted:
            stopped.append(name)
        edges = "; ".join(
            f"{enclosure_text(e.lo, e.hi, digits=10)} ({e.kind.replace('_', ' ')})" for e in b.edges
        )
        rows.append(
            (name, value, f"[{b.lo:g}, {b.hi:g}]", format_intervals(b.intervals, b.hi),
             edges or "none", "yes" if b.design_passive else "no",
             intervals_text(_joined(b.undecided), most=5) if b.undecided else "none")
        )  # fmt: skip
    setup = (
        f"T = {loop.period * 1e3:.4g} ms ({loop.rate:g} Hz), delay {loop.delay} "
        f"sample(s), velocity filter "
        + ("none" if loop.velocity_filter is None else f"{loop.velocity_filter:g} Hz")
    )
    if res.passive:
        verdict = f"**Passive under sampled-data control** ({setup})."
    elif res.outcome is Outcome.UNDECIDED:
        verdict = f"**Undecided under sampled-data control** ({setup}): {res.detail}; treated as not passive."
    else:
        w = f" Witness ω = {res.omega:.6g} rad/s." if res.omega else ""
        verdict = f"**NOT passive under sampled-data control** ({setup}): {res.detail}.{w}"
    return Section(
        key="sampled",
        title="Sampled-data passivity",
        text=verdict
        + "\n\nCertified with the Colgate–Schenkel alias argument generalised to the SEA "
        "(`seapass.sampled.passivity`): the power polynomial's sign is decided with ball "
        "arithmetic, ω → 0 included. Each gain's passive set is certified by branch and bound "
        f"(`seapass.sampled.bound`): no scan, edges enclosed to a relative width of {rtol:g}; "
        "the range includes the design's own value."
        + (
            f"\n\n**Stopped at the budget of {context.budget} boxes per bound** for "
            + ", ".join(f"`{g}`" for g in stopped)
            + ": the part of the range the branch and bound did not settle is listed as "
            "undecided (never passive); raise it with `--budget sampled=N`."
            if stopped
            else ""
        ),
        tables=(
            Table(
                name="sampled_ranges",
                title=f"Passive gains under sampling ({setup})",
                columns=(
                    "gain",
                    "value",
                    "range",
                    "passive set (sampled, certified)",
                    "edge enclosures",
                    "value passive",
                    "undecided",
                ),
                rows=tuple(rows),
            ),
        ),
        findings=(
            Finding(
                f"{design.name} stays passive at {design.control_rate:g} Hz",
                Verdict.AGREES if res.passive else Verdict.DIFFERS,
                res.detail,
            ),
        ),
        files={"sampled.json": to_json({"verdict": res.to_dict(), "bounds": bounds})},
        status=SectionStatus.STOPPED_AT_BUDGET if stopped else SectionStatus.OK,
    )


def _joined(pieces: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    """Touching intervals joined (the undecided leaves of a bound stopped at its budget)."""
    out: list[tuple[float, float]] = []
    for a, b in sorted(pieces):
        if out and a <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], b))
        else:
            out.append((a, b))
    return out


def matching_experiment_design(design: Design) -> str | None:
    """``"LP"`` (``C_L = kd``) or ``"ours"`` (``C_A = kd + bd*s``) for the rig experiment, else None."""

    sea = design.sea()
    kd, bd, s = symbol("kd"), symbol("bd"), S
    if sea.CA == 0 and sp.expand(sea.CL - kd) == 0:
        return "LP"
    if sea.CL == 0 and sp.expand(sea.CA - (kd + bd * s)) == 0:
        return "ours"
    return None


@dataclass(frozen=True, kw_only=True)
class DesignRigData:
    """The design's controller swept over kd on the twin of its rig (`rig_data`)."""

    rig: Rig
    sweeps: tuple[RigSweepResult, ...]
    gains_cut: int = 0
    """Gains of the kd grid left out by the budget (the highest ones)."""


_RIG_TITLE = "On the digital twin of a rig"


def rig_data(
    design: Design, quick: bool, *, budget: int | None = None, progress: ProgressLike = None
) -> DesignRigData | Section:
    """The kd sweeps on the twin, or the skipped section when the twin does not apply.

    At most ``budget`` twin runs (gains × load masses): the kd grid is cut from the top.
    """
    if design.rig_file is None:
        return Section(
            "rig",
            _RIG_TITLE,
            status=SectionStatus.SKIPPED,
            text="Skipped: the design file has no `[rig]` section.",
        )
    rig = paper_rig() if design.rig_file == "paper" else load_rig(design.rig_file)
    key = matching_experiment_design(design)
    ex = rig.experiment
    if key is None:  # any other controller: its realization runs on the twin
        if not design.gains:
            return Section(
                "rig", _RIG_TITLE, status=SectionStatus.SKIPPED,
                text="Skipped: the design has no controller gain to sweep on the twin.",
            )  # fmt: skip
        gain = design_gain(design)
        lo, hi = design.analysis_ranges()[gain]
        step = (hi - lo) / (10 if quick else 20)
        shown = as_progress(progress, where="rig_data")
        with task(shown, f"{gain} sweeps on the twin of {rig.name}", 1):
            sweeps = run_design_sweeps(rig, design, gain=gain, load_masses=ex.load_masses,
                                       gain_step=step)  # fmt: skip
            shown.advance(1)
        return DesignRigData(rig=rig, sweeps=tuple(sweeps))
    bd = design.values.get("bd") if key == "ours" else None
    step = ex.kd_step * (4 if quick else 1)
    grid = np.arange(0.0, ex.kd_max + 0.5 * step, step)
    keep = grid.size if budget is None else min(grid.size, budget // len(ex.load_masses))
    if keep == 0:
        return Section(
            "rig", _RIG_TITLE, status=SectionStatus.STOPPED_AT_BUDGET,
            text=f"Stopped at the budget of {budget} twin runs: fewer than one gain per load "
            f"mass ({len(ex.load_masses)}); raise it with `--budget rig=N`.",
        )  # fmt: skip
    shown = as_progress(progress, where="rig_data")
    runs = keep * len(ex.load_masses)
    with task(shown, f"kd sweeps on the twin of {rig.name}: {runs} runs", 1):
        sweeps = run_rig_sweeps(
            rig, designs=(key,), load_masses=ex.load_masses, kd=grid[:keep], bd=bd
        )
        shown.advance(1)
    return DesignRigData(rig=rig, sweeps=tuple(sweeps), gains_cut=grid.size - keep)


def rig_figures(data: DesignRigData) -> tuple[FigureData, ...]:
    fig = plot_rig_sweep(ExperimentResult(rig_name=data.rig.name, sweeps=data.sweeps, findings=()))
    gain = data.sweeps[0].gain if data.sweeps else "kd"
    return (FigureData.of("rig_sweep", f"{gain} sweep on the twin.", fig),)


def rig_section(design: Design, data: DesignRigData, figures: Sequence[FigureData]) -> Section:
    """The section of `rig_data` with the figures of `rig_figures`."""
    rig, sweeps = data.rig, data.sweeps
    ex = rig.experiment
    gain = sweeps[0].gain if sweeps else "kd"
    kd = design.values[gain]
    unit = " [N/m]" if gain == "kd" else ""
    if gain == "kd":
        swept = f"kd is swept from 0 to {ex.kd_max:g} N/m."
    else:
        lo, hi = float(min(s.kd.min() for s in sweeps)), float(max(s.kd.max() for s in sweeps))
        swept = (
            f"{gain} is swept from {lo:g} to {hi:g}. The design's controller (its other gains "
            "as in the file) runs as one difference equation, discretized at the rig's rate "
            "(`seapass.rig.design_sweep`)."
        )
    rows = []
    for s in sweeps:
        i = int(np.argmin(np.abs(s.kd - kd)))
        rows.append(
            (s.load_mass, float(s.kd[i]), s.status[i], float(s.settling_time[i]),
             float(s.steady_state_error[i]) * 1e3, s.unstable_gain_twin)
        )  # fmt: skip
    return Section(
        key="rig",
        title=_RIG_TITLE,
        text=(
            f"The controller runs on the twin of `{rig.name}` ({rig.control.rate:g} Hz, "
            f"{rig.control.delay} sample delay, friction, quantization, saturation) "
            f"with the **rig's** plant (m = {rig.actuator_mass:.4g} kg, b = "
            f"{rig.actuator_damping:g} N·s/m, k1 = {rig.damper.k1:g} N/m, b1 = "
            f"{rig.damper.b1:g} N·s/m), not the file's: the load starts "
            f"{ex.initial_position * 1e3:g} mm from the reference; " + swept
        ),
        tables=(
            Table(
                name="rig_at_design_kd",
                title=f"At the gain nearest to the design's {gain}",
                columns=(
                    "load mass [kg]",
                    f"{gain}{unit}",
                    "status",
                    "settling time [s]",
                    "steady-state error [mm]",
                    f"unstable from {gain} (twin){unit}",
                ),
                rows=tuple(rows),
            ),
        ),
        figures=tuple(figures),
        files={"rig_sweeps.json": to_json([s.to_dict() for s in sweeps])},
    )


def stage_rig(design: Design, context: StageContext) -> Section:
    """A kd sweep on the twin of the design's rig.

    Budget: twin runs (kd gains × load masses); the highest gains beyond it are not
    run and the stage is stopped at its budget.
    """
    data = rig_data(design, context.quick, budget=context.budget, progress=context.progress)
    if isinstance(data, Section):
        return data
    sec = rig_section(design, data, rig_figures(data))
    if not data.gains_cut:
        return sec
    top = max(float(s.kd[-1]) for s in data.sweeps)
    return replace(
        sec,
        status=SectionStatus.STOPPED_AT_BUDGET,
        text=sec.text + f" **Stopped at the budget of {context.budget} twin runs**: kd swept up to "
        f"{top:g} N/m only, {data.gains_cut} higher gain(s) per load mass not run (raise it "
        "with `--budget rig=N`).",
    )
