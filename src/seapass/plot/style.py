"""The one figure style, new figures without global state, and byte-stable saving.

Plot functions in [`seapass.plot`][seapass.plot] take ``ax=None`` (or ``axes=None``) and
return the Axes they drew on.  Given no Axes they create a figure with pyplot,
as a notebook user expects; inside `bare_figures` (the report and the
CLI) they create a bare `matplotlib.figure.Figure` instead, which needs
no backend and is never registered with pyplot.  Nothing here changes
``rcParams`` or the backend: the style applies only inside `figure_style`.
"""

from __future__ import annotations

import io
import os
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path
from typing import Any, cast

import numpy as np

from ..files.owned import check_replaceable, write_output_bytes

__all__ = [
    "FIGURE_FORMATS",
    "STYLE",
    "axes_grid",
    "bare_figures",
    "figure_bytes",
    "figure_of",
    "figure_paths",
    "figure_renders",
    "figure_style",
    "save_figure",
]

STYLE: dict[str, Any] = {
    "font.size": 11,
    "axes.titlesize": 12,
    "axes.labelsize": 11,
    "legend.fontsize": 9,
    "svg.hashsalt": "seapass",
    "svg.fonttype": "path",
    "figure.dpi": 100,
}
"""rcParams of every seapass figure (applied with `figure_style`, never globally)."""

FIGURE_FORMATS: tuple[str, ...] = ("png", "svg", "pdf")
"""Every figure format seapass writes; `save_figure` writes all of them when the path has
no suffix, and the command line's ``--plot FILE`` accepts these suffixes."""


_BARE: ContextVar[bool] = ContextVar("seapass_bare_figures", default=False)


@contextmanager
def bare_figures() -> Iterator[None]:
    """Context in which plot functions given no Axes draw on bare figures, not pyplot's.

    Used by the report and the CLI: the figures they render need no backend,
    are never shown, and leave pyplot's figure list untouched.
    """
    token = _BARE.set(True)
    try:
        yield
    finally:
        _BARE.reset(token)


@contextmanager
def figure_style() -> Iterator[None]:
    """Context in which figures are drawn with `STYLE` (restores rcParams after)."""
    import matplotlib

    with matplotlib.rc_context(cast(Any, STYLE)):
        yield


def axes_grid(
    axes: Any, nrows: int, ncols: int, *, figsize: tuple[float, float], **kw: Any
) -> np.ndarray:
    """The ``nrows × ncols`` Axes to draw on, as a 2-D object array.

    ``axes`` if given; else a new figure's: a bare one inside
    `bare_figures`, otherwise pyplot's (so a notebook shows it).

    Raises
    ------
    ValueError
        If ``axes`` does not hold ``nrows × ncols`` Axes.
    """
    if axes is None:
        if _BARE.get():
            from matplotlib.figure import Figure

            fig = Figure(figsize=figsize, layout="constrained")
            axes = fig.subplots(nrows, ncols, squeeze=False, **kw)
        else:
            import matplotlib.pyplot as plt

            _fig, axes = plt.subplots(
                nrows, ncols, figsize=figsize, layout="constrained", squeeze=False, **kw
            )
    grid = np.asarray(axes, dtype=object)
    if grid.size != nrows * ncols:
        raise ValueError(f"axes: expected {nrows}×{ncols} Axes, got {grid.size}")
    return grid.reshape(nrows, ncols)


def figure_of(axes: Any) -> Any:
    """The figure that ``axes`` (one Axes or an array of them) belongs to."""
    return np.asarray(axes, dtype=object).flat[0].figure


def figure_bytes(fig: Any, fmt: str = "png", *, dpi: int = 110) -> bytes:
    """Render ``fig`` to byte-stable ``fmt`` bytes (no date or software metadata); close it.

    ``fig`` is a figure, or Axes (one or an array) of the figure to render.
    """
    if not hasattr(fig, "savefig"):
        fig = figure_of(fig)
    try:
        return _render(fig, fmt, dpi)
    finally:
        _close(fig)


def figure_renders(fig: Any, formats: Sequence[str], *, dpi: int = 110) -> dict[str, bytes]:
    """Render ``fig`` once per format (byte-stable, as `figure_bytes`); close it.

    Returns ``{format: bytes}``; ``fig`` is a figure or Axes of it.
    """
    if not hasattr(fig, "savefig"):
        fig = figure_of(fig)
    try:
        out = {}
        for i, f in enumerate(formats):
            out[f] = _render(fig, f, dpi)
            if i == 0:
                # the layout is done: keep it for the other formats instead of redoing it
                fig.set_layout_engine("none")
        return out
    finally:
        _close(fig)


def figure_paths(path: str | os.PathLike[str], formats: Sequence[str] | None = None) -> list[Path]:
    """The files `save_figure` writes for ``path`` and ``formats``.

    >>> [p.name for p in figure_paths("fig", ("png", "pdf"))], figure_paths("a.svg")
    (['fig.png', 'fig.pdf'], [PosixPath('a.svg')])
    """
    p = Path(path)
    if p.suffix and formats is None:
        return [p]
    return [p.with_name(f"{p.name}.{f}") for f in (formats or FIGURE_FORMATS)]


def save_figure(
    fig: Any,
    path: str | os.PathLike[str],
    *,
    formats: Sequence[str] | None = None,
    dpi: int = 150,
    force: bool = False,
) -> list[Path]:
    """Write ``fig`` atomically; return the paths written.

    ``path`` with a suffix (``fig.png``, ``fig.svg``, ``fig.pdf``) writes that
    format; without one, every format in ``formats`` (default
    `FIGURE_FORMATS`) is written as ``path.<format>``.  An existing file that
    seapass did not write is not replaced unless ``force``
    ([`seapass.files.owned`][seapass.files.owned]); every target is checked
    before the first is written.

    Raises
    ------
    OutputPathError
        When a target exists and seapass did not write it (and not ``force``).
    """
    if not hasattr(fig, "savefig"):
        fig = figure_of(fig)
    targets = figure_paths(path, formats)
    try:
        for t in targets:
            check_replaceable(t, force=force, argument="path")
        for t in targets:
            data = _render(fig, t.suffix.lstrip(".").lower(), dpi)
            write_output_bytes(t, data, force=force, argument="path")
    finally:
        _close(fig)
    return targets


def _render(fig: Any, fmt: str, dpi: int) -> bytes:
    if fmt not in FIGURE_FORMATS:
        raise ValueError(f"unsupported figure format {fmt!r}; use {', '.join(FIGURE_FORMATS)}")
    buf = io.BytesIO()
    meta: dict[str, Any] = {"Software": None}
    if fmt == "svg":
        meta = {"Date": None}
    elif fmt == "pdf":
        meta = {"CreationDate": None, "Producer": None, "Creator": None}
    fig.savefig(buf, format=fmt, dpi=dpi, metadata=meta)
    return buf.getvalue()


def _close(fig: Any) -> None:
    """Release a pyplot-managed figure (a bare figure needs nothing)."""
    import sys

    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close(fig)
