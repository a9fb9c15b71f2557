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
from .document import Report, Section, SectionStatus, Verdict, to_json
from .pipeline import Stage, run_stages, select_stages
from .stages import design_dynamics, design_frequency, design_hardware, design_passivity, zwidth
from .stages.design_passivity import values_text

__all__ = ["ANALYSIS_STAGES", "analyze", "verdict_line"]


# ----------------------------------------------------------------- entry point

_STAGE_FUNCS: tuple[tuple[str, str, Callable[[Design, bool], Section]], ...] = (
    ("passivity", "Passivity verdict", design_passivity.stage_passivity),
    ("witness", "Destabilizing environment", design_passivity.stage_witness),
    ("stiffness", "Stiffness frequency response", design_dynamics.stage_stiffness),
    ("frequency", "Passivity in the frequency domain", design_frequency.stage_frequency),
    ("ranges", "Exact passive ranges", design_passivity.stage_ranges),
    ("response", "Step response", design_dynamics.stage_response),
    ("tuning", "Tuned gains", design_dynamics.stage_tuning),
    ("sampled", "Sampled-data passivity", design_hardware.stage_sampled),
    ("zwidth", "Z-width map", zwidth.stage_design_zwidth),
    ("rig", "Digital twin of the rig", design_hardware.stage_rig),
)

ANALYSIS_STAGES: tuple[str, ...] = tuple(k for k, _t, _f in _STAGE_FUNCS)
"""Stage keys of `analyze`, in order."""


def analyze(
    design: Design,
    *,
    quick: bool = False,
    stages: Sequence[str] | None = None,
    progress: bool | None = None,
    log: Callable[[str], None] | None = None,
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

    Returns
    -------
    Report
        Write it with [`seapass.report.output.write_report`][seapass.report.output.write_report].
    """
    core = {"passivity", "stiffness", "ranges"}
    all_stages = [Stage(k, t, partial(f, design), core=k in core) for k, t, f in _STAGE_FUNCS]
    chosen = select_stages(stages, all_stages)
    sections = run_stages(chosen, quick=quick, progress=progress, log=log)
    head = verdict_line(sections, design)
    head = f"**Verdict: {head}.** " if head else ""
    title = design.title or design.name
    intro = (
        f"{head}Analysis of the design `{design.name}`"
        + (f" ({design.title})" if design.title else "")
        + f": D1 = `{design.D1}`, D2 = `{design.D2}`, C_A = `{design.CA}`, C_L = `{design.CL}`; "
        f"{values_text(dict(design.values))} (SI units). Every number is in `data/`, every "
        "figure in `figures/`; verdicts are exact."
        + (" Reduced budgets (`--quick`)." if quick else "")
    )
    extra = Section(
        key="design-file",
        title="Design file (as validated)",
        text="The design as read and validated; the same content is in `data/design.json`.",
        files={"design.json": to_json(design.to_dict())},
    )
    return Report(
        title=f"seapass analysis: {title}",
        intro=intro,
        sections=(*sections, extra),
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
