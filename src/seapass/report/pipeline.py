"""The stage pipeline shared by [`reproduce`][seapass.report.reproduce.reproduce] and
[`analyze`][seapass.report.analyze.analyze].

A report is a sequence of independent `Stage` objects, each returning a
[`Section`][seapass.report.document.Section].  `run_stages` runs them under
a progress bar, in this process or in forked workers (the costliest stages
first, so two workers finish together), with every figure drawn in the one
seapass style on bare (non-pyplot) figures.  A stage reports progress within
itself with `stage_progress`; the bar shows it, whichever process runs the
stage.  A stage that needs an
optional extra that is not installed (`seapass.errors.MissingExtraError`, e.g.
MuJoCo) becomes a *skipped* section; a stage that raises anything else, a
missing module included, becomes a *failed* section naming the error, and the
command exits non-zero.
"""

from __future__ import annotations

import functools
import sys
import threading
import time
from collections.abc import Callable, Sequence
from contextvars import ContextVar
from dataclasses import dataclass
from typing import Any

from ..errors import MissingExtraError, ParameterError, SeapassError
from ..plot.style import bare_figures, figure_style
from .document import Section, SectionStatus

__all__ = ["Stage", "run_stages", "select_stages", "stage_progress"]


@dataclass(frozen=True)
class Stage:
    """One step of a report: ``run(quick)`` returns a [`Section`][seapass.report.document.Section].

    ``cost`` is the stage's expected run time relative to the others (any
    unit); with several workers the costliest stages start first.
    """

    key: str
    title: str
    run: Callable[[bool], Section]
    core: bool = True
    cost: float = 1.0


_PROGRESS: ContextVar[Callable[[float, str], None] | None] = ContextVar(
    "seapass_stage_progress", default=None
)


def stage_progress(done: float, total: float, text: str = "") -> None:
    """Report progress within the running stage: ``done`` of ``total`` steps, at ``text``.

    Stages call it in their loops; `run_stages` shows it on the progress bar
    (also from worker processes).  Outside `run_stages` it does nothing.
    """
    callback = _PROGRESS.get()
    if callback is not None and total > 0:
        callback(min(max(done / total, 0.0), 1.0), text)


class _Throttle:
    """Forward at most one update per ``interval`` seconds (always the last of a stage)."""

    def __init__(self, send: Callable[[float, str], None], interval: float = 0.1) -> None:
        self.send, self.interval, self.last = send, interval, -1.0

    def __call__(self, fraction: float, text: str) -> None:
        now = time.monotonic()
        if now - self.last >= self.interval or fraction >= 1.0:
            self.last = now
            self.send(fraction, text)


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


def _run_one(
    stage: Stage, quick: bool, on_progress: Callable[[float, str], None] | None = None
) -> tuple[Section, float]:
    """Run one stage; failures become sections."""
    t0 = time.perf_counter()
    token = _PROGRESS.set(None if on_progress is None else _Throttle(on_progress))
    try:
        with figure_style(), bare_figures():
            sec = stage.run(quick)
    except MissingExtraError as exc:
        sec = Section(stage.key, stage.title, status=SectionStatus.SKIPPED, text=f"Skipped: {exc}")
    except ImportError as exc:  # a broken install or a bug: never skipped
        sec = _failed(stage, exc)
    except (SeapassError, ArithmeticError, ValueError, RuntimeError, TypeError) as exc:
        sec = _failed(stage, exc)
    finally:
        _PROGRESS.reset(token)
    return sec, time.perf_counter() - t0


def _failed(stage: Stage, exc: BaseException) -> Section:
    msg = " ".join(str(exc).split()) or type(exc).__name__
    return Section(
        stage.key, stage.title, status=SectionStatus.FAILED,
        text=f"Failed: `{type(exc).__name__}`: {msg}",
    )  # fmt: skip


# set in the parent just before the workers fork, so stages (closures over designs) are
# inherited, never pickled
_WORKER_STAGES: Sequence[Stage] = ()
_WORKER_QUEUE: Any = None


def _init_worker(queue: Any) -> None:
    import signal

    global _WORKER_QUEUE
    # the parent handles Ctrl-C and terminates the workers
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _WORKER_QUEUE = queue


def _run_in_worker(index: int, quick: bool) -> tuple[Section, float]:
    """Worker entry point: stage ``index`` of the inherited list; progress through the queue."""
    queue = _WORKER_QUEUE

    def send(fraction: float, text: str) -> None:
        queue.put((index, fraction, text))

    return _run_one(_WORKER_STAGES[index], quick, send if queue is not None else None)


