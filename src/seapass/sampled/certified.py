"""Certified decisions on ball polynomials: sign on an interval, Schur stability.

Everything here takes python-flint balls whose enclosures are rigorous and decides only
what the balls prove: a sign is returned when a ball excludes zero, otherwise the answer
is "undecided" and the caller raises the working precision (or reports that it could not
decide).  Nothing is concluded from a ball that contains zero.

* `sign_on` decides ``p(x) > 0`` on ``[lo, hi]`` or finds ``x`` with ``p(x) < 0``, by
  Descartes' rule of signs on Möbius-transformed intervals (Vincent–Collins–Akritas
  bisection).  It also works for a family ``p(x; λ)``, ``λ`` in a box, given the Bernstein
  coefficients of ``p`` in ``λ`` (`bernstein`): the family lies in their convex hull,
  so a positive answer holds for every ``λ`` in the box.
* `schur_stable` decides whether all roots of a ball polynomial lie strictly inside
  the unit disk (Schur–Cohn reduction); `schur_stable_exact` does the same exactly.
* `interpolation_matrix` maps values at Chebyshev nodes to monomial coefficients
  (exact for polynomials of the given degree).

References
----------
.. [1] G. E. Collins, A. G. Akritas, "Polynomial real root isolation using Descartes'
   rule of signs", SYMSAC 1976.
.. [2] P. Henrici, *Applied and Computational Complex Analysis*, vol. 1, Wiley, 1974,
   §6.8 (the Schur–Cohn algorithm).
.. [3] F. Johansson, "Arb: efficient arbitrary-precision midpoint-radius interval
   arithmetic", IEEE Trans. Computers 66(8), 2017.
"""

from __future__ import annotations

import enum
import functools
import itertools
import math
import threading
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from flint import acb, arb, arb_mat, arb_poly, ctx, fmpq

__all__ = [
    "Sign",
    "SignResult",
    "interpolation_matrix",
    "precision",
    "schur_stable",
    "schur_stable_exact",
    "sign_on",
]

#: python-flint keeps its working precision in one process-wide context: every
#: computation that sets it holds this lock, so threads cannot change it mid-way.
_PRECISION_LOCK = threading.RLock()


@contextmanager
def precision(bits: int) -> Iterator[None]:
    """Work at ``bits`` of precision (thread-safe for seapass' own computations)."""
    with _PRECISION_LOCK, ctx.workprec(bits):
        yield


class Sign(enum.Enum):
    """Outcome of `sign_on`."""

    POSITIVE = "positive"
    NEGATIVE = "negative"
    UNDECIDED = "undecided"


@dataclass(frozen=True, kw_only=True)
class SignResult:
    """``sign``; ``witness``: an ``x`` with ``p(x) < 0`` proven (point decisions only)."""

    sign: Sign
    witness: Fraction | None = None
    intervals: int = 0
    partition: tuple[tuple[Fraction, Fraction], ...] = ()


def _transformed(p: arb_poly, a: arb, b: arb, n: int) -> list[arb]:
    """Coefficients of ``(1+t)^n p((a + b t)/(1 + t))`` (all positive ⇒ ``p > 0`` on ``[a, b]``)."""
    c = p(arb_poly([a, b - a])).coeffs()
    c = c + [arb(0)] * (n + 1 - len(c))
    return arb_poly(list(reversed(c)))(arb_poly([1, 1])).coeffs()


def _signs(coeffs: list[arb]) -> list[int] | None:
    out = []
    for x in coeffs:
        if x > 0:
            out.append(1)
        elif x < 0:
            out.append(-1)
        elif x.is_zero():
            continue
        else:
            return None
    return out


def _arb(x: Fraction) -> arb:
    return arb(fmpq(x.numerator, x.denominator))


def negative_at(controls: Sequence[arb_poly], x: Fraction) -> bool:
    """Every member of the family is negative at ``x`` (all control polynomials are)."""
    xa = _arb(x)
    return all(p(xa) < 0 for p in controls)


