"""Running a sweep: every chunk is computed and written by whoever runs it.

Chunks run in this process or on Dask (``scheduler="local"`` starts a
``LocalCluster`` with one single-threaded worker per core, ``workers=`` to
choose; ``"tcp://host:port"`` connects to a running scheduler).  Each task
computes its chunk and writes the Parquet part itself to the output location
(a shared path or an fsspec URL such as ``s3://bucket/sweep/``), and returns
only a [`PartSummary`][seapass.sweep.store.PartSummary] of a few numbers.  The
client tracks the manifest and, for a single-file output, merges the parts at
the end, so its work per chunk does not grow with the data.  The results are
identical however the chunks run.  What a sweep is lives in
[`seapass.sweep.spec`][seapass.sweep.spec], where it is stored in
[`seapass.sweep.store`][seapass.sweep.store].
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
import pyarrow as pa

from ..batch.step_metrics import batch_step_metrics
from ..batch.verdicts import batch_is_passive
from ..errors import OutputPathError, ParameterError
from ..files.owned import check_replaceable, record_written
from ..model.display import html_card, short_repr
from ..model.sea import SEA
from ..progress import ProgressLike, as_progress, task
from ..sim.metrics import SETTLING_CODES
from .cluster import check_scheduler, dask_client, run_bounded, total_threads
from .location import Location, open_location
from .spec import LOAD_MASS, SweepSpec, spec_from_state, spec_state
from .store import CONSOLIDATED_SUFFIXES, PartSummary, SweepStore, summarize_part, write_part

__all__ = [
    "DesignSweepResult",
    "check_consolidated_target",
    "compute_part",
    "evaluate_chunk",
    "run_design_sweep",
]


def evaluate_chunk(spec: SweepSpec, c: int) -> pa.Table:
    """Compute chunk ``c``: one row per design.

    Columns: ``index`` (int64), the swept parameters (float64), ``passive``
    (bool), ``margin`` (float64) and, with metrics, ``settling_time`` (s,
    NaN if not settled), ``final_error`` (m), ``overshoot`` (fraction) and
    ``status`` (``settled``/``did not settle``/``unstable``/``invalid``).
    """
    idx, vals = spec.chunk_values(c)
    model_vals = {k: v for k, v in vals.items() if k != LOAD_MASS}
    if model_vals:
        pas = batch_is_passive(spec.sea, model_vals, margin=spec.margin)
        passive, margin = pas.passive, pas.margin
    else:
        one = batch_is_passive(
            spec.sea, {p: [v] for p, v in _fixed(spec.sea).items()}, margin=spec.margin
        )
        passive = np.repeat(one.passive.reshape(-1)[:1], idx.size)
        margin = np.repeat(one.margin.reshape(-1)[:1], idx.size)
    cols: dict[str, Any] = {"index": idx, **vals, "passive": passive, "margin": margin}
    if spec.metrics:
        ml = vals.get(LOAD_MASS, spec.load_mass)
        m = batch_step_metrics(
            spec.sea,
            model_vals,
            load_mass=np.broadcast_to(ml, idx.shape),
            step=spec.step,
            horizon=spec.horizon,
            tolerance=spec.tolerance,
        )
        names = np.array([s.value for s in SETTLING_CODES])
        cols.update(
            settling_time=m.settling_time,
            final_error=m.final_error,
            overshoot=m.overshoot,
            status=names[m.status],
        )
    return pa.table(cols)


def _fixed(sea: SEA) -> dict[str, float]:
    return {k: float(v) for k, v in sea.values.items() if v is not None and k in sea.parameters}


def compute_part(spec: SweepSpec, c: int, parts: Location) -> PartSummary:
    """Compute chunk ``c`` and write it to ``parts`` (atomically); a summary, not the data.

    This is what a Dask worker runs for every chunk.
    """
    t0 = time.thread_time()
    table = evaluate_chunk(spec, c)
    nbytes = write_part(parts, c, table)
    return summarize_part(c, table, nbytes, time.thread_time() - t0)


_SPECS: dict[str, SweepSpec] = {}


def _part_task(c: int, state: Mapping[str, Any], parts: Location) -> PartSummary:
    """Dask task: rebuild the spec once per worker process, then compute and write chunk ``c``."""
    key = repr(sorted(state.items(), key=lambda kv: kv[0]))
    spec = _SPECS.get(key)
    if spec is None:
        _SPECS.clear()  # one sweep at a time per worker is the common case
        spec = _SPECS[key] = spec_from_state(state)
    return compute_part(spec, c, parts)


# --------------------------------------------------------------------------- result


@dataclass(frozen=True, repr=False, kw_only=True)
class DesignSweepResult:
    """Summary of a finished sweep.

    Attributes
    ----------
    path : str
        The output: the consolidated file, or the directory of parts (a path or URL).
    n_designs, n_chunks : int
    chunks_computed, chunks_resumed : int
        Chunks computed by this run, and finished chunks found on disk.
    n_passive : int
    n_settled : int or None
        None without metrics.
    seconds : float
        Wall-clock time of the run.
    complete : bool
    columns : tuple of str
    workers : int
        Worker threads that computed chunks (1 in this process).
    compute_seconds : float
        CPU time the workers spent computing and writing the chunks of this run.
    migrated : bool
        The directory had an old-style ``manifest.json`` and was migrated.
    """

    path: str
    n_designs: int
    n_chunks: int
    chunks_computed: int
    chunks_resumed: int
    n_passive: int
    n_settled: int | None
    seconds: float
    complete: bool
    columns: tuple[str, ...] = field(default=())
    workers: int = 1
    compute_seconds: float = 0.0
    migrated: bool = False

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["columns"] = list(self.columns)
        d["passive_fraction"] = self.n_passive / self.n_designs if self.n_designs else None
        return d

    def __repr__(self) -> str:
        return short_repr(
            "DesignSweepResult",
            {
                "path": self.path,
                "designs": self.n_designs,
                "passive": self.n_passive,
                "settled": self.n_settled,
                "complete": self.complete,
                "chunks": self.n_chunks,
            },
        )

    def _repr_html_(self) -> str:
        def share(n: int) -> str:
            return f"{n} ({100 * n / self.n_designs:.3g} %)" if self.n_designs else str(n)

        rows: list[tuple[str, Any]] = [
            ("output", self.path),
            ("designs", self.n_designs),
            ("passive (exact)", share(self.n_passive)),
        ]
        if self.n_settled is not None:
            rows.append(("settled", share(self.n_settled)))
        done = self.chunks_computed + self.chunks_resumed
        rows += [
            (
                "chunks",
                f"{done} of {self.n_chunks} ({self.chunks_computed} computed, "
                f"{self.chunks_resumed} resumed)",
            ),
            ("workers", self.workers),
            ("time", f"{self.seconds:.3g} s wall, {self.compute_seconds:.3g} s computing"),
            ("columns", ", ".join(self.columns)),
        ]
        status = "complete" if self.complete else "incomplete (resume to finish)"
        return html_card(f"Design sweep: {status}", rows)


# --------------------------------------------------------------------------- running


@contextmanager
def _executor(
    spec: SweepSpec, parts: Location, scheduler: str | None, workers: int | None
) -> Iterator[tuple[int, Callable[[Sequence[int]], Iterator[PartSummary]]]]:
    """``(worker threads, run)`` where ``run(chunks)`` computes and writes them."""
    if scheduler is None:
        yield 1, lambda todo: (compute_part(spec, c, parts) for c in todo)
        return
    state = spec_state(spec)
    with dask_client(scheduler, workers) as client:
        yield (
            total_threads(client),
            lambda todo: run_bounded(client, _part_task, todo, state, parts),
        )


def _check_output(out: Location, scheduler: str | None, force: bool) -> None:
    if scheduler is not None and out.is_memory:
        raise ParameterError(
            f"out: {out.url} lives inside this process, where Dask workers cannot write; "
            "use a shared path or an object store URL (s3://...) with a scheduler"
        )
    check_consolidated_target(out, force=force)


def check_consolidated_target(out: Location, *, force: bool = False) -> None:
    """Refuse a ``.parquet``/``.csv`` output that exists and that seapass did not write.

    The rule of [`seapass.files.owned`][seapass.files.owned]: a local file must be
    listed, unchanged, in its directory's manifest; a remote one (no manifest) is
    replaced only with ``force``.
    """
    if out.suffix not in CONSOLIDATED_SUFFIXES:
        return
    if out.is_local:
        check_replaceable(out.local_path(), force=force)
    elif out.exists() and not force:
        raise OutputPathError(
            f"out: {out.url} exists and seapass cannot tell that it wrote it (no manifest in "
            "an object store); choose another name, remove it, or pass force=True",
            argument="out",
        )


def run_design_sweep(
    spec: SweepSpec,
    out: str | os.PathLike[str] | Location,
    *,
    resume: bool = False,
    scheduler: str | None = None,
    workers: int | None = None,
    storage_options: Mapping[str, Any] | None = None,
    progress: ProgressLike = None,
    on_part: Callable[[PartSummary], None] | None = None,
    force: bool = False,
) -> DesignSweepResult:
    """Run ``spec``: every chunk is written atomically where it is computed; then finish ``out``.

    Parameters
    ----------
    spec : SweepSpec
    out : path, fsspec URL or Location
        ``*.parquet`` or ``*.csv`` for one consolidated file (parts are kept in
        ``<out>.parts`` until the end), or a directory for a dataset of parts
        with ``_manifest.json`` (read it with ``pyarrow.dataset.dataset(out)``).
        URLs such as ``s3://bucket/sweep/`` or ``memory://x`` go through fsspec.
    resume : bool
        Continue an interrupted sweep of the same spec, skipping finished chunks.
    scheduler : None, "local" or "tcp://host:port"
        Run chunks in this process, on a new Dask ``LocalCluster``, or on an
        existing Dask scheduler.  The workers write the parts, so ``out`` must
        be a file system they share with the client or an object store.
    workers : int, optional
        Worker processes of the LocalCluster (default: this machine's cores);
        only with ``scheduler="local"``.
    storage_options : mapping, optional
        Options of the fsspec file system of ``out`` (credentials, endpoint).
    progress : Progress, optional
        Where the sweep reports: one task with a step per chunk (resumed chunks count
        at the start).  Default: none; ``True``/``False`` still work for one release.
    on_part : callable, optional
        Called as ``on_part(summary)`` after each part is recorded (tests, monitoring).
    force : bool
        Replace an existing ``.parquet``/``.csv`` output that seapass did not write
        (by default it is refused before any work; see
        [`seapass.files.owned`][seapass.files.owned]).

    Returns
    -------
    DesignSweepResult
        A ``KeyboardInterrupt`` is re-raised after the journal is saved; the
        finished parts stay on disk for ``resume=True``.
    """
    shown = as_progress(progress, where="run_design_sweep")
    check_scheduler(scheduler, workers)
    where = open_location(out, storage_options)
    _check_output(where, scheduler, force)
    t0 = time.perf_counter()
    store = SweepStore.open(spec, where, resume=resume)
    todo = store.todo
    computed = 0
    compute_seconds = 0.0
    threads = 1
    try:
        with (
            _executor(spec, store.parts, scheduler, workers) as (threads, run),  # may refuse
            task(
                shown, f"sweep: {spec.n_designs} designs in {spec.n_chunks} chunks", spec.n_chunks
            ),
        ):
            if store.resumed:
                shown.advance(store.resumed, note="resumed")
            for summary in run(todo):
                store.record(summary)
                computed += 1
                compute_seconds += summary.seconds
                shown.advance(1)
                if on_part is not None:
                    on_part(summary)
    finally:
        store.flush()
    check_consolidated_target(where, force=force)  # again: it may have appeared meanwhile
    final = store.finish()
    if where.suffix in CONSOLIDATED_SUFFIXES and where.is_local:
        record_written([where.local_path()])
    return DesignSweepResult(
        path=final.url,
        n_designs=spec.n_designs,
        n_chunks=spec.n_chunks,
        chunks_computed=computed,
        chunks_resumed=store.resumed,
        n_passive=store.n_passive,
        n_settled=store.n_settled if spec.metrics else None,
        seconds=time.perf_counter() - t0,
        complete=True,
        columns=store.columns,
        workers=threads,
        compute_seconds=compute_seconds,
        migrated=store.migrated,
    )
