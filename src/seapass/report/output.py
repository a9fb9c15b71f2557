"""Writing a report directory: ``report.html``, ``report.md``, ``data/`` and ``figures/``.

`write_report` writes the whole directory into a temporary sibling
directory and swaps it in only when complete: an interrupted write leaves the
previous directory untouched.  A report written again as it grows (``analyze``
writes each finished stage at once) reuses the files that did not change: they
are hard-linked from the previous directory, not written again.

Files seapass did not write are never deleted.  The directory's manifest
``.seapass-written`` (the one record of what seapass wrote, see
[`seapass.files.owned`][seapass.files.owned]) lists every file of the report with
the digest of its content; a file the user added elsewhere in the directory
(``notes.txt``, ``my-plots/``) is carried over into the new report, and a file
the user put (or changed) where seapass writes its own (``report.html``,
``report.md``, ``data/``, ``figures/``) stops the run before any work, naming
the file, unless ``force``.  A symbolic link given as the directory is kept:
the directory it points to is updated.  Report directories of earlier versions
(a ``.seapass-report`` marker) are recognized.
"""

from __future__ import annotations

import hashlib
import os
import shutil
from pathlib import Path

from ..errors import OutputPathError
from ..files.atomic import atomic_write, check_writable, sibling_dir
from ..files.owned import MANIFEST, file_digest, read_manifest, write_manifest
from .document import Report
from .render import render_html, render_markdown

__all__ = [
    "LEGACY_MARKER",
    "MARKER",
    "OWNED",
    "check_output_dir",
    "foreign_files",
    "report_paths",
    "write_report",
]


MARKER = MANIFEST
"""The manifest of what seapass wrote (`seapass.files.owned.MANIFEST`), at the report's top."""

LEGACY_MARKER = ".seapass-report"
"""The marker of report directories written by earlier versions (a list of names, or none)."""

OWNED = ("report.html", "report.md", "data", "figures", MARKER, LEGACY_MARKER)
"""Top-level names seapass writes in a report directory; everything else is the user's."""


def _target(out: Path) -> Path:
    """The directory to update: ``out``, or the directory a symbolic link ``out`` points to."""
    return Path(os.path.realpath(out)) if out.is_symlink() else out


def _is_report_dir(target: Path) -> bool:
    """A directory seapass wrote a report into (this version's manifest, or an old marker)."""
    return read_manifest(target) is not None or (target / LEGACY_MARKER).is_file()


def _manifest(target: Path) -> dict[str, str | None] | None:
    """``{relative path: digest}`` seapass wrote in ``target``; None: an old marker, no list."""
    listed = read_manifest(target)
    if listed is not None:
        return listed
    return read_manifest(target, LEGACY_MARKER)  # a list of names: digests None


def _entries(target: Path) -> list[str]:
    """Relative paths of every file, link and empty directory below ``target``."""
    out: list[str] = []
    for root, dirs, files in os.walk(target):
        rel = Path(root).relative_to(target)
        for name in files + [d for d in dirs if os.path.islink(os.path.join(root, d))]:
            out.append((rel / name).as_posix())
        if not dirs and not files and root != str(target):
            out.append(rel.as_posix() + "/")
    return sorted(out)


def _ours(target: Path, rel: str, written: dict[str, str | None] | None) -> bool:
    if written is None:  # an old marker without a list: everything in the owned names was
        return rel.split("/", 1)[0] in OWNED
    if rel not in written:
        return False
    want = written[rel]
    path = target / rel
    return want is None or (path.is_file() and not path.is_symlink() and file_digest(path) == want)


def foreign_files(target: str | os.PathLike[str]) -> list[str]:
    """Files (relative paths) in a previous report directory that seapass did not write.

    A file seapass wrote and someone changed since counts as not seapass's.
    """
    target = Path(target)
    if not target.is_dir():
        return []
    if not _is_report_dir(target):
        return _entries(target)
    written = _manifest(target)
    return [
        rel
        for rel in _entries(target)
        if rel not in (MARKER, LEGACY_MARKER) and not _ours(target, rel, written)
    ]