def sign_on(
    controls: Sequence[arb_poly],
    lo: Fraction,
    hi: Fraction,
    *,
    budget: int = 400,
    probes: Sequence[Fraction] = (),
    start: Sequence[tuple[Fraction, Fraction]] = (),
) -> SignResult:
    """Certified sign on ``[lo, hi]`` of a polynomial, or of a family of polynomials.

    ``controls`` are polynomials whose convex combinations contain the family (one
    polynomial for a point decision; Bernstein coefficients in a parameter for a box).
    Call under `precision`.  Returns POSITIVE (every member ``> 0`` on the closed
    ``[lo, hi]``), NEGATIVE (a proven negative value: ``witness`` for a point decision; for
    a family some ``x`` where every member is negative), or UNDECIDED when ``budget``
    sub-intervals did not settle it.  ``probes`` are tried first for a negative value;
    ``start`` is a partition of ``[lo, hi]`` to begin with (e.g. the ``partition`` of a
    previous positive answer for a nearby family).
    """
    n = max((p.degree() for p in controls), default=-1)
    if n < 0:
        return SignResult(sign=Sign.UNDECIDED)
    point = len(controls) == 1
    for x in (*probes, lo, hi, (lo + hi) / 2):
        if negative_at(controls, x):
            return SignResult(sign=Sign.NEGATIVE, witness=x)
    stack = list(reversed(start)) if start else [(lo, hi)]
    count = 0
    certified: list[tuple[Fraction, Fraction]] = []
    while stack:
        a, b = stack.pop()
        count += 1
        if count > budget:
            return SignResult(sign=Sign.UNDECIDED, witness=None, intervals=count)
        aa, bb = _arb(a), _arb(b)
        all_signs = [_signs(_transformed(p, aa, bb, n)) for p in controls]
        if all(s is not None and s and all(v > 0 for v in s) for s in all_signs):
            certified.append((a, b))  # every control > 0 on the closed [a, b]
            continue
        if point and all_signs[0]:
            signs = all_signs[0]
            if all(v < 0 for v in signs):
                return SignResult(sign=Sign.NEGATIVE, witness=(a + b) / 2, intervals=count)
            changes = sum(1 for u, v in itertools.pairwise(signs) if u != v)
            if changes % 2 == 1:  # an odd number of roots in (a, b): a sign change
                for x in (a, b):
                    if negative_at(controls, x):
                        return SignResult(sign=Sign.NEGATIVE, witness=x, intervals=count)
        mid = (a + b) / 2
        if negative_at(controls, mid):
            return SignResult(sign=Sign.NEGATIVE, witness=mid, intervals=count)
        if not point and any(p(_arb(mid)) < 0 for p in controls):
            # the box is too wide in λ
            return SignResult(sign=Sign.UNDECIDED, witness=None, intervals=count)
        stack.append((mid, b))
        stack.append((a, mid))
    return SignResult(
        sign=Sign.POSITIVE, witness=None, intervals=count, partition=tuple(sorted(certified))
    )


def bernstein(taylor: Sequence, width: Any) -> list:
    """Bernstein coefficients over ``μ ∈ [0, 1]`` of ``Σ_j c_j (width μ)^j`` (``c_j`` at the
    left end of the box); the family's values lie in their convex hull."""
    K = len(taylor) - 1
    scaled = [c * width**j for j, c in enumerate(taylor)]
    out = []
    for i in range(K + 1):
        acc = None
        for j in range(i + 1):
            term = scaled[j] * fmpq(math.comb(i, j), math.comb(K, j))
            acc = term if acc is None else acc + term
        out.append(acc)
    return out


def schur_stable(coeffs: Sequence[acb | arb]) -> bool | None:
    """All roots of ``Σ c_k z^k`` strictly inside the unit circle; ``None`` if undecided.

    ``p → (ā_n p − a_0 p*)/z`` keeps "all roots inside" iff ``|a_0| < |a_n|``; a proven
    ``|a_0| ≥ |a_n|`` at any step proves a root on or outside the circle.
    """
    a = [acb(c) for c in coeffs]
    while len(a) > 1 and a[-1].is_zero():
        a.pop()
    while len(a) > 1:
        a0, an = a[0], a[-1]
        m0 = (a0 * a0.conjugate()).real
        mn = (an * an.conjugate()).real
        if not m0 < mn:
            return False if m0 >= mn else None
        n = len(a) - 1
        anc = an.conjugate()
        a = [anc * a[k] - a0 * a[n - k].conjugate() for k in range(1, n + 1)]
    return True


