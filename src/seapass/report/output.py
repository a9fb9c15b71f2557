"""Writing a report directory: ``report.html``, ``report.md``, ``data/`` and ``figures/``.

`write_report` writes the whole directory into a temporary sibling
directory and swaps it in only when complete: an interrupted write leaves the
previous directory untouched.  A report written again as it grows (``analyze``
writes each finished stage at once) reuses the files that did not change: they
are hard-linked from the previous directory, not written again.

Files seapass did not write are never deleted.  The marker file
``.seapass-report`` holds the manifest of what seapass wrote; a file the user
added elsewhere in the directory (``notes.txt``, ``my-plots/``) is carried over
into the new report, and a file the user put where seapass writes its own
(``report.html``, ``report.md``, ``data/``, ``figures/``) stops the run before any
work, naming the file.  A symbolic link given as the directory is kept: the
directory it points to is updated.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

from ..errors import OutputPathError
from ..files.atomic import atomic_write, check_writable, sibling_dir
from ..version import __version__
from .document import Report
from .render import render_html, render_markdown

__all__ = [
    "MARKER",
    "OWNED",
    "check_output_dir",
    "foreign_files",
    "report_paths",
    "write_report",
]


MARKER = ".seapass-report"
"""File that marks a directory as written by seapass, with the manifest of its files."""

OWNED = ("report.html", "report.md", "data", "figures", MARKER)
"""Top-level names seapass writes in a report directory; everything else is the user's."""


def _target(out: Path) -> Path:
    """The directory to update: ``out``, or the directory a symbolic link ``out`` points to."""
    return Path(os.path.realpath(out)) if out.is_symlink() else out


def _manifest(target: Path) -> set[str] | None:
    """Relative paths seapass wrote in ``target``; None for a marker without a manifest."""
    try:
        data = json.loads((target / MARKER).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return None
    files = data.get("files") if isinstance(data, dict) else None
    if not isinstance(files, list) or not all(isinstance(f, str) for f in files):
        return None
    return set(files)


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


def foreign_files(target: str | os.PathLike[str]) -> list[str]:
    """Files (relative paths) in a previous report directory that seapass did not write."""
    target = Path(target)
    if not (target / MARKER).is_file():
        return _entries(target) if target.is_dir() else []
    written = _manifest(target)
    out = []
    for rel in _entries(target):
        top = rel.split("/", 1)[0]
        if rel == MARKER:
            continue
        # an old marker has no manifest: everything in the owned names was seapass's
        ours = rel in written if written is not None else top in OWNED
        if not ours:
            out.append(rel)
    return out


def check_output_dir(out: str | os.PathLike[str]) -> None:
    """Raise unless ``out`` can take a report (call it before long work).

    ``out`` must be new, empty, or a previous seapass report whose added files
    lie outside ``report.html``, ``report.md``, ``data/`` and ``figures/``; its
    parent must be writable.  A symbolic link is followed (its target is updated).

    Raises
    ------
    OutputPathError
        Naming the problem: a file in the way, a dangling link, a read-only
        parent, or a directory seapass did not write.
    """
    out = Path(out)
    check_writable(out, directory=True)
    target = _target(out)
    if target.is_dir() and any(target.iterdir()):
        if not (target / MARKER).is_file():
            raise OutputPathError(
                f"out: {out} is a non-empty directory that seapass did not write; choose a "
                "new or empty directory (seapass updates its own report directories only)",
                argument="out",
            )
        clash = [f for f in foreign_files(target) if f.split("/", 1)[0] in OWNED]
        if clash:
            raise OutputPathError(
                f"out: {target / clash[0]} was not written by seapass but lies where seapass "
                f"writes its report ({', '.join(OWNED[:4])}/); move it elsewhere (files you "
                "add outside those names are kept)",
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
    names = {"report.html", "report.md", MARKER, *report.files()}
    return [Path(rel) for rel in sorted(names)]


def write_report(report: Report, out: str | os.PathLike[str]) -> list[Path]:
    """Write ``report.html``, ``report.md``, ``data/`` and ``figures/`` into ``out``.

    Everything is written into a temporary sibling directory first; only when
    it is complete does it replace the previous directory.  Files the user
    added outside the names seapass owns are carried over; a symbolic link
    ``out`` stays a link to the updated directory.  Returns the written paths,
    relative to ``out``.
    """
    out = Path(out)
    check_output_dir(out)
    target = _target(out)
    target.parent.mkdir(parents=True, exist_ok=True)
    files: dict[str, str | bytes] = {
        "report.html": render_html(report),
        "report.md": render_markdown(report),
        **report.files(),
    }
    manifest = {
        "written_by": "seapass",
        "version": __version__,
        "note": "seapass replaces the files listed here on the next run and keeps all others",
        "files": sorted(files),
    }
    files[MARKER] = json.dumps(manifest, indent=1) + "\n"
    keep = foreign_files(target) if target.is_dir() else []
    tmp = sibling_dir(target)
    old: Path | None = None
    ours = (_manifest(target) or set()) if target.is_dir() else set()
    try:
        for rel, content in sorted(files.items()):
            path = tmp / rel
            data = content if isinstance(content, bytes) else content.encode("utf-8")
            if rel in ours and _link_same(target / rel, path, data):
                continue
            with atomic_write(path, "wb") as fh:
                fh.write(data)
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
