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
from dataclasses import dataclass
from fractions import Fraction

from . import poly as ep

__all__ = [
    "HalfLineMinimum",
    "HalfLinePoint",
    "enclose",
    "half_line_cells",
    "minimum_on_half_line",
]

DEFAULT_RTOL = Fraction(1, 2**60)
"""Relative width of the enclosures `minimum_on_half_line` returns (below double precision)."""


@dataclass(frozen=True)
class HalfLinePoint:
    """A point ``x ≥ 0``: the rational ``lower`` (when ``lower == upper``) or the unique
    root in ``(lower, upper]`` of the square-free polynomial ``poly``."""

    lower: Fraction
    upper: Fraction
    poly: ep.Poly = ()

    @property
    def is_rational(self) -> bool:
        return self.lower == self.upper

    def sign(self, q: ep.Poly) -> int:
        """Exact sign of ``q`` at the point."""
        if self.is_rational:
            v = ep.evaluate(ep.normalize(q), self.lower)
            return (v > 0) - (v < 0)
        return ep.sign_at_root(ep.normalize(q), self.poly, self.lower, self.upper)

    def refined(self, width: Fraction) -> HalfLinePoint:
        """The same point with an isolating interval narrower than ``width``."""
        if self.is_rational:
            return self
        a, b = ep.refine(self.poly, self.lower, self.upper, width)
        return HalfLinePoint(a, b, self.poly)

    def __float__(self) -> float:
        if self.is_rational:
            return float(self.lower)
        return ep.root_value(self.poly, self.lower, self.upper)


def _square_free_product(polys: Sequence[ep.Poly]) -> ep.Poly:
    prod: ep.Poly = (Fraction(1),)
    for p in polys:
        p = ep.normalize(p)
        if ep.degree(p) >= 1:
            prod = ep.mul(prod, ep.squarefree_part(p))
    return ep.squarefree_part(prod) if ep.degree(prod) >= 1 else prod


def half_line_cells(polys: Sequence[ep.Poly]) -> list[HalfLinePoint]:
    """One exact point per sign cell of ``polys`` on ``[0, ∞)``, in increasing order.

    The points are ``x = 0``, every positive real root of any of ``polys`` and a
    rational point strictly inside every open interval between consecutive
    roots (and beyond the last).  On each open interval every polynomial has a
    constant sign, the sign at its point.

    Examples
    --------
    >>> from fractions import Fraction as F
    >>> pts = half_line_cells([(F(-1), F(0), F(1))])   # x**2 - 1
    >>> [(float(p), p.sign((F(-1), F(0), F(1)))) for p in pts]
    [(0.0, -1), (0.5, -1), (1.0, 0), (2.0, 1)]
    """
    sf = _square_free_product(polys)
    zero = HalfLinePoint(Fraction(0), Fraction(0))
    if ep.degree(sf) < 1:
        return [zero, HalfLinePoint(Fraction(1), Fraction(1))]
    out = [zero]
    prev = Fraction(0)  # a rational at or beyond the previous root, with no root in between
    for a, b in ep.isolate_real_roots(sf, Fraction(0), None):
        if ep.evaluate(sf, b) == 0:
            a = b  # the root is the rational b
        while a <= prev and a != b:  # make room for a sample after the previous root
            a, b = ep.refine(sf, a, b, (b - a) / 2)
        # a rational root a == b: no root in (prev, a); else prev < a < root
        out.append(HalfLinePoint((prev + a) / 2, (prev + a) / 2))
        out.append(HalfLinePoint(a, b, sf) if a != b else HalfLinePoint(a, a))
        prev = b
    out.append(HalfLinePoint(prev + 1, prev + 1))
    return out


def enclose(p: ep.Poly, lo: Fraction, hi: Fraction) -> tuple[Fraction, Fraction]:
    """Exact bounds of ``p`` over ``[lo, hi]``, ``0 <= lo <= hi`` (monotone halves).

    ``p = p₊ − p₋`` with non-negative coefficients: both halves increase on
    ``x ≥ 0``, so ``p([lo, hi]) ⊂ [p₊(lo) − p₋(hi), p₊(hi) − p₋(lo)]``.  The
    bounds converge to ``p(x)`` as the interval shrinks to ``x``.
    """
    pos = tuple(c if c > 0 else Fraction(0) for c in p)
    neg = tuple(-c if c < 0 else Fraction(0) for c in p)
    return (
        ep.evaluate(pos, lo) - ep.evaluate(neg, hi),
        ep.evaluate(pos, hi) - ep.evaluate(neg, lo),
    )


