"""The command line's progress: a live bar on a terminal, one line per task otherwise.

The library's long jobs report to a [`Progress`][seapass.progress.Progress]; the command
line alone decides which one (`choose_progress`): `RichBar` when stderr is a terminal,
[`TextProgress`][seapass.progress.TextProgress] on stderr when it is not (a log, a pipe,
CI), [`NoProgress`][seapass.progress.NoProgress] with ``--no-progress``.  Use it as a
context manager: the bar is taken down however the command ends (Ctrl-C included).
"""

from __future__ import annotations

import sys
from typing import Any

from ..progress import NoProgress, Progress, TextProgress

__all__ = ["RichBar", "choose_progress"]


class RichBar:
    """A rich live display on stderr: one row per open task (bar, count, elapsed time).

    The display starts with the first task and stops when the last one closes (or when
    the ``with`` block ends), so the command's own output is never torn.
    """

    def __init__(self) -> None:
        self._bar: Any = None
        self._tasks: list[tuple[Any, str]] = []

    def _live(self) -> Any:
        if self._bar is None:
            from rich.console import Console
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
            )

            self._bar = Progress(
                TextColumn("{task.description}"),
                BarColumn(),
                MofNCompleteColumn(),
                TimeElapsedColumn(),
                console=Console(file=sys.stderr),
                transient=True,
            )
            self._bar.start()
        return self._bar

    def start(self, task: str, total: int | None = None) -> None:
        bar = self._live()
        label = "  " * len(self._tasks) + " ".join(str(task).split())
        self._tasks.append((bar.add_task(label, total=total), label))

    def advance(self, n: int = 1, *, note: str = "") -> None:
        if not self._tasks:
            return
        tid, label = self._tasks[-1]
        self._bar.update(tid, advance=n, description=f"{label}: {note}" if note else label)

    def close(self) -> None:
        if self._tasks:
            tid, _label = self._tasks.pop()
            self._bar.remove_task(tid)
        if not self._tasks:
            self.stop()

    def stop(self) -> None:
        """Take the display down (idempotent)."""
        if self._bar is not None:
            self._bar.stop()
            self._bar = None
        self._tasks.clear()

    def __enter__(self) -> RichBar:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()


class _Quiet(NoProgress):
    def __enter__(self) -> _Quiet:
        return self

    def __exit__(self, *exc: object) -> None:
        pass


class _Lines(TextProgress):
    def __enter__(self) -> _Lines:
        return self

    def __exit__(self, *exc: object) -> None:
        pass


def choose_progress(enabled: bool = True) -> Any:
    """The progress of a command, as a context manager yielding a `Progress`.

    ``enabled`` False (``--no-progress``, or ``--json`` where the command says so):
    none.  Otherwise a live bar when stderr is a terminal, else one line per task on
    stderr.
    """
    chosen: Progress
    if not enabled:
        chosen = _Quiet()
    elif sys.stderr.isatty():
        chosen = RichBar()
    else:
        chosen = _Lines()
    return chosen
