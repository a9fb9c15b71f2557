"""Exact failing frequency bands of sign conditions on ``x = ω² ≥ 0``, and named conditions.

A frequency condition is a predicate on the signs of a few exact polynomials in
``x`` (for example Llewellyn's "``a ≥ 0`` and ``a² − |q|² ≥ 0``").  The real
roots of all of them cut ``[0, ∞)`` into cells on which every sign is constant
([`half_line_cells`][seapass.exact.halfline.half_line_cells]); the predicate is
decided exactly at one point per cell and at every root.  The failing set is a
union of cells, returned as `Band` objects whose edges are exact (``0``, ``∞`` or
a root held by an isolating interval) and, for display, floats in rad/s rounded
*outward*, so that every frequency outside a printed band is certified to pass.

A root where the predicate holds between two failing cells (the polynomial
touches zero) does not split a band, as in
[`negative_bands`][seapass.exact.axis.negative_bands].
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from flint import fmpq, fmpq_poly

from ..exact import poly as ep
from ..exact.axis import safe_float
from ..exact.halfline import HalfLinePoint
from ..outcome import Outcome

__all__ = [
    "Band",
    "Condition",
    "combine",
    "failing_bands",
    "half_line_points",
    "minimal_point",
    "omega_of",
    "root_point",
]

#: Relative width to which band edges are refined before rounding them (outward) to floats.
EDGE_RTOL = fmpq(1, 2**56)


def _sqrt_down(q: fmpq) -> float:
    """A float ``<= sqrt(q)`` (``q >= 0``)."""
    if q <= 0:
        return 0.0
    v = math.sqrt(safe_float(q))
    return max(0.0, math.nextafter(math.nextafter(v, 0.0), 0.0))


def _sqrt_up(q: fmpq) -> float:
    """A float ``>= sqrt(q)``."""
    if q <= 0:
        return 0.0
    v = math.sqrt(safe_float(q))
    return math.nextafter(math.nextafter(v, math.inf), math.inf)


def omega_of(point: HalfLinePoint) -> float:
    """The frequency ``√x`` of a point ``x`` to double precision (for display)."""
    try:
        return math.sqrt(float(point))
    except OverflowError:
        return math.inf


def minimal_point(point: HalfLinePoint) -> HalfLinePoint:
    """The same root held by the irreducible factor of its polynomial that vanishes there.

    Refining by bisection costs one exact evaluation per step; on the factor alone
    instead of a product of many polynomials it is far cheaper.
    """
    if point.is_rational or point.poly.degree() <= 2:
        return point
    _c, factors = point.poly.factor()
    for f, _e in factors:
        fq = fmpq_poly(f)
        lo, hi = fq(point.lower), fq(point.upper)
        if hi == 0:
            return HalfLinePoint(point.upper, point.upper)
        if lo * hi < 0:
            return HalfLinePoint(point.lower, point.upper, fq)
    return point  # pragma: no cover - one factor changes sign on an isolating interval


def half_line_points(polys: Sequence[fmpq_poly]) -> list[HalfLinePoint]:
    """One exact point per sign cell of ``polys`` on ``[0, ∞)``, as
    [`half_line_cells`][seapass.exact.halfline.half_line_cells] gives them.

    The roots are isolated on each irreducible factor separately and separated
    across factors by bisecting the factors themselves, never their product
    (whose exact evaluation is what makes the bisection slow); each root point
    keeps its own factor, so later sign evaluations there are cheap too.
    """
    factors: dict[str, fmpq_poly] = {}
    for p in polys:
        if p.degree() < 1:
            continue
        _c, fs = p.factor()
        for f, _e in fs:
            fq = ep.monic(fmpq_poly(f))
            factors[str(fq)] = fq
    roots: list[list[Any]] = []  # [lo, hi, factor]
    for f in factors.values():
        if f.degree() == 1:
            root = -f[0] / f[1]
            if root > 0:
                roots.append([root, root, f])
            continue
        for a, b in ep.isolate_real_roots(f, 0):
            if f(b) == 0:
                a = b
            roots.append([a, b, f])
    roots.sort(key=lambda x: x[0])
    steps = 0
    i = 0
    while i < len(roots) - 1:  # separate neighbours held by different factors
        left, right = roots[i], roots[i + 1]
        if left[1] < right[0]:
            i += 1
            continue
        wider = left if left[1] - left[0] >= right[1] - right[0] else right
        if wider[0] == wider[1]:
            raise ArithmeticError("roots of distinct irreducible factors coincide")
        a, b = ep.refine(wider[2], (wider[0], wider[1]), (wider[1] - wider[0]) / 2)
        wider[0], wider[1] = a, b
        steps += 1
        if steps > ep.MAX_BISECTIONS:
            raise ArithmeticError("could not separate the roots within the bisection bound")
        roots.sort(key=lambda x: x[0])
        i = max(i - 1, 0)
    out = [HalfLinePoint(fmpq(0), fmpq(0))]
    prev = fmpq(0)
    for lo, hi, f in roots:
        if lo <= prev and lo != hi:  # room for a sample point after the previous root
            lo, hi = ep.refine_past(f, (lo, hi), prev)
        mid = (prev + lo) / 2
        out.append(HalfLinePoint(mid, mid))
        out.append(HalfLinePoint(lo, lo) if lo == hi else HalfLinePoint(lo, hi, f))
        prev = hi
    out.append(HalfLinePoint(prev + 1, prev + 1))
    return out


def _tight(point: HalfLinePoint) -> HalfLinePoint:
    if point.is_rational:
        return point
    width = max(abs(point.upper), fmpq(1, 2**200)) * EDGE_RTOL
    return minimal_point(point).refined(width)


@dataclass(frozen=True, kw_only=True)
class Band:
    """An open frequency band where a condition fails, with exact edges.

    Attributes
    ----------
    lo, hi : float
        Edges in rad/s, rounded outward (``hi`` may be ``inf``).
    lo_x, hi_x : HalfLinePoint or None
        The exact edges in ``x = ω²``: a rational or a root in an isolating
        interval; ``None`` for ``x = 0`` (``lo_x``) and ``x = ∞`` (``hi_x``).
    """

    lo: float
    hi: float
    lo_x: HalfLinePoint | None = field(default=None, compare=False)
    hi_x: HalfLinePoint | None = field(default=None, compare=False)

    def to_list(self) -> list[float]:
        return [self.lo, self.hi]

    def contains(self, omega: float) -> bool:
        return self.lo <= omega <= self.hi


def _band(lo: HalfLinePoint | None, hi: HalfLinePoint | None) -> Band:
    lo_t = None if lo is None or (lo.is_rational and lo.lower == 0) else _tight(lo)
    hi_t = None if hi is None else _tight(hi)
    lo_f = 0.0 if lo_t is None else _sqrt_down(lo_t.lower)
    hi_f = math.inf if hi_t is None else _sqrt_up(hi_t.upper)
    return Band(lo=lo_f, hi=hi_f, lo_x=lo_t, hi_x=hi_t)


def failing_bands(
    polys: Sequence[fmpq_poly],
    fails: Callable[[tuple[int, ...]], bool],
) -> tuple[Band, ...]:
    """The bands of ``x ≥ 0`` where ``fails(signs of polys)`` is true, decided exactly.

    Parameters
    ----------
    polys : sequence of flint.fmpq_poly
        Exact polynomials in ``x``.
    fails : callable
        Gets the tuple of exact signs (−1, 0, 1) of ``polys`` at a point.

    Examples
    --------
    >>> x = fmpq_poly([0, 1])
    >>> (band,) = failing_bands([x - 4], lambda s: s[0] < 0)   # x < 4: ω < 2
    >>> band.lo, 2 <= band.hi < 2 + 1e-14
    (0.0, True)
    """
    points = half_line_points([p for p in polys if not p.is_zero()])
    flags = [fails(tuple(pt.sign(p) for p in polys)) for pt in points]
    bands: list[Band] = []
    i, n = 0, len(points)
    while i < n:
        if not flags[i]:
            i += 1
            continue
        # a band starts at point i (x = 0 or a root, even index) or in the cell i (odd index)
        start = points[i] if i % 2 == 0 else points[i - 1]
        j = i
        while True:
            if j + 1 < n and flags[j + 1]:
                j += 1
            elif j % 2 == 1 and j + 2 < n and flags[j + 2]:
                j += 2  # a passing root between two failing cells does not split the band
            else:
                break
        if j % 2 == 0:
            end: HalfLinePoint | None = points[j]
        else:
            end = points[j + 1] if j + 1 < n else None
        bands.append(_band(None if start is points[0] else start, end))
        i = j + 1
    return tuple(bands)


@dataclass(frozen=True, kw_only=True)
class Condition:
    """One condition of a criterion, decided exactly, with its failing bands.

    Attributes
    ----------
    name : str
        Short identifier (``"llewellyn"``, ``"minor_12"``, ...).
    outcome : Outcome
        ``PASSIVE``: the condition holds; ``NOT_PASSIVE``: it fails;
        ``UNDECIDED``: it could not be decided.
    bands : tuple of Band
        Where a frequency condition fails (empty for the others).
    description : str
        What the condition says, in words.
    detail : str
        Why it fails, when it does.
    """

    name: str
    outcome: Outcome
    bands: tuple[Band, ...] = ()
    description: str = ""
    detail: str = ""

    @property
    def holds(self) -> bool | None:
        """True, False, or None when undecided."""
        if self.outcome is Outcome.UNDECIDED:
            return None
        return self.outcome is Outcome.PASSIVE

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "holds": self.holds,
            "outcome": self.outcome.value,
            "bands": [b.to_list() for b in self.bands],
            "description": self.description,
            "detail": self.detail,
        }


def combine(outcomes: Sequence[Outcome]) -> Outcome:
    """All hold ⇒ ``PASSIVE``; any fails ⇒ ``NOT_PASSIVE``; else ``UNDECIDED``."""
    if any(o is Outcome.NOT_PASSIVE for o in outcomes):
        return Outcome.NOT_PASSIVE
    if all(o is Outcome.PASSIVE for o in outcomes):
        return Outcome.PASSIVE
    return Outcome.UNDECIDED


def root_point(p: fmpq_poly, iv: ep.Interval) -> HalfLinePoint:
    """The root of ``p`` in ``(a, b]`` as a `HalfLinePoint` (exact rational when ``a == b``)."""
    a, b = iv
    if a == b:
        return HalfLinePoint(a, a)
    sf = ep.squarefree_part(p)
    if sf(b) == 0:
        return HalfLinePoint(b, b)
    return HalfLinePoint(a, b, sf)