class _Tracker:
    """The progress bar over the stages, the results, and the per-stage log lines."""

    def __init__(
        self,
        stages: Sequence[Stage],
        bar: Any,
        show: bool,
        log: Callable[[str], None] | None,
        on_progress: Callable[[str, float, str], None] | None,
    ) -> None:
        self.stages, self.bar, self.show = stages, bar, show
        self.log, self.on_progress = log, on_progress
        self.task = bar.add_task("starting", total=len(stages))
        self.fractions = [0.0] * len(stages)
        self.results: dict[int, tuple[Section, float]] = {}

    def moved(self, i: int, fraction: float, text: str) -> None:
        """Stage ``i`` reports ``fraction`` done (from this process or a worker's queue)."""
        if self.on_progress is not None:
            self.on_progress(self.stages[i].key, fraction, text)
        self.fractions[i] = fraction
        where = f"{self.stages[i].title}: {text}" if text else self.stages[i].title
        self.bar.update(self.task, completed=sum(self.fractions), description=where)

    def done(self, i: int, res: tuple[Section, float]) -> None:
        self.results[i] = res
        self.fractions[i] = 1.0
        left = len(self.stages) - len(self.results)
        self.bar.update(
            self.task, completed=sum(self.fractions),
            description=f"finished {self.stages[i].title} ({left} to go)",
        )  # fmt: skip
        if self.log is not None:
            line = f"{self.stages[i].key}: {res[0].status} in {res[1]:.1f} s"
            # above a live bar, print through it so the lines do not tear it
            if self.show:
                self.bar.console.print(line, highlight=False)
            else:
                self.log(line)


def run_stages(
    stages: Sequence[Stage],
    *,
    quick: bool = False,
    progress: bool | None = None,
    log: Callable[[str], None] | None = None,
    jobs: int = 1,
    on_progress: Callable[[str, float, str], None] | None = None,
) -> tuple[Section, ...]:
    """Run ``stages`` under a progress bar; failures become sections.

    A stage that needs an optional extra that is not installed
    (`MissingExtraError`) becomes a ``skipped`` section; any other exception,
    a broken import included, becomes a ``failed`` section naming the error.
    ``KeyboardInterrupt`` propagates (workers are terminated).  ``log``
    receives one line per stage with its wall time (never written to the
    report, which stays deterministic).  With ``jobs > 1`` the stages run in
    that many forked worker processes (stages are independent), the costliest
    first; the sections are returned in stage order and are identical to a
    sequential run.  ``on_progress`` receives ``(stage key, fraction done,
    text)`` whenever a stage reports progress with `stage_progress` (also
    from the workers, at most ten times a second per stage).
    """
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    if jobs < 1:
        raise ParameterError(f"jobs must be at least 1, got {jobs}")
    show = sys.stderr.isatty() if progress is None else progress
    jobs = min(jobs, len(stages))
    # fork before the progress bar starts its refresh thread
    pool: Any = None
    queue: Any = None
    if jobs > 1:
        pool, queue = _start_workers(stages, jobs)
    listener: threading.Thread | None = None
    columns = (TextColumn("[bold]{task.description}"), BarColumn(),
               TextColumn("{task.percentage:>3.0f}%"), TimeElapsedColumn())  # fmt: skip
    try:
        with Progress(
            *columns, console=Console(file=sys.stderr), disable=not show, transient=True
        ) as bar:
            track = _Tracker(stages, bar, show, log, on_progress)
            if pool is None:
                for i, st in enumerate(stages):
                    bar.update(track.task, description=st.title)
                    track.done(i, _run_one(st, quick, functools.partial(track.moved, i)))
            else:
                listener = threading.Thread(target=_listen, args=(queue, track.moved), daemon=True)
                listener.start()
                bar.update(track.task, description=f"{len(stages)} stages on {jobs} processes")
                order = sorted(range(len(stages)), key=lambda i: -stages[i].cost)
                pending = [
                    pool.apply_async(
                        _run_in_worker, (i, quick), callback=functools.partial(track.done, i)
                    )
                    for i in order
                ]
                for p in pending:
                    p.get()
    finally:
        if pool is not None:
            _stop_workers(pool)
        if listener is not None:
            queue.put(None)
            listener.join(timeout=2.0)  # daemon: never blocks an interrupted run
    return tuple(track.results[i][0] for i in range(len(stages)))


def _start_workers(stages: Sequence[Stage], jobs: int) -> tuple[Any, Any]:
    """A pool of ``jobs`` forked workers that inherit ``stages``, and their progress queue."""
    import multiprocessing

    global _WORKER_STAGES
    _WORKER_STAGES = tuple(stages)
    ctx = multiprocessing.get_context("fork")
    queue = ctx.SimpleQueue()
    return ctx.Pool(jobs, initializer=_init_worker, initargs=(queue,)), queue


def _stop_workers(pool: Any) -> None:
    global _WORKER_STAGES
    pool.terminate()
    pool.join()
    _WORKER_STAGES = ()


def _listen(queue: Any, moved: Callable[[int, float, str], None]) -> None:
    """Forward progress messages of the workers until the sentinel ``None``."""
    while (msg := queue.get()) is not None:
        moved(*msg)
