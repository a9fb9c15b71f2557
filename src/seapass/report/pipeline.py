"""The stage pipeline shared by [`reproduce`][seapass.report.reproduce.reproduce] and
[`analyze`][seapass.report.analyze.analyze].

A report is a sequence of independent `Stage` objects, each returning a
[`Section`][seapass.report.document.Section].  `run_stages` runs them under
a progress bar, in this process or in forked workers, with every figure drawn
in the one seapass style on bare (non-pyplot) figures.  A stage that needs an
optional extra that is not installed (`seapass.errors.MissingExtraError`, e.g.
MuJoCo) becomes a *skipped* section; a stage that raises anything else, a
missing module included, becomes a *failed* section naming the error, and the
command exits non-zero.
"""

from __future__ import annotations

import functools
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from ..errors import MissingExtraError, ParameterError, SeapassError
from ..plot.style import bare_figures, figure_style
from .document import Section, SectionStatus

__all__ = ["Stage", "run_stages", "select_stages"]


@dataclass(frozen=True)
class Stage:
    """One step of a report: ``run(quick)`` returns a [`Section`][seapass.report.document.Section]."""

    key: str
    title: str
    run: Callable[[bool], Section]
    core: bool = True


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


def _run_one(stage: Stage, quick: bool) -> tuple[Section, float]:
    """Run one stage; failures become sections (also the worker entry point)."""
    t0 = time.perf_counter()
    try:
        with figure_style(), bare_figures():
            sec = stage.run(quick)
    except MissingExtraError as exc:
        sec = Section(stage.key, stage.title, status=SectionStatus.SKIPPED, text=f"Skipped: {exc}")
    except ImportError as exc:  # a broken install or a bug: never skipped
        sec = _failed(stage, exc)
    except (SeapassError, ArithmeticError, ValueError, RuntimeError, TypeError) as exc:
        sec = _failed(stage, exc)
    return sec, time.perf_counter() - t0


def _failed(stage: Stage, exc: BaseException) -> Section:
    msg = " ".join(str(exc).split()) or type(exc).__name__
    return Section(
        stage.key, stage.title, status=SectionStatus.FAILED,
        text=f"Failed: `{type(exc).__name__}`: {msg}",
    )  # fmt: skip


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

    A stage that needs an optional extra that is not installed
    (`MissingExtraError`) becomes a ``skipped`` section; any other exception,
    a broken import included, becomes a ``failed`` section naming the error.  ``KeyboardInterrupt`` propagates (workers are terminated).  ``log``
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
