"""Atomic file output: an interrupted run never leaves a half-written file.

Temporary files and directories are created beside their target with
``os.open(..., 0o666)`` / ``os.mkdir(..., 0o777)``, so the process umask
applies to them exactly as to a plain ``open()``; nothing here reads or
changes the umask (which would race with other threads).
"""

from __future__ import annotations

import os
import secrets
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ..errors import OutputPathError

__all__ = [
    "atomic_save",
    "atomic_write",
    "atomic_write_text",
    "check_writable",
    "sibling_dir",
    "sibling_file",
]


def sibling_file(target: Path, suffix: str = ".part") -> tuple[int, Path]:
    """Create a new empty file beside ``target`` with default permissions; ``(fd, path)``."""
    for _ in range(100):
        tmp = target.with_name(f".{target.name}.{secrets.token_hex(6)}{suffix}")
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC, 0o666)
        except FileExistsError:
            continue
        return fd, tmp
    raise FileExistsError(f"could not create a temporary file beside {target}")  # pragma: no cover


def sibling_dir(target: Path, suffix: str = ".part") -> Path:
    """Create a new empty directory beside ``target`` with default permissions."""
    for _ in range(100):
        tmp = target.with_name(f".{target.name}.{secrets.token_hex(6)}{suffix}")
        try:
            os.mkdir(tmp, 0o777)
        except FileExistsError:
            continue
        return tmp
    raise FileExistsError(
        f"could not create a temporary directory beside {target}"
    )  # pragma: no cover


@contextmanager
def atomic_write(path: str | os.PathLike[str], mode: str = "w") -> Iterator[Any]:
    """Open a temporary file beside ``path``; rename it over ``path`` only on success."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = sibling_file(target)
    try:
        with os.fdopen(fd, mode) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def atomic_write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_write(path) as fh:
        fh.write(text)


def atomic_save(path: str | os.PathLike[str], save: Callable[[str], None]) -> None:
    """Call ``save(tmp_path)`` (e.g. ``fig.savefig``) and rename the result over ``path``.

    The temporary path keeps ``path``'s suffix, so savers that pick a format
    from the suffix write the right one.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = sibling_file(target, suffix=target.suffix)
    os.close(fd)
    try:
        save(str(tmp))
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _dangling(p: Path) -> Path | None:
    """The first of ``p`` and its ancestors that is a symbolic link to nothing."""
    for q in (p, *p.parents):
        if q.is_symlink() and not q.exists():
            return q
    return None


def check_writable(path: str | os.PathLike[str], *, directory: bool, argument: str = "out") -> Path:
    """Raise `OutputPathError` unless seapass can create ``path`` (a file or a directory).

    Call it before long work, so that a read-only directory or a dangling
    symbolic link is reported at once, not after the results are computed.
    The test is real: a probe file is created and removed in the nearest
    existing directory (permission bits alone mislead for root, ACLs and
    read-only mounts).  ``argument`` names the option in the message.

    Returns
    -------
    Path
        ``path``, unchanged.
    """
    p = Path(path)
    link = _dangling(p)
    if link is not None:
        raise OutputPathError(
            f"{argument}: {link} is a symbolic link to {os.readlink(link)}, which does not "
            "exist; create the target or remove the link",
            argument=argument,
        )
    if p.exists():
        if directory and not p.is_dir():
            raise OutputPathError(
                f"{argument}: {p} exists and is not a directory", argument=argument
            )
        if not directory and p.is_dir():
            raise OutputPathError(
                f"{argument}: {p} is a directory; give a file name", argument=argument
            )
    where = p if directory and p.is_dir() else p.parent
    while not where.exists():
        where = where.parent
    if not where.is_dir():
        raise OutputPathError(
            f"{argument}: {where} is not a directory, so {p} cannot be created",
            argument=argument,
        )
    try:
        fd, probe = sibling_file(where / ".seapass-probe", suffix=".tmp")
    except OSError as exc:
        raise OutputPathError(
            f"{argument}: cannot write in {where}: {exc.strerror or exc}", argument=argument
        ) from None
    os.close(fd)
    probe.unlink(missing_ok=True)
    return p
