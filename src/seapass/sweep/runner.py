"""Design-space sweeps: grids or random samples streamed to Parquet/CSV in resumable chunks.

A sweep is a :class:`SweepSpec` (a configuration, the swept parameters and
the metric options).  Designs are numbered ``0 … n−1``; chunk ``c`` holds
designs ``[c·chunk_size, (c+1)·chunk_size)`` and its parameters are computed
from the indices alone (grid: ``numpy.unravel_index`` in C order, first axis
slowest; random: a generator seeded with ``(seed, c)``), so the full design
set is never materialized and any chunk can be recomputed independently and
identically, on any machine.

Each finished chunk is written atomically to ``<out>.parts/part-<c>.parquet``
next to a ``manifest.json`` holding the sweep's fingerprint.  A run that is
interrupted keeps its finished parts; ``resume=True`` skips them, so the final
dataset has no duplicated or lost rows.  When every chunk is done the parts are
streamed into the consolidated ``<out>`` (``.parquet`` or ``.csv``), written
atomically, and the parts directory is removed.  An ``out`` without one of
those suffixes is a dataset directory of parts and is kept as is.

Chunks run in this process or on a Dask cluster (``scheduler="local"`` starts
a 2-worker ``LocalCluster``; ``"tcp://host:port"`` connects to a running
scheduler).  Workers only compute; the client writes every part, so workers
need no shared file system.  The results are identical either way.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import shutil
import sys
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

from ..batch.verdicts import batch_is_passive
from ..batch.step_metrics import STATUS_NAMES, batch_step_metrics
from ..errors import FileFormatError, ParameterError
from ..model.expr import parse_value
from ..files.atomic import atomic_save, atomic_write_text
from ..model.sea import SEA

__all__ = [
    "GridAxis",
    "HeatmapData",
    "RangeAxis",
    "SweepResult",
    "SweepSpec",
    "evaluate_chunk",
    "heatmap_data",
    "parse_grid",
    "parse_range",
    "run_sweep",
]

LOAD_MASS = "m_L"
MAX_DESIGNS = 10**12
MANIFEST = "manifest.json"
_PART = re.compile(r"^part-(\d{6,})\.parquet$")


# --------------------------------------------------------------------------- specification


@dataclass(frozen=True)
class GridAxis:
    """Values ``lo, lo + step, …`` up to ``hi`` inclusive (within 1e-9 steps)."""

    name: str
    lo: float
    hi: float
    step: float

    def __post_init__(self) -> None:
        for attr in ("lo", "hi", "step"):
            v = float(getattr(self, attr))
            if not math.isfinite(v):
                raise ParameterError(f"--grid {self.name}: {attr} must be finite")
            object.__setattr__(self, attr, v)
        if self.step <= 0:
            raise ParameterError(f"--grid {self.name}: step must be positive, got {self.step:g}")
        if self.hi < self.lo:
            raise ParameterError(f"--grid {self.name}: hi ({self.hi:g}) is below lo ({self.lo:g})")

    @property
    def size(self) -> int:
        return math.floor((self.hi - self.lo) / self.step + 1e-9) + 1

    def values(self, idx: np.ndarray) -> np.ndarray:
        return self.lo + self.step * idx.astype(np.float64)


@dataclass(frozen=True)
class RangeAxis:
    """Uniform random values in ``[lo, hi]``."""

    name: str
    lo: float
    hi: float

    def __post_init__(self) -> None:
        for attr in ("lo", "hi"):
            v = float(getattr(self, attr))
            if not math.isfinite(v):
                raise ParameterError(f"--range {self.name}: {attr} must be finite")
            object.__setattr__(self, attr, v)
        if self.hi < self.lo:
            raise ParameterError(f"--range {self.name}: hi ({self.hi:g}) is below lo ({self.lo:g})")


def _split_spec(text: str, flag: str, parts: int) -> tuple[str, list[float]]:
    example = "kd=0:5000:200" if parts == 3 else "kd=0:5000"
    if "=" not in text:
        raise ParameterError(
            f"{flag} {text!r}: expected NAME=LO:HI{':STEP' * (parts == 3)}, e.g. {example}"
        )
    name, rhs = (x.strip() for x in text.split("=", 1))
    fields = rhs.split(":")
    if not name.isidentifier() or len(fields) != parts:
        raise ParameterError(
            f"{flag} {text!r}: expected NAME=LO:HI{':STEP' * (parts == 3)}, e.g. {example}"
        )
    return name, [parse_value(f, f"{flag} {name}") for f in fields]


def parse_grid(text: str) -> GridAxis:
    """``"kd=0:5000:200"`` → :class:`GridAxis` (``lo:hi:step``, inclusive)."""
    name, (lo, hi, step) = _split_spec(text, "--grid", 3)
    return GridAxis(name, lo, hi, step)


def parse_range(text: str) -> RangeAxis:
    """``"kd=0:5000"`` → :class:`RangeAxis`."""
    name, (lo, hi) = _split_spec(text, "--range", 2)
    return RangeAxis(name, lo, hi)


def _sea_state(sea: SEA) -> dict[str, Any]:
    return {"elements": sea.describe(), "values": dict(sea.values), "name": sea.name}


def _sea_from_state(state: Mapping[str, Any]) -> SEA:
    e = state["elements"]
    return SEA(
        D1=e["D1"], D2=e["D2"], CA=e["CA"], CL=e["CL"], m=e["m"], b=e["b"],
        values=dict(state["values"]), name=state["name"],
    )  # fmt: skip


@dataclass(frozen=True)
class SweepSpec:
    """What to sweep and what to compute for every design.

    Parameters
    ----------
    sea : SEA
        The configuration; swept parameters override its values.
    grid : sequence of GridAxis
        Full factorial grid (C order: the first axis varies slowest).
    ranges : sequence of RangeAxis
        Random uniform sampling with ``samples`` designs (exclusive with ``grid``).
    samples : int or None
    seed : int
    load_mass, step, horizon, tolerance : float
        Metric options; ``m_L`` may also be swept as a parameter.
    metrics : bool
        Compute settling time, final error and overshoot (else passivity only).
    margin : bool
        Compute the passivity margin (about 3x the cost of the verdict alone);
        the column holds NaN otherwise.
    chunk_size : int
        Designs per chunk (memory and the unit of resumption).
    """

    sea: SEA
    grid: tuple[GridAxis, ...] = ()
    ranges: tuple[RangeAxis, ...] = ()
    samples: int | None = None
    seed: int = 0
    load_mass: float = 10.0
    step: float = 0.5
    horizon: float = 5.0
    tolerance: float = 0.02
    metrics: bool = True
    margin: bool = True
    chunk_size: int = 65536

    def __post_init__(self) -> None:
        object.__setattr__(self, "grid", tuple(self.grid))
        object.__setattr__(self, "ranges", tuple(self.ranges))
        if bool(self.grid) == bool(self.ranges):
            raise ParameterError(
                "give either grid axes (--grid NAME=LO:HI:STEP) or random ranges "
                "(--sample N --range NAME=LO:HI), not both or neither"
            )
        if self.ranges and (self.samples is None or self.samples < 1):
            raise ParameterError("random sampling needs --sample N with N >= 1")
        if self.grid and self.samples is not None:
            raise ParameterError("--sample is only for random ranges; a grid has its own size")
        names = self.names
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ParameterError(f"parameter(s) {', '.join(dup)} swept more than once")
        allowed = set(self.sea.parameters) | {LOAD_MASS}
        unknown = [n for n in names if n not in allowed]
        if unknown:
            raise ParameterError(
                f"swept parameter(s) {', '.join(unknown)} do not appear in the model; "
                f"its parameters are {', '.join(self.sea.parameters)} (and {LOAD_MASS})"
            )
        missing = [p for p in self.sea.free_parameters if p not in names]
        if missing:
            raise ParameterError(
                f"parameter(s) {', '.join(missing)} have no value: sweep them or give "
                f"--set {missing[0]}=VALUE"
            )
        if not 1 <= self.chunk_size <= 10**7:
            raise ParameterError(f"chunk size must be in [1, 1e7], got {self.chunk_size}")
        if self.n_designs > MAX_DESIGNS:
            raise ParameterError(
                f"the sweep has {self.n_designs:.3g} designs, more than the limit of "
                f"{MAX_DESIGNS:.0e}; use coarser steps"
            )
        if self.metrics:
            if not (math.isfinite(self.load_mass) and self.load_mass > 0):
                raise ParameterError(f"--load-mass must be positive, got {self.load_mass}")
            if not (math.isfinite(self.horizon) and self.horizon > 0):
                raise ParameterError(f"--horizon must be positive, got {self.horizon}")
            if not (math.isfinite(self.step) and self.step != 0):
                raise ParameterError(f"--step must be nonzero, got {self.step}")

    @property
    def names(self) -> list[str]:
        return [a.name for a in self.grid] + [a.name for a in self.ranges]

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(a.size for a in self.grid) if self.grid else (int(self.samples or 0),)

    @property
    def n_designs(self) -> int:
        return math.prod(self.shape)

    @property
    def n_chunks(self) -> int:
        return -(-self.n_designs // self.chunk_size)

    def describe(self) -> dict[str, Any]:
        """A JSON-able description (the fingerprint is its hash)."""
        return {
            "model": _sea_state(self.sea),
            "grid": [asdict(a) for a in self.grid],
            "ranges": [asdict(a) for a in self.ranges],
            "samples": self.samples,
            "seed": self.seed,
            "load_mass": self.load_mass,
            "step": self.step,
            "horizon": self.horizon,
            "tolerance": self.tolerance,
            "metrics": self.metrics,
            "margin": self.margin,
            "chunk_size": self.chunk_size,
            "n_designs": self.n_designs,
        }

    def fingerprint(self) -> str:
        text = json.dumps(self.describe(), sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def chunk_values(self, c: int) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Design indices and parameter arrays of chunk ``c``."""
        if not 0 <= c < self.n_chunks:
            raise ParameterError(f"chunk {c} is outside 0..{self.n_chunks - 1}")
        start = c * self.chunk_size
        stop = min(self.n_designs, start + self.chunk_size)
        idx = np.arange(start, stop, dtype=np.int64)
        if self.grid:
            sub = np.unravel_index(idx, self.shape)
            return idx, {a.name: a.values(i) for a, i in zip(self.grid, sub, strict=True)}
        rng = np.random.default_rng([self.seed, c])
        u = rng.random((len(self.ranges), idx.size))
        return idx, {a.name: a.lo + (a.hi - a.lo) * u[k] for k, a in enumerate(self.ranges)}


