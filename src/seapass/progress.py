"""Progress of long jobs: one small protocol, silent by default.

Every long job of seapass (tuning, design sweeps, sampled bounds and Z-width maps,
``analyze`` and ``reproduce``, the rig's kd sweep, the export's certification) takes
``progress=``: an object with three methods, after diffrax's progress meters [1]_.

``start(task, total)``
    A task begins; ``total`` is its number of steps (None: unknown).  Tasks nest: a
    task started while another is open is a part of it (a stage of a report, a row of
    a map).
``advance(n=1, *, note="")``
    ``n`` more steps of the innermost open task are done; ``note`` says where it is
    (the best cost so far, the share of a range decided).
``close()``
    The innermost open task ends (also when it is interrupted: jobs close their tasks
    in ``finally``).

`NoProgress` (the default everywhere) is silent.  `TextProgress` writes one line
per task to a stream, for logs and pipes.  The command line chooses the
implementation (a live bar on a terminal, `TextProgress` on stderr otherwise,
nothing with ``--no-progress``); the library never asks whether a terminal is
attached.  A ``KeyboardInterrupt`` raised by ``advance`` (or anywhere in a job)
stops the job cleanly: its tasks are closed, nothing half-written is left, and the
library stays usable.

The old spellings (``progress=True``/``False``, a callable) are accepted for one
release by `as_progress`, with a
[`SeapassDeprecationWarning`][seapass.errors.SeapassDeprecationWarning].

This module imports only `seapass.errors`: it sits at the bottom layer so that
every subpackage can take a progress.

References
----------
.. [1] P. Kidger, diffrax: ``AbstractProgressMeter``, ``TextProgressMeter``,
   ``NoProgressMeter`` (https://docs.kidger.site/diffrax/api/progress_meter/).

Examples
--------
>>> import io
>>> out = io.StringIO()
>>> p = TextProgress(out)
>>> with task(p, "tuning LP", total=3):
...     for _ in range(3):
...         p.advance(note="best 0.5")
>>> print(out.getvalue(), end="")
tuning LP
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, Protocol, TextIO, runtime_checkable

from .errors import ParameterError, SeapassDeprecationWarning

__all__ = [
    "NoProgress",
    "Progress",
    "ProgressLike",
    "TextProgress",
    "as_progress",
    "task",
]


@runtime_checkable
class Progress(Protocol):
    """What a long job reports to: ``start``, ``advance`` and ``close`` (see the module)."""

    def start(self, task: str, total: int | None = None) -> None:
        """A task (or a part of the open one) begins; ``total`` steps, None if unknown."""

    def advance(self, n: int = 1, *, note: str = "") -> None:
        """``n`` more steps of the innermost open task are done."""

    def close(self) -> None:
        """The innermost open task ends."""


class NoProgress:
    """Silent: the default of every long job."""

    def start(self, task: str, total: int | None = None) -> None:
        pass

    def advance(self, n: int = 1, *, note: str = "") -> None:
        pass

    def close(self) -> None:
        pass

    def __repr__(self) -> str:
        return "NoProgress()"


class TextProgress:
    """One line per task on ``stream`` (default ``sys.stderr``), for logs and pipes.

    A line is written when a task starts, indented by its depth, for tasks less than
    ``depth`` levels deep (default 2: a job and its parts, e.g. ``analyze`` and its
    stages); ``advance`` and ``close`` write nothing.
    """

    def __init__(self, stream: TextIO | None = None, *, depth: int = 2) -> None:
        if isinstance(depth, bool) or not isinstance(depth, int) or depth < 1:
            raise ParameterError(f"depth must be a whole number >= 1, got {depth!r}")
        self.stream = stream
        self.depth = depth
        self.open = 0

    def start(self, task: str, total: int | None = None) -> None:
        if self.open < self.depth:
            out = sys.stderr if self.stream is None else self.stream
            out.write("  " * self.open + " ".join(str(task).split()) + "\n")
            out.flush()
        self.open += 1

    def advance(self, n: int = 1, *, note: str = "") -> None:
        pass

    def close(self) -> None:
        self.open = max(self.open - 1, 0)

    def __repr__(self) -> str:
        return f"TextProgress(depth={self.depth})"


class _Calls:
    """An old callback as a progress: called after every step of the outermost task."""

    def __init__(self, call: Callable[[int, int | None, str], None]) -> None:
        self.call, self.open, self.done = call, 0, 0
        self.total: int | None = None

    def start(self, task: str, total: int | None = None) -> None:
        if self.open == 0:
            self.done, self.total = 0, total
        self.open += 1

    def advance(self, n: int = 1, *, note: str = "") -> None:
        if self.open == 1:
            self.done += n
            self.call(self.done, self.total, note)

    def close(self) -> None:
        self.open = max(self.open - 1, 0)


#: What ``progress=`` accepts: a `Progress`, or None for none.
ProgressLike = Progress | None


def as_progress(
    progress: Any,
    *,
    where: str,
    call: Callable[[Callable[..., Any]], Callable[[int, int | None, str], None]] | None = None,
) -> Progress:
    """The `Progress` of a ``progress=`` argument of the function ``where``.

    None is `NoProgress`.  The old spellings work for one release with a
    `SeapassDeprecationWarning`: ``False`` is `NoProgress`, ``True`` is `TextProgress`
    on stderr (the library no longer looks for a terminal), and a callable, when the
    function took one (``call`` adapts it: it receives the callable and returns
    ``f(done, total, note)``), is called after every step.

    Raises
    ------
    ParameterError
        For anything else, naming ``progress``.
    """
    if progress is None:
        return NoProgress()
    if isinstance(progress, bool):
        warnings.warn(
            f"{where}(progress={progress}) is deprecated; pass a seapass.progress.Progress "
            f"({'TextProgress()' if progress else 'or None'}) instead",
            SeapassDeprecationWarning,
            stacklevel=3,
        )
        return TextProgress() if progress else NoProgress()
    if isinstance(progress, Progress):
        return progress
    if callable(progress) and call is not None:
        warnings.warn(
            f"{where}(progress=<callable>) is deprecated; pass a seapass.progress.Progress "
            "whose advance() does what the callable did",
            SeapassDeprecationWarning,
            stacklevel=3,
        )
        return _Calls(call(progress))
    raise ParameterError(
        f"progress must be a seapass.progress.Progress (start, advance, close) or None, "
        f"got {type(progress).__name__}",
        argument="progress",
    )


@contextmanager
def task(progress: Progress, name: str, total: int | None = None) -> Iterator[Progress]:
    """``progress.start(name, total)``, then ``progress.close()`` however the block ends."""
    progress.start(name, total)
    try:
        yield progress
    finally:
        progress.close()
