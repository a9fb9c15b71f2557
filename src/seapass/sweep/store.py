"""Where a sweep lives on disk: the parts directory, its manifest, consolidation, reading.

Each finished chunk is written atomically to ``<out>.parts/part-<c>.parquet``
next to a manifest holding the sweep's fingerprint.  A run that is interrupted
keeps its finished parts; a resumed run skips them, so the final dataset has no
duplicated or lost rows.  When every chunk is done the parts are streamed into
the consolidated ``<out>`` (``.parquet`` or ``.csv``), written atomically, and
the parts directory is removed.  An ``out`` without one of those suffixes is a
dataset directory of parts and is kept as is.
"""

from __future__ import annotations

import json
import re
import shutil
from collections.abc import Iterator, Sequence
from pathlib import Path

import pyarrow as pa
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

from ..errors import FileFormatError
from ..files.atomic import atomic_save, atomic_write_text
from ..files.textfile import read_text_file
from .spec import SweepSpec

__all__ = [
    "MANIFEST",
    "PART_NAME",
    "consolidate",
    "done_chunks",
    "iter_batches",
    "part_path",
    "parts_dir",
    "prepare_parts",
    "schema_columns",
    "write_part",
]


MANIFEST = "manifest.json"


PART_NAME = re.compile(r"^part-(\d{6,})\.parquet$")


def parts_dir(out: Path) -> Path:
    return (
        out
        if out.suffix.lower() not in (".parquet", ".csv")
        else out.with_name(out.name + ".parts")
    )


def done_chunks(parts: Path) -> set[int]:
    if not parts.is_dir():
        return set()
    return {int(m.group(1)) for p in parts.iterdir() if (m := PART_NAME.match(p.name))}


def part_path(parts: Path, c: int) -> Path:
    return parts / f"part-{c:06d}.parquet"


def prepare_parts(spec: SweepSpec, out: Path, resume: bool) -> tuple[Path, set[int]]:
    parts = parts_dir(out)
    manifest = parts / MANIFEST
    fp = spec.fingerprint()
    if parts.exists() and any(parts.iterdir()):
        if not manifest.is_file():
            raise FileFormatError(
                f"out: {parts} exists and is not a seapass sweep directory; choose another "
                "output path",
                argument="out",
            )
        try:
            old = json.loads(read_text_file(manifest, what="sweep manifest"))
        except (OSError, json.JSONDecodeError, FileFormatError) as exc:
            raise FileFormatError(f"{manifest}: unreadable manifest ({exc})") from None
        if old.get("fingerprint") != fp:
            raise FileFormatError(
                f"{parts} holds a different sweep (fingerprint {old.get('fingerprint')}, this "
                f"one {fp}); use another output path or delete it",
                argument="out",
            )
        if not resume and done_chunks(parts):
            raise FileFormatError(
                f"{parts} holds {len(done_chunks(parts))} finished chunk(s) of this sweep; "
                "pass resume=True to continue it, or delete the directory to start over"
            )
    parts.mkdir(parents=True, exist_ok=True)
    atomic_write_text(
        manifest,
        json.dumps({"fingerprint": fp, "spec": spec.describe(), "format": 1}, indent=2, default=str)
        + "\n",
    )
    done = done_chunks(parts) if resume else set()
    return parts, {c for c in done if c < spec.n_chunks}


def write_part(parts: Path, c: int, table: pa.Table) -> None:
    atomic_save(part_path(parts, c), lambda tmp: pq.write_table(table, tmp))


def consolidate(parts: Path, out: Path, n_chunks: int) -> None:
    """Stream all parts, in chunk order, into ``out`` atomically (bounded memory)."""
    first = pq.read_schema(part_path(parts, 0))
    if out.suffix.lower() == ".parquet":

        def save(tmp: str) -> None:
            with pq.ParquetWriter(tmp, first) as writer:
                for c in range(n_chunks):
                    writer.write_table(pq.read_table(part_path(parts, c)))

    else:

        def save(tmp: str) -> None:
            with pacsv.CSVWriter(tmp, first) as writer:
                for c in range(n_chunks):
                    writer.write_table(pq.read_table(part_path(parts, c)))

    atomic_save(out, save)
    shutil.rmtree(parts)


def iter_batches(path: Path, columns: Sequence[str]) -> Iterator[pa.RecordBatch]:
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if PART_NAME.match(p.name))
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


def schema_columns(path: Path) -> list[str]:
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if PART_NAME.match(p.name))
        if not files:
            raise FileFormatError(f"{path}: no part-*.parquet files")
        return list(pq.read_schema(files[0]).names)
    if not path.is_file():
        raise FileFormatError(f"{path}: no such sweep output")
    if path.suffix.lower() == ".parquet":
        return list(pq.read_schema(path).names)
    with pacsv.open_csv(path) as reader:
        return list(reader.schema.names)
