"""Certified sign of a multivariate polynomial on a box: exact Bernstein enclosures.

A polynomial ``f(v_0, …, v_k)`` is stored as a dense array of exact rationals
(`flint.fmpq`), ``coeffs[i_0, …, i_k]`` the coefficient of ``v_0^i_0 ⋯ v_k^i_k``.
On a box ``[a_0, b_0] × ⋯`` its tensor Bernstein coefficients enclose its range
(the range lies between their minimum and maximum, the corner coefficients are
the values at the corners), and halving the box along one axis (de Casteljau)
tightens the enclosure quadratically.  Everything is exact rational arithmetic:
nothing is rounded.

`positive_on_box` runs a best-first branch and bound with a counted budget:

* a box whose Bernstein coefficients are all ``> 0`` is **proven** positive;
* a corner coefficient ``≤ 0`` is an exact **point** where ``f ≤ 0``;
* otherwise the box is halved along the axis where the coefficients vary most.

It ends with ``PROVEN`` (every box proven), ``POINT`` (with the point), or
``BUDGET`` (boxes left when the budget ran out: not proven, never a "yes").

References
----------
.. [1] J. Garloff, "The Bernstein algorithm", Interval Computations 2, 1993.
.. [2] P. S. V. Nataraj and K. Kotecha, "Global optimization with higher order
   inclusion function forms, part 1", Reliable Computing 10, 2004 (Bernstein
   branch and bound).
"""

from __future__ import annotations

import heapq
import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from math import comb
from typing import Any

import numpy as np
from flint import fmpq

__all__ = ["BoxSign", "SignSearch", "bernstein_coefficients", "from_terms", "positive_on_box"]


class BoxSign(StrEnum):
    """How a branch and bound ended."""

    PROVEN = "proven"
    POINT = "point"
    BUDGET = "budget"


@dataclass(frozen=True, kw_only=True)
class SignSearch:
    """Result of `positive_on_box`.

    Attributes
    ----------
    sign : BoxSign
        ``PROVEN`` (``f > 0`` on the whole box), ``POINT`` (``f(point) ≤ 0``,
        exact) or ``BUDGET`` (neither within ``budget`` boxes).
    point : tuple of fmpq or None
        The exact point where ``f ≤ 0`` (``POINT`` only).
    boxes : int
        Boxes examined.
    """

    sign: BoxSign
    point: tuple[fmpq, ...] | None = None
    boxes: int = 0


def from_terms(terms: Mapping[tuple[int, ...], fmpq], nvars: int) -> np.ndarray:
    """Dense coefficient array of ``{exponents: coefficient}`` with ``nvars`` variables."""
    if not terms:
        return np.full((1,) * nvars, fmpq(0), dtype=object)
    shape = tuple(max(e[i] for e in terms) + 1 for i in range(nvars))
    arr = np.full(shape, fmpq(0), dtype=object)
    for e, c in terms.items():
        arr[e] = arr[e] + fmpq(c)
    return arr


def _axis_matrix(n: int, a: fmpq, b: fmpq) -> np.ndarray:
    """``M[i, j]``: Bernstein coefficient ``i`` on ``[a, b]`` of the monomial ``v^j`` (degree ``n``)."""
    w = b - a
    m = np.full((n + 1, n + 1), fmpq(0), dtype=object)
    for i in range(n + 1):
        for j in range(n + 1):
            acc = fmpq(0)
            for k in range(min(i, j) + 1):
                acc += fmpq(comb(i, k) * comb(j, k), comb(n, k)) * a ** (j - k) * w**k
            m[i, j] = acc
    return m


def _along(m: np.ndarray, arr: np.ndarray, axis: int) -> np.ndarray:
    out = np.tensordot(m, arr, axes=([1], [axis]))
    return np.moveaxis(out, 0, axis)


def bernstein_coefficients(coeffs: np.ndarray, box: Sequence[tuple[fmpq, fmpq]]) -> np.ndarray:
    """Tensor Bernstein coefficients of ``coeffs`` on ``box`` (one ``(lo, hi)`` per axis).

    >>> from flint import fmpq
    >>> f = from_terms({(2,): fmpq(1), (0,): fmpq(-1)}, 1)  # v² − 1
    >>> print(*bernstein_coefficients(f, [(fmpq(0), fmpq(2))]))
    -1 -1 3
    """
    out = coeffs
    for axis, (a, b) in enumerate(box):
        out = _along(_axis_matrix(out.shape[axis] - 1, fmpq(a), fmpq(b)), out, axis)
    return out


