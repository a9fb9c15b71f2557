"""The main job: regenerate every table and figure of the paper and what seapass adds.

`reproduce` runs a sequence of *stages* and returns a
[`Report`][seapass.report.document.Report]; [`seapass.report.output.write_report`][seapass.report.output.write_report] writes it.
Stages (in order, keys for ``stages=``):

``tables``
    Tables I and II and the proposed design, paper and derived side by side
    ([`seapass.paper.tables.build_tables`][seapass.paper.tables.build_tables]), discrepancies flagged.
``stiffness``
    Rendered-stiffness frequency response of every row at the reference values.
``regions``
    The exact passive set of ``kd`` of every row at the paper's values
    (``m = 1, b = 10, k1 = 1000, b1 = 20, bd = 25``) against the paper's bound;
    the exact ``kd × b1`` map of load-side P with a damped spring with the
    paper's sufficient bound overlaid; the proposed design over a wide range;
    for a bound that admits non-passive gains, a passive environment that
    destabilizes one ([`seapass.analysis.witness`][seapass.analysis.witness]).
``simulation``
    The paper's simulation study (Sec. V, Fig. 4) from [`seapass.paper.simstudy`][seapass.paper.simstudy].
``rig``
    The hardware experiment (Sec. VI, Fig. 3) on the digital twin
    ([`seapass.rig.experiment`][seapass.rig.experiment]): ``kd`` sweeps and impact stiffness.
``sampled``
    Largest passive ``kd`` at the rig's 500 Hz ([`seapass.sampled.passivity`][seapass.sampled.passivity]),
    ideal and with the rig's delay and velocity filter, against continuous time.
``deploy``
    The discrete controllers run by [`seapass.sampled.runtime.ControlLoop`][seapass.sampled.runtime.ControlLoop] on the
    twin behind the continuous and sampled passivity gate.
``tradeoff``
    Exact passivity and settling time over whole ``(kd, bd)`` and ``(kd, b1)``
    grids ([`seapass.batch.verdicts`][seapass.batch.verdicts], [`seapass.batch.step_metrics`][seapass.batch.step_metrics]).

Every stage is deterministic (fixed seeds; no timestamps).  A stage that
raises is reported as *failed* with its error and the others still run
([`seapass.report.pipeline`][seapass.report.pipeline]).  Figures only consume the stages' result
objects.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from ..progress import ProgressLike, as_progress
from ..version import __version__
from .document import Report, SectionStatus
from .pipeline import Stage, run_stages, select_stages
from .stages import hardware, regions, simulation, tables, zwidth

__all__ = ["STAGES", "reproduce", "stage_keys"]


STAGES: tuple[Stage, ...] = (
    Stage("tables", "Tables I and II", tables.stage_tables, cost=8.0),
    Stage("stiffness", "Stiffness frequency responses", tables.stage_stiffness, cost=3.0),
    Stage("regions", "Exact passive regions", regions.stage_regions, cost=5.0),
    Stage("simulation", "Simulation study", simulation.stage_simulation, core=False, cost=10.0),
    Stage("rig", "Rig experiment (digital twin)", hardware.stage_rig, core=False, cost=8.0),
    Stage("sampled", "Sampled-data passivity", hardware.stage_sampled, core=False, cost=8.0),
    Stage("zwidth", "Z-width map (sampled)", zwidth.stage_zwidth, core=False, cost=8.0),
    Stage("deploy", "Deployable controllers", hardware.stage_deploy, core=False),
    Stage("tradeoff", "Design-space trade-off", simulation.stage_tradeoff, core=False, cost=4.0),
)


def stage_keys() -> tuple[str, ...]:
    """Keys of every stage of `reproduce`, in order."""
    return tuple(s.key for s in STAGES)


def reproduce(
    *,
    quick: bool = False,
    stages: Sequence[str] | None = None,
    progress: ProgressLike = None,
    log: Callable[[str], None] | None = None,
    jobs: int = 1,
) -> Report:
    """Regenerate the paper's results and seapass's additions as a `Report`.

    Parameters
    ----------
    quick : bool
        Reduced optimiser budgets and coarser grids (about a minute in total).
    stages : sequence of str, optional
        Stage keys to run (see `STAGES`; ``"core"`` selects the stages
        that need only the core modules).  Default: all.
    progress : Progress, optional
        Where the run reports (a [`seapass.progress.Progress`][seapass.progress.Progress]):
        a task of one step per stage, each stage a task inside it.  Default: none;
        ``True``/``False`` still work for one release.
    log : callable, optional
        Receives one line per finished stage (name, status, wall time).
    jobs : int
        Worker processes; the stages are independent, so 2 halves the wall
        time on two cores.  The report is the same for every ``jobs``.

    Returns
    -------
    Report
        Write it with [`seapass.report.output.write_report`][seapass.report.output.write_report].

    References
    ----------
    .. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
       Linear Control of Series Elastic Actuators".
    """
    chosen = select_stages(stages, STAGES)
    sections = run_stages(
        chosen,
        quick=quick,
        progress=as_progress(progress, where="reproduce"),
        log=log,
        jobs=jobs,
        title="reproduce",
    )
    skipped = [s.key for s in STAGES if s not in chosen]
    intro = (
        "Mehta & Losey, *Combining Performance and Passivity in Linear Control of Series "
        f"Elastic Actuators*, regenerated by seapass {__version__}"
        + (" with reduced budgets (`--quick`)." if quick else ".")
        + " Every number shown is in [`data/`](data/) (CSV or JSON); every figure is in "
        "[`figures/`](figures/) (PNG and SVG). Verdicts are exact (rational arithmetic, "
        "certified root isolation), not sampled on a grid."
    )
    ok = [s.title for s in sections if s.status is SectionStatus.OK]
    headline = (
        f"**Reproduced:** {'; '.join(ok) if ok else 'nothing'}"
        f" ({len(ok)} of {len(sections)} stages completed"
        + (f"; not run: {', '.join(skipped)}" if skipped else "")
        + "). Each difference from the paper is classified below: a typo in a printed "
        "formula, a bound that is only conservative, a bound that is unsafe, or a check of "
        "seapass's own (twin, sampled data) that does not hold."
    )
    return Report(
        title="seapass: the paper, reproduced and checked",
        intro=intro,
        sections=sections,
        headline=headline,
    )
