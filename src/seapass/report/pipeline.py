"""The stage pipeline shared by [`reproduce`][seapass.report.reproduce.reproduce] and
[`analyze`][seapass.report.analyze.analyze].

A report is a sequence of independent `Stage` objects, each returning a
[`Section`][seapass.report.document.Section] from a `StageContext` (the reduced
budgets of ``--quick``, the stage's work budget, its progress).  `run_stages` runs them
in this process or in forked workers (the costliest stages first, so two workers
finish together), with every figure drawn in the one seapass style on bare
(non-pyplot) figures, and reports to one [`Progress`][seapass.progress.Progress]: the
run is a task of one step per stage, each stage a task inside it (in this process,
the stage's own tasks nest inside that; from workers, they become notes).  Each
finished section is handed to ``on_section`` at once (``analyze`` writes it), so an
interrupted run keeps what it finished.  A stage that needs an optional extra that is
not installed (`seapass.errors.MissingExtraError`, e.g. MuJoCo) becomes a *skipped*
section; a stage that raises anything else, a missing module included, becomes a
*failed* section naming the error, and the command exits non-zero.  A stage that
reaches its work budget returns its section with status ``stopped_at_budget`` and
what it has.
"""

from __future__ import annotations

import functools
import queue as queues
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..errors import ContinuousOnlyError, MissingExtraError, ParameterError, SeapassError
from ..plot.style import bare_figures, figure_style
from ..progress import NoProgress, Progress, ProgressLike, as_progress, task
from .document import Section, SectionStatus

__all__ = ["Stage", "StageContext", "run_stages", "select_stages"]


@dataclass(frozen=True, kw_only=True)
class StageContext:
    """What a running stage is given.

    Attributes
    ----------
    quick : bool
        Reduced budgets and coarser grids (``--quick``).
    budget : int or None
        The stage's work budget in its own counted unit (boxes of a certified bound,
        generations, twin runs...; see the stage); None: the stage's default.
    progress : Progress
        Where the stage reports; its tasks nest inside the stage's task.
    """

    quick: bool = False
    budget: int | None = None
    progress: Progress = field(default_factory=NoProgress)

    def budget_or(self, default: int) -> int:
        """The budget given, else ``default``."""
        return default if self.budget is None else self.budget


@dataclass(frozen=True)
class Stage:
    """One step of a report: ``run(context)`` returns a [`Section`][seapass.report.document.Section].

    ``cost`` is the stage's expected run time relative to the others (any
    unit); with several workers the costliest stages start first.  ``budget`` is
    handed to ``run`` in its `StageContext` (None: the stage's default).
    """

    key: str
    title: str
    run: Callable[[StageContext], Section]
    core: bool = True
    cost: float = 1.0
    budget: int | None = None


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


def _run_one(stage: Stage, context: StageContext) -> tuple[Section, float]:
    """Run one stage; failures become sections."""
    t0 = time.perf_counter()
    try:
        with figure_style(), bare_figures():
            sec = stage.run(context)
    except MissingExtraError as exc:
        sec = Section(stage.key, stage.title, status=SectionStatus.SKIPPED, text=f"Skipped: {exc}")
    except ContinuousOnlyError as exc:  # a controller given in z: the stage does not apply
        sec = Section(stage.key, stage.title, status=SectionStatus.SKIPPED,
                      text=f"Not applicable: {exc}")  # fmt: skip
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


# set in the parent just before the workers fork, so stages (closures over designs) are
# inherited, never pickled
_WORKER_STAGES: Sequence[Stage] = ()
_WORKER_QUEUE: Any = None


def _init_worker(queue: Any) -> None:
    import signal

    global _WORKER_QUEUE
    # the parent handles Ctrl-C and SIGTERM and terminates the workers
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _WORKER_QUEUE = queue


class _QueueProgress:
    """A stage's progress in a worker: every call goes to the parent through the queue."""

    def __init__(self, index: int, queue: Any) -> None:
        self.index, self.queue = index, queue

    def start(self, task: str, total: int | None = None) -> None:
        self.queue.put((self.index, "start", task, total))

    def advance(self, n: int = 1, *, note: str = "") -> None:
        self.queue.put((self.index, "advance", n, note))

    def close(self) -> None:
        self.queue.put((self.index, "close", None, None))


def _run_in_worker(index: int, quick: bool) -> None:
    """Worker entry point: stage ``index`` of the inherited list.  Its progress and then its
    result go through the one queue, so the parent sees every note before the result."""
    stage, queue = _WORKER_STAGES[index], _WORKER_QUEUE
    queue.put((index, "begin", None, None))
    context = StageContext(quick=quick, budget=stage.budget, progress=_QueueProgress(index, queue))
    queue.put((index, "finished", _run_one(stage, context), None))


def _stage_line(i: int, n: int, stage: Stage) -> str:
    return f"[{i + 1}/{n}] {stage.key}: {stage.title}"


