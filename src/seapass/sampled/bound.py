"""The passive range of one parameter under sampled-data control."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..model.sea import SEA
from .controllers import Method
from .passivity import sampled_passivity

__all__ = ["SampledBoundResult", "sampled_passive_bound"]


@dataclass(frozen=True)
class SampledBoundResult:
    """Passive values of one parameter under sampling (`sampled_passive_bound`).

    Attributes
    ----------
    param : str
    period : float
    intervals : list of (float, float)
        Passive sub-intervals of ``[lo, hi]`` (ends refined to ``rtol``).
    max_passive : float or None
        Largest passive value found (``hi`` if passive up to the range end).
    samples : list of (float, bool)
        The scan that located the intervals (each verdict exact).
    """

    param: str
    period: float
    lo: float
    hi: float
    intervals: list[tuple[float, float]]
    max_passive: float | None
    samples: list[tuple[float, bool]]

    def to_dict(self) -> dict[str, Any]:
        return {
            "param": self.param,
            "period": self.period,
            "range": [self.lo, self.hi],
            "intervals": [list(iv) for iv in self.intervals],
            "max_passive": self.max_passive,
        }


def _scan(fn: Any, xs: list[float], progress: bool, label: str) -> list[bool]:
    import sys

    if not (progress and sys.stderr.isatty()):
        return [bool(fn(float(x))) for x in xs]
    from rich.progress import Progress

    out = []
    with Progress(transient=True) as bar:
        task = bar.add_task(label, total=len(xs))
        for x in xs:
            out.append(bool(fn(float(x))))
            bar.advance(task)
    return out


def sampled_passive_bound(
    sea: SEA,
    param: str,
    *,
    period: float,
    lo: float,
    hi: float,
    delay: int = 0,
    velocity_filter: float | None = None,
    method: Method = "tustin",
    values: Mapping[str, float] | None = None,
    samples: int = 17,
    rtol: float = 1e-6,
    progress: bool = False,
) -> SampledBoundResult:
    """Passive values of ``param`` in ``[lo, hi]`` at sampling period ``period``.

    The range is scanned at ``samples`` points (each verdict exact, by
    `sampled_passivity`) and every change of verdict is refined by
    bisection to ``rtol·(hi − lo)``.  Passive islands narrower than the scan
    step can be missed; raise ``samples`` to look closer.  ``progress=True``
    shows a rich progress bar when stderr is a terminal.

    Examples
    --------
    >>> ours = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1005, b1=30, bd=0))
    >>> r = sampled_passive_bound(ours, "kd", period=0.002, lo=0, hi=2e4, samples=5, rtol=1e-3)
    >>> r.max_passive is not None
    True
    """
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ParameterError(f"need a finite range lo < hi, got [{lo}, {hi}]")
    if samples < 2:
        raise ParameterError(f"samples must be at least 2, got {samples}")
    base = sea.with_values(**(values or {}))

    def passive(v: float) -> bool:
        return sampled_passivity(
            base,
            period=period,
            delay=delay,
            velocity_filter=velocity_filter,
            method=method,
            values={param: v},
        ).passive

    xs = list(np.linspace(lo, hi, samples))
    verdicts = _scan(passive, xs, progress, f"sampled bound of {param}")
    width = rtol * (hi - lo)
    edges: list[float] = []
    for i in range(samples - 1):
        if verdicts[i] != verdicts[i + 1]:
            a, b = float(xs[i]), float(xs[i + 1])
            va = verdicts[i]
            while b - a > width:
                mid = (a + b) / 2
                if passive(mid) == va:
                    a = mid
                else:
                    b = mid
            edges.append(a if va else b)
    intervals: list[tuple[float, float]] = []
    start = float(xs[0]) if verdicts[0] else None
    k = 0
    for i in range(samples - 1):
        if verdicts[i] != verdicts[i + 1]:
            e = edges[k]
            k += 1
            if verdicts[i]:
                intervals.append((start if start is not None else e, e))
                start = None
            else:
                start = e
    if start is not None:
        intervals.append((start, float(xs[-1])))
    best = intervals[-1][1] if intervals else None
    return SampledBoundResult(
        param,
        float(period),
        float(lo),
        float(hi),
        intervals,
        best,
        [(float(x), v) for x, v in zip(xs, verdicts, strict=True)],
    )
