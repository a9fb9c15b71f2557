"""Where sweep files live: a local or shared path, or an fsspec URL such as ``s3://bucket/x``.

A [`Location`][seapass.sweep.location.Location] pairs an fsspec file system with
a path in it.  It pickles as ``(url, storage_options)``, so a Dask worker
re-opens the same place on its own machine: a path on a file system that the
client and the workers share, or an object store they all reach.  Local paths
are made absolute on the client first (a worker's working directory is not the
client's).

Writes are atomic on every file system: locally a temporary file beside the
target is renamed over it; object stores (S3, GCS, Azure, ``memory://``) make a
single upload visible only when it is complete; anything else gets a temporary
object that is moved into place.  Temporary names start with a dot, which
dataset readers (pyarrow, Spark, DuckDB globs on ``*.parquet``) skip.
"""

from __future__ import annotations

import os
import re
import secrets
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from ..errors import FileFormatError, MissingExtraError, ParameterError
from ..files.atomic import atomic_save, atomic_write
from ..files.textfile import check_input_file, read_text_file

__all__ = ["ATOMIC_PUT_PROTOCOLS", "TEMP_NAME", "Location", "open_location"]


#: Protocols whose single-object writes appear all at once or not at all.
ATOMIC_PUT_PROTOCOLS = frozenset({"s3", "s3a", "gs", "gcs", "abfs", "az", "abfss", "memory"})

#: Temporary files written by seapass beside a target (``.NAME.<hex>.part``).
TEMP_NAME = re.compile(r"^\.(?P<target>.+)\.[0-9a-f]{12}\.part$")