def check_output_dir(out: str | os.PathLike[str], *, force: bool = False) -> None:
    """Raise unless ``out`` can take a report (call it before long work).

    ``out`` must be new, empty, or a previous seapass report whose added files
    lie outside ``report.html``, ``report.md``, ``data/`` and ``figures/``; its
    parent must be writable.  A symbolic link is followed (its target is updated).
    With ``force``, files the user put in those names are replaced too (files
    outside them are still kept).

    Raises
    ------
    OutputPathError
        Naming the problem: a file in the way, a dangling link, a read-only
        parent, or a directory seapass did not write.
    """
    out = Path(out)
    check_writable(out, directory=True)
    target = _target(out)
    if target.is_dir() and any(target.iterdir()) and not force:
        if not _is_report_dir(target):
            raise OutputPathError(
                f"out: {out} is a non-empty directory that seapass did not write; choose a "
                "new or empty directory (seapass updates its own report directories only), "
                "or pass force=True",
                argument="out",
            )
        clash = [f for f in foreign_files(target) if f.split("/", 1)[0] in OWNED]
        if clash:
            raise OutputPathError(
                f"out: {target / clash[0]} was not written by seapass (or was changed since) "
                f"but lies where seapass writes its report ({', '.join(OWNED[:4])}/); move it "
                "elsewhere (files you add outside those names are kept), or pass force=True",
                argument="out",
            )
    check_writable(target.parent, directory=True)  # the new report is built beside it


def _carry_over(old: Path, new: Path, rels: list[str]) -> None:
    """Hard-link (or copy) the user's files from the old directory into the new one."""
    for rel in rels:
        src, dst = old / rel.rstrip("/"), new / rel.rstrip("/")
        if rel.endswith("/"):
            dst.mkdir(parents=True, exist_ok=True)
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        try:
            os.link(src, dst, follow_symlinks=False)
        except OSError:
            if src.is_symlink():
                os.symlink(os.readlink(src), dst)
            else:
                shutil.copy2(src, dst)


def _remove(path: Path) -> None:
    """Remove a directory seapass made; an interrupt in the middle finishes it first."""
    try:
        shutil.rmtree(path, ignore_errors=True)
    except BaseException:  # Ctrl-C or SIGTERM while removing: no leftovers, then go on
        shutil.rmtree(path, ignore_errors=True)
        raise


def _link_same(old: Path, new: Path, data: bytes) -> bool:
    """Hard-link ``old`` (a file seapass wrote) to ``new`` when it holds exactly ``data``."""
    try:
        if old.is_symlink() or not old.is_file() or old.stat().st_size != len(data):
            return False
        if old.read_bytes() != data:
            return False
        new.parent.mkdir(parents=True, exist_ok=True)
        os.link(old, new)
    except OSError:
        return False
    return True


def report_paths(report: Report) -> list[Path]:
    """The paths `write_report` writes for ``report``, relative to the directory, sorted."""
    names = {"report.html", "report.md", *report.files()}
    return [Path(rel) for rel in sorted(names)]


def write_report(report: Report, out: str | os.PathLike[str], *, force: bool = False) -> list[Path]:
    """Write ``report.html``, ``report.md``, ``data/`` and ``figures/`` into ``out``.

    Everything is written into a temporary sibling directory first; only when
    it is complete does it replace the previous directory.  Files the user
    added outside the names seapass owns are carried over (and files seapass
    wrote there by other commands, with their manifest entries); a symbolic
    link ``out`` stays a link to the updated directory.  A file the user put
    in those names stops the run unless ``force`` (see `check_output_dir`).
    Returns the written paths, relative to ``out``.
    """
    out = Path(out)
    check_output_dir(out, force=force)
    target = _target(out)
    target.parent.mkdir(parents=True, exist_ok=True)
    files: dict[str, bytes] = {
        rel: content if isinstance(content, bytes) else content.encode("utf-8")
        for rel, content in {
            "report.html": render_html(report),
            "report.md": render_markdown(report),
            **report.files(),
        }.items()
    }
    digests: dict[str, str | None] = {
        rel: "sha256:" + hashlib.sha256(data).hexdigest() for rel, data in files.items()
    }
    keep: list[str] = []
    also: dict[str, str | None] = {}
    if target.is_dir():
        written = _manifest(target) if _is_report_dir(target) else {}
        for rel in _entries(target):
            if rel.split("/", 1)[0] in OWNED:
                continue
            keep.append(rel)
            if written and rel in written and _ours(target, rel, written):
                also[rel] = written[rel]  # another command's file: still seapass's
    tmp = sibling_dir(target)
    old: Path | None = None
    ours = (_manifest(target) or {}) if target.is_dir() and _is_report_dir(target) else {}
    try:
        for rel, data in sorted(files.items()):
            path = tmp / rel
            if rel in ours and _link_same(target / rel, path, data):
                continue  # unchanged since the last write (analyze writes as stages finish)
            with atomic_write(path, "wb") as fh:
                fh.write(data)
        write_manifest(tmp, {**also, **digests})
        _carry_over(target, tmp, keep)
        if target.exists():
            old = sibling_dir(target, suffix=".old")
            os.replace(target, old / "previous")
        os.replace(tmp, target)
    except BaseException:
        _remove(tmp)
        if old is not None and not target.exists() and (old / "previous").exists():
            os.replace(old / "previous", target)
        raise
    finally:
        if old is not None:
            _remove(old)
    return [Path(rel) for rel in sorted(files)]
