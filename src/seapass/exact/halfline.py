"""Exact questions on the half-line ``x ≥ 0``: sign conditions and the minimum of a rational function.

Frequency-domain quantities of an impedance are functions of ``x = ω²`` on
``[0, ∞)``.  Two questions recur:

* *is there an ``x > 0`` where these polynomials have these signs?*  The
  positive real roots of all of them cut ``(0, ∞)`` into cells where every sign
  is constant; `half_line_cells` returns one exact point per root and per open
  cell (`HalfLinePoint`), at which signs are evaluated exactly;
* *what is ``inf_{x ≥ 0} p(x)/q(x)``?*  An algebraic number, attained at
  ``x = 0``, at a root of ``p' q − p q'``, or approached as ``x → ∞`` (or
  ``−∞`` next to a pole).  `minimum_on_half_line` finds which, decides its sign
  exactly, and brackets its value by a certified rational enclosure (interval
  arithmetic on isolating intervals refined by bisection).

Nothing is decided in floating point; floats are returned for display only.

References
----------
.. [1] S. Basu, R. Pollack, M.-F. Roy, *Algorithms in Real Algebraic Geometry*,
   2nd ed., Springer, 2006, ch. 2 (sign determination, cell decompositions).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from flint import fmpq, fmpq_poly

from . import poly as ep

__all__ = [
    "HalfLineMinimum",
    "HalfLinePoint",
    "enclose",
    "half_line_cells",
    "minimum_on_half_line",
]

DEFAULT_RTOL = fmpq(1, 2**60)
"""Relative width of the enclosures `minimum_on_half_line` returns (below double precision)."""


@dataclass(frozen=True)
class HalfLinePoint:
    """A point ``x ≥ 0``: the rational ``lower`` (when ``lower == upper``) or the unique
    root in ``(lower, upper]`` of the square-free polynomial ``poly``."""

    lower: fmpq
    upper: fmpq
    poly: fmpq_poly = field(default_factory=fmpq_poly)

    @property
    def is_rational(self) -> bool:
        return self.lower == self.upper

    def sign(self, q: ep.PolyLike) -> int:
        """Exact sign of ``q`` at the point."""
        if self.is_rational:
            return ep.sign_at(ep.as_poly(q), self.lower)
        return ep.sign_at_root(ep.as_poly(q), self.poly, (self.lower, self.upper))

    def refined(self, width: fmpq) -> HalfLinePoint:
        """The same point with an isolating interval narrower than ``width``."""
        if self.is_rational:
            return self
        a, b = ep.refine(self.poly, (self.lower, self.upper), width)
        return HalfLinePoint(a, b, self.poly)

    def __float__(self) -> float:
        if self.is_rational:
            return float(self.lower)
        return ep.root_value(self.poly, (self.lower, self.upper))


def _square_free_product(polys: Sequence[ep.PolyLike]) -> fmpq_poly:
    prod = fmpq_poly([1])
    for p in polys:
        p = ep.as_poly(p)
        if p.degree() >= 1:
            prod = prod * ep.squarefree_part(p)
    return ep.squarefree_part(prod) if prod.degree() >= 1 else prod


def half_line_cells(polys: Sequence[ep.PolyLike]) -> list[HalfLinePoint]:
    """One exact point per sign cell of ``polys`` on ``[0, ∞)``, in increasing order.

    The points are ``x = 0``, every positive real root of any of ``polys`` and a
    rational point strictly inside every open interval between consecutive
    roots (and beyond the last).  On each open interval every polynomial has a
    constant sign, the sign at its point.

    Examples
    --------
    >>> pts = half_line_cells([fmpq_poly([-1, 0, 1])])   # x**2 - 1
    >>> [(float(p), p.sign(fmpq_poly([-1, 0, 1]))) for p in pts]
    [(0.0, -1), (0.5, -1), (1.0, 0), (2.0, 1)]
    """
    sf = _square_free_product(polys)
    zero = HalfLinePoint(fmpq(0), fmpq(0))
    if sf.degree() < 1:
        return [zero, HalfLinePoint(fmpq(1), fmpq(1))]
    out = [zero]
    prev = fmpq(0)  # a rational at or beyond the previous root, with no root in between
    for a, b in ep.isolate_real_roots(sf, 0):
        if sf(b) == 0:
            a = b  # the root is the rational b
        a, b = ep.refine_past(sf, (a, b), prev)  # room for a sample after the previous root
        # a rational root a == b: no root in (prev, a); else prev < a < root
        out.append(HalfLinePoint((prev + a) / 2, (prev + a) / 2))
        out.append(HalfLinePoint(a, b, sf) if a != b else HalfLinePoint(a, a))
        prev = b
    out.append(HalfLinePoint(prev + 1, prev + 1))
    return out


def enclose(p: ep.PolyLike, lo: fmpq, hi: fmpq) -> tuple[fmpq, fmpq]:
    """Exact bounds of ``p`` over ``[lo, hi]``, ``0 <= lo <= hi`` (monotone halves).

    ``p = p₊ − p₋`` with non-negative coefficients: both halves increase on
    ``x ≥ 0``, so ``p([lo, hi]) ⊂ [p₊(lo) − p₋(hi), p₊(hi) − p₋(lo)]``.  The
    bounds converge to ``p(x)`` as the interval shrinks to ``x``.
    """
    coeffs = ep.as_poly(p).coeffs()
    pos = fmpq_poly([c if c > 0 else 0 for c in coeffs])
    neg = fmpq_poly([-c if c < 0 else 0 for c in coeffs])
    return pos(lo) - neg(hi), pos(hi) - neg(lo)


@dataclass(frozen=True, kw_only=True)
class HalfLineMinimum:
    """``inf_{x ≥ 0} p(x)/q(x)`` from `minimum_on_half_line`.

    Attributes
    ----------
    lower, upper : flint.fmpq or None
        A certified enclosure ``lower <= inf <= upper``; both None when the
        infimum is ``−∞``; equal when it is rational and known exactly.
    sign : int
        The exact sign of the infimum (−1, 0 or 1).
    at : HalfLinePoint or None
        Where it is attained (``None``: approached as ``x → ∞``, or ``−∞`` next to a pole).
    """

    lower: fmpq | None
    upper: fmpq | None
    sign: int
    at: HalfLinePoint | None

    @property
    def value(self) -> float:
        """The infimum as a float (``-inf`` when unbounded)."""
        if self.lower is None or self.upper is None:
            return -math.inf
        return float((self.lower + self.upper) / 2)


def _value_enclosure(
    p: fmpq_poly, q: fmpq_poly, point: HalfLinePoint, rtol: fmpq
) -> tuple[fmpq, fmpq, HalfLinePoint]:
    """Certified bounds of ``p/q`` at ``point`` (``q`` nonzero there), narrower than ``rtol``."""
    if point.is_rational:
        v = p(point.lower) / q(point.lower)
        return v, v, point
    width = point.upper - point.lower
    while True:
        lo_q, hi_q = enclose(q, point.lower, point.upper)
        if lo_q > 0 or hi_q < 0:  # q keeps its sign: the quotient is enclosed
            lo_p, hi_p = enclose(p, point.lower, point.upper)
            corners = [lo_p / lo_q, lo_p / hi_q, hi_p / lo_q, hi_p / hi_q]
            lo, hi = min(corners), max(corners)
            scale = max(abs(lo), abs(hi), fmpq(1, 2**1000))
            if hi - lo <= rtol * scale:
                return lo, hi, point
        width /= 2**8
        point = point.refined(width)
        if point.is_rational:
            v = p(point.lower) / q(point.lower)
            return v, v, point


def minimum_on_half_line(
    p: ep.PolyLike, q: ep.PolyLike, *, rtol: fmpq = DEFAULT_RTOL
) -> HalfLineMinimum:
    """``inf_{x ≥ 0} p(x)/q(x)`` exactly located, exactly signed and enclosed.

    Parameters
    ----------
    p, q : flint.fmpq_poly or sequence of rationals
        Exact polynomials (ascending coefficients); ``q`` not identically zero.
        Common factors are cancelled first (removable singularities).
    rtol : flint.fmpq
        Relative width of the returned enclosure.

    Returns
    -------
    HalfLineMinimum

    Examples
    --------
    >>> m = minimum_on_half_line([1, -4, 1], [1])   # x**2 - 4x + 1: -3 at x = 2
    >>> m.lower <= -3 <= m.upper, m.upper - m.lower < fmpq(1, 10**15), m.sign, float(m.at)
    (True, True, -1, 2.0)
    """
    p, q = ep.as_poly(p), ep.as_poly(q)
    if q.is_zero():
        raise ZeroDivisionError("q is identically zero")
    if p.is_zero():
        return HalfLineMinimum(
            lower=fmpq(0), upper=fmpq(0), sign=0, at=HalfLinePoint(fmpq(0), fmpq(0))
        )
    g = p.gcd(q)
    if g.degree() > 0:
        p, q = p // g, q // g
    crit = p.derivative() * q - p * q.derivative()
    points = half_line_cells([p, q, crit])
    # next to a root of q, p/q runs to ±∞: to -∞ if an adjacent cell has p/q < 0
    for i, pt in enumerate(points):
        if pt.sign(q) == 0:
            sides = [points[j] for j in (i - 1, i + 1) if 0 <= j < len(points)]
            if any(s.sign(p) * s.sign(q) < 0 for s in sides):
                return HalfLineMinimum(lower=None, upper=None, sign=-1, at=pt)
    candidates: list[tuple[int, HalfLinePoint | None]] = [
        (pt.sign(p) * pt.sign(q), pt)
        for pt in points
        if pt.sign(q) != 0 and (pt.lower == 0 or not pt.is_rational or pt.sign(crit) == 0)
    ]
    lead = p.leading_coefficient() / q.leading_coefficient()
    if p.degree() > q.degree():
        if lead < 0:
            return HalfLineMinimum(lower=None, upper=None, sign=-1, at=None)
    else:
        at_inf = lead if p.degree() == q.degree() else fmpq(0)
        candidates.append(((at_inf > 0) - (at_inf < 0), None))
    sign = min(s for s, _ in candidates)
    if sign == 0:  # the infimum is exactly 0, attained where p vanishes (or at infinity)
        where = next(c for s, c in candidates if s == 0)
        return HalfLineMinimum(lower=fmpq(0), upper=fmpq(0), sign=0, at=where)
    best: tuple[fmpq, fmpq, HalfLinePoint | None] | None = None
    lows = []
    for s, cand in candidates:
        if s > sign:
            continue  # a candidate of larger sign cannot be the minimum
        at: HalfLinePoint | None = cand
        if cand is None:
            lo = hi = at_inf
        else:
            lo, hi, at = _value_enclosure(p, q, cand, rtol)
        lows.append(lo)
        if best is None or hi < best[1]:
            best = (lo, hi, at)
    assert best is not None
    lower, upper = min(lows), best[1]
    return HalfLineMinimum(lower=lower, upper=upper, sign=sign, at=best[2])
