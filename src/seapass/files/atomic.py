"""Atomic file output: an interrupted run never leaves a half-written file."""

from __future__ import annotations

import os
import tempfile
import tomllib
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeVar

from ..errors import FileFormatError

__all__ = ["atomic_save", "atomic_write", "atomic_write_text", "load_toml_file"]

T = TypeVar("T")


def _umask_mode() -> int:
    """Permissions a plain ``open()`` would give (mkstemp creates files 0600)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


@contextmanager
def atomic_write(path: str | os.PathLike[str], mode: str = "w") -> Iterator[Any]:
    """Open a temporary file beside ``path``; rename it over ``path`` only on success."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent)
    try:
        with os.fdopen(fd, mode) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, _umask_mode())
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def atomic_write_text(path: str | os.PathLike[str], text: str) -> None:
    with atomic_write(path) as fh:
        fh.write(text)


def atomic_save(path: str | os.PathLike[str], save: Callable[[str], None]) -> None:
    """Call ``save(tmp_path)`` (e.g. ``fig.savefig``) and rename the result over ``path``."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=target.suffix, dir=target.parent)
    os.close(fd)
    try:
        save(tmp)
        os.chmod(tmp, _umask_mode())
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def load_toml_file(path: str | os.PathLike[str], parse: Callable[[dict[str, Any]], T]) -> T:
    """Read a TOML file and ``parse`` its table; every error names the file.

    Raises
    ------
    FileFormatError
        For invalid TOML, non-UTF-8 text, or content ``parse`` rejects.
    OSError
        If the file cannot be read.
    """
    p = Path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise FileFormatError(f"{p}: invalid TOML: {exc}") from None
    except UnicodeDecodeError:
        raise FileFormatError(f"{p}: not a UTF-8 text file") from None
    try:
        return parse(data)
    except FileFormatError as exc:
        raise FileFormatError(f"{p}: {exc}") from None
