"""Matrices on the imaginary axis as exact polynomials: Hermitian parts, minors, Llewellyn's terms.

With a common denominator ``d`` of the matrix, ``P = N/d`` and on the axis
``P(jω) = G(ω)/|d(jω)|²`` with ``G = N(jω)·conj(d(jω))``, a matrix of complex
polynomials in ``ω`` (pairs ``(re, im)`` of real ones).  As ``|d(jω)|² > 0``
off the poles, every sign question about ``P(jω)`` is one about ``G``:

* ``P + P^H ⪰ 0`` ⟺ every principal minor of ``W = G + G^H`` is ``≥ 0``
  (all of them, not only the leading ones: Sylvester's criterion for
  semidefiniteness needs every principal minor);
* ``Re p11 ≥ 0`` ⟺ ``Re G11 ≥ 0``, and Llewellyn's
  ``2 Re p11 Re p22 − Re(p12 p21) − |p12 p21| ≥ 0`` ⟺ ``a ≥ 0`` and
  ``a² − |G12|²|G21|² ≥ 0`` with ``a = 2 Re G11 Re G22 − Re(G12 G21)``
  (the modulus squared away exactly).

Each of these is even in ``ω`` and is returned as a polynomial in ``x = ω²``.
The functions work on `flint.fmpq_poly` (all values substituted) and on
`flint.fmpq_mpoly` whose variable 0 is ``s`` (free parameters kept, for the
critical gains of [`seapass.ports.criticals`][seapass.ports.criticals]) alike.

References
----------
.. [1] B. D. O. Anderson and S. Vongpanitlerd, *Network Analysis and Synthesis*,
   Prentice-Hall, 1973, sec. 5.2 (positive real matrices).
.. [2] F. B. Llewellyn, "Some fundamental properties of transmission systems",
   Proc. IRE 40(3), 1952.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import Any, TypeAlias

from flint import fmpq_poly

from ..exact.axis import at_j_omega, even_to_x

__all__ = [
    "CPoly",
    "axis_matrix",
    "cadd",
    "cconj",
    "cdet",
    "cmul",
    "csub",
    "hermitian_part",
    "jw",
    "llewellyn_polynomials",
    "principal_minors",
    "to_x",
]

Poly: TypeAlias = Any  # fmpq_poly or fmpq_mpoly (variable 0 is s, then ω)
CPoly = tuple[Any, Any]
"""A complex polynomial in ``ω`` as ``(real part, imaginary part)``."""


def jw(p: Poly) -> CPoly:
    """``p(jω)`` as ``(re, im)``, real polynomials in ``ω`` of the same type as ``p``."""
    if isinstance(p, fmpq_poly):
        return at_j_omega(p)
    ctx = p.context()
    re: dict[tuple[int, ...], Any] = {}
    im: dict[tuple[int, ...], Any] = {}
    for monom, c in p.to_dict().items():
        k = monom[0]
        signed = -c if k % 4 >= 2 else c  # j^k = 1, j, −1, −j, ...
        (re if k % 2 == 0 else im)[monom] = signed
    return ctx.from_dict(re), ctx.from_dict(im)


def to_x(p: Poly) -> Poly:
    """``q`` with ``p(ω) = q(ω²)`` (`ArithmeticError` for an odd power of ``ω``)."""
    if isinstance(p, fmpq_poly):
        return even_to_x(p)
    out = {}
    for monom, c in p.to_dict().items():
        if monom[0] % 2:
            raise ArithmeticError("the polynomial is not even in w")
        out[(monom[0] // 2, *monom[1:])] = c
    return p.context().from_dict(out)


def _zero(like: Poly) -> Poly:
    return like - like


def cadd(a: CPoly, b: CPoly) -> CPoly:
    return a[0] + b[0], a[1] + b[1]


def csub(a: CPoly, b: CPoly) -> CPoly:
    return a[0] - b[0], a[1] - b[1]


def cmul(a: CPoly, b: CPoly) -> CPoly:
    return a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]


def cconj(a: CPoly) -> CPoly:
    return a[0], -a[1]


def axis_matrix(nmat: Sequence[Sequence[Poly]], d: Poly) -> list[list[CPoly]]:
    """``G = N(jω)·conj(d(jω))``: ``P(jω) = G/|d(jω)|²`` for ``P = N/d``."""
    dc = cconj(jw(d))
    return [[cmul(jw(p), dc) for p in row] for row in nmat]


def hermitian_part(g: Sequence[Sequence[CPoly]]) -> list[list[CPoly]]:
    """``W = G + G^H`` (entrywise ``G_ik + conj(G_ki)``)."""
    n = len(g)
    return [[cadd(g[i][k], cconj(g[k][i])) for k in range(n)] for i in range(n)]


def cdet(m: Sequence[Sequence[CPoly]], rows: Sequence[int], cols: Sequence[int]) -> CPoly:
    """Determinant of the submatrix ``m[rows][cols]`` (Laplace expansion along the first row)."""
    if len(rows) == 1:
        return m[rows[0]][cols[0]]
    first = m[rows[0]][cols[0]]
    total = (_zero(first[0]), _zero(first[0]))
    rest = rows[1:]
    for k, c in enumerate(cols):
        entry = m[rows[0]][c]
        if entry[0].is_zero() and entry[1].is_zero():
            continue
        minor = cdet(m, rest, [x for x in cols if x != c])
        term = cmul(entry, minor)
        total = cadd(total, term) if k % 2 == 0 else csub(total, term)
    return total


def principal_minors(w: Sequence[Sequence[CPoly]]) -> dict[tuple[int, ...], Poly]:
    """Every principal minor of the Hermitian ``W`` as a real polynomial in ``ω``.

    Keys are the (0-based) index sets, smallest first; an imaginary part that does
    not vanish identically would mean ``W`` is not Hermitian (`ArithmeticError`).
    """
    n = len(w)
    out: dict[tuple[int, ...], Poly] = {}
    for r in range(1, n + 1):
        for subset in itertools.combinations(range(n), r):
            re, im = cdet(w, subset, subset)
            if not im.is_zero():
                raise ArithmeticError("a principal minor of a Hermitian matrix is not real")
            out[subset] = re
    return out


def llewellyn_polynomials(g: Sequence[Sequence[CPoly]]) -> tuple[Poly, Poly, Poly, Poly]:
    """``(Re G11, Re G22, a, a² − |G12 G21|²)`` in ``ω`` for Llewellyn's conditions.

    ``a = 2 Re G11 Re G22 − Re(G12 G21)``; the third condition holds at ``ω``
    exactly when ``a ≥ 0`` and ``a² − |G12 G21|² ≥ 0``.
    """
    r11, r22 = g[0][0][0], g[1][1][0]
    q = cmul(g[0][1], g[1][0])
    a = 2 * r11 * r22 - q[0]
    return r11, r22, a, a * a - (q[0] * q[0] + q[1] * q[1])