def _halves(arr: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """de Casteljau at ``u = 1/2`` along ``axis``: Bernstein coefficients of both halves."""
    b = np.moveaxis(arr, axis, 0).copy()
    n = b.shape[0] - 1
    left = [b[0]]
    right = [b[n]]
    half = fmpq(1, 2)
    for _ in range(n):
        b = (b[:-1] + b[1:]) * half
        left.append(b[0])
        right.append(b[-1])
    lo = np.moveaxis(np.stack(left), 0, axis)
    hi = np.moveaxis(np.stack(right[::-1]), 0, axis)
    return lo, hi


def _split_axis(arr: np.ndarray) -> int:
    """The axis along which the coefficients vary most (ties: the first)."""
    best, best_axis = fmpq(-1), 0
    for axis in range(arr.ndim):
        if arr.shape[axis] < 2:
            continue
        d = np.diff(arr, axis=axis)
        v = max(abs(x) for x in d.flat)
        if v > best:
            best, best_axis = v, axis
    return best_axis


def _corners(arr: np.ndarray) -> list[tuple[tuple[int, ...], Any]]:
    idx = [(0, s - 1) if s > 1 else (0,) for s in arr.shape]
    return [(c, arr[c]) for c in itertools.product(*idx)]


def positive_on_box(
    coeffs: np.ndarray,
    box: Sequence[tuple[fmpq, fmpq]],
    *,
    budget: int,
) -> SignSearch:
    """Prove ``f > 0`` on ``box``, or find an exact point where ``f ≤ 0``, within ``budget`` boxes.

    Parameters
    ----------
    coeffs : ndarray of fmpq
        Dense coefficients (see `from_terms`), one axis per variable of ``box``.
    box : sequence of (fmpq, fmpq)
        The box, ``lo <= hi`` on every axis.
    budget : int
        Most boxes examined.

    Examples
    --------
    >>> from flint import fmpq
    >>> f = from_terms({(2,): fmpq(1), (1,): fmpq(-2), (0,): fmpq(11, 10)}, 1)  # (v−1)² + 0.1
    >>> positive_on_box(f, [(fmpq(0), fmpq(3))], budget=100).sign
    <BoxSign.PROVEN: 'proven'>
    >>> g = from_terms({(2,): fmpq(1), (1,): fmpq(-2), (0,): fmpq(9, 10)}, 1)  # (v−1)² − 0.1
    >>> r = positive_on_box(g, [(fmpq(0), fmpq(3))], budget=100)
    >>> print(r.sign, *r.point)
    point 3/4
    """
    lows = [fmpq(a) for a, _ in box]
    highs = [fmpq(b) for _, b in box]
    start = bernstein_coefficients(coeffs, list(zip(lows, highs, strict=True)))
    counter = itertools.count()
    heap: list[tuple[float, int, np.ndarray, list[fmpq], list[fmpq]]] = []
    heapq.heappush(heap, (0.0, next(counter), start, lows, highs))
    boxes = 0
    while heap:
        if boxes >= budget:
            return SignSearch(sign=BoxSign.BUDGET, boxes=boxes)
        _key, _n, arr, lo, hi = heapq.heappop(heap)
        boxes += 1
        for corner, value in _corners(arr):
            if value <= 0:
                point = tuple(hi[i] if c else lo[i] for i, c in enumerate(corner))
                return SignSearch(sign=BoxSign.POINT, point=point, boxes=boxes)
        low = min(arr.flat)
        if low > 0:
            continue
        axis = _split_axis(arr)
        mid = (lo[axis] + hi[axis]) / 2
        left, right = _halves(arr, axis)
        for part, a, b in ((left, lo[axis], mid), (right, mid, hi[axis])):
            nlo, nhi = list(lo), list(hi)
            nlo[axis], nhi[axis] = a, b
            key = float(min(part.flat))
            heapq.heappush(heap, (key, next(counter), part, nlo, nhi))
    return SignSearch(sign=BoxSign.PROVEN, boxes=boxes)
