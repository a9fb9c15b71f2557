"""Conditions that vanish on a face of the box: prove them off the face, decide the face apart.

A box often has a face where the structure of the plant changes: a damper ``b1 = 0`` at
the low end of ``b1 ∈ [0, 300]`` drops the degree of ``N`` and of ``Re Z``'s numerator.
There a family condition of [`seapass.robust.family`][seapass.robust.family] is zero, not
negative, so the Bernstein search ([`positive_on_box`][seapass.robust.bernstein.positive_on_box])
stops at a corner that is not a counterexample.  The box is then split into the face
(a box with one parameter fewer, decided on its own) and the rest, where the condition
is replaced by sufficient conditions that hold strictly on the closed box:

* a condition ``f(p)`` divisible by ``(p_i − c)^r`` (``c`` the face's end, ``r`` as large
  as exact division allows): ``f/(p_i − c)^r`` has the sign of ``f`` off the face, with
  ``(c − p_i)`` at the upper end so that the factor is positive inside;
* the compactified real part ``Q(t, p)`` whose value at ``t = 1`` (the leading
  coefficient ``c_d(p)`` of ``P(x)``) is zero on the face: with
  ``Q = c_d(p)·t^e + (1 − t)·Q_R(t, p)`` (``e`` the degree of ``Q`` in ``t``), ``c_d > 0``
  off the face (the first rule) and ``Q_R > 0`` on ``[0, 1] × box`` give ``Q > 0`` off
  the face for ``t < 1`` and ``Q(1) = c_d > 0``.

Where two such faces meet, or where the condition vanishes on the face only at an edge
(``Re Z``'s numerator at ``t = 1`` and ``b1 = 0``), the quotients are not enough: the
condition is zero at a corner and negative nowhere, but no quotient is positive on the
whole closed box.  [`seapass.robust.corners`][seapass.robust.corners] then blows the
corner up; the substitutions it needs live here (`shift_axis`, `blow_axis`), each an
exact identity of polynomials.

Everything is exact rational arithmetic on the dense coefficient arrays of
[`seapass.robust.bernstein`][seapass.robust.bernstein].
"""

from __future__ import annotations

from math import comb

import numpy as np
from flint import fmpq, fmpz

__all__ = ["at_value", "blow_axis", "divide_out", "evaluate", "shift_axis", "split_top"]


def at_value(coeffs: np.ndarray, axis: int, c: fmpq) -> np.ndarray:
    """``coeffs`` with variable ``axis`` set to ``c`` (the axis keeps length 1).

    >>> from seapass.robust.bernstein import from_terms
    >>> f = from_terms({(1,): fmpq(2), (0,): fmpq(-4)}, 1)  # 2v - 4
    >>> print(*at_value(f, 0, fmpq(2)).flat)
    0
    """
    a = np.moveaxis(coeffs, axis, 0)
    acc = np.asarray(a[-1], dtype=object).copy()  # a 0-d array when coeffs is 1-D
    for j in range(a.shape[0] - 2, -1, -1):
        acc = np.asarray(acc * c + a[j], dtype=object)
    return np.moveaxis(acc[np.newaxis, ...], 0, axis)


def _is_zero(arr: np.ndarray) -> bool:
    return all(x == 0 for x in np.asarray(arr, dtype=object).flat)


def divide_out(coeffs: np.ndarray, axis: int, c: fmpq, *, upper: bool) -> np.ndarray | None:
    """``coeffs / (v − c)^r`` (``(c − v)^r`` when ``upper``), ``r ≥ 1`` as large as exact
    division allows along ``axis``; None when ``coeffs`` does not vanish on ``v = c``.

    >>> from seapass.robust.bernstein import from_terms
    >>> f = from_terms({(2,): fmpq(3), (1,): fmpq(0)}, 1)  # 3v²
    >>> print(*divide_out(f, 0, fmpq(0), upper=False).flat)
    3
    """
    a = np.moveaxis(coeffs, axis, 0)
    divided = 0
    while a.shape[0] > 1:
        n = a.shape[0] - 1
        q = [a[n]]  # synthetic division by (v - c): b_{n-1} = a_n, b_{j-1} = a_j + c b_j
        for j in range(n - 1, 0, -1):
            q.append(a[j] + c * q[-1])
        remainder = a[0] + c * q[-1]
        if not _is_zero(remainder):
            break
        a = np.stack(q[::-1])
        divided += 1
        if upper:
            a = -a
    if divided == 0:
        return None
    return np.moveaxis(a, 0, axis)


