"""Never replace a file seapass did not write: the manifest of what seapass wrote.

The one rule of every command that writes: an existing file is replaced only
if seapass wrote it and nobody changed it since, or if the caller says so
(``force=True``, the command line's ``--force``).  Every directory seapass
writes a file into holds ``.seapass-written``, a small JSON manifest listing
the files seapass wrote there with the SHA-256 digest of their content; a file
is seapass's when the manifest of its directory lists it with the digest of
its current content.  A file the user wrote, copied over, or edited after
seapass wrote it is not, so it is never lost by running a command again.
Devices, FIFOs, sockets and directories are never replaced, even with
``force``.

The writers here check, write atomically ([`seapass.files.atomic`][seapass.files.atomic])
and record: [`write_output_text`][seapass.files.owned.write_output_text],
[`write_output_bytes`][seapass.files.owned.write_output_bytes],
[`save_output`][seapass.files.owned.save_output] (a saver such as
``savefig`` given a temporary path) and [`record_written`][seapass.files.owned.record_written]
for a file written by other means (a consolidated sweep).  Call
[`check_replaceable`][seapass.files.owned.check_replaceable] on every output path
before long work, so a refusal costs nothing.  A report directory
([`seapass.report.output`][seapass.report.output]) keeps the same manifest at its
top, listing paths relative to it.

Two processes writing into one directory at the same moment may lose one
manifest entry; the file is then treated as the user's (the next run needs
``force``), never the other way round.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path

from ..errors import OutputPathError
from .atomic import atomic_save, atomic_write, atomic_write_text
from .textfile import check_input_file, read_text_file

__all__ = [
    "MANIFEST",
    "check_replaceable",
    "file_digest",
    "read_manifest",
    "record_written",
    "save_output",
    "seapass_wrote",
    "write_manifest",
    "write_output_bytes",
    "write_output_text",
]

MANIFEST = ".seapass-written"
"""Name of the manifest of the files seapass wrote in a directory."""

_MAX_MANIFEST_BYTES = 16 << 20
_NOTE = "seapass replaces the files listed here while their content is unchanged, and no others"


def file_digest(path: str | os.PathLike[str]) -> str:
    """``"sha256:<hex>"`` of a regular file's content (streamed in 1 MiB blocks)."""
    p = check_input_file(path, max_bytes=None)
    h = hashlib.sha256()
    with p.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return "sha256:" + h.hexdigest()


def _digest_bytes(data: bytes) -> str:
    return "sha256:" + hashlib.sha256(data).hexdigest()


def read_manifest(
    directory: str | os.PathLike[str], name: str = MANIFEST
) -> dict[str, str | None] | None:
    """The files the manifest of ``directory`` lists, ``{relative path: digest}``.

    None when there is no manifest or the file of that name is not one (a
    digest of None: an entry of an older manifest that listed names only).

    Raises
    ------
    FileFormatError
        When the manifest is a directory, a FIFO, a device or larger than 16 MiB.
    """
    p = Path(directory) / name
    try:
        check_input_file(p, max_bytes=_MAX_MANIFEST_BYTES, what="manifest")
    except FileNotFoundError:  # none, or a dangling link
        return None
    try:
        data = json.loads(read_text_file(p, max_bytes=_MAX_MANIFEST_BYTES, what="manifest"))
    except (ValueError, OSError):  # not UTF-8, not JSON, unreadable: not a manifest
        return None
    if not isinstance(data, dict) or data.get("written_by") != "seapass":
        return None
    files = data.get("files")
    if isinstance(files, list) and all(isinstance(f, str) for f in files):
        return dict.fromkeys(files)
    if isinstance(files, dict) and all(
        isinstance(k, str) and isinstance(v, str) for k, v in files.items()
    ):
        return dict(files)
    return None


def write_manifest(directory: str | os.PathLike[str], files: Mapping[str, str | None]) -> Path:
    """Write the manifest of ``directory`` listing ``files`` (atomically); its path."""
    from ..version import __version__

    doc = {
        "written_by": "seapass",
        "version": __version__,
        "note": _NOTE,
        "files": {k: v for k, v in sorted(files.items()) if v is not None},
    }
    path = Path(directory) / MANIFEST
    atomic_write_text(path, json.dumps(doc, indent=1) + "\n")
    return path


