"""Exact tools for polynomials on the imaginary axis.

The parts of ``p(jω)`` as real polynomials, the even-to-``x = ω²`` change of
variable, the real-part polynomial of a rational function, the factor
``∏(s − jω_i)`` of imaginary-axis roots, the Routh–Hurwitz test, and a point
where an even polynomial is negative.  Polynomials are `flint.fmpq_poly`
(see [`seapass.exact.poly`][seapass.exact.poly]); everything is exact, and the
floats returned are only for display.

References
----------
.. [1] F. R. Gantmacher, *The Theory of Matrices*, vol. 2, Chelsea, 1959,
   ch. XV (Routh–Hurwitz).
"""

from __future__ import annotations

import math

from flint import fmpq, fmpq_poly

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
    "real_part_polynomial",
    "safe_float",
    "sign_regions",
    "sqrt_float",
    "squared_magnitude_polynomial",
]


def at_j_omega(p: fmpq_poly) -> tuple[fmpq_poly, fmpq_poly]:
    """Real and imaginary parts of ``p(jω)`` as real polynomials in ``ω``.

    >>> at_j_omega(fmpq_poly([1, 2, 3, 4]))  # 1 + 2jω − 3ω² − 4jω³
    ((-3)*x^2 + 1, (-4)*x^3 + 2*x)
    """
    c = p.coeffs()
    re = [fmpq(0)] * len(c)
    im = [fmpq(0)] * len(c)
    for k, v in enumerate(c):
        signed = -v if k % 4 >= 2 else v  # j^k = 1, j, −1, −j, ...
        if k % 2 == 0:
            re[k] = signed
        else:
            im[k] = signed
    return fmpq_poly(re), fmpq_poly(im)


def even_to_x(p: fmpq_poly) -> fmpq_poly:
    """``q`` with ``p(ω) = q(ω²)``; `ArithmeticError` if ``p`` has an odd power."""
    c = p.coeffs()
    if any(c[k] != 0 for k in range(1, len(c), 2)):
        raise ArithmeticError("Re(N(jw)D(-jw)) is not even in w")
    return fmpq_poly(c[0::2])


def real_part_polynomial(num: fmpq_poly, den: fmpq_poly) -> fmpq_poly:
    """``P(x)`` with ``P(ω²) = Re N(jω) D(−jω)``: the sign of ``Re Z(jω)`` off the poles.

    >>> real_part_polynomial(fmpq_poly([1, 1]), fmpq_poly([2, 1]))  # (s + 1)/(s + 2)
    x + 2
    """
    nr, ni = at_j_omega(num)
    dr, di = at_j_omega(den)
    return even_to_x(nr * dr + ni * di)


def squared_magnitude_polynomial(p: fmpq_poly) -> fmpq_poly:
    """``M(x)`` with ``M(ω²) = |p(jω)|²``.

    >>> squared_magnitude_polynomial(fmpq_poly([2, 1]))  # |jω + 2|² = ω² + 4
    x + 4
    """
    re, im = at_j_omega(p)
    return even_to_x(re * re + im * im)


