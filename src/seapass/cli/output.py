"""Output conventions of the command line: JSON on stdout, files announced on stderr.

* ``--json``: strict JSON only on stdout (`add_json_option`, `print_json`);
  text is the default.
* One figure: ``--plot FILE`` (`add_plot_option`, `plot_path`); the suffix
  ``.png``/``.svg``/``.pdf`` picks the format, none means ``.png``.
* Several files: ``--out DIR`` (`add_out_dir_option`, `check_out_dir`).
* Every file written is announced by one line ``wrote PATH`` on stderr
  (`save_plot`, `write_text`, `write_bytes`), atomically written.
* Output paths are checked before any work starts (read-only directories,
  dangling links, a file where a directory is needed).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from ..errors import ParameterError
from ..files.atomic import atomic_save, atomic_write, atomic_write_text, check_writable
from ..files.jsontext import json_text

__all__ = [
    "add_json_option",
    "add_out_dir_option",
    "add_plot_option",
    "announce",
    "atomic_save",
    "atomic_write",
    "atomic_write_text",
    "check_out_dir",
    "json_text",
    "plot_path",
    "print_json",
    "save_plot",
    "write_bytes",
    "write_text",
]


def add_json_option(p: argparse.ArgumentParser, what: str = "the result") -> None:
    """``--json``: print ``what`` as strict JSON on stdout instead of text."""
    p.add_argument("--json", action="store_true", help=f"print {what} as JSON (stdout: JSON only)")


def add_plot_option(p: argparse.ArgumentParser, what: str = "the figure") -> None:
    """``--plot FILE``: write one figure (PNG, SVG or PDF by suffix)."""
    p.add_argument(
        "--plot", metavar="FILE", help=f"write {what} to FILE (.png, .svg or .pdf; none: .png)"
    )


def add_out_dir_option(
    p: argparse.ArgumentParser, what: str = "figures and data", *, required: bool = False
) -> None:
    """``--out DIR``: write several files into a directory."""
    p.add_argument("--out", metavar="DIR", required=required, help=f"write {what} into DIR")


def plot_path(text: str | None, flag: str = "--plot") -> Path | None:
    """The figure path of ``--plot`` (``.png`` added when there is no suffix), checked now.

    Raises `ParameterError` for an unknown format and
    [`OutputPathError`][seapass.errors.OutputPathError] when the file cannot be
    created, before any work starts.
    """
    if text is None:
        return None
    from ..plot.style import FIGURE_FORMATS

    p = Path(text)
    if not p.suffix:
        p = p.with_name(p.name + ".png")
    if p.suffix.lower().lstrip(".") not in FIGURE_FORMATS:
        known = ", ".join(f".{f}" for f in FIGURE_FORMATS)
        raise ParameterError(f"{flag} {text}: unknown figure format {p.suffix!r}; use {known}")
    check_writable(p, directory=False, argument=flag)
    return p


def check_out_dir(text: str | None, flag: str = "--out") -> Path | None:
    """The directory of ``--out DIR``, checked now (not a file, writable, no dangling link)."""
    if text is None:
        return None
    return check_writable(Path(text), directory=True, argument=flag)


def announce(path: str | os.PathLike[str]) -> None:
    """``wrote PATH`` on stderr."""
    print(f"wrote {path}", file=sys.stderr)


def save_plot(
    draw: Callable[[], Any], path: str | os.PathLike[str], *, formats: Sequence[str] | None = None
) -> list[Path]:
    """Draw a figure in the seapass style on a bare figure, save it atomically, announce it.

    ``draw()`` calls a [`seapass.plot`][seapass.plot] function without Axes and returns
    its Axes.  ``path`` with a suffix writes that format; without one, every
    format in ``formats`` (default PNG, SVG and PDF).
    """
    from ..plot.style import bare_figures, figure_style, save_figure

    with figure_style(), bare_figures():
        axes = draw()
        paths = save_figure(axes, path, formats=formats)
    for p in paths:
        announce(p)
    return paths


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) atomically and announce it."""
    atomic_write_text(path, text)
    announce(path)
    return Path(path)


def write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` atomically and announce it."""
    with atomic_write(path, "wb") as fh:
        fh.write(data)
    announce(path)
    return Path(path)


def print_json(obj: Any) -> None:
    """Print strict JSON on stdout ([`json_text`][seapass.files.jsontext.json_text])."""
    sys.stdout.write(json_text(obj))
