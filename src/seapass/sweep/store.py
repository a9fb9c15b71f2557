"""Where a sweep lives: the parts directory, its manifest, consolidation and reading.

Each finished chunk ``c`` is written atomically, by whoever computed it (this
process or a Dask worker), to ``part-<c>.parquet`` in the parts directory: the
output directory itself, or ``<out>.parts`` for a consolidated ``.parquet`` or
``.csv`` output.  Beside the parts, ``_manifest.json`` holds the sweep's
fingerprint and a journal of the chunks known to be finished with their counts.
Its leading underscore makes pyarrow, Spark and DuckDB skip it, so the
directory reads as a plain Parquet dataset.

The journal is rewritten by the client only, at most about once a second and
at the end, so its cost does not grow with the data.  After a hard kill the
parts written since the last rewrite are still on disk; a resumed run finds
them by listing the directory and counts them from their ``passive`` and
``status`` columns, so resumption loses and duplicates nothing.  When every
chunk is done the parts of a ``.parquet``/``.csv`` output are streamed, in
chunk order, into the output (written atomically) and removed.
"""

from __future__ import annotations

import io
import json
import re
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

from ..errors import FileFormatError
from ..files.limits import MAX_SWEEP_MANIFEST_BYTES
from ..sim.metrics import Settling
from ..version import __version__
from .location import TEMP_NAME, Location
from .spec import SweepSpec

__all__ = [
    "CONSOLIDATED_SUFFIXES",
    "LEGACY_MANIFEST",
    "MANIFEST",
    "MANIFEST_FORMAT",
    "PART_NAME",
    "PartSummary",
    "SweepStore",
    "consolidate",
    "iter_batches",
    "part_location",
    "parts_location",
    "schema_columns",
    "summarize_part",
    "write_part",
]


MANIFEST = "_manifest.json"
#: The manifest's name in earlier seapass versions (format 1); dataset readers took it for a part.
LEGACY_MANIFEST = "manifest.json"
MANIFEST_FORMAT = 2
PART_NAME = re.compile(r"^part-(\d{6,})\.parquet$")
CONSOLIDATED_SUFFIXES = (".parquet", ".csv")
#: Seconds between journal rewrites while a sweep runs.
JOURNAL_INTERVAL = 1.0


@dataclass(frozen=True, kw_only=True)
class PartSummary:
    """What the writer of one part reports: a few numbers, never the data.

    Attributes
    ----------
    chunk : int
    rows : int
    n_passive : int
    n_settled : int or None
        None without metrics.
    nbytes : int
        Size of the Parquet file written.
    seconds : float
        CPU time of the thread that computed and wrote the part.
    columns : tuple of str
    """

    chunk: int
    rows: int
    n_passive: int
    n_settled: int | None
    nbytes: int
    seconds: float
    columns: tuple[str, ...]


def parts_location(out: Location) -> Location:
    """The directory of parts: ``out`` itself, or ``<out>.parts`` for a consolidated file."""
    return out if out.suffix not in CONSOLIDATED_SUFFIXES else out.sibling(out.name + ".parts")


def part_location(parts: Location, c: int) -> Location:
    return parts.child(f"part-{c:06d}.parquet")


def summarize_part(c: int, table: pa.Table, nbytes: int = 0, seconds: float = 0.0) -> PartSummary:
    """Counts of one part's table (``passive`` and, with metrics, ``status``)."""
    passive = table.column("passive").to_numpy(zero_copy_only=False)
    settled = None
    if "status" in table.column_names:
        status = table.column("status").to_numpy(zero_copy_only=False)
        settled = int(np.count_nonzero(status == Settling.SETTLED.value))
    return PartSummary(
        chunk=c,
        rows=table.num_rows,
        n_passive=int(np.count_nonzero(passive)),
        n_settled=settled,
        nbytes=nbytes,
        seconds=seconds,
        columns=tuple(table.column_names),
    )


def write_part(parts: Location, c: int, table: pa.Table) -> int:
    """Write chunk ``c`` atomically; the number of bytes written."""
    sink = io.BytesIO()
    pq.write_table(table, sink)
    data = sink.getvalue()
    part_location(parts, c).put_bytes(data)
    return len(data)


# --------------------------------------------------------------------------- the store