def axis_factor(g: fmpq_poly) -> fmpq_poly:
    """``∏(s − jω_i)`` over the roots ``ω_i`` of ``g`` (all real, conjugate-symmetric)."""
    c = g.coeffs()
    n = len(c) - 1
    lead = c[-1]
    out = []
    for k, v in enumerate(c):
        if (n + k) % 2:
            if v != 0:
                raise ArithmeticError("imaginary-axis factor is not conjugate-symmetric")
            out.append(fmpq(0))
            continue
        sign = (-1) ** k * (-1) ** ((n + k) // 2)
        out.append(sign * v / lead)
    return fmpq_poly(out)


def is_hurwitz(p: fmpq_poly) -> bool:
    """Exact Routh test: all roots of ``p`` in the open left half-plane.

    >>> is_hurwitz(fmpq_poly([2, 3, 1])), is_hurwitz(fmpq_poly([1, 0, 1]))
    (True, False)
    """
    if p.degree() <= 0:
        return not p.is_zero()
    desc = p.coeffs()[::-1]
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
            bi1 = b[i + 1] if i + 1 < len(b) else fmpq(0)
            new.append((b[0] * a[i + 1] - a[0] * bi1) / b[0])
        rows.append(new)
    return all(r and r[0] > 0 for r in rows[: n + 1])


def log2(q: fmpq) -> float:
    """``log2 q`` of a positive rational, without converting it to a float (no overflow)."""
    return math.log2(int(q.p)) - math.log2(int(q.q))


def safe_float(q: fmpq) -> float:
    """``float(q)``, saturating to ``±inf`` beyond the double range."""
    try:
        return float(q)
    except OverflowError:
        return math.inf if q > 0 else -math.inf


def all_real_roots(g: fmpq_poly) -> bool:
    """Every root of ``g`` (degree >= 1) is real (certified isolation, exact count)."""
    sf = ep.squarefree_part(g)
    return ep.count_real_roots(sf) == sf.degree()


def sign_regions(px: fmpq_poly) -> tuple[list[ep.Interval], list[fmpq]]:
    """The distinct positive roots of ``px`` and a rational point in each region between them.

    Returns the isolating intervals ``(a, b]`` of the roots in ``(0, ∞)``,
    refined so that each starts strictly after the previous one ends (and
    after 0), however close the roots are, and one point strictly inside each
    of the ``len(intervals) + 1`` regions they cut ``(0, ∞)`` into; ``px`` has
    a constant non-zero sign on each region.

    >>> sign_regions(fmpq_poly([-1, 0, 1]))[1]  # P(x) = x² − 1: one root, two regions
    [1/2, 3]
    """
    tight: list[ep.Interval] = []
    prev = fmpq(0)
    for a, b in ep.isolate_real_roots(px, 0):
        a, b = ep.refine_past(px, (a, b), prev)
        tight.append((a, b))
        prev = b
    points: list[fmpq] = []
    lo = fmpq(0)
    for a, b in tight:
        points.append((lo + a) / 2)
        lo = b
    points.append(lo * 2 + 1)
    return tight, points


def negative_point(px: fmpq_poly) -> float:
    """A frequency ``ω`` where ``P(ω²) < 0`` (exactly checked), preferring the most negative.

    ``px`` is a real-part polynomial in ``x = ω²`` that is negative somewhere on
    ``x > 0``.  The candidates are the points of `sign_regions` (between
    consecutive positive roots, and one beyond the last); the one with the
    largest relative depth ``|P(x)|/Σ|c_i|x^i`` wins.

    >>> negative_point(fmpq_poly([-1, 0, 1]))  # P(x) = x² − 1 < 0 on (0, 1)
    0.7071067811865476
    """
    _tight, points = sign_regions(px)
    neg = [x for x in points if x > 0 and px(x) < 0]
    if not neg:
        raise ArithmeticError("no witness found although P changes sign")  # pragma: no cover
    # relative depth |P|/Σ|c_i|x^i lies in [0, 1], so it converts to float safely
    absp = fmpq_poly([abs(c) for c in px.coeffs()])
    depth = [float(abs(px(x)) / absp(x)) for x in neg]
    best = neg[max(range(len(neg)), key=depth.__getitem__)]  # the first maximum
    return sqrt_float(best)


def negative_bands(px: fmpq_poly) -> list[tuple[float, float]]:
    """The frequency bands where ``P(ω²) < 0``, decided exactly; ``px`` is ``P`` in ``x = ω²``.

    Disjoint open bands ``(lo, hi)`` in rad/s, increasing; ``lo`` may be 0 and
    ``hi`` ``inf``.  Whether ``P`` is negative between consecutive positive
    roots is decided exactly at a rational point; only the edges, ``√x`` of the
    roots, are rounded to double precision.  A root of even multiplicity inside
    a band (``P`` touches zero) does not split it.

    Examples
    --------
    >>> negative_bands(fmpq_poly([-2, 1]))   # P = x - 2
    [(0.0, 1.4142135623730951)]
    """
    if px.is_zero():
        return []
    tight, points = sign_regions(px)
    edges = [0.0] + [root_sqrt(px, iv) for iv in tight] + [math.inf]
    bands: list[tuple[float, float]] = []
    previous = False
    for i, x in enumerate(points):
        negative = px(x) < 0
        if negative and previous:
            bands[-1] = (bands[-1][0], edges[i + 1])
        elif negative:
            bands.append((edges[i], edges[i + 1]))
        previous = negative
    return bands


def root_sqrt(px: fmpq_poly, iv: ep.Interval) -> float:
    """``√x`` of the root of ``px`` in ``(a, b]``, to double precision (``inf`` beyond range)."""
    a, b = iv
    if a == b:
        return sqrt_float(a) if a > 0 else 0.0
    try:
        return math.sqrt(ep.root_value(px, iv))
    except OverflowError:
        return sqrt_float(b)


def sqrt_float(q: fmpq) -> float:
    """``sqrt(q)`` as a float without overflow for rationals beyond the float range."""
    half_log = 0.5 * (math.log(int(q.p)) - math.log(int(q.q)))
    return math.exp(half_log) if half_log < 709.0 else math.inf
