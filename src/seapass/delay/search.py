"""Branch and bound on the first failing delay ``g(ω)``: where its minimum lies (a search in
floating point, for candidates only) and a proof that ``g ≥ T`` on a set of frequencies.

The proof uses only enclosures from [`FirstDelay`][seapass.delay.firstdelay.FirstDelay]:
a piece is discarded when its enclosure lies at or above ``T`` (or it is outside the
dangerous band), bisected otherwise; a proven ``g(c) < T`` at a point is returned as a
counterexample; beyond the budget the answer is ``"budget"`` (undecided).
"""

from __future__ import annotations

import math
from enum import StrEnum

from flint import fmpq

from ..exact import poly as ep
from .balls import PRECISIONS, arb_of, precision
from .firstdelay import FirstDelay

__all__ = ["prove_at_least", "search_minimum"]


class SearchStatus(StrEnum):
    """How a search for ``g(ω) >= bound`` ended."""

    OK = "ok"
    """Proven on every segment."""
    COUNTER = "counter"
    """A rational ``ω`` with ``g(ω) < bound`` proven."""
    BUDGET = "budget"
    """The budget ran out first."""


def _value(g: FirstDelay, w: float) -> float:
    with precision(64):
        q = ep.rational(w)
        if g.safe(arb_of(q)):
            return math.inf
        v = g.at(q)
        return float(v.mid()) if v.is_finite() else math.inf


def search_minimum(
    g: FirstDelay, segments: list[tuple[fmpq, fmpq]], points: int = 160
) -> list[fmpq]:
    """Candidate minimisers of ``g`` (one per segment, refined by golden section); floats
    only choose where to look, the caller certifies."""
    out: list[fmpq] = []
    for lo, hi in segments:
        a, b = float(lo), float(hi)
        if not (math.isfinite(b) and b > 0):
            continue
        a = max(a, b * 1e-6)
        grid = [a * (b / a) ** (i / (points - 1)) for i in range(points)]
        vals = [_value(g, w) for w in grid]
        i = min(range(points), key=vals.__getitem__)
        if not math.isfinite(vals[i]) or (i == 0 and lo == 0):
            continue  # g falls towards ω → 0: that limit is the exact low-frequency root
        left, right = grid[max(i - 1, 0)], grid[min(i + 1, points - 1)]
        phi = (math.sqrt(5) - 1) / 2
        x1, x2 = right - phi * (right - left), left + phi * (right - left)
        f1, f2 = _value(g, x1), _value(g, x2)
        for _ in range(60):
            if f1 <= f2:
                right, x2, f2 = x2, x1, f1
                x1 = right - phi * (right - left)
                f1 = _value(g, x1)
            else:
                left, x1, f1 = x1, x2, f2
                x2 = left + phi * (right - left)
                f2 = _value(g, x2)
        best = min((vals[i], grid[i]), (f1, x1), (f2, x2))
        out.append(ep.rational(best[1]))
    return out


def prove_at_least(
    g: FirstDelay,
    segments: list[tuple[fmpq, fmpq]],
    bound: fmpq,
    *,
    budget: int,
) -> tuple[SearchStatus, fmpq | None, int]:
    """Prove ``g(ω) ≥ bound`` for every ``ω`` in the segments.

    Returns ``("ok", None, n)``, ``("counter", ω, n)`` with ``g(ω) < bound`` proven, or
    ``("budget", None, n)``; ``n`` is the number of pieces evaluated.
    """
    todo: list[tuple[fmpq, fmpq]] = []
    for lo, hi in segments:
        if lo <= 0:
            raise ValueError("segments must start above 0")
        cur = lo
        while cur < hi:  # pieces with hi/lo <= 1.25 to start
            nxt = min(hi, cur * fmpq(5, 4))
            todo.append((cur, nxt))
            cur = nxt
    todo.reverse()
    count = 0
    for level, bits in enumerate(PRECISIONS[:3]):
        harder: list[tuple[fmpq, fmpq]] = []
        with precision(bits):
            while todo:
                a, b = todo.pop()
                count += 1
                if count > budget:
                    return SearchStatus.BUDGET, None, count
                enc = g.gap_bound(a, b, bound)
                if enc is None or enc >= 0:
                    continue
                c = (a + b) / 2
                if g.gap(c, bound) < 0 and not g.safe(arb_of(c)):
                    return SearchStatus.COUNTER, c, count
                if b - a <= c / fmpq(2) ** (bits - 30):
                    harder.append((a, b))
                    continue
                todo.append((c, b))
                todo.append((a, c))
        if not harder:
            return SearchStatus.OK, None, count
        if level == 2:
            return SearchStatus.BUDGET, None, count
        todo = list(reversed(harder))
    return SearchStatus.BUDGET, None, count