def split_top(q: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """``(c_d, Q_R)`` with ``Q = c_d·t^e + (1 − t)·Q_R`` (``t`` is axis 0, ``e`` its degree);
    ``c_d`` keeps a length-1 ``t`` axis.  None when ``Q`` does not depend on ``t``.

    >>> from seapass.robust.bernstein import from_terms
    >>> q = from_terms({(2,): fmpq(1), (0,): fmpq(1)}, 1)  # t² + 1 = 2·t² + (1 − t)(1 + t)
    >>> top, rest = split_top(q)
    >>> print(*top.flat, "|", *rest.flat)
    2 | 1 1
    """
    e = q.shape[0] - 1
    if e < 1:
        return None
    top = at_value(q, 0, fmpq(1))
    rest = q.copy()
    rest[e] = rest[e] - top[0]
    return top, _over_one_minus_t(rest)


def _over_one_minus_t(rest: np.ndarray) -> np.ndarray:
    """``rest / (1 − t)`` for ``rest`` vanishing at ``t = 1`` (axis 0)."""
    n = rest.shape[0] - 1
    q = [rest[n]]
    for j in range(n - 1, 0, -1):
        q.append(rest[j] + q[-1])
    return -np.stack(q[::-1])


def evaluate(coeffs: np.ndarray, point: tuple[fmpq, ...]) -> fmpq:
    """The exact value of ``coeffs`` at ``point`` (one coordinate per axis).

    >>> from seapass.robust.bernstein import from_terms
    >>> f = from_terms({(1, 1): fmpq(2), (0, 0): fmpq(-1)}, 2)  # 2uv - 1
    >>> print(evaluate(f, (fmpq(1, 2), fmpq(3))))
    2
    """
    acc = coeffs
    for axis in range(len(point) - 1, -1, -1):
        acc = at_value(acc, axis, point[axis])
    return fmpq(next(iter(np.asarray(acc, dtype=object).flat)))


def shift_axis(coeffs: np.ndarray, axis: int, c: fmpq, d: int) -> np.ndarray:
    """``coeffs`` with ``v = c + d·y`` substituted along ``axis`` (``d = ±1``): the same
    polynomial in the local coordinate ``y`` that is 0 at ``v = c`` (Taylor shift).

    >>> from seapass.robust.bernstein import from_terms
    >>> f = from_terms({(2,): fmpq(1)}, 1)  # v², v = 1 - y: 1 - 2y + y²
    >>> print(*shift_axis(f, 0, fmpq(1), -1).flat)
    1 -2 1
    """
    a = np.moveaxis(coeffs, axis, 0)
    n = a.shape[0] - 1
    out = []
    for k in range(n + 1):
        acc = a[k] * 0
        for j in range(k, n + 1):
            acc = acc + a[j] * (fmpz(comb(j, k)) * c ** (j - k))
        out.append(acc * (d**k))
    return np.moveaxis(np.stack(out), 0, axis)


def blow_axis(coeffs: np.ndarray, main: int, axis: int, scale: fmpq) -> np.ndarray:
    """``coeffs`` with ``y_axis = scale·y_main·σ`` substituted (``σ`` takes the place of
    ``y_axis``): one chart of the blow-up of the corner ``y_main = y_axis = 0``.

    >>> from seapass.robust.bernstein import from_terms
    >>> f = from_terms({(1, 0): fmpq(1), (0, 1): fmpq(1)}, 2)  # u + w, w = 2uσ: u + 2uσ
    >>> g = blow_axis(f, 0, 1, fmpq(2))
    >>> print(g[1, 0], g[1, 1])
    1 2
    """
    n_main, n_axis = coeffs.shape[main], coeffs.shape[axis]
    shape = list(coeffs.shape)
    shape[main] = n_main + n_axis - 1
    out = np.full(shape, fmpq(0), dtype=object)
    for idx in np.ndindex(*coeffs.shape):
        c = coeffs[idx]
        if c == 0:
            continue
        new = list(idx)
        new[main] = idx[main] + idx[axis]
        out[tuple(new)] = out[tuple(new)] + c * scale ** idx[axis]
    return out
