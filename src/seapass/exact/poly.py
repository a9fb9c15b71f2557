"""Exact univariate polynomials over the rationals, on python-flint.

Polynomials are `flint.fmpq_poly` objects (exact rational coefficients,
arithmetic in FLINT); scalars are `flint.fmpq`.  Convert at the boundaries with
[`as_poly`][seapass.exact.poly.as_poly], [`rational`][seapass.exact.poly.rational],
[`to_fractions`][seapass.exact.poly.to_fractions] and
[`to_fraction`][seapass.exact.poly.to_fraction].  What FLINT provides is used
directly: ``p + q``, ``p * q``, ``divmod(p, q)``, ``p // q``, ``p.gcd(q)``
(monic), ``p.derivative()``, ``p(x)`` (the exact value at a rational ``x``).

Every decision here is exact or certified:

* gcd, division, squarefree parts and multiplicities are exact (FLINT);
* the sign of ``p`` at a rational point is an exact evaluation;
* real roots are isolated, one irreducible factor at a time (FLINT's
  ``fmpz_poly.factor``; roots of different factors are then separated by
  exact bisection), by FLINT's certified root finder
  (``arb_fmpz_poly_complex_roots``, Arb ball arithmetic): it returns pairwise
  disjoint complex balls, proven to hold one root each, and proves which roots
  are real (their balls get an imaginary part of exactly zero).  Each real
  ball becomes the rational interval with the same end points, and the sign
  change of the squarefree part across it is re-checked in exact arithmetic;
  if that check fails, `ArithmeticError` is raised: a failure is an error,
  never a guess.  No comparison is ever decided by a ball: a root is compared
  with a rational by one exact sign evaluation inside its interval.
* the global precision `flint.ctx.prec` is never changed; the certificates
  hold at any working precision.

Isolating intervals are half-open, ``(a, b]``, and hold exactly one distinct
root; ``a == b`` is the exact rational root ``a``.  They are the intervals of
the classical Sturm bisection of ``(lo, hi]`` (the coarsest dyadic subdivision
that separates the roots), so they do not depend on how the roots were found.
See the verification page for the certification argument.

References
----------
.. [1] S. Basu, R. Pollack, M.-F. Roy, *Algorithms in Real Algebraic Geometry*,
   2nd ed., Springer, 2006, ch. 2 and 10 (root isolation by bisection).
.. [2] F. Johansson, "Arb: efficient arbitrary-precision midpoint-radius
   interval arithmetic", IEEE Trans. Computers 66(8), 2017.
.. [3] The FLINT team, *FLINT: Fast Library for Number Theory*,
   https://flintlib.org (``fmpq_poly``, ``arb_fmpz_poly_complex_roots``).

Examples
--------
>>> from flint import fmpq_poly
>>> x = fmpq_poly([0, 1])
>>> p = (x**2 - 2) * (x - 1) ** 2
>>> count_real_roots(p, 0), isolate_real_roots(p, 0)
(2, [(3/4, 9/8), (9/8, 3/2)])
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterable
from fractions import Fraction
from numbers import Rational as _PyRational
from typing import cast

from flint import acb, fmpq, fmpq_poly, fmpz, fmpz_poly

__all__ = [
    "Interval",
    "Poly",
    "PolyLike",
    "RationalLike",
    "as_poly",
    "cauchy_bound",
    "count_real_roots",
    "degree",
    "isolate_real_roots",
    "monic",
    "positive_roots_odd_multiplicity",
    "rational",
    "refine",
    "refine_past",
    "root_value",
    "sign",
    "sign_at",
    "sign_at_root",
    "squarefree_part",
    "to_fraction",
    "to_fractions",
]

Poly = fmpq_poly
#: An isolating interval ``(a, b]``; ``a == b`` is the exact rational root ``a``.
Interval = tuple[fmpq, fmpq]
RationalLike = fmpq | fmpz | int | Fraction | float
PolyLike = fmpq_poly | fmpz_poly | Iterable[RationalLike]

#: Upper bound on the bisection steps of one refinement or separation (never
#: reached for exact input; a bound on the time, not a tolerance).
MAX_BISECTIONS = 100_000


# ---------------------------------------------------------------- conversion


def rational(x: RationalLike) -> fmpq:
    """``x`` as an exact `flint.fmpq` (a float converts to the rational it represents).

    >>> rational(0.5), rational(Fraction(1, 3)), rational(7)
    (1/2, 1/3, 7)
    """
    if isinstance(x, fmpq):
        return x
    if isinstance(x, bool):
        raise TypeError("a bool is not a rational number")
    if isinstance(x, int | fmpz):
        return fmpq(x)
    if isinstance(x, float):
        x = Fraction(x)  # exact; raises on nan/inf
    if isinstance(x, _PyRational):
        return fmpq(int(x.numerator), int(x.denominator))
    raise TypeError(f"cannot convert {type(x).__name__} to an exact rational")


def as_poly(p: PolyLike) -> fmpq_poly:
    """An `flint.fmpq_poly` from a polynomial or from ascending coefficients.

    >>> as_poly([Fraction(1, 2), 0, 3])
    3*x^2 + 1/2
    """
    if isinstance(p, fmpq_poly):
        return p
    if isinstance(p, fmpz_poly):
        return fmpq_poly(p)
    return fmpq_poly([rational(c) for c in p])


def to_fraction(q: fmpq | fmpz | int) -> Fraction:
    """Exact `fractions.Fraction` of a FLINT rational."""
    if isinstance(q, fmpq):
        return Fraction(int(q.p), int(q.q))
    return Fraction(int(q))


def to_fractions(p: Poly) -> tuple[Fraction, ...]:
    """Ascending coefficients as Fractions (``()`` for the zero polynomial)."""
    return tuple(to_fraction(c) for c in p.coeffs())


# ---------------------------------------------------------------- structure


def degree(p: Poly) -> int:
    """Degree, with ``-1`` for the zero polynomial."""
    return int(p.degree())


def sign(x: fmpq | fmpz | int) -> int:
    """``-1``, ``0`` or ``1``."""
    return (x > 0) - (x < 0)


def sign_at(p: Poly, x: RationalLike) -> int:
    """Exact sign of ``p(x)`` at a rational ``x``."""
    return sign(p(rational(x)))


def monic(p: Poly) -> fmpq_poly:
    """``p`` divided by its leading coefficient (the zero polynomial is returned as is)."""
    return p / p.leading_coefficient() if not p.is_zero() else p


def squarefree_part(p: Poly) -> fmpq_poly:
    """``p / gcd(p, p')``, monic: the same roots, each simple (``1`` for a constant)."""
    if p.degree() <= 0:
        return monic(p)
    g = p.gcd(p.derivative())
    return monic(p // g) if g.degree() > 0 else monic(p)


def positive_roots_odd_multiplicity(p: Poly) -> fmpq_poly:
    """Monic product of the squarefree factors of odd multiplicity.

    Its roots are exactly the roots where ``p`` changes sign (FLINT's exact
    squarefree factorization).

    >>> x = fmpq_poly([0, 1])
    >>> positive_roots_odd_multiplicity((x - 1) ** 2 * (x - 2) * (x - 3) ** 3)
    x^2 + (-5)*x + 6
    """
    out = fmpq_poly([1])
    if p.degree() <= 0:
        return out
    for f, e in p.factor_squarefree()[1]:
        if e % 2 == 1:
            out *= f
    return monic(out)


def cauchy_bound(p: Poly) -> fmpq:
    """Every root ``r`` of ``p`` (degree >= 1) satisfies ``|r| < bound``."""
    c = p.coeffs()
    lead = abs(c[-1])
    return 1 + max((abs(x) / lead for x in c[:-1]), default=fmpq(0))


# ---------------------------------------------------------------- certified roots


def _dyadic(x: object) -> fmpq:
    """The exact value of an arb midpoint or radius (a binary floating-point number)."""
    m, e = x.man_exp()  # type: ignore[attr-defined]
    return fmpq(m) * fmpq(2) ** int(e)


class _Root:
    """One real root of a squarefree integer polynomial ``z``, isolated exactly.

    Either exact (``lo == hi``, ``z(lo) == 0``) or inside the open interval
    ``(lo, hi)`` where ``z`` has no other root and ``z(lo)``, ``z(hi)`` are
    nonzero with opposite signs.  Comparisons with rationals narrow the
    interval in place (exact evaluations only).
    """

    __slots__ = ("hi", "lo", "s_lo", "z")

    def __init__(self, z: fmpz_poly, lo: fmpq, hi: fmpq, s_lo: int) -> None:
        self.z, self.lo, self.hi, self.s_lo = z, lo, hi, s_lo

    def cmp(self, x: fmpq) -> int:
        """Sign of ``root − x``, exactly."""
        if self.lo == self.hi:
            return sign(self.lo - x)
        if x <= self.lo:
            return 1
        if x >= self.hi:
            return -1
        s = sign(self.z(x))
        if s == 0:
            self.lo = self.hi = x
            return 0
        if s == self.s_lo:
            self.lo = x
            return 1
        self.hi = x
        return -1


def _complex_roots(z: fmpz_poly) -> list[tuple[acb, int]]:
    """FLINT's certified complex roots of ``z`` with multiplicities (a seam for tests)."""
    # python-flint's stub says list[acb]; the call returns (root, multiplicity) pairs
    return cast("list[tuple[acb, int]]", z.complex_roots())


def _factor_roots(f: fmpz_poly) -> list[_Root]:
    """The real roots of an irreducible (or squarefree) integer polynomial ``f``, certified."""
    found = _complex_roots(f)
    if len(found) != f.degree() or any(m != 1 for _, m in found):
        raise ArithmeticError("root isolation did not return every simple root")
    out: list[_Root] = []
    for c, _ in found:
        if not c.imag.is_zero():
            continue  # certified non-real (FLINT zeroes the imaginary part of real roots only)
        mid, rad = _dyadic(c.real.mid()), _dyadic(c.real.rad())
        a, b = mid - rad, mid + rad
        sa, sb = sign(f(a)), sign(f(b))
        if sa == 0 or sb == 0 or rad == 0:  # an exact rational root
            x = a if sa == 0 else b
            out.append(_Root(f, x, x, 0))
        elif sa == -sb:
            out.append(_Root(f, a, b, sa))
        else:
            raise ArithmeticError("enclosure fails the exact sign check; refusing to guess")
    return out


def _separate(roots: list[_Root]) -> list[_Root]:
    """Sort roots of pairwise coprime factors and narrow them (exactly) until disjoint."""
    roots = sorted(roots, key=lambda r: r.lo)
    i, steps = 0, 0
    while i < len(roots) - 1:
        r, s = roots[i], roots[i + 1]
        if r.hi < s.lo:
            i += 1
            continue
        wider = r if r.hi - r.lo >= s.hi - s.lo else s
        if wider.lo == wider.hi:  # two exact roots at one point: the factors were not coprime
            raise ArithmeticError("roots of coprime factors coincide; refusing to guess")
        wider.cmp((wider.lo + wider.hi) / 2)
        steps += 1
        if steps > MAX_BISECTIONS:
            raise ArithmeticError("could not separate the real roots within the bisection bound")
        roots.sort(key=lambda r: r.lo)
        i = max(i - 1, 0)
    return roots


def _certified_real_roots(sf: fmpq_poly) -> list[_Root]:
    """Real roots of a squarefree ``sf`` (degree >= 1), ascending, exactly isolated.

    Per irreducible factor: FLINT's root finder can take minutes on a product
    whose factors share near-equal roots (from extreme values); the factors'
    roots are separated exactly and re-checked on ``sf``.
    """
    z = sf.numer()  # same roots and same signs (positive denominator)
    _content, factors = z.factor()
    if any(e != 1 for _, e in factors) or sum(f.degree() for f, _ in factors) != z.degree():
        raise ArithmeticError("a squarefree polynomial factored with a repeated factor")
    roots = _separate([r for f, _ in factors for r in _factor_roots(f)])
    out: list[_Root] = []
    for r in roots:
        sa = sign(z(r.lo)) if r.lo != r.hi else 0
        if r.lo != r.hi and (sa == 0 or sa != -sign(z(r.hi))):
            raise ArithmeticError("a separated root failed the exact sign check")
        out.append(_Root(z, r.lo, r.hi, sa))
    if any(r.hi >= s.lo for r, s in itertools.pairwise(out)):
        raise ArithmeticError("real root enclosures overlap; refusing to guess")
    return out


def _in_range(r: _Root, lo: fmpq | None, hi: fmpq | None) -> bool:
    return (lo is None or r.cmp(lo) > 0) and (hi is None or r.cmp(hi) <= 0)


def count_real_roots(
    p: Poly, lo: RationalLike | None = None, hi: RationalLike | None = None
) -> int:
    """Number of distinct real roots of ``p`` in the half-open interval ``(lo, hi]``.

    ``lo=None`` stands for ``-infinity`` and ``hi=None`` for ``+infinity``.
    ``p`` need not be squarefree; the zero polynomial is an error.

    >>> x = fmpq_poly([0, 1])
    >>> count_real_roots((x**2 - 2) * (x - 1) ** 2 * (x**2 + 1), 0)
    2
    """
    if p.is_zero():
        raise ValueError("the zero polynomial has every number as a root")
    sf = squarefree_part(p)
    if sf.degree() <= 0:
        return 0
    lo_q = None if lo is None else rational(lo)
    hi_q = None if hi is None else rational(hi)
    if lo_q is not None and hi_q is not None and hi_q <= lo_q:
        return 0
    return sum(1 for r in _certified_real_roots(sf) if _in_range(r, lo_q, hi_q))


def isolate_real_roots(
    p: Poly, lo: RationalLike | None = None, hi: RationalLike | None = None
) -> list[Interval]:
    """Disjoint intervals ``(a, b]``, each holding exactly one distinct root of ``p`` in ``(lo, hi]``.

    Sorted increasingly.  ``lo=None`` means ``−cauchy_bound``, ``hi=None``
    means ``max(cauchy_bound, lo + 1)``: every root lies inside.  The intervals
    are those of bisecting ``(lo, hi]`` until each part holds at most one root
    (a root at a bisection point ``b`` lies in ``(a, b]``).

    >>> x = fmpq_poly([0, 1])
    >>> isolate_real_roots((x - 1) * (x - 3) * (x**2 - 2), 0)
    [(0, 9/8), (9/8, 9/4), (9/4, 9/2)]
    """
    if p.is_zero():
        raise ValueError("the zero polynomial has every number as a root")
    sf = squarefree_part(p)
    if sf.degree() <= 0:
        return []
    bound = cauchy_bound(sf)
    a0 = -bound if lo is None else rational(lo)
    b0 = max(bound, a0 + 1) if hi is None else rational(hi)
    if b0 <= a0:
        return []
    roots = [r for r in _certified_real_roots(sf) if _in_range(r, a0, b0)]
    out: list[Interval] = []
    stack: list[tuple[fmpq, fmpq, list[_Root]]] = [(a0, b0, roots)]
    while stack:
        a, b, rs = stack.pop()
        if len(rs) == 1:
            out.append((a, b))
        elif len(rs) > 1:
            mid = (a + b) / 2
            left = [r for r in rs if r.cmp(mid) <= 0]
            stack.append((a, mid, left))
            stack.append((mid, b, rs[len(left) :]))
    return sorted(out)


def _bisect_once(sf: Poly, a: fmpq, b: fmpq) -> Interval:
    """One bisection step on the unique simple root of ``sf`` in ``(a, b]``, ``sf(b) != 0``."""
    mid = (a + b) / 2
    fm = sf(mid)
    if fm == 0:
        return mid, mid
    if (fm > 0) == (sf(b) > 0):
        return a, mid
    return mid, b


def _bisect_while(sf: Poly, iv: Interval, more: Callable[[fmpq, fmpq], bool]) -> Interval:
    """Bisect ``(a, b]`` on the simple root of ``sf`` while ``more(a, b)``; ``(r, r]`` if met."""
    a, b = iv
    if a == b:
        return b, b
    sb = sign(sf(b))
    if sb == 0:
        return b, b
    for _ in range(MAX_BISECTIONS):
        if not more(a, b):
            return a, b
        mid = (a + b) / 2
        sm = sign(sf(mid))
        if sm == 0:
            return mid, mid
        a, b = (a, mid) if sm == sb else (mid, b)
    raise ArithmeticError(f"no isolating interval after {MAX_BISECTIONS} bisections")


def _refine_sf(sf: Poly, iv: Interval, width: fmpq) -> Interval:
    return _bisect_while(sf, iv, lambda a, b: b - a > width)


def refine_past(p: Poly, iv: Interval, x: RationalLike) -> Interval:
    """Bisect an isolating interval ``(a, b]`` of a root of ``p`` until ``a > x`` (or ``a == b``).

    The same intervals as halving the width with `refine` step by step, with
    the squarefree part computed once.  The root must lie above ``x``.

    >>> refine_past(fmpq_poly([-2, 0, 1]), (fmpq(0), fmpq(2)), 1)   # √2 in (5/4, 3/2]
    (5/4, 3/2)
    """
    xq = rational(x)
    if iv[0] > xq:
        return iv
    return _bisect_while(squarefree_part(p), iv, lambda a, b: a <= xq)


def refine(p: Poly, iv: Interval, width: RationalLike) -> Interval:
    """Shrink an isolating interval ``(a, b]`` of a root of ``p`` to a width ``<= width``.

    Exact bisection on the squarefree part of ``p``; a root met exactly gives ``(r, r]``.
    """
    return _refine_sf(squarefree_part(p), iv, rational(width))


def root_value(p: Poly, iv: Interval) -> float:
    """The root of ``p`` in ``(a, b]`` as a float, to full double precision.

    Exact bisection to a width of ``max(|b|, 1)·2^-60``, continued for roots
    below about ``2^-8`` until the width is ``2^-60`` relative to the root.
    Raises `OverflowError` when the root is beyond the double range.
    """
    a, b = iv
    if a == b:
        return float(a)
    sf = squarefree_part(p)
    a, b = _refine_sf(sf, iv, max(abs(b), fmpq(1)) / fmpq(2) ** 60)
    if a < 0 <= b and sf(0) == 0:
        return 0.0
    # tiny roots: the absolute width above is coarser than double precision
    while a != b and (a < 0 <= b or b - a > min(abs(a), abs(b)) / fmpq(2) ** 60):
        a, b = _bisect_once(sf, a, b)
    return float((a + b) / 2)


def sign_at_root(q: Poly, p: Poly, iv: Interval) -> int:
    """Exact sign of ``q`` at the unique root of ``p`` in ``(a, b]``.

    >>> x = fmpq_poly([0, 1])
    >>> p = x**2 - 2
    >>> (iv,) = isolate_real_roots(p, 0)
    >>> sign_at_root(x - fmpq(141421356, 10**8), p, iv), sign_at_root(p * (x + 3), p, iv)
    (1, 0)
    """
    sf = squarefree_part(p)
    a, b = iv
    if a == b or sf(b) == 0:
        return sign(q(b))
    g = sf.gcd(q)
    if g.degree() >= 1 and count_real_roots(g, a, b) == 1:
        return 0
    sq = squarefree_part(q)
    if sq.degree() >= 1:
        roots = _certified_real_roots(sq)
        for _ in range(MAX_BISECTIONS):
            if not any(_in_range(r, a, b) for r in roots):
                break
            a, b = _bisect_once(sf, a, b)
            if a == b:
                break
        else:  # pragma: no cover - q(root) != 0, so the loop ends far earlier
            raise ArithmeticError("sign_at_root: bisection did not separate the roots")
    return sign(q(b))