class SweepStore:
    """The client's view of one sweep's output: what is done, and the journal.

    Use [`SweepStore.open`][seapass.sweep.store.SweepStore.open]; then
    [`record`][seapass.sweep.store.SweepStore.record] each part as its writer
    reports it, and [`finish`][seapass.sweep.store.SweepStore.finish].
    """

    def __init__(
        self, spec: SweepSpec, out: Location, *, clock: Callable[[], float] = time.monotonic
    ) -> None:
        self.spec = spec
        self.out = out
        self.parts = parts_location(out)
        self.done: set[int] = set()
        self.resumed = 0
        self.n_passive = 0
        self.n_settled = 0
        self.columns: tuple[str, ...] = ()
        self.migrated = False
        self._clock = clock
        self._last_flush = clock()
        self._checked_visible = False
        self._legacy_pending = False
        self._header: dict[str, Any] | None = None

    @classmethod
    def open(cls, spec: SweepSpec, out: Location, *, resume: bool) -> SweepStore:
        """Check ``out`` against ``spec``, take over finished parts (with ``resume``)."""
        store = cls(spec, out)
        names = store.parts.list_names()
        if names:
            store._adopt(names, resume)
        store.parts.makedirs()
        store.flush()
        return store

    @property
    def todo(self) -> list[int]:
        return [c for c in range(self.spec.n_chunks) if c not in self.done]

    def _adopt(self, names: list[str], resume: bool) -> None:
        manifest = _read_existing_manifest(self.parts, names, self.spec)
        legacy = MANIFEST not in names
        on_disk = {int(m.group(1)) for n in names if (m := PART_NAME.match(n))}
        on_disk = {c for c in on_disk if c < self.spec.n_chunks}
        if on_disk and not resume:
            what = (
                "a finished sweep"
                if manifest.get("complete")
                else f"{len(on_disk)} finished chunk(s)"
            )
            old, new = (f"{self.parts.url}/{name}" for name in (LEGACY_MANIFEST, MANIFEST))
            hint = (
                f"; it has an old-style {LEGACY_MANIFEST}, which dataset readers take for a "
                f"part: rerun with resume=True to migrate it to {MANIFEST}, or rename it "
                f"yourself (mv {old} {new})"
                if legacy
                else ""
            )
            raise FileFormatError(
                f"{self.parts.url} holds {what} of this sweep; pass resume=True to continue it, "
                f"or delete the directory to start over{hint}"
            )
        for n in names:  # temporary files of writes that a hard kill interrupted
            if (m := TEMP_NAME.match(n)) and PART_NAME.match(m.group("target")):
                self.parts.child(n).remove()
        journal = _journal_chunks(manifest) if not legacy else set()
        if journal <= on_disk:
            self.n_passive = int(manifest.get("n_passive", 0)) if journal else 0
            self.n_settled = int(manifest.get("n_settled") or 0) if journal else 0
            self.columns = tuple(manifest.get("columns") or ())
        else:  # parts listed in the journal are gone: count everything again
            journal = set()
        for c in sorted(on_disk - journal):
            self._count_from_disk(c)
        self.done = set(on_disk)
        self.resumed = len(on_disk)
        if legacy:
            self.migrated = self._legacy_pending = True

    def _count_from_disk(self, c: int) -> None:
        cols = ["passive"] + (["status"] if self.spec.metrics else [])
        with part_location(self.parts, c).reader() as src:
            s = summarize_part(c, pq.read_table(src, columns=cols))
        self.n_passive += s.n_passive
        self.n_settled += s.n_settled or 0

    def record(self, s: PartSummary) -> None:
        """Account for a part its writer reports as written."""
        if not self._checked_visible:
            self._check_visible(s)
        if s.chunk in self.done:
            return
        self.done.add(s.chunk)
        self.n_passive += s.n_passive
        self.n_settled += s.n_settled or 0
        self.columns = self.columns or s.columns
        if self._clock() - self._last_flush >= JOURNAL_INTERVAL:
            self.flush()

    def _check_visible(self, s: PartSummary) -> None:
        # a worker on another machine writing to its own disk would lose the part
        where = part_location(self.parts, s.chunk)
        if where.size() != s.nbytes:
            raise FileFormatError(
                f"a worker wrote {where.name} ({s.nbytes} bytes) but this client sees "
                f"{'no such file' if where.size() is None else f'{where.size()} bytes'} at "
                f"{self.parts.url}: out must be on a file system shared by the client and "
                "every worker, or an object store URL such as s3://bucket/sweep/"
            )
        self._checked_visible = True

    def flush(self, *, complete: bool = False) -> None:
        """Rewrite the journal (atomically)."""
        if self._header is None:  # the fixed part, computed once
            self._header = {
                "format": MANIFEST_FORMAT,
                "seapass": __version__,
                "fingerprint": self.spec.fingerprint(),
                "spec": json.loads(json.dumps(self.spec.describe(), default=str)),
                "n_chunks": self.spec.n_chunks,
            }
        doc = {
            **self._header,
            "columns": list(self.columns),
            "done": _ranges(self.done),
            "n_done": len(self.done),
            "n_passive": self.n_passive,
            "n_settled": self.n_settled if self.spec.metrics else None,
            "complete": complete,
        }
        text = json.dumps(doc, indent=1) + "\n"
        self.parts.child(MANIFEST).put_bytes(text.encode())
        if self._legacy_pending:
            self.parts.child(LEGACY_MANIFEST).remove()
            self._legacy_pending = False
        self._last_flush = self._clock()

    def finish(self) -> Location:
        """Check every part is there, close the journal, consolidate; the final location."""
        names = set(self.parts.list_names())
        missing = [c for c in range(self.spec.n_chunks) if f"part-{c:06d}.parquet" not in names]
        if missing:
            self.flush()
            raise FileFormatError(
                f"{len(missing)} of {self.spec.n_chunks} parts are missing from "
                f"{self.parts.url} (first: chunk {missing[0]}); rerun with resume=True"
            )
        if not self.columns and self.spec.n_chunks:
            self.columns = tuple(schema_columns(self.parts))
        self.flush(complete=True)
        if self.out.suffix in CONSOLIDATED_SUFFIXES:
            consolidate(self.parts, self.out, self.spec.n_chunks)
            return self.out
        return self.parts


