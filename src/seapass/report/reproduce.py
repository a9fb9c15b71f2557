"""The main job: regenerate every table and figure of the paper and what seapass adds.

:func:`reproduce` runs a sequence of *stages* and returns a
:class:`~seapass.report.document.Report`; :func:`seapass.report.document.write_report` writes it.
Stages (in order, keys for ``stages=``):

``tables``
    Tables I and II and the proposed design, paper and derived side by side
    (:func:`seapass.paper.tables.build_tables`), discrepancies flagged.
``stiffness``
    Rendered-stiffness frequency response of every row at the reference values.
``regions``
    The exact passive set of ``kd`` of every row at the paper's values
    (``m = 1, b = 10, k1 = 1000, b1 = 20, bd = 25``) against the paper's bound;
    the exact ``kd × b1`` map of load-side P with a damped spring with the
    paper's sufficient bound overlaid; the proposed design over a wide range;
    for a bound that admits non-passive gains, a passive environment that
    destabilizes one (:mod:`seapass.analysis.witness`).
``simulation``
    The paper's simulation study (Sec. V, Fig. 4) from :mod:`seapass.paper.simstudy`.
``rig``
    The hardware experiment (Sec. VI, Fig. 3) on the digital twin
    (:mod:`seapass.rig.experiment`): ``kd`` sweeps and impact stiffness.
``sampled``
    Largest passive ``kd`` at the rig's 500 Hz (:mod:`seapass.sampled.passivity`),
    ideal and with the rig's delay and velocity filter, against continuous time.
``deploy``
    The discrete controllers run by :class:`seapass.sampled.runtime.ControlLoop` on the
    twin behind the continuous and sampled passivity gate.
``tradeoff``
    Exact passivity and settling time over whole ``(kd, bd)`` and ``(kd, b1)``
    grids (:mod:`seapass.batch.verdicts`, :mod:`seapass.batch.step_metrics`).

Every stage is deterministic (fixed seeds; no timestamps).  A stage whose
module is missing is reported as *skipped*; a stage that raises is reported
as *failed* with its error, and the others still run.  Figures only consume
the stages' result objects.
"""

from __future__ import annotations

import functools
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import ParameterError, SeapassError
from .document import Report, Section
from .stages.paper_core import stage_regions, stage_stiffness, stage_tables
from .stages.paper_extra import (
    stage_deploy,
    stage_rig,
    stage_sampled,
    stage_simulation,
    stage_tradeoff,
)

__all__ = ["STAGES", "Stage", "reproduce", "run_stages", "select_stages", "stage_keys"]


@dataclass(frozen=True)
class Stage:
    """One step of a report: ``run(quick)`` returns a :class:`~seapass.report.document.Section`."""

    key: str
    title: str
    run: Callable[[bool], Section]
    core: bool = True


# ----------------------------------------------------------------- orchestration

STAGES: tuple[Stage, ...] = (
    Stage("tables", "Tables I and II", stage_tables),
    Stage("stiffness", "Stiffness frequency responses", stage_stiffness),
    Stage("regions", "Exact passive regions", stage_regions),
    Stage("simulation", "Simulation study", stage_simulation, core=False),
    Stage("rig", "Rig experiment (digital twin)", stage_rig, core=False),
    Stage("sampled", "Sampled-data passivity", stage_sampled, core=False),
    Stage("deploy", "Deployable controllers", stage_deploy, core=False),
    Stage("tradeoff", "Design-space trade-off", stage_tradeoff, core=False),
)


def stage_keys() -> tuple[str, ...]:
    """Keys of every stage of :func:`reproduce`, in order."""
    return tuple(s.key for s in STAGES)


def select_stages(stages: Sequence[str] | None, available: Sequence[Stage]) -> list[Stage]:
    """The stages named in ``stages`` (``"core"`` = all core stages), in run order."""
    if stages is None:
        return list(available)
    keys = {s.key for s in available}
    wanted: set[str] = set()
    for name in stages:
        if name == "core":
            wanted |= {s.key for s in available if s.core}
        elif name in keys:
            wanted.add(name)
        else:
            raise ParameterError(
                f"unknown stage {name!r}; choose from {', '.join(sorted(keys))} or 'core'"
            )
    return [s for s in available if s.key in wanted]


#: One matplotlib style for every figure, set before each stage: a stage's figures
#: must not depend on which plotting modules earlier stages imported.
FIGURE_STYLE: dict[str, Any] = {
    "font.size": 11,
    "axes.titlesize": 12,
    "axes.labelsize": 11,
    "legend.fontsize": 9,
    "svg.hashsalt": "seapass",
    "figure.dpi": 100,
}
_PLOTTING = (
    "plotting",
    "plotting_sim",
    "plotting_rig",
    "plotting_sampled",
    "plotting_sweep",
    "plotting_witness",
)


def _prepare_matplotlib() -> None:
    import importlib

    import matplotlib

    matplotlib.use("Agg")
    for name in _PLOTTING:  # import-time rcParams changes happen here, once
        try:
            importlib.import_module(f"{__package__}.{name}")
        except ImportError:
            pass


