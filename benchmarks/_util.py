"""Timing helpers shared by the benchmark modules."""

from __future__ import annotations

import math
import time
import tracemalloc
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


@dataclass
class Timing:
    """Best CPU time of ``repeat`` runs (this process), and the result of the last run.

    CPU time rather than wall-clock time, so that other jobs on a shared
    machine do not distort the figures; ``run.py`` pins BLAS to one thread, so
    this is single-core time.
    """

    seconds: float
    result: Any
    peak_bytes: int | None = None


def timed(fn: Callable[[], Any], *, repeat: int = 1, memory: bool = False) -> Timing:
    best = float("inf")
    result = None
    for _ in range(repeat):
        t0 = time.process_time()
        result = fn()
        best = min(best, time.process_time() - t0)
    peak = None
    if memory:
        tracemalloc.start()
        fn()
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return Timing(best, result, peak)


@dataclass
class Row:
    """One line of the results table."""

    task: str
    ours: str
    ours_rate: float
    peer: str
    peer_rate: float
    note: str = ""

    @property
    def ratio(self) -> float:
        return self.ours_rate / self.peer_rate if self.peer_rate > 0 else float("nan")


def rate(n: int, seconds: float) -> float:
    return n / seconds if seconds > 0 else float("inf")


def fmt_rate(r: float) -> str:
    if math.isnan(r):  # a peer that did not run here (e.g. no previous checkout)
        return "n/a"
    if r >= 1e6:
        return f"{r / 1e6:.2f} M/s"
    if r >= 1e3:
        return f"{r / 1e3:.1f} k/s"
    return f"{r:.3g} /s"
