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
* A file seapass did not write (or that was changed since) is never replaced
  unless the user passes ``--force`` (`add_force_option`); the rule and the
  record of what seapass wrote are [`seapass.files.owned`][seapass.files.owned].
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
from ..files.owned import check_replaceable, write_output_bytes, write_output_text

__all__ = [
    "add_force_option",
    "add_json_option",
    "add_out_dir_option",
    "add_plot_option",
    "announce",
    "atomic_save",
    "atomic_write",
    "atomic_write_text",
    "check_out_dir",
    "check_out_file",
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


def add_force_option(p: argparse.ArgumentParser) -> None:
    """``--force``: replace output files that seapass did not write (or that were changed)."""
    p.add_argument(
        "--force",
        action="store_true",
        help="replace existing output files even if seapass did not write them",
    )


def add_out_dir_option(
    p: argparse.ArgumentParser, what: str = "figures and data", *, required: bool = False
) -> None:
    """``--out DIR``: write several files into a directory."""
    p.add_argument("--out", metavar="DIR", required=required, help=f"write {what} into DIR")


def plot_path(text: str | None, flag: str = "--plot", *, force: bool = False) -> Path | None:
    """The figure path of ``--plot`` (``.png`` added when there is no suffix), checked now.

    Raises `ParameterError` for an unknown format and
    [`OutputPathError`][seapass.errors.OutputPathError] when the file cannot be
    created or is a file seapass did not write (unless ``force``), before any
    work starts.
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
    return check_replaceable(p, force=force, argument=flag)


def check_out_file(text: str | None, flag: str, *, force: bool = False) -> Path | None:
    """The path of a one-file output option (``--rig-out FILE``), checked now: writable, and
    new or seapass's (unless ``force``)."""
    if text is None:
        return None
    p = check_writable(Path(text), directory=False, argument=flag)
    return check_replaceable(p, force=force, argument=flag)


def check_out_dir(
    text: str | None, flag: str = "--out", *, files: Sequence[str] = (), force: bool = False
) -> Path | None:
    """The directory of ``--out DIR``, checked now (not a file, writable, no dangling link).

    ``files`` are the names the command will write there: each must be new or
    seapass's (unless ``force``), so a refusal comes before the work.
    """
    if text is None:
        return None
    d = check_writable(Path(text), directory=True, argument=flag)
    for name in files:
        check_replaceable(d / name, force=force, argument=flag)
    return d


def announce(path: str | os.PathLike[str]) -> None:
    """``wrote PATH`` on stderr."""
    print(f"wrote {path}", file=sys.stderr)


def save_plot(
    draw: Callable[[], Any],
    path: str | os.PathLike[str],
    *,
    formats: Sequence[str] | None = None,
    force: bool = False,
    flag: str = "--out",
) -> list[Path]:
    """Draw a figure in the seapass style on a bare figure, save it atomically, announce it.

    ``draw()`` calls a [`seapass.plot`][seapass.plot] function without Axes and returns
    its Axes.  ``path`` with a suffix writes that format; without one, every
    format in ``formats`` (default PNG, SVG and PDF).  A file seapass did not
    write is not replaced unless ``force`` (checked before drawing; ``flag``
    names the option in the message).
    """
    from ..plot.style import bare_figures, figure_paths, figure_style, save_figure

    for target in figure_paths(path, formats):
        check_replaceable(target, force=force, argument=flag)
    with figure_style(), bare_figures():
        axes = draw()
        paths = save_figure(axes, path, formats=formats, force=force)
    for p in paths:
        announce(p)
    return paths


def write_text(
    path: str | os.PathLike[str], text: str, *, force: bool = False, flag: str = "--out"
) -> Path:
    """Write ``text`` (UTF-8) atomically and announce it (never over a file seapass did not
    write, unless ``force``)."""
    write_output_text(path, text, force=force, argument=flag)
    announce(path)
    return Path(path)


def write_bytes(
    path: str | os.PathLike[str], data: bytes, *, force: bool = False, flag: str = "--out"
) -> Path:
    """Write ``data`` atomically and announce it (never over a file seapass did not write,
    unless ``force``)."""
    write_output_bytes(path, data, force=force, argument=flag)
    announce(path)
    return Path(path)


def print_json(obj: Any) -> None:
    """Print strict JSON on stdout ([`json_text`][seapass.files.jsontext.json_text])."""
    sys.stdout.write(json_text(obj))