def _read_existing_manifest(parts: Location, names: list[str], spec: SweepSpec) -> dict[str, Any]:
    name = MANIFEST if MANIFEST in names else LEGACY_MANIFEST if LEGACY_MANIFEST in names else None
    if name is None:
        raise FileFormatError(
            f"{parts.url} exists and is not a seapass sweep directory (no {MANIFEST}); "
            "choose another out"
        )
    where = parts.child(name)
    try:
        doc = json.loads(where.read_text(MAX_SWEEP_MANIFEST_BYTES))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise FileFormatError(f"{where.url}: unreadable manifest ({exc})") from None
    if not isinstance(doc, dict) or "fingerprint" not in doc:
        raise FileFormatError(f"{where.url}: not a seapass sweep manifest (no fingerprint)")
    fp = spec.fingerprint()
    if doc["fingerprint"] != fp:
        raise FileFormatError(
            f"{parts.url} holds a different sweep (fingerprint {doc['fingerprint']}, this "
            f"one {fp}); use another output path or delete it"
        )
    if int(doc.get("format", 1)) > MANIFEST_FORMAT:
        raise FileFormatError(
            f"{where.url}: manifest format {doc['format']} is newer than this seapass "
            f"understands ({MANIFEST_FORMAT}); upgrade seapass"
        )
    return doc


def _ranges(done: Iterable[int]) -> list[list[int]]:
    """``{0, 1, 2, 5}`` → ``[[0, 3], [5, 6]]`` (half-open runs)."""
    out: list[list[int]] = []
    for c in sorted(done):
        if out and out[-1][1] == c:
            out[-1][1] = c + 1
        else:
            out.append([c, c + 1])
    return out


def _journal_chunks(doc: dict[str, Any]) -> set[int]:
    try:
        return {c for a, b in doc.get("done", []) for c in range(int(a), int(b))}
    except (TypeError, ValueError):
        raise FileFormatError("manifest: malformed 'done' list") from None


# --------------------------------------------------------------------------- merging and reading


def consolidate(parts: Location, out: Location, n_chunks: int) -> None:
    """Stream all parts, in chunk order, into ``out`` atomically; then remove them."""
    first = _part_schema(part_location(parts, 0))

    def tables() -> Iterator[pa.Table]:
        for c in range(n_chunks):
            with part_location(parts, c).reader() as src:
                table = pq.read_table(src)
            yield table.replace_schema_metadata(None)

    if out.suffix == ".parquet":

        def write(fh: Any) -> None:
            with pq.ParquetWriter(fh, first) as writer:
                for t in tables():
                    writer.write_table(t)

    else:

        def write(fh: Any) -> None:
            with pacsv.CSVWriter(fh, first) as writer:
                for t in tables():
                    writer.write_table(t)

    out.save_via(write)
    for c in range(n_chunks):
        part_location(parts, c).remove()
    parts.child(MANIFEST).remove()
    parts.remove_empty_dir()


def _part_schema(where: Location) -> pa.Schema:
    with where.reader() as src:
        return pq.read_schema(src).remove_metadata()


def _part_files(where: Location) -> list[Location]:
    files = [where.child(n) for n in where.list_names() if PART_NAME.match(n)]
    if not files:
        raise FileFormatError(f"{where.url}: no part-*.parquet files")
    return files


def iter_batches(where: Location, columns: Sequence[str]) -> Iterator[pa.RecordBatch]:
    """Record batches of ``columns`` of a sweep output: a parts directory, Parquet or CSV."""
    if where.is_dir():
        files = _part_files(where)
    elif where.suffix == ".parquet":
        files = [where]
    elif where.suffix == ".csv":
        opts = pacsv.ConvertOptions(include_columns=list(columns))
        with where.reader() as src, pacsv.open_csv(src, convert_options=opts) as reader:
            yield from reader
        return
    else:
        raise FileFormatError(
            f"{where.url}: expected a .parquet or .csv file or a directory of parts"
        )
    for f in files:
        with f.reader() as src:
            yield from pq.ParquetFile(src).iter_batches(columns=list(columns))


def schema_columns(where: Location) -> list[str]:
    """Column names of a sweep output."""
    if where.is_dir():
        return list(_part_schema(_part_files(where)[0]).names)
    if not where.is_file():
        raise FileFormatError(f"{where.url}: no such sweep output")
    if where.suffix == ".parquet":
        return list(_part_schema(where).names)
    with where.reader() as src, pacsv.open_csv(src) as reader:
        return list(reader.schema.names)
