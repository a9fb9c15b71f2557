"""Running a sweep: compute chunks here or on a Dask cluster and stream them to disk.

Chunks run in this process or on a Dask cluster (``scheduler="local"`` starts
a 2-worker ``LocalCluster``; ``"tcp://host:port"`` connects to a running
scheduler).  Workers only compute; the client writes every part, so workers
need no shared file system.  The results are identical either way.  What a
sweep is lives in [`seapass.sweep.spec`][seapass.sweep.spec], where it is stored in
[`seapass.sweep.store`][seapass.sweep.store].
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from ..batch.step_metrics import batch_step_metrics
from ..batch.verdicts import batch_is_passive
from ..errors import MissingExtraError, ParameterError
from ..model.sea import SEA
from ..sim.metrics import SETTLING_CODES, Settling
from .spec import LOAD_MASS, SweepSpec, spec_from_state, spec_state
from .store import consolidate, part_path, prepare_parts, write_part

__all__ = [
    "SCHEDULER_TIMEOUT",
    "DesignSweepResult",
    "evaluate_chunk",
    "probe_scheduler",
    "run_design_sweep",
]


# --------------------------------------------------------------------------- specification


# --------------------------------------------------------------------------- computation


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


def _chunk_task(state: Mapping[str, Any], c: int) -> pa.Table:
    """Dask task: rebuild the spec in the worker and compute one chunk."""
    return evaluate_chunk(spec_from_state(state), c)


# --------------------------------------------------------------------------- output


@dataclass(frozen=True)
class DesignSweepResult:
    """Summary of a finished (or interrupted) sweep."""

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

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["columns"] = list(self.columns)
        d["passive_fraction"] = self.n_passive / self.n_designs if self.n_designs else None
        return d


def _progress(enabled: bool, total: int, done: int) -> Any:
    if not (enabled and sys.stderr.isatty()):
        return None
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeRemainingColumn,
    )

    prog = Progress(
        TextColumn("sweep"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeRemainingColumn(),
        transient=True,
    )
    prog.start()
    prog.add_task("chunks", total=total, completed=done)
    return prog


def _local_results(spec: SweepSpec, todo: Sequence[int]) -> Iterator[tuple[int, pa.Table]]:
    for c in todo:
        yield c, evaluate_chunk(spec, c)


SCHEDULER_TIMEOUT = 10.0
"""Seconds to reach a Dask scheduler, to hear its greeting and to find a worker."""


def probe_scheduler(address: str, timeout: float = SCHEDULER_TIMEOUT) -> None:
    """Raise `ConnectionError` unless a Dask scheduler answers at ``tcp://host:port``.

    Dask's client waits without a deadline for the greeting of whatever
    listens at the address, and reads any bytes it gets as a message length
    (an HTTP server makes it allocate gigabytes).  So first, with a plain
    socket and a deadline: connect, read the scheduler's handshake (a length
    prefix, then a small msgpack map with ``python`` and ``pickle-protocol``)
    and check it, reading at most 64 KiB.
    """
    import socket
    import struct

    import msgpack

    hostport = address.removeprefix("tcp://")
    host, _, port_text = hostport.rpartition(":")
    host = host.strip("[]")
    if not host or not port_text.isdigit() or not 0 < int(port_text) < 65536:
        raise ParameterError(
            f"scheduler: {address!r} is not a tcp://host:port address", argument="scheduler"
        )
    what = f"scheduler: nothing at {address} answers like a Dask scheduler"
    deadline = time.monotonic() + timeout

    def recv_exactly(sock: socket.socket, n: int) -> bytes:
        data = b""
        while len(data) < n:
            sock.settimeout(max(deadline - time.monotonic(), 0.01))
            chunk = sock.recv(n - len(data))
            if not chunk:
                raise ConnectionError(f"{what} (it closed the connection)")
            data += chunk
        return data

    try:
        with socket.create_connection((host, int(port_text)), timeout=timeout) as sock:
            (size,) = struct.unpack("<Q", recv_exactly(sock, 8))
            if not 16 <= size <= 65536:
                raise ConnectionError(what)
            body = recv_exactly(sock, size)
            (frames,) = struct.unpack("<Q", body[:8])
            if not 1 <= frames <= 16 or 8 + 8 * frames > size:
                raise ConnectionError(what)
            first = struct.unpack("<Q", body[8:16])[0]
            start = 8 + 8 * frames
            info = msgpack.unpackb(body[start : start + first], raw=False)
            if not isinstance(info, dict) or "python" not in info:
                raise ConnectionError(what)
    except TimeoutError:
        raise ConnectionError(f"{what} within {timeout:g} s") from None
    except ConnectionError as exc:
        if exc.errno is None:  # raised above, already says what is wrong
            raise
        raise ConnectionError(f"{what} ({exc.strerror})") from None
    except (OSError, ValueError, struct.error, msgpack.UnpackException) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise ConnectionError(f"{what} ({reason})") from None


def _dask_results(
    spec: SweepSpec, todo: Sequence[int], scheduler: str
) -> Iterator[tuple[int, pa.Table]]:
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise MissingExtraError(
            "scheduler: running on Dask needs the dask extra; install it with "
            "pip install 'seapass[dask]' (or run without a scheduler)"
        ) from None

    cluster = None
    if scheduler == "local":
        cluster = LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = Client(cluster)
    else:
        probe_scheduler(scheduler, SCHEDULER_TIMEOUT)
        client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
        try:
            client.wait_for_workers(1, timeout=SCHEDULER_TIMEOUT)
        except TimeoutError:
            client.close()
            raise ConnectionError(
                f"scheduler: the Dask scheduler at {scheduler} has no workers "
                f"(waited {SCHEDULER_TIMEOUT:g} s); start some with 'dask worker {scheduler}'"
            ) from None
    state = spec_state(spec)
    window = max(2, 2 * len(client.scheduler_info().get("workers", {})) or 2)
    try:
        pending = list(todo)
        futures: dict[Any, int] = {}
        ac = as_completed()
        while pending and len(futures) < window:
            c = pending.pop(0)
            f = client.submit(_chunk_task, state, c, pure=False)
            futures[f] = c
            ac.add(f)
        for f in ac:
            c = futures.pop(f)
            table = f.result()
            yield c, table
            if pending:
                c2 = pending.pop(0)
                f2 = client.submit(_chunk_task, state, c2, pure=False)
                futures[f2] = c2
                ac.add(f2)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def run_design_sweep(
    spec: SweepSpec,
    out: str | os.PathLike[str],
    *,
    resume: bool = False,
    scheduler: str | None = None,
    progress: bool = True,
    on_chunk: Callable[[int, pa.Table], None] | None = None,
) -> DesignSweepResult:
    """Run ``spec``, writing every chunk atomically, then consolidate into ``out``.

    Parameters
    ----------
    spec : SweepSpec
    out : path
        ``*.parquet`` or ``*.csv`` for one consolidated file (parts are kept in
        ``<out>.parts`` until the end), or a directory for a dataset of parts.
    resume : bool
        Continue an interrupted sweep of the same spec, skipping finished chunks.
    scheduler : None, "local" or "tcp://host:port"
        Run chunks in this process, on a new 2-worker Dask ``LocalCluster``, or
        on an existing Dask scheduler.
    progress : bool
        Show a rich progress bar (only on a terminal).
    on_chunk : callable, optional
        Called as ``on_chunk(c, table)`` after chunk ``c`` is written (tests, monitoring).

    Returns
    -------
    DesignSweepResult
        ``complete=False`` when interrupted (``KeyboardInterrupt`` is re-raised
        after the finished chunks are safely on disk).
    """
    out = Path(out)
    if scheduler is not None and not (scheduler == "local" or scheduler.startswith("tcp://")):
        raise ParameterError(
            f"scheduler: must be 'local' or a tcp://host:port address, got {scheduler!r}",
            argument="scheduler",
        )
    t0 = time.perf_counter()
    parts, done = prepare_parts(spec, out, resume)
    todo = [c for c in range(spec.n_chunks) if c not in done]
    n_passive = 0
    n_settled = 0
    for c in sorted(done):
        t = pq.read_table(
            part_path(parts, c), columns=["passive"] + (["status"] if spec.metrics else [])
        )
        n_passive += int(np.count_nonzero(t.column("passive").to_numpy(zero_copy_only=False)))
        if spec.metrics:
            n_settled += int(
                np.count_nonzero(
                    t.column("status").to_numpy(zero_copy_only=False) == Settling.SETTLED.value
                )
            )
    bar = _progress(progress, spec.n_chunks, len(done))
    computed = 0
    columns: tuple[str, ...] = ()
    try:
        results = (
            _local_results(spec, todo)
            if scheduler is None
            else _dask_results(spec, todo, scheduler)
        )
        for c, table in results:
            write_part(parts, c, table)
            computed += 1
            columns = tuple(table.column_names)
            n_passive += int(
                np.count_nonzero(table.column("passive").to_numpy(zero_copy_only=False))
            )
            if spec.metrics:
                st = table.column("status").to_numpy(zero_copy_only=False)
                n_settled += int(np.count_nonzero(st == Settling.SETTLED.value))
            if bar is not None:
                bar.advance(bar.task_ids[0])
            if on_chunk is not None:
                on_chunk(c, table)
    finally:
        if bar is not None:
            bar.stop()
    if not columns:
        columns = tuple(pq.read_schema(part_path(parts, 0)).names) if spec.n_chunks else ()
    final = parts
    if out.suffix.lower() in (".parquet", ".csv"):
        consolidate(parts, out, spec.n_chunks)
        final = out
    return DesignSweepResult(
        path=str(final),
        n_designs=spec.n_designs,
        n_chunks=spec.n_chunks,
        chunks_computed=computed,
        chunks_resumed=len(done),
        n_passive=n_passive,
        n_settled=n_settled if spec.metrics else None,
        seconds=time.perf_counter() - t0,
        complete=True,
        columns=columns,
    )


# --------------------------------------------------------------------------- heat maps