def _run_one(stage: Stage, quick: bool) -> tuple[Section, float]:
    """Run one stage; failures become sections (also the worker entry point)."""
    import matplotlib
    import matplotlib.style

    matplotlib.rcdefaults()
    matplotlib.style.use(FIGURE_STYLE)
    t0 = time.perf_counter()
    try:
        sec = stage.run(quick)
    except ImportError as exc:
        sec = Section(
            stage.key, stage.title, status="skipped",
            text=f"Skipped: a module this stage needs is not available ({exc}).",
        )  # fmt: skip
    except (SeapassError, ArithmeticError, ValueError, RuntimeError, TypeError) as exc:
        msg = " ".join(str(exc).split()) or type(exc).__name__
        sec = Section(
            stage.key, stage.title, status="failed",
            text=f"Failed: `{type(exc).__name__}`: {msg}",
        )  # fmt: skip
    return sec, time.perf_counter() - t0


def _ignore_sigint() -> None:
    import signal

    # the parent handles Ctrl-C and terminates the workers
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def run_stages(
    stages: Sequence[Stage],
    *,
    quick: bool = False,
    progress: bool | None = None,
    log: Callable[[str], None] | None = None,
    jobs: int = 1,
) -> tuple[Section, ...]:
    """Run ``stages`` under a progress bar; failures become sections.

    A stage that needs a module which is not installed becomes a ``skipped``
    section; any other exception becomes a ``failed`` section naming the
    error.  ``KeyboardInterrupt`` propagates (workers are terminated).  ``log``
    receives one line per stage with its wall time (never written to the
    report, which stays deterministic).  With ``jobs > 1`` the stages run in
    that many forked worker processes (stages are independent); the sections
    are returned in stage order and are identical to a sequential run.
    """
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    if jobs < 1:
        raise ParameterError(f"jobs must be at least 1, got {jobs}")
    show = sys.stderr.isatty() if progress is None else progress
    _prepare_matplotlib()
    jobs = min(jobs, len(stages))
    pool = None
    if jobs > 1:
        import multiprocessing

        # fork before the progress bar starts its refresh thread
        pool = multiprocessing.get_context("fork").Pool(jobs, initializer=_ignore_sigint)
    results: dict[int, tuple[Section, float]] = {}
    try:
        with Progress(
            TextColumn("[bold]{task.description}"),
            BarColumn(),
            TextColumn("{task.completed}/{task.total} stages"),
            TimeElapsedColumn(),
            console=Console(file=sys.stderr),
            disable=not show,
            transient=True,
        ) as bar:
            task = bar.add_task("starting", total=len(stages))

            def done(i: int, res: tuple[Section, float]) -> None:
                results[i] = res
                bar.advance(task)
                bar.update(task, description=f"finished {stages[i].title}")
                if log is not None:
                    line = f"{stages[i].key}: {res[0].status} in {res[1]:.1f} s"
                    # above a live bar, print through it so the lines do not tear it
                    if show:
                        bar.console.print(line, highlight=False)
                    else:
                        log(line)

            if pool is None:
                for i, st in enumerate(stages):
                    bar.update(task, description=st.title)
                    done(i, _run_one(st, quick))
            else:
                bar.update(task, description=f"{len(stages)} stages on {jobs} processes")
                pending = [
                    pool.apply_async(_run_one, (st, quick), callback=functools.partial(done, i))
                    for i, st in enumerate(stages)
                ]
                for p in pending:
                    p.get()
    finally:
        if pool is not None:
            pool.terminate()
            pool.join()
    return tuple(results[i][0] for i in range(len(stages)))


def reproduce(
    *,
    quick: bool = False,
    stages: Sequence[str] | None = None,
    progress: bool | None = None,
    log: Callable[[str], None] | None = None,
    jobs: int = 1,
) -> Report:
    """Regenerate the paper's results and seapass's additions as a :class:`Report`.

    Parameters
    ----------
    quick : bool
        Reduced optimiser budgets and coarser grids (about a minute in total).
    stages : sequence of str, optional
        Stage keys to run (see :data:`STAGES`; ``"core"`` selects the stages
        that need only the core modules).  Default: all.
    progress : bool, optional
        Rich progress bar over the stages on stderr (default: when stderr is a TTY).
    log : callable, optional
        Receives one line per finished stage (name, status, wall time).
    jobs : int
        Worker processes; the stages are independent, so 2 halves the wall
        time on two cores.  The report is the same for every ``jobs``.

    Returns
    -------
    Report
        Write it with :func:`seapass.report.document.write_report`.

    References
    ----------
    .. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
       Linear Control of Series Elastic Actuators".
    """
    from .. import __version__

    chosen = select_stages(stages, STAGES)
    sections = run_stages(chosen, quick=quick, progress=progress, log=log, jobs=jobs)
    skipped = [s.key for s in STAGES if s not in chosen]
    intro = (
        "Mehta & Losey, *Combining Performance and Passivity in Linear Control of Series "
        f"Elastic Actuators*, regenerated by seapass {__version__}"
        + (" with reduced budgets (`--quick`)." if quick else ".")
        + " Every number shown is in `data/` (CSV or JSON); every figure is in `figures/`. "
        "Verdicts are exact (rational arithmetic, Sturm sequences), not sampled on a grid."
        + (f"\n\nStages not run: {', '.join(skipped)}." if skipped else "")
    )
    return Report(
        title="seapass: the paper, reproduced and checked", intro=intro, sections=sections
    )