def schur_stable_exact(coeffs: Sequence[Fraction]) -> bool:
    """`schur_stable` for rational coefficients, decided exactly."""
    a = [fmpq(c.numerator, c.denominator) for c in coeffs]
    while len(a) > 1 and a[-1] == 0:
        a.pop()
    while len(a) > 1:
        a0, an = a[0], a[-1]
        if not a0 * a0 < an * an:
            return False
        n = len(a) - 1
        a = [an * a[k] - a0 * a[n - k] for k in range(1, n + 1)]
    return True


def chebyshev_nodes(n: int) -> list[arb]:
    """``θ_i = π (2i + 1)/(2n + 2)``, ``i = 0..n`` (call under `precision`)."""
    pi = arb.pi()
    return [pi * (2 * i + 1) / (2 * (n + 1)) for i in range(n + 1)]


@functools.lru_cache(maxsize=64)
def interpolation_matrix(n: int, prec: int) -> arb_mat:
    """Values at ``cos θ_i`` (`chebyshev_nodes`) → monomial coefficients, degree ≤ n."""
    with precision(prec):
        theta = chebyshev_nodes(n)
        dct = arb_mat(n + 1, n + 1)
        for k in range(n + 1):
            scale = arb(2) / (n + 1) / (2 if k == 0 else 1)
            for i in range(n + 1):
                dct[k, i] = (k * theta[i]).cos() * scale
        to_mono = arb_mat(n + 1, n + 1)
        t_prev: list[int] = [1]
        t_cur: list[int] = [0, 1]
        for k in range(n + 1):
            if k == 0:
                tk = t_prev
            elif k == 1:
                tk = t_cur
            else:
                nxt = [0, *(2 * c for c in t_cur)]
                for j, c in enumerate(t_prev):
                    nxt[j] -= c
                t_prev, t_cur = t_cur, nxt
                tk = t_cur
            for j, c in enumerate(tk):
                to_mono[j, k] = c
        return to_mono * dct


def _chebyshev_to_monomial(c: Sequence[arb]) -> arb_poly:
    """``Σ c_k T_k(x)`` as a monomial-basis ball polynomial."""
    out = arb_poly([0])
    t_prev, t_cur = arb_poly([1]), arb_poly([0, 1])
    for k, ck in enumerate(c):
        if k == 0:
            tk = t_prev
        elif k == 1:
            tk = t_cur
        else:
            t_prev, t_cur = t_cur, arb_poly([0, 2]) * t_cur - t_prev
            tk = t_cur
        out += tk * ck
    return out


def modulus_on_circle(family: Sequence[Sequence[arb]]) -> list[arb_poly]:
    """``|χ(e^{jφ}; λ)|² = Σ_k λ^k M_k(cos φ)`` for ``χ = Σ_a λ^a χ_a(z)`` (real coefficients).

    ``family[a]`` are the ascending ``z``-coefficients of ``χ_a``.  ``M_k > 0`` on ``[−1, 1]``
    over a box in ``λ`` proves that no root of ``χ`` crosses the unit circle there.
    """
    K = len(family) - 1
    n = max((len(f) for f in family), default=0)
    out = []
    for k in range(2 * K + 1):
        cheb = [arb(0)] * n
        for a in range(max(0, k - K), min(k, K) + 1):
            fa, fb = family[a], family[k - a]
            for i, x in enumerate(fa):
                for j, y in enumerate(fb):
                    d = abs(i - j)  # z^i z^{-j} + conj = 2 cos((i - j) φ)
                    cheb[d] += x * y
        out.append(_chebyshev_to_monomial(cheb))
    return out