@dataclass(frozen=True)
class Location:
    """A path on an fsspec file system.

    Attributes
    ----------
    url : str
        What the user gave, made absolute for local paths (``/abs/dir``) or
        with its protocol (``s3://bucket/dir``); shown in messages and results.
    storage_options : mapping
        Keyword arguments of the file system (credentials, endpoint, ...).
    """

    url: str
    storage_options: Mapping[str, Any] = field(default_factory=dict)
    fs: Any = field(init=False, repr=False, compare=False)
    path: str = field(init=False, compare=False)

    def __post_init__(self) -> None:
        fs, path = _resolve(self.url, self.storage_options)
        object.__setattr__(self, "fs", fs)
        object.__setattr__(self, "path", path.rstrip("/") or "/")

    def __reduce__(self) -> tuple[Any, ...]:
        return (Location, (self.url, dict(self.storage_options)))

    @property
    def is_local(self) -> bool:
        """True for the machine's own file system (atomic rename, mmap reads)."""
        return "file" in _protocols(self.fs)

    @property
    def is_memory(self) -> bool:
        """True for ``memory://``, which lives inside one process only."""
        return "memory" in _protocols(self.fs)

    @property
    def name(self) -> str:
        return self.path.rsplit("/", 1)[-1]

    @property
    def suffix(self) -> str:
        """Lower-case suffix of the last path component (``".parquet"``), or ``""``."""
        stem, dot, ext = self.name.rpartition(".")
        return f".{ext.lower()}" if dot and stem else ""

    def child(self, name: str) -> Location:
        """The location ``name`` inside this one."""
        sep = "" if self.url.endswith("/") else "/"
        return Location(self.url + sep + name, self.storage_options)

    def sibling(self, name: str) -> Location:
        """The location ``name`` beside this one (same parent)."""
        parent = self.url.rstrip("/").rsplit("/", 1)[0] if "/" in self.url.rstrip("/") else "."
        return Location(f"{parent}/{name}", self.storage_options)

    # ----------------------------------------------------------------- queries

    def exists(self) -> bool:
        return bool(self.fs.exists(self.path))

    def is_dir(self) -> bool:
        return bool(self.fs.isdir(self.path))

    def is_file(self) -> bool:
        return bool(self.fs.isfile(self.path))

    def size(self) -> int | None:
        """Size in bytes, or None if there is no such file."""
        try:
            info = self.fs.info(self.path)
        except FileNotFoundError:
            return None
        return int(info["size"]) if info.get("type") != "directory" else None

    def list_names(self) -> list[str]:
        """Names of the entries directly inside this directory ([] if it does not exist)."""
        try:
            entries = self.fs.ls(self.path, detail=False, refresh=True)
        except FileNotFoundError:
            return []
        except TypeError:  # file systems without a cache have no ``refresh``
            entries = self.fs.ls(self.path, detail=False)
        own = self.path.rstrip("/")
        return sorted(e.rstrip("/").rsplit("/", 1)[-1] for e in entries if e.rstrip("/") != own)

    def local_path(self) -> str:
        """The operating-system path of a local location."""
        if not self.is_local:
            raise ParameterError(f"{self.url} is not on the local file system")
        return str(Path(self.path))

    @contextmanager
    def reader(self) -> Iterator[Any]:
        """For pyarrow readers: the path of a local file (read natively), else an open file.

        A local path is checked to be a regular file first (a FIFO or a device
        named like a part would block or never end); pyarrow streams it.
        """
        if self.is_local:
            yield str(check_input_file(self.local_path(), max_bytes=None, what="sweep file"))
            return
        with self.fs.open(self.path, "rb") as fh:
            yield fh

    def read_text(self, max_bytes: int) -> str:
        """The UTF-8 text of this file, of at most ``max_bytes`` (local files: `read_text_file`)."""
        if self.is_local:
            return read_text_file(self.local_path(), max_bytes=max_bytes, what="sweep file")
        with self.fs.open(self.path, "rb") as fh:
            data = bytes(fh.read(max_bytes + 1))
        if len(data) > max_bytes:
            raise FileFormatError(f"{self.url}: larger than the limit of {max_bytes:,} bytes")
        try:
            return data.decode("utf-8")
        except UnicodeDecodeError:
            raise FileFormatError(f"{self.url}: not a UTF-8 text file") from None

    # ----------------------------------------------------------------- writes

    def makedirs(self) -> None:
        self.fs.makedirs(self.path, exist_ok=True)

    def put_bytes(self, data: bytes) -> None:
        """Write ``data`` atomically (readers see the old file, or all of the new one)."""
        if self.is_local:
            with atomic_write(self.local_path(), "wb") as fh:
                fh.write(data)
        elif _protocols(self.fs) & ATOMIC_PUT_PROTOCOLS:
            self.fs.pipe_file(self.path, data)
        else:
            self.save_via(lambda fh: fh.write(data))

    def save_via(self, write: Callable[[IO[bytes]], Any]) -> None:
        """Call ``write(binary_file)`` and publish the result atomically under this name."""
        if self.is_local:

            def save(tmp: str) -> None:
                with open(tmp, "wb") as fh:
                    write(fh)

            atomic_save(self.local_path(), save)
            return
        tmp = self.sibling(f".{self.name}.{secrets.token_hex(6)}.part")
        try:
            with tmp.fs.open(tmp.path, "wb") as fh:
                write(fh)
            self.fs.mv(tmp.path, self.path)
        except BaseException:
            if tmp.exists():
                tmp.fs.rm(tmp.path)
            raise

    def remove(self) -> None:
        """Remove this file (not a directory); nothing if it does not exist."""
        if self.fs.isfile(self.path):
            self.fs.rm(self.path)

    def rename(self, target: Location) -> None:
        self.fs.mv(self.path, target.path)

    def remove_empty_dir(self) -> None:
        """Remove this directory if it is empty (object stores have none to remove)."""
        if self.list_names():
            return
        try:
            self.fs.rmdir(self.path)
        except (FileNotFoundError, OSError, NotImplementedError):
            pass


def open_location(
    where: str | os.PathLike[str] | Location, storage_options: Mapping[str, Any] | None = None
) -> Location:
    """A `Location` from a path, a URL or an existing `Location`."""
    if isinstance(where, Location):
        return where
    text = os.fspath(where)
    if not text:
        raise ParameterError("out: empty path")
    if "://" not in text and "::" not in text:
        text = str(Path(text).expanduser().absolute())
    return Location(text, dict(storage_options or {}))


def _protocols(fs: Any) -> set[str]:
    p = fs.protocol
    return {p} if isinstance(p, str) else set(p)


def _resolve(url: str, storage_options: Mapping[str, Any]) -> tuple[Any, str]:
    try:
        from fsspec.core import url_to_fs
    except ImportError:  # pragma: no cover - fsspec is a dependency
        raise MissingExtraError("fsspec is needed for sweep output; pip install fsspec") from None
    try:
        fs, path = url_to_fs(url, **dict(storage_options))
    except ImportError as exc:
        raise MissingExtraError(
            f"out: {url.split('://', 1)[0]}:// needs a package that is not installed ({exc})"
        ) from None
    except ValueError as exc:
        raise ParameterError(f"out: {url!r} is not a path or a known fsspec URL ({exc})") from None
    return fs, str(path)
