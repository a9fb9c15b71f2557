"""The report for a user's own design (``seapass analyze design.toml``).

`analyze` runs these stages on a [`Design`][seapass.model.design_file.Design] and
returns a [`Report`][seapass.report.document.Report]:

``passivity``
    The exact verdict at the given values (with the reason and a witness
    frequency when not passive), the derived stiffness ``F_L/X_L`` and the
    exact symbolic passivity condition.
``witness``
    For a design that is not passive: a passive mass-spring-damper environment
    that destabilizes it, verified exactly, with the growing response
    ([`seapass.analysis.witness.find_destabilizing_environment`][seapass.analysis.witness.find_destabilizing_environment]).
``stiffness``
    Rendered-stiffness frequency response.
``frequency``
    Passivity in the frequency domain: Bode of ``F_L/X_L`` with phase,
    ``Re Z_L(jω)`` with the exact bands where it is negative shaded, and the
    Nyquist plot of ``Z_L``.
``ranges``
    The exact passive set of every controller gain (and of every parameter with
    a ``[ranges]`` entry), the others held at their values
    ([`seapass.analysis.region.passive_intervals`][seapass.analysis.region.passive_intervals]).
``twoport``
    The SEA as a two-port between the person and the virtual environment it
    renders: absolute stability (Llewellyn) with the exact failing bands and
    the infimum of η, two-port passivity, reciprocity, a verified destabilizing
    pair of passive terminations, the exact absolutely-stable set of every gain
    and the friction certificate
    ([`seapass.ports`][seapass.ports]; the stage is ``report.stages.design_twoport``).
``response``
    Step response at every load mass, with 2 % settling time and final error.
``tuning``
    The fastest passive gains of the controller ([`seapass.tuning.tune`][seapass.tuning.optimize.tune]),
    each in its ``[ranges]`` box, the other parameters at their values; with ``[control]``,
    also the verdict of the tuned gains under the digital controller.
``sampled``
    Passivity under the digital controller and the largest passive value of
    every gain, when ``[control] rate`` is given ([`seapass.sampled.passivity`][seapass.sampled.passivity]).
``rig``
    A ``kd`` sweep on the digital twin of the ``[rig]`` (load-side P or
    actuator-side PD designs; [`seapass.rig.experiment.run_rig_sweep`][seapass.rig.experiment.run_rig_sweep]).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import partial

from ..model.design_file import Design
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
from .pipeline import Stage, run_stages, select_stages
from .stages import (
    design_dynamics,
    design_frequency,
    design_hardware,
    design_passivity,
    design_twoport,
    zwidth,
)
from .stages.design_passivity import values_text

__all__ = ["ANALYSIS_STAGES", "analyze", "design_file_section", "verdict_line"]


# ----------------------------------------------------------------- entry point

_STAGE_FUNCS: tuple[tuple[str, str, Callable[[Design, bool], Section]], ...] = (
    ("passivity", "Passivity verdict", design_passivity.stage_passivity),
    ("witness", "Destabilizing environment", design_passivity.stage_witness),
    ("stiffness", "Stiffness frequency response", design_dynamics.stage_stiffness),
    ("frequency", "Passivity in the frequency domain", design_frequency.stage_frequency),
    ("ranges", "Exact passive ranges", design_passivity.stage_ranges),
    (
        "twoport",
        "Two-port: any passive person, any passive virtual environment",
        design_twoport.stage_twoport,
    ),
    ("response", "Step response", design_dynamics.stage_response),
    ("tuning", "Tuned gains", design_dynamics.stage_tuning),
    ("sampled", "Sampled-data passivity", design_hardware.stage_sampled),
    ("zwidth", "Z-width map", zwidth.stage_design_zwidth),
    ("rig", "Digital twin of the rig", design_hardware.stage_rig),
)

_COSTS = {
    "zwidth": 5.3, "tuning": 4.8, "rig": 3.6, "witness": 1.5, "twoport": 1.2, "ranges": 1.1,
    "frequency": 1.1,
}  # fmt: skip
"""Run times [s] of the costly stages on examples/ours.toml (2 cores; the pool starts the
costliest first, so the two workers finish together); others count 1."""

ANALYSIS_STAGES: tuple[str, ...] = tuple(k for k, _t, _f in _STAGE_FUNCS)
"""Stage keys of `analyze`, in order."""


def analyze(
    design: Design,
    *,
    quick: bool = False,
    stages: Sequence[str] | None = None,
    progress: bool | None = None,
    log: Callable[[str], None] | None = None,
    jobs: int = 1,
) -> Report:
    """The analysis report of one design.

    Parameters
    ----------
    design : Design
        From [`seapass.model.design_file.load_design`][seapass.model.design_file.load_design].
    quick : bool
        Reduced tuning budget, coarser grids and scans.
    stages : sequence of str, optional
        Subset of `ANALYSIS_STAGES` (``"core"``: passivity, stiffness,
        ranges); default all.
    progress : bool, optional
        Progress bar over the stages (default: when stderr is a TTY).
    log : callable, optional
        Receives one line per finished stage.
    jobs : int
        Worker processes for the independent stages; the report is the same for every ``jobs``.

    Returns
    -------
    Report
        Write it with [`seapass.report.output.write_report`][seapass.report.output.write_report].
    """
    core = {"passivity", "stiffness", "ranges"}
    all_stages = [
        Stage(k, t, partial(f, design), core=k in core, cost=_COSTS.get(k, 1.0))
        for k, t, f in _STAGE_FUNCS
    ]
    chosen = select_stages(stages, all_stages)
    sections = run_stages(chosen, quick=quick, progress=progress, log=log, jobs=jobs)
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
    headline = (
        f"**Verdict: {verdict}.** " if verdict else ""
    ) + f"{len(sections)} analyses run, {ok} completed."
    return Report(
        title=f"seapass analysis: {title}",
        intro=intro,
        sections=(*sections, design_file_section(design)),
        headline=headline,
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
    control_units = {"rate": "Hz", "delay": "samples", "velocity_filter": "Hz"}
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
    by = {s.key: s for s in sections if s.status == SectionStatus.OK and s.findings}
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