def _kind(mode: int) -> str | None:
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISLNK(mode):
        return "a symbolic link"
    if stat.S_ISFIFO(mode):
        return "a pipe (FIFO)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    return "not a regular file"


def seapass_wrote(path: str | os.PathLike[str]) -> bool:
    """True when ``path`` is a regular file that seapass wrote and nobody changed since."""
    p = Path(path)
    try:
        st = p.lstat()
    except OSError:
        return False
    if not stat.S_ISREG(st.st_mode):
        return False
    listed = read_manifest(p.parent)
    if listed is None or p.name not in listed:
        return False
    want = listed[p.name]
    return want is None or file_digest(p) == want


def check_replaceable(
    path: str | os.PathLike[str], *, force: bool = False, argument: str = "out"
) -> Path:
    """Raise `OutputPathError` unless seapass may write ``path`` (call it before long work).

    Allowed: a path where nothing is, a regular file that seapass wrote and
    nobody changed since, and with ``force`` any regular file.  Never: a
    directory, a symbolic link, a FIFO or a device (their targets are not
    seapass's to replace), or a directory whose manifest slot holds a file
    that is not a seapass manifest (unless ``force``).

    Returns
    -------
    Path
        ``path``, unchanged.
    """
    p = Path(path)
    try:
        st = p.lstat()
    except FileNotFoundError:
        st = None
    except OSError as exc:
        raise OutputPathError(
            f"{argument}: cannot examine {p}: {exc.strerror or exc}", argument=argument
        ) from None
    if st is not None:
        kind = _kind(st.st_mode)
        if kind is not None:
            raise OutputPathError(
                f"{argument}: {p} is {kind}; seapass replaces only regular files it wrote "
                "(choose another name)",
                argument=argument,
            )
        if not force and not seapass_wrote(p):
            raise OutputPathError(
                f"{argument}: {p} exists and was not written by seapass (or was changed since); "
                "choose another name, move the file away, or pass force=True to replace it",
                argument=argument,
            )
    slot = p.parent / MANIFEST
    if (slot.exists() or slot.is_symlink()) and read_manifest(p.parent) is None:
        if force and slot.is_file() and not slot.is_symlink():
            return p
        raise OutputPathError(
            f"{argument}: {slot} is not a seapass manifest, and seapass records there what it "
            "writes; move it away" + (" or pass force=True" if slot.is_file() else ""),
            argument=argument,
        )
    return p


def record_written(
    paths: Iterable[str | os.PathLike[str]], digests: Mapping[Path, str] | None = None
) -> None:
    """Add ``paths`` (files seapass just wrote) to the manifests of their directories.

    Entries of files that are gone are dropped.  ``digests`` gives the digest of
    a path whose content is known (else the file is read).
    """
    by_dir: dict[Path, dict[str, str]] = {}
    for path in paths:
        p = Path(path)
        digest = (digests or {}).get(p) or file_digest(p)
        by_dir.setdefault(p.parent, {})[p.name] = digest
    for directory, new in by_dir.items():
        listed = read_manifest(directory) or {}
        kept = {k: v for k, v in listed.items() if (directory / k).is_file()}
        write_manifest(directory, {**kept, **new})


def write_output_text(
    path: str | os.PathLike[str], text: str, *, force: bool = False, argument: str = "out"
) -> Path:
    """Check, write ``text`` (UTF-8) atomically and record it; the path."""
    return write_output_bytes(path, text.encode("utf-8"), force=force, argument=argument)


def write_output_bytes(
    path: str | os.PathLike[str], data: bytes, *, force: bool = False, argument: str = "out"
) -> Path:
    """Check, write ``data`` atomically and record it; the path."""
    p = check_replaceable(path, force=force, argument=argument)
    with atomic_write(p, "wb") as fh:
        fh.write(data)
    record_written([p], {p: _digest_bytes(data)})
    return p


def save_output(
    path: str | os.PathLike[str],
    save: Callable[[str], None],
    *,
    force: bool = False,
    argument: str = "out",
) -> Path:
    """Check, call ``save(tmp_path)`` (e.g. ``fig.savefig``), rename it over ``path``, record it."""
    p = check_replaceable(path, force=force, argument=argument)
    atomic_save(p, save)
    record_written([p])
    return p