def _picklable(spec: SweepSpec) -> dict[str, Any]:
    d = {k: getattr(spec, k) for k in spec.__dataclass_fields__ if k != "sea"}
    d["sea_state"] = _sea_state(spec.sea)
    return d


def _unpickle(d: Mapping[str, Any]) -> SweepSpec:
    kw = {k: v for k, v in d.items() if k != "sea_state"}
    return SweepSpec(sea=_sea_from_state(d["sea_state"]), **kw)


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
        names = np.array(STATUS_NAMES)
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
    return evaluate_chunk(_unpickle(state), c)


# --------------------------------------------------------------------------- output


@dataclass(frozen=True)
class SweepResult:
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


def _parts_dir(out: Path) -> Path:
    return (
        out
        if out.suffix.lower() not in (".parquet", ".csv")
        else out.with_name(out.name + ".parts")
    )


def _done_chunks(parts: Path) -> set[int]:
    if not parts.is_dir():
        return set()
    return {int(m.group(1)) for p in parts.iterdir() if (m := _PART.match(p.name))}


def _part_path(parts: Path, c: int) -> Path:
    return parts / f"part-{c:06d}.parquet"


def _prepare(spec: SweepSpec, out: Path, resume: bool) -> tuple[Path, set[int]]:
    parts = _parts_dir(out)
    manifest = parts / MANIFEST
    fp = spec.fingerprint()
    if parts.exists() and any(parts.iterdir()):
        if not manifest.is_file():
            raise FileFormatError(
                f"{parts} exists and is not a seapass sweep directory; choose another --out"
            )
        try:
            old = json.loads(manifest.read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise FileFormatError(f"{manifest}: unreadable manifest ({exc})") from None
        if old.get("fingerprint") != fp:
            raise FileFormatError(
                f"{parts} holds a different sweep (fingerprint {old.get('fingerprint')}, this "
                f"one {fp}); use another --out or delete it"
            )
        if not resume and _done_chunks(parts):
            raise FileFormatError(
                f"{parts} holds {len(_done_chunks(parts))} finished chunk(s) of this sweep; "
                "pass --resume to continue it, or delete the directory to start over"
            )
    parts.mkdir(parents=True, exist_ok=True)
    atomic_write_text(
        manifest,
        json.dumps({"fingerprint": fp, "spec": spec.describe(), "format": 1}, indent=2, default=str)
        + "\n",
    )
    done = _done_chunks(parts) if resume else set()
    return parts, {c for c in done if c < spec.n_chunks}


def _write_part(parts: Path, c: int, table: pa.Table) -> None:
    atomic_save(_part_path(parts, c), lambda tmp: pq.write_table(table, tmp))


def _consolidate(parts: Path, out: Path, n_chunks: int) -> None:
    """Stream all parts, in chunk order, into ``out`` atomically (bounded memory)."""
    first = pq.read_schema(_part_path(parts, 0))
    if out.suffix.lower() == ".parquet":

        def save(tmp: str) -> None:
            with pq.ParquetWriter(tmp, first) as writer:
                for c in range(n_chunks):
                    writer.write_table(pq.read_table(_part_path(parts, c)))

    else:

        def save(tmp: str) -> None:
            with pacsv.CSVWriter(tmp, first) as writer:
                for c in range(n_chunks):
                    writer.write_table(pq.read_table(_part_path(parts, c)))

    atomic_save(out, save)
    shutil.rmtree(parts)


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


def _dask_results(
    spec: SweepSpec, todo: Sequence[int], scheduler: str
) -> Iterator[tuple[int, pa.Table]]:
    from dask.distributed import Client, LocalCluster, as_completed

    cluster = None
    if scheduler == "local":
        cluster = LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = Client(cluster)
    else:
        client = Client(scheduler, timeout=10)
    state = _picklable(spec)
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


def run_sweep(
    spec: SweepSpec,
    out: str | os.PathLike[str],
    *,
    resume: bool = False,
    scheduler: str | None = None,
    progress: bool = True,
    on_chunk: Callable[[int, pa.Table], None] | None = None,
) -> SweepResult:
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
    SweepResult
        ``complete=False`` when interrupted (``KeyboardInterrupt`` is re-raised
        after the finished chunks are safely on disk).
    """
    out = Path(out)
    if scheduler is not None and not (scheduler == "local" or scheduler.startswith("tcp://")):
        raise ParameterError(
            f"--scheduler must be 'local' or a tcp://host:port address, got {scheduler!r}"
        )
    t0 = time.perf_counter()
    parts, done = _prepare(spec, out, resume)
    todo = [c for c in range(spec.n_chunks) if c not in done]
    n_passive = 0
    n_settled = 0
    for c in sorted(done):
        t = pq.read_table(
            _part_path(parts, c), columns=["passive"] + (["status"] if spec.metrics else [])
        )
        n_passive += int(np.count_nonzero(t.column("passive").to_numpy(zero_copy_only=False)))
        if spec.metrics:
            n_settled += int(
                np.count_nonzero(t.column("status").to_numpy(zero_copy_only=False) == "settled")
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
            _write_part(parts, c, table)
            computed += 1
            columns = tuple(table.column_names)
            n_passive += int(
                np.count_nonzero(table.column("passive").to_numpy(zero_copy_only=False))
            )
            if spec.metrics:
                st = table.column("status").to_numpy(zero_copy_only=False)
                n_settled += int(np.count_nonzero(st == "settled"))
            if bar is not None:
                bar.advance(bar.task_ids[0])
            if on_chunk is not None:
                on_chunk(c, table)
    finally:
        if bar is not None:
            bar.stop()
    if not columns:
        columns = tuple(pq.read_schema(_part_path(parts, 0)).names) if spec.n_chunks else ()
    final = parts
    if out.suffix.lower() in (".parquet", ".csv"):
        _consolidate(parts, out, spec.n_chunks)
        final = out
    return SweepResult(
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


@dataclass(frozen=True)
class HeatmapData:
    """Per-cell aggregates of a sweep over two parameters.

    Arrays have shape ``(len(y_centers), len(x_centers))`` (rows: ``y``).
    Cells without designs hold NaN.

    Attributes
    ----------
    x, y : str
        Parameter names.
    x_centers, y_centers : ndarray
        Cell centres (the grid values themselves for a grid sweep).
    passive_fraction : ndarray
        Fraction of the cell's designs that are passive (over all other parameters).
    settling_time : ndarray or None
        Mean settling time (s) of the cell's settled designs.
    settled_fraction : ndarray or None
    count : ndarray of int
    """

    x: str
    y: str
    x_centers: np.ndarray
    y_centers: np.ndarray
    passive_fraction: np.ndarray
    settling_time: np.ndarray | None
    settled_fraction: np.ndarray | None
    count: np.ndarray


def _iter_batches(path: Path, columns: Sequence[str]) -> Iterator[pa.RecordBatch]:
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if _PART.match(p.name))
        if not files:
            raise FileFormatError(f"{path}: no part-*.parquet files")
        for f in files:
            yield from pq.ParquetFile(f).iter_batches(columns=list(columns))
    elif path.suffix.lower() == ".parquet":
        yield from pq.ParquetFile(path).iter_batches(columns=list(columns))
    elif path.suffix.lower() == ".csv":
        opts = pacsv.ConvertOptions(include_columns=list(columns))
        with pacsv.open_csv(path, convert_options=opts) as reader:
            yield from reader
    else:
        raise FileFormatError(f"{path}: expected a .parquet or .csv file or a parts directory")


def _axis_bins(
    path: Path, name: str, bins: int
) -> tuple[np.ndarray, Callable[[np.ndarray], np.ndarray]]:
    uniq: set[float] = set()
    lo, hi = math.inf, -math.inf
    rows = 0
    for b in _iter_batches(path, [name]):
        v = b.column(0).to_numpy(zero_copy_only=False).astype(float)
        rows += v.size
        if v.size:
            lo, hi = min(lo, float(v.min())), max(hi, float(v.max()))
        if len(uniq) <= 400:
            uniq.update(np.unique(v).tolist())
    if not math.isfinite(lo):
        raise FileFormatError(f"{path}: no rows")
    if len(uniq) <= 400:
        centers = np.array(sorted(uniq))
        return centers, lambda v: np.searchsorted(centers, v)
    # scattered samples: about 8 designs per cell on average, at most `bins` per axis
    nb = int(min(bins, max(4, math.isqrt(max(rows // 8, 1)))))
    edges = np.linspace(lo, hi, nb + 1)
    centers = 0.5 * (edges[1:] + edges[:-1])
    return centers, lambda v: np.clip(np.searchsorted(edges, v, side="right") - 1, 0, nb - 1)


def heatmap_data(path: str | os.PathLike[str], x: str, y: str, *, bins: int = 60) -> HeatmapData:
    """Aggregate a sweep dataset over the parameters ``x`` and ``y`` (streaming, bounded memory).

    Grid axes with at most 400 distinct values keep their values as cells;
    other axes are binned into ``bins`` equal cells.  Other swept parameters
    are aggregated over.
    """
    path = Path(path)
    if x == y:
        raise ParameterError(f"--heatmap needs two different parameters, got {x},{y}")
    schema_cols = set(_schema(path))
    for name in (x, y):
        if name not in schema_cols:
            params = sorted(
                schema_cols
                - {
                    "index",
                    "passive",
                    "margin",
                    "settling_time",
                    "final_error",
                    "overshoot",
                    "status",
                }
            )
            raise ParameterError(
                f"--heatmap: {name!r} is not a column of {path}; swept parameters: {', '.join(params)}"
            )
    has_metrics = "settling_time" in schema_cols
    xc, xb = _axis_bins(path, x, bins)
    yc, yb = _axis_bins(path, y, bins)
    shape = (yc.size, xc.size)
    count = np.zeros(shape, dtype=np.int64)
    npass = np.zeros(shape, dtype=np.int64)
    nset = np.zeros(shape, dtype=np.int64)
    tsum = np.zeros(shape)
    cols = [x, y, "passive"] + (["settling_time"] if has_metrics else [])
    for b in _iter_batches(path, cols):
        xv = b.column(0).to_numpy(zero_copy_only=False).astype(float)
        yv = b.column(1).to_numpy(zero_copy_only=False).astype(float)
        flat = yb(yv) * xc.size + xb(xv)
        count += np.bincount(flat, minlength=count.size).reshape(shape)
        pv = b.column(2).to_numpy(zero_copy_only=False).astype(bool)
        npass += np.bincount(flat, weights=pv, minlength=count.size).astype(np.int64).reshape(shape)
        if has_metrics:
            ts = b.column(3).to_numpy(zero_copy_only=False).astype(float)
            ok = np.isfinite(ts)
            nset += np.bincount(flat[ok], minlength=count.size).reshape(shape)
            tsum += np.bincount(flat[ok], weights=ts[ok], minlength=count.size).reshape(shape)
    with np.errstate(invalid="ignore", divide="ignore"):
        frac = np.where(count > 0, npass / count, np.nan)
        st = np.where(nset > 0, tsum / np.maximum(nset, 1), np.nan) if has_metrics else None
        sf = np.where(count > 0, nset / count, np.nan) if has_metrics else None
    return HeatmapData(
        x=x,
        y=y,
        x_centers=xc,
        y_centers=yc,
        passive_fraction=frac,
        settling_time=st,
        settled_fraction=sf,
        count=count,
    )


def _schema(path: Path) -> list[str]:
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if _PART.match(p.name))
        if not files:
            raise FileFormatError(f"{path}: no part-*.parquet files")
        return list(pq.read_schema(files[0]).names)
    if not path.is_file():
        raise FileFormatError(f"{path}: no such sweep output")
    if path.suffix.lower() == ".parquet":
        return list(pq.read_schema(path).names)
    with pacsv.open_csv(path) as reader:
        return list(reader.schema.names)