def run_stages(
    stages: Sequence[Stage],
    *,
    quick: bool = False,
    progress: ProgressLike = None,
    log: Callable[[str], None] | None = None,
    jobs: int = 1,
    on_section: Callable[[int, Section], None] | None = None,
    title: str = "report",
) -> tuple[Section, ...]:
    """Run ``stages``; failures become sections.

    A stage that needs an optional extra that is not installed
    (`MissingExtraError`) becomes a ``skipped`` section; any other exception,
    a broken import included, becomes a ``failed`` section naming the error.
    ``KeyboardInterrupt`` propagates (workers are terminated); every section
    finished before it has been handed to ``on_section``.

    Parameters
    ----------
    stages : sequence of Stage
    quick : bool
        Handed to every stage in its `StageContext`.
    progress : Progress, optional
        The run is one task (``title``, one step per stage), each stage a task inside
        it.  Default: none (``True``/``False`` still work for one release).
    log : callable, optional
        Receives one line per finished stage with its wall time (never written to
        the report, which stays deterministic).
    jobs : int
        Worker processes (forked; stages are independent), the costliest first;
        the sections are returned in stage order and are identical to a sequential
        run.
    on_section : callable, optional
        ``on_section(index, section)`` as soon as stage ``index`` finishes (in this
        process, in the order they finish).
    title : str
        The run's task in ``progress``.
    """
    if jobs < 1:
        raise ParameterError(f"jobs must be at least 1, got {jobs}")
    shown = as_progress(progress, where="run_stages")
    jobs = min(jobs, len(stages))
    results: dict[int, tuple[Section, float]] = {}

    def finished(i: int, res: tuple[Section, float]) -> None:
        results[i] = res
        if log is not None:
            log(f"{stages[i].key}: {res[0].status.label} in {res[1]:.1f} s")
        if on_section is not None:
            on_section(i, res[0])

    n = len(stages)
    what = f"{title}: {n} stage{'s' if n != 1 else ''}" + (
        f" on {jobs} processes" if jobs > 1 else ""
    )
    # fork before a live progress display starts its refresh thread
    workers = _start_workers(stages, jobs) if jobs > 1 else None
    try:
        with task(shown, what, n):
            if workers is not None:
                _run_parallel(stages, quick, workers, shown, finished)
            for i, st in enumerate(stages if workers is None else ()):
                with task(shown, _stage_line(i, n, st)):
                    res = _run_one(st, StageContext(quick=quick, budget=st.budget, progress=shown))
                shown.advance(1, note=f"{st.key} {res[0].status.label}")
                finished(i, res)
    finally:
        if workers is not None:
            _stop_workers(workers[0])
    return tuple(results[i][0] for i in range(n))


def _run_parallel(
    stages: Sequence[Stage],
    quick: bool,
    workers: tuple[Any, Any],
    shown: Progress,
    finished: Callable[[int, tuple[Section, float]], None],
) -> None:
    """The stages on the forked ``workers``; every event is handled in this thread."""
    pool, mp_queue = workers
    events: queues.Queue[tuple[Any, ...]] = queues.Queue()
    listener = threading.Thread(target=_listen, args=(mp_queue, events.put), daemon=True)
    running: list[str] = []
    try:
        listener.start()
        for i in sorted(range(len(stages)), key=lambda i: -stages[i].cost):
            pool.apply_async(
                _run_in_worker, (i, quick), error_callback=functools.partial(_put_error, events, i)
            )
        left = len(stages)
        while left:
            try:
                msg = events.get(timeout=0.2)  # a timeout keeps Ctrl-C responsive
            except queues.Empty:
                continue
            i, kind, a, b = msg
            st = stages[i]
            if kind == "finished":
                left -= 1
                if st.key in running:
                    running.remove(st.key)
                shown.advance(1, note=f"{st.key} {a[0].status.label}")
                finished(i, a)
            elif kind == "error":
                raise a
            elif kind == "begin":
                running.append(st.key)
                with task(shown, _stage_line(i, len(stages), st)):
                    pass  # announced: the workers' stages overlap, so none stays open here
                shown.advance(0, note="running " + ", ".join(running))
            elif kind == "advance" and b:  # a stage's own progress: a note here
                shown.advance(0, note=f"{st.key}: {b}")
    finally:
        mp_queue.put(None)
        listener.join(timeout=2.0)  # daemon: never blocks an interrupted run


def _put_error(events: Any, i: int, exc: BaseException) -> None:
    events.put((i, "error", exc, None))


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
    pool.terminate()  # idempotent
    pool.join()
    _WORKER_STAGES = ()


def _listen(queue: Any, put: Callable[[tuple[Any, ...]], None]) -> None:
    """Forward the workers' messages until the sentinel ``None``."""
    while (msg := queue.get()) is not None:
        put(msg)
