"""The exact polynomial kernel before python-flint (benchmark reference only).

A frozen copy of ``seapass.exact.poly`` as it was before it moved onto
python-flint (seapass 0.1.0, ``exactpoly.py``): Sturm sequences in Python
Fractions.  ``bench_exact.py`` times it against the current kernel on the same
inputs.  Not part of the package.

Exact univariate polynomial arithmetic over the rationals.

Polynomials are tuples of `fractions.Fraction` in *ascending* powers:
``(a0, a1, a2)`` is ``a0 + a1 x + a2 x**2``.  The zero polynomial is ``()``.
Everything here is exact; nothing is decided in floating point.  The routines
are small on purpose (the degrees in SEA analysis are below ~20), and fast
enough to be called thousands of times.

References
----------
.. [1] S. Basu, R. Pollack, M.-F. Roy, *Algorithms in Real Algebraic Geometry*,
   2nd ed., Springer, 2006, ch. 2 (Sturm sequences, root isolation).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from fractions import Fraction

__all__ = [
    "Poly",
    "cauchy_bound",
    "count_real_roots",
    "degree",
    "derivative",
    "evaluate",
    "isolate_real_roots",
    "normalize",
    "pdivmod",
    "pgcd",
    "positive_roots_odd_multiplicity",
    "refine",
    "root_value",
    "sign_at_root",
    "squarefree_part",
    "sturm_sequence",
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
    acc = Fraction(0)
    for c in reversed(p):
        acc = acc * x + c
    return acc


def add(p: Poly, q: Poly) -> Poly:
    n = max(len(p), len(q))
    return normalize([(p[i] if i < len(p) else 0) + (q[i] if i < len(q) else 0) for i in range(n)])


def scale(p: Poly, c: Fraction) -> Poly:
    return normalize([c * x for x in p])


def sub(p: Poly, q: Poly) -> Poly:
    return add(p, scale(q, Fraction(-1)))


def mul(p: Poly, q: Poly) -> Poly:
    if not p or not q:
        return ()
    out = [Fraction(0)] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        if a:
            for j, b in enumerate(q):
                out[i + j] += a * b
    return normalize(out)


def derivative(p: Poly) -> Poly:
    return normalize([i * p[i] for i in range(1, len(p))])


def pdivmod(p: Poly, q: Poly) -> tuple[Poly, Poly]:
    """Polynomial long division ``p = quot*q + rem`` with ``deg rem < deg q``."""
    if not q:
        raise ZeroDivisionError("polynomial division by zero")
    rem = list(p)
    dq = len(q) - 1
    lead = q[-1]
    quot = [Fraction(0)] * max(len(p) - dq, 0)
    for k in range(len(p) - 1 - dq, -1, -1):
        c = rem[k + dq] / lead
        quot[k] = c
        if c:
            for j, qc in enumerate(q):
                rem[k + j] -= c * qc
    return normalize(quot), normalize(rem[:dq] if dq > 0 else [])


def monic(p: Poly) -> Poly:
    return scale(p, 1 / p[-1]) if p else p


def pgcd(p: Poly, q: Poly) -> Poly:
    """Monic greatest common divisor (``()`` if both are zero)."""
    a, b = normalize(p), normalize(q)
    while b:
        a, b = b, pdivmod(a, b)[1]
    return monic(a)


def squarefree_part(p: Poly) -> Poly:
    """``p / gcd(p, p')``, monic: same roots, each simple."""
    if degree(p) <= 0:
        return monic(p)
    g = pgcd(p, derivative(p))
    return monic(pdivmod(p, g)[0])


def sturm_sequence(p: Poly) -> list[Poly]:
    """Sturm sequence of a square-free polynomial ``p``."""
    seq = [p, derivative(p)]
    while seq[-1]:
        r = pdivmod(seq[-2], seq[-1])[1]
        if not r:
            break
        seq.append(scale(r, Fraction(-1)))
    return seq


def _sign_changes(vals: list[Fraction]) -> int:
    nz = [v for v in vals if v != 0]
    return sum(1 for a, b in itertools.pairwise(nz) if (a > 0) != (b > 0))


def _changes_at(seq: list[Poly], x: Fraction | None) -> int:
    """Sign changes at ``x``; ``x=None`` means ``+infinity``."""
    if x is None:
        return _sign_changes([q[-1] for q in seq if q])
    return _sign_changes([evaluate(q, x) for q in seq])


def count_real_roots(p: Poly, lo: Fraction, hi: Fraction | None) -> int:
    """Number of distinct real roots of ``p`` in the half-open interval ``(lo, hi]``.

    ``hi=None`` stands for ``+infinity``.  ``p`` need not be square-free.
    """
    p = squarefree_part(p)
    if degree(p) <= 0:
        return 0
    seq = sturm_sequence(p)
    return _changes_at(seq, lo) - _changes_at(seq, hi)


def cauchy_bound(p: Poly) -> Fraction:
    """Every real root ``r`` of ``p`` satisfies ``|r| < bound``."""
    lead = abs(p[-1])
    return 1 + max((abs(c) / lead for c in p[:-1]), default=Fraction(0))


def isolate_real_roots(
    p: Poly, lo: Fraction, hi: Fraction | None = None
) -> list[tuple[Fraction, Fraction]]:
    """Disjoint intervals ``(a, b]`` each holding exactly one distinct root of ``p`` in ``(lo, hi]``.

    ``hi=None`` means ``+infinity``.  Sorted increasingly.  Sturm counts are
    valid on half-open intervals even when an endpoint is a root.
    """
    sp_ = squarefree_part(p)
    if degree(sp_) <= 0:
        return []
    if hi is None:
        hi = max(cauchy_bound(sp_), lo + 1)
    seq = sturm_sequence(sp_)
    out: list[tuple[Fraction, Fraction]] = []
    stack = [(lo, hi, _changes_at(seq, lo), _changes_at(seq, hi))]
    while stack:
        a, b, ca, cb = stack.pop()
        n = ca - cb
        if n == 1:
            out.append((a, b))
        elif n > 1:
            mid = (a + b) / 2
            cm = _changes_at(seq, mid)
            stack.append((a, mid, ca, cm))
            stack.append((mid, b, cm, cb))
    return sorted(out)


def _bisect_once(p: Poly, a: Fraction, b: Fraction) -> tuple[Fraction, Fraction]:
    """One bisection step on the unique simple root of ``p`` in ``(a, b]``, ``p(b) != 0``."""
    mid = (a + b) / 2
    fm = evaluate(p, mid)
    if fm == 0:
        return mid, mid
    if (fm > 0) == (evaluate(p, b) > 0):
        return a, mid
    return mid, b


def refine(p: Poly, a: Fraction, b: Fraction, width: Fraction) -> tuple[Fraction, Fraction]:
    """Shrink an isolating interval ``(a, b]`` of square-free ``p`` to below ``width``."""
    if evaluate(p, b) == 0:
        return b, b
    while b - a > width and a != b:
        a, b = _bisect_once(p, a, b)
    return a, b


def root_value(p: Poly, a: Fraction, b: Fraction) -> float:
    """The root of square-free ``p`` in ``(a, b]`` as a float, to full double precision."""
    a, b = refine(p, a, b, max(abs(b), Fraction(1)) * Fraction(1, 2**60))
    return float((a + b) / 2)


def sign_at_root(q: Poly, p: Poly, a: Fraction, b: Fraction) -> int:
    """Exact sign of ``q`` at the unique root of square-free ``p`` in ``(a, b]``."""
    if evaluate(p, b) == 0:
        a = b
    if a == b:
        v = evaluate(q, a)
        return (v > 0) - (v < 0)
    g = pgcd(p, q)
    if degree(g) >= 1 and count_real_roots(g, a, b) == 1:
        return 0
    while count_real_roots(q, a, b) > 0:
        a, b = _bisect_once(p, a, b)
        if a == b:
            break
    v = evaluate(q, b)
    return (v > 0) - (v < 0)


def positive_roots_odd_multiplicity(p: Poly) -> Poly:
    """Product of the square-free factors of odd multiplicity (Yun's algorithm)."""
    if degree(p) <= 0:
        return (Fraction(1),)
    factors: list[Poly] = []
    a = monic(p)
    b = derivative(a)
    c = pgcd(a, b)
    w = pdivmod(a, c)[0]
    while degree(w) > 0:
        y = pgcd(w, c)
        factors.append(monic(pdivmod(w, y)[0]))
        w = y
        c = pdivmod(c, y)[0]
    out: Poly = (Fraction(1),)
    for i, f in enumerate(factors, start=1):
        if i % 2 == 1:
            out = mul(out, f)
    return out
