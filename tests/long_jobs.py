"""Shared by the tests of long jobs: a `seapass.progress.Progress` that records every call,
and a design whose certified sampled search is hard."""

from __future__ import annotations

from pathlib import Path
from typing import Any

#: Load-side P on a damped spring at 4 kHz with one sample of delay: the certified bound
#: of kd needs thousands of boxes at its edge (minutes without a budget).
HARD = """name = "hard"

[model]
D1 = "k1 + b1*s"
CL = "kd"

[parameters]
m = 1.0
b = 10.0
k1 = 1000.0
b1 = 30.0
kd = 500.0

[ranges]
kd = [0.0, 5000.0]

[control]
rate = 4000.0
delay = 1
"""


def hard_design(folder: Path) -> Path:
    """`HARD` written as ``folder/hard.toml``."""
    path = folder / "hard.toml"
    path.write_text(HARD, encoding="utf-8")
    return path


class Recorder:
    """Every call, in order; raises KeyboardInterrupt at the ``stop_at``-th advance."""

    def __init__(self, stop_at: int | None = None) -> None:
        self.calls: list[tuple[Any, ...]] = []
        self.stop_at = stop_at
        self.advances = 0

    def start(self, task: str, total: int | None = None) -> None:
        self.calls.append(("start", task, total))

    def advance(self, n: int = 1, *, note: str = "") -> None:
        self.calls.append(("advance", n, note))
        self.advances += 1
        if self.stop_at is not None and self.advances >= self.stop_at:
            raise KeyboardInterrupt

    def close(self) -> None:
        self.calls.append(("close",))

    @property
    def balanced(self) -> bool:
        depth = 0
        for c in self.calls:
            depth += {"start": 1, "close": -1}.get(c[0], 0)
            if depth < 0:
                return False
        return depth == 0