@dataclass(frozen=True)
class HalfLineMinimum:
    """``inf_{x ≥ 0} p(x)/q(x)`` from `minimum_on_half_line`.

    Attributes
    ----------
    lower, upper : Fraction or None
        A certified enclosure ``lower <= inf <= upper``; both None when the
        infimum is ``−∞``; equal when it is rational and known exactly.
    sign : int
        The exact sign of the infimum (−1, 0 or 1).
    at : HalfLinePoint or None
        Where it is attained (``None``: approached as ``x → ∞``, or ``−∞`` next to a pole).
    """

    lower: Fraction | None
    upper: Fraction | None
    sign: int
    at: HalfLinePoint | None

    @property
    def value(self) -> float:
        """The infimum as a float (``-inf`` when unbounded)."""
        if self.lower is None or self.upper is None:
            return -math.inf
        return float((self.lower + self.upper) / 2)


def _value_enclosure(
    p: ep.Poly, q: ep.Poly, point: HalfLinePoint, rtol: Fraction
) -> tuple[Fraction, Fraction, HalfLinePoint]:
    """Certified bounds of ``p/q`` at ``point`` (``q`` nonzero there), narrower than ``rtol``."""
    if point.is_rational:
        v = ep.evaluate(p, point.lower) / ep.evaluate(q, point.lower)
        return v, v, point
    width = point.upper - point.lower
    while True:
        lo_q, hi_q = enclose(q, point.lower, point.upper)
        if lo_q > 0 or hi_q < 0:  # q keeps its sign: the quotient is enclosed
            lo_p, hi_p = enclose(p, point.lower, point.upper)
            corners = [lo_p / lo_q, lo_p / hi_q, hi_p / lo_q, hi_p / hi_q]
            lo, hi = min(corners), max(corners)
            scale = max(abs(lo), abs(hi), Fraction(1, 2**1000))
            if hi - lo <= rtol * scale:
                return lo, hi, point
        width /= 2**8
        point = point.refined(width)
        if point.is_rational:
            v = ep.evaluate(p, point.lower) / ep.evaluate(q, point.lower)
            return v, v, point


def minimum_on_half_line(
    p: ep.Poly, q: ep.Poly, *, rtol: Fraction = DEFAULT_RTOL
) -> HalfLineMinimum:
    """``inf_{x ≥ 0} p(x)/q(x)`` exactly located, exactly signed and enclosed.

    Parameters
    ----------
    p, q : Poly
        Ascending Fraction coefficients; ``q`` not identically zero.  Common
        factors are cancelled first (removable singularities).
    rtol : Fraction
        Relative width of the returned enclosure.

    Returns
    -------
    HalfLineMinimum

    Examples
    --------
    >>> from fractions import Fraction as F
    >>> m = minimum_on_half_line((F(1), F(-4), F(1)), (F(1),))   # x**2 - 4x + 1: -3 at x = 2
    >>> m.lower <= -3 <= m.upper, m.upper - m.lower < F(1, 10**15), m.sign, float(m.at)
    (True, True, -1, 2.0)
    """
    p, q = ep.normalize(p), ep.normalize(q)
    if not q:
        raise ZeroDivisionError("q is identically zero")
    if not p:
        return HalfLineMinimum(Fraction(0), Fraction(0), 0, HalfLinePoint(Fraction(0), Fraction(0)))
    g = ep.pgcd(p, q)
    if ep.degree(g) > 0:
        p, q = ep.pdivmod(p, g)[0], ep.pdivmod(q, g)[0]
    dp, dq = ep.derivative(p), ep.derivative(q)
    crit = ep.sub(ep.mul(dp, q), ep.mul(p, dq))
    points = half_line_cells([p, q, crit])
    # next to a root of q, p/q runs to ±∞: to -∞ if an adjacent cell has p/q < 0
    for i, pt in enumerate(points):
        if pt.sign(q) == 0:
            sides = [points[j] for j in (i - 1, i + 1) if 0 <= j < len(points)]
            if any(s.sign(p) * s.sign(q) < 0 for s in sides):
                return HalfLineMinimum(None, None, -1, pt)
    candidates: list[tuple[int, HalfLinePoint | None]] = [
        (pt.sign(p) * pt.sign(q), pt)
        for pt in points
        if pt.sign(q) != 0 and (pt.lower == 0 or not pt.is_rational or pt.sign(crit) == 0)
    ]
    lead = Fraction(p[-1]) / q[-1]
    if ep.degree(p) > ep.degree(q):
        if lead < 0:
            return HalfLineMinimum(None, None, -1, None)
    else:
        at_inf = lead if ep.degree(p) == ep.degree(q) else Fraction(0)
        candidates.append(((at_inf > 0) - (at_inf < 0), None))
    sign = min(s for s, _ in candidates)
    if sign == 0:  # the infimum is exactly 0, attained where p vanishes (or at infinity)
        where = next(c for s, c in candidates if s == 0)
        return HalfLineMinimum(Fraction(0), Fraction(0), 0, where)
    best: tuple[Fraction, Fraction, HalfLinePoint | None] | None = None
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
    return HalfLineMinimum(lower, upper, sign, best[2])
