"""Writing a report directory: ``report.html``, ``report.md``, ``data/`` and ``figures/``.

`write_report` writes the whole directory into a temporary sibling
directory and swaps it in only when complete: an interrupted run leaves the
previous directory untouched.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from ..files.atomic import atomic_write, atomic_write_text, sibling_dir
from .document import Report
from .render import render_html, render_markdown

__all__ = ["MARKER", "check_output_dir", "write_report"]


MARKER = ".seapass-report"
"""File that marks a directory as written by seapass (safe to replace)."""


def check_output_dir(out: str | os.PathLike[str]) -> None:
    """Raise unless ``out`` is new, empty or a previous seapass output (call before long work)."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise NotADirectoryError(f"--out {str(out)!r} exists and is not a directory")
    if out.is_dir() and any(out.iterdir()) and not (out / MARKER).exists():
        raise FileExistsError(
            f"--out {str(out)!r} is a non-empty directory that seapass did not write; "
            "choose a new or empty directory (seapass replaces its own output directories only)"
        )


def write_report(report: Report, out: str | os.PathLike[str]) -> list[Path]:
    """Write ``report.html``, ``report.md``, ``data/`` and ``figures/`` into ``out``.

    Everything is written into a temporary sibling directory first; only when
    it is complete does it replace ``out`` (which must be new, empty, or a
    previous seapass output).  Returns the written paths, relative to ``out``.
    """
    target = Path(out)
    check_output_dir(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    files: dict[str, str | bytes] = {
        "report.html": render_html(report),
        "report.md": render_markdown(report),
        **report.files(),
        MARKER: "written by seapass; this directory is replaced as a whole on the next run\n",
    }
    tmp = sibling_dir(target)
    old: Path | None = None
    try:
        for rel, content in sorted(files.items()):
            path = tmp / rel
            if isinstance(content, bytes):
                with atomic_write(path, "wb") as fh:
                    fh.write(content)
            else:
                atomic_write_text(path, content)
        if target.exists():
            old = sibling_dir(target, suffix=".old")
            os.replace(target, old / "previous")
        os.replace(tmp, target)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None and not target.exists() and (old / "previous").exists():
            os.replace(old / "previous", target)
        raise
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    return [Path(rel) for rel in sorted(files)]
