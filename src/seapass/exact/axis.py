"""Exact tools for polynomials on the imaginary axis.

The parts of ``p(jω)`` as real polynomials, the even-to-``x = ω²`` change of
variable, the factor ``∏(s − jω_i)`` of imaginary-axis roots, the Routh–Hurwitz
test, and a point where an even polynomial is negative.  Everything is exact
(rational coefficients, Sturm sequences); the floats returned are only for
display.

References
----------
.. [1] F. R. Gantmacher, *The Theory of Matrices*, vol. 2, Chelsea, 1959,
   ch. XV (Routh–Hurwitz).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from . import poly as ep

__all__ = [
    "all_real_roots",
    "at_j_omega",
    "axis_factor",
    "even_to_x",
    "is_hurwitz",
    "log2",
    "negative_bands",
    "negative_point",
    "safe_float",
    "sign_regions",
    "sqrt_float",
]


def at_j_omega(p: ep.Poly) -> tuple[ep.Poly, ep.Poly]:
    """Real and imaginary parts of ``p(jω)`` as real polynomials in ``ω``."""
    re = [Fraction(0)] * len(p)
    im = [Fraction(0)] * len(p)
    for k, c in enumerate(p):
        sign = -1 if (k // 2) % 2 else 1
        if k % 2 == 0:
            re[k] = sign * c
        else:
            im[k] = sign * c
    return ep.normalize(re), ep.normalize(im)


def axis_factor(g: ep.Poly) -> ep.Poly:
    """``∏(s − jω_i)`` over the roots ``ω_i`` of ``g`` (all real, conjugate-symmetric)."""
    n = ep.degree(g)
    lead = g[-1]
    out = []
    for k, c in enumerate(g):
        if (n + k) % 2:
            if c != 0:
                raise ArithmeticError("imaginary-axis factor is not conjugate-symmetric")
            out.append(Fraction(0))
            continue
        sign = (-1) ** k * (-1) ** ((n + k) // 2)
        out.append(sign * c / lead)
    return ep.normalize(out)


def is_hurwitz(p: ep.Poly) -> bool:
    """Exact Routh test: all roots of ``p`` in the open left half-plane."""
    if ep.degree(p) <= 0:
        return bool(p)
    desc = list(reversed(p))
    if desc[0] < 0:
        desc = [-c for c in desc]
    rows = [desc[0::2], desc[1::2]]
    n = len(desc) - 1
    for _ in range(n - 1):
        a, b = rows[-2], rows[-1]
        if not b or b[0] <= 0:
            return False
        new = []
        for i in range(len(a) - 1):
            bi1 = b[i + 1] if i + 1 < len(b) else Fraction(0)
            new.append((b[0] * a[i + 1] - a[0] * bi1) / b[0])
        rows.append(new)
    return all(r and r[0] > 0 for r in rows[: n + 1])


def even_to_x(p: ep.Poly) -> ep.Poly:
    if any(p[k] != 0 for k in range(1, len(p), 2)):
        raise ArithmeticError("Re(N(jw)D(-jw)) is not even in w")
    return ep.normalize(list(p[0::2]))


def log2(q: Fraction) -> float:
    return math.log2(q.numerator) - math.log2(q.denominator)


def safe_float(q: Fraction) -> float:
    """``float(q)``, saturating to ``±inf`` beyond the double range."""
    try:
        return float(q)
    except OverflowError:
        return math.inf if q > 0 else -math.inf


def all_real_roots(g: ep.Poly) -> bool:
    sf = ep.squarefree_part(g)
    lo = -ep.cauchy_bound(sf)
    return ep.count_real_roots(sf, lo, None) == ep.degree(sf)


def sign_regions(px: ep.Poly) -> tuple[list[tuple[Fraction, Fraction]], list[Fraction]]:
    """The distinct positive roots of ``px`` and a rational point in each region between them.

    Returns the isolating intervals ``(a, b]`` of the roots in ``(0, ∞)``,
    refined so that each starts strictly after the previous one ends (and
    after 0), however close the roots are, and one point strictly inside each
    of the ``len(intervals) + 1`` regions they cut ``(0, ∞)`` into; ``px`` has
    a constant non-zero sign on each region.
    """
    sf = ep.squarefree_part(px)
    tight: list[tuple[Fraction, Fraction]] = []
    prev = Fraction(0)
    for a, b in ep.isolate_real_roots(px, Fraction(0), None):
        while a <= prev:
            a, b = ep.refine(sf, a, b, (b - a) / 2)
        tight.append((a, b))
        prev = b
    points: list[Fraction] = []
    lo = Fraction(0)
    for a, b in tight:
        points.append((lo + a) / 2)
        lo = b
    points.append(lo * 2 + 1)
    return tight, points


def negative_point(px: ep.Poly) -> float:
    """A frequency where ``P(ω²) < 0`` (exactly checked), preferring the most negative one."""
    _tight, points = sign_regions(px)
    neg = [x for x in points if x > 0 and ep.evaluate(px, x) < 0]
    if not neg:
        raise ArithmeticError("no witness found although P changes sign")  # pragma: no cover
    # relative depth |P|/Σ|c_i|x^i lies in [0, 1], so it converts to float safely
    depth = [abs(ep.evaluate(px, x)) / sum(abs(c) * x**i for i, c in enumerate(px)) for x in neg]
    best = neg[int(np.argmax([float(d) for d in depth]))]
    return sqrt_float(best)


def negative_bands(px: ep.Poly) -> list[tuple[float, float]]:
    """The frequency bands where ``P(ω²) < 0``, decided exactly; ``px`` is ``P`` in ``x = ω²``.

    Disjoint open bands ``(lo, hi)`` in rad/s, increasing; ``lo`` may be 0 and
    ``hi`` ``inf``.  Whether ``P`` is negative between consecutive positive
    roots is decided exactly at a rational point; only the edges, ``√x`` of the
    roots, are rounded to double precision.  A root of even multiplicity inside
    a band (``P`` touches zero) does not split it.

    Examples
    --------
    >>> negative_bands((Fraction(-2), Fraction(1)))   # P = x - 2
    [(0.0, 1.4142135623730951)]
    """
    if not ep.normalize(px):
        return []
    sf = ep.squarefree_part(px)
    tight, points = sign_regions(px)
    edges = [0.0] + [_sqrt_root(sf, a, b) for a, b in tight] + [math.inf]
    bands: list[tuple[float, float]] = []
    previous = False
    for i, x in enumerate(points):
        negative = ep.evaluate(px, x) < 0
        if negative and previous:
            bands[-1] = (bands[-1][0], edges[i + 1])
        elif negative:
            bands.append((edges[i], edges[i + 1]))
        previous = negative
    return bands


def _sqrt_root(sf: ep.Poly, a: Fraction, b: Fraction) -> float:
    """``√x`` of the root of square-free ``sf`` in ``(a, b]``, to double precision."""
    return math.sqrt(safe_float(a) if a == b else ep.root_value(sf, a, b))


def sqrt_float(q: Fraction) -> float:
    """``sqrt(q)`` as a float without overflow for rationals beyond the float range."""
    half_log = 0.5 * (math.log(q.numerator) - math.log(q.denominator))
    return math.exp(half_log) if half_log < 709.0 else math.inf
