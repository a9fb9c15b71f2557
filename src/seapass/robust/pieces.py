"""Unions of closed intervals with exact rational ends, and their doubles rounded in or out.

The set algebra of the robust passive sets
([`sampled_intervals`][seapass.robust.sampled_intervals]): `merge`, `intersect`, `minus`
on lists of closed ``(lo, hi)`` pieces of `fractions.Fraction`; `widen` (one double
outward, for sets read back from rounded ends); `as_floats` (ends rounded inward for an
inner set, outward for an outer set); `text`.

>>> from fractions import Fraction as F
>>> minus([(F(0), F(4))], [(F(1), F(2))])
[(Fraction(0, 1), Fraction(1, 1)), (Fraction(2, 1), Fraction(4, 1))]
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from fractions import Fraction

from ..exact.rounding import enclosure_text, interval_text

__all__ = [
    "Pieces",
    "as_floats",
    "bisect_inner",
    "down",
    "intersect",
    "merge",
    "minus",
    "robust_gain_set",
    "text",
    "up",
    "widen",
]

Pieces = list[tuple[Fraction, Fraction]]
"""Closed intervals ``[lo, hi]`` with exact ends."""


def text(ivs: tuple[tuple[float, float], ...], *, outer: bool = False) -> str:
    """``[a, b], [c, d]`` (6 significant digits) or ``none``: a certified (inner) set with
    its ends rounded inward, so that every printed end is itself in the set; an ``outer``
    set with its ends rounded outward, so that the printed set still encloses it."""
    if outer:
        return ", ".join(enclosure_text(a, b, digits=6) for a, b in ivs) or "none"
    return ", ".join(interval_text(a, b) for a, b in ivs) or "none"


def down(x: Fraction) -> float:
    """The largest double ``<= x``."""
    f = float(x)
    return f if Fraction(f) <= x else math.nextafter(f, -math.inf)


def up(x: Fraction) -> float:
    """The smallest double ``>= x``."""
    f = float(x)
    return f if Fraction(f) >= x else math.nextafter(f, math.inf)


def merge(pieces: Pieces) -> Pieces:
    """Union of closed intervals, as disjoint sorted closed intervals."""
    out: Pieces = []
    for a, b in sorted(pieces):
        if out and a <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], b))
        else:
            out.append((a, b))
    return out


def intersect(xs: Pieces, ys: Pieces) -> Pieces:
    """Intersection of two unions of closed intervals."""
    return merge([(max(a, c), min(b, d)) for a, b in xs for c, d in ys if max(a, c) <= min(b, d)])


def minus(xs: Pieces, ys: Pieces) -> Pieces:
    """Closure of ``xs`` minus ``ys`` (closed pieces; the shared ends stay in both)."""
    out: Pieces = []
    for a, b in xs:
        cur = a
        for c, d in sorted(ys):
            if d < cur or c > b:
                continue
            if c > cur:
                out.append((cur, c))
            cur = max(cur, d)
        if cur < b or (cur == a == b and not any(c <= a <= d for c, d in ys)):
            out.append((cur, b))
    return out


def widen(pieces: Pieces, lo: Fraction, hi: Fraction) -> Pieces:
    """Each end one double outward, clipped to ``[lo, hi]`` (outer sets from rounded ends)."""
    return merge(
        [
            (max(lo, Fraction(math.nextafter(down(a), -math.inf))),
             min(hi, Fraction(math.nextafter(up(b), math.inf))))
            for a, b in pieces
        ]
    )  # fmt: skip


def as_floats(pieces: Pieces, *, inward: bool) -> tuple[tuple[float, float], ...]:
    if inward:
        return tuple((up(a), down(b)) for a, b in pieces if up(a) <= down(b))
    return tuple((down(a), up(b)) for a, b in pieces)


def bisect_inner(
    outer: Callable[[], Pieces],
    decide: Callable[[Fraction, Fraction], bool],
    *,
    width: Fraction,
    max_segments: int,
) -> tuple[Pieces, int]:
    """The certified inner set of a robust gain set, by bisection of its outer set.

    ``outer()`` is the current outer set (``decide`` may shrink it, e.g. by a verified
    worst plant); ``decide(a, b)`` is True when the whole segment ``[a, b]`` is certified.
    Segments not certified are halved (at a double) down to ``width``; at most
    ``max_segments`` are decided.  Returns the certified segments and how many were decided.

    >>> inner, n = bisect_inner(lambda: [(Fraction(0), Fraction(4))],
    ...                         lambda a, b: b <= 3, width=Fraction(1), max_segments=20)
    >>> merge(inner), n
    ([(Fraction(0, 1), Fraction(3, 1))], 5)
    """
    inner: Pieces = []
    queue = list(outer())
    seen = 0
    while queue and seen < max_segments:
        a, b = queue.pop(0)
        current = outer()
        if not any(c <= a and b <= d for c, d in current):  # the outer set shrank meanwhile
            queue += [(max(a, c), min(b, d)) for c, d in current if max(a, c) < min(b, d)]
            continue
        seen += 1
        if decide(a, b):
            inner.append((a, b))
            continue
        if b - a > width:
            mid = Fraction(float((a + b) / 2))
            if a < mid < b:
                queue += [(a, mid), (mid, b)]
    return inner, seen


Plant = Mapping[str, float]


def robust_gain_set(
    lo: Fraction,
    hi: Fraction,
    *,
    plants: Sequence[Plant],
    exact_set: Callable[[Plant], Sequence[tuple[float, float]]],
    verdict: Callable[[Fraction, Fraction], tuple[bool, Plant | None]],
    width: Fraction,
    max_segments: int,
) -> tuple[Pieces, Pieces, int]:
    """Certified inner and outer sets of a gain over a box of plants: ``(inner, outer, n)``.

    The outer set starts as ``[lo, hi]`` and is cut by the set of the gain at each plant
    of ``plants`` and at every worst plant ``verdict`` returns (``exact_set``: its ends
    rounded to doubles, so each is widened by one double); ``verdict(a, b)`` decides the
    segment ``[a, b]`` times the box (True: certified) and may name a failing plant.  The
    inner set comes from `bisect_inner`; ``n`` segments were decided.
    """
    outer: Pieces = [(lo, hi)]

    def cut(plant: Plant) -> None:
        nonlocal outer
        ivs = [
            (Fraction(math.nextafter(a, -math.inf)), Fraction(math.nextafter(b, math.inf)))
            for a, b in exact_set(plant)
        ]
        outer = intersect(outer, ivs)  # outer stays inside [lo, hi]

    for plant in plants:
        cut(plant)

    def decide(a: Fraction, b: Fraction) -> bool:
        passive, worst = verdict(a, b)
        if worst is not None:
            cut(worst)
        return passive

    inner, seen = bisect_inner(lambda: outer, decide, width=width, max_segments=max_segments)
    return inner, outer, seen
