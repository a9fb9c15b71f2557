"""Transitional: the old tuple-of-Fractions polynomial API, on the python-flint kernel.

Polynomials are tuples of `fractions.Fraction` in ascending powers (``()`` is
zero), as before seapass moved onto python-flint.  Only
[`seapass.sampled`][seapass.sampled] still uses this API; it moves to
[`seapass.exact.poly`][seapass.exact.poly] in its rewrite (issue 11), and this
module is deleted then.  Arithmetic is plain Python; everything about roots
delegates to [`seapass.exact.poly`][seapass.exact.poly], so its answers are the
kernel's (and equal to the old hand-written ones, interval for interval).
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction

from . import poly as ep

__all__ = [
    "Poly",
    "count_real_roots",
    "degree",
    "evaluate",
    "isolate_real_roots",
    "normalize",
    "pdivmod",
    "positive_roots_odd_multiplicity",
    "refine",
    "squarefree_part",
]

Poly = tuple[Fraction, ...]


def normalize(coeffs: Sequence[Fraction | int]) -> Poly:
    """Strip trailing zero coefficients (highest powers)."""
    c = [x if type(x) is Fraction else Fraction(x) for x in coeffs]
    while c and c[-1] == 0:
        c.pop()
    return tuple(c)


def degree(p: Poly) -> int:
    """Degree, with ``-1`` for the zero polynomial."""
    return len(p) - 1


def evaluate(p: Poly, x: Fraction) -> Fraction:
    """``p(x)``, exactly (Horner)."""
    acc = Fraction(0)
    for c in reversed(p):
        acc = acc * x + c
    return acc


def pdivmod(p: Poly, q: Poly) -> tuple[Poly, Poly]:
    """Polynomial long division ``p = quot*q + rem`` with ``deg rem < deg q``."""
    if not q:
        raise ZeroDivisionError("polynomial division by zero")
    quot, rem = divmod(ep.as_poly(p), ep.as_poly(q))
    return ep.to_fractions(quot), ep.to_fractions(rem)


def squarefree_part(p: Poly) -> Poly:
    """``p / gcd(p, p')``, monic: same roots, each simple."""
    return ep.to_fractions(ep.squarefree_part(ep.as_poly(p)))


def positive_roots_odd_multiplicity(p: Poly) -> Poly:
    """Monic product of the squarefree factors of odd multiplicity."""
    return ep.to_fractions(ep.positive_roots_odd_multiplicity(ep.as_poly(p)))


def count_real_roots(p: Poly, lo: Fraction, hi: Fraction | None) -> int:
    """Number of distinct real roots of ``p`` in ``(lo, hi]`` (``hi=None``: ``+infinity``)."""
    return ep.count_real_roots(ep.as_poly(p), lo, hi)


def isolate_real_roots(
    p: Poly, lo: Fraction, hi: Fraction | None = None
) -> list[tuple[Fraction, Fraction]]:
    """Disjoint intervals ``(a, b]``, one distinct root of ``p`` in ``(lo, hi]`` each, sorted."""
    return [
        (ep.to_fraction(a), ep.to_fraction(b))
        for a, b in ep.isolate_real_roots(ep.as_poly(p), lo, hi)
    ]


def refine(p: Poly, a: Fraction, b: Fraction, width: Fraction) -> tuple[Fraction, Fraction]:
    """Shrink an isolating interval ``(a, b]`` of squarefree ``p`` to below ``width``."""
    ra, rb = ep.refine(ep.as_poly(p), (ep.rational(a), ep.rational(b)), width)
    return ep.to_fraction(ra), ep.to_fraction(rb)
