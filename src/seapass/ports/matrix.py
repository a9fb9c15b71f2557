"""`ExactMatrix`: an n×n matrix of exact rational functions of ``s`` at given parameter values.

Each entry ``p_ij = N_ij/D_ij`` is evaluated exactly (every float value is the
rational it represents) from its symbolic form, where common factors were
cancelled for *all* parameter values.  A factor that cancels only for the given
numbers is removed from the entry and kept in `ExactMatrix.hidden` unless it is
a pole of the matrix anyway: a mode the ports cannot see, which must not lie in
the closed right half-plane (as in the one-port test of
[`seapass.analysis.passivity`][seapass.analysis.passivity]).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import sympy as sp
from flint import fmpq_poly

from ..exact import poly as ep
from .ratfunc import frac_of, to_fmpq_poly, variables_of

__all__ = ["ExactMatrix", "exact_matrix", "from_polynomials", "lcm"]


def lcm(a: fmpq_poly, b: fmpq_poly) -> fmpq_poly:
    """Monic least common multiple of two nonzero polynomials."""
    g = a.gcd(b)
    return ep.monic((a // g) * b)


def _reduced(n: fmpq_poly, d: fmpq_poly) -> tuple[fmpq_poly, fmpq_poly, fmpq_poly]:
    """``(N, D, g)``: ``N/D`` in lowest terms with ``D`` monic, and the cancelled factor ``g``."""
    if n.is_zero():
        return n, fmpq_poly([1]), fmpq_poly([1])
    g = n.gcd(d)
    if g.degree() > 0:
        n, d = n // g, d // g
    lead = d.leading_coefficient()
    return n / lead, d / lead, g if g.degree() > 0 else fmpq_poly([1])


@dataclass(frozen=True, kw_only=True)
class ExactMatrix:
    """An n×n matrix of reduced exact rational functions of ``s``.

    Attributes
    ----------
    num, den : tuple of tuple of flint.fmpq_poly
        ``p_ij = num[i][j] / den[i][j]`` in lowest terms, ``den`` monic
        (a zero entry is ``0/1``).
    hidden : flint.fmpq_poly
        Monic product of the factors that cancelled only for these numbers and
        are not poles of the matrix (``1`` when there are none).
    """

    num: tuple[tuple[fmpq_poly, ...], ...]
    den: tuple[tuple[fmpq_poly, ...], ...]
    hidden: fmpq_poly

    @property
    def n(self) -> int:
        return len(self.num)

    def entry(self, i: int, j: int) -> tuple[fmpq_poly, fmpq_poly]:
        return self.num[i][j], self.den[i][j]

    def common_denominator(self) -> fmpq_poly:
        """Monic lcm of every denominator: the poles of the matrix, each at its highest order."""
        d = fmpq_poly([1])
        for row in self.den:
            for q in row:
                d = lcm(d, q)
        return d

    def numerator_matrix(self, d: fmpq_poly | None = None) -> list[list[fmpq_poly]]:
        """``N`` with ``P = N/d`` for the common denominator ``d``."""
        d = self.common_denominator() if d is None else d
        return [
            [self.num[i][j] * (d // self.den[i][j]) for j in range(self.n)] for i in range(self.n)
        ]

    def determinant(self) -> tuple[fmpq_poly, fmpq_poly]:
        """``det P`` of a 2×2 matrix as a reduced fraction (``num``, monic ``den``)."""
        if self.n != 2:
            raise ValueError("determinant() is for two-ports")
        n, d = self.num, self.den
        top = n[0][0] * n[1][1] * d[0][1] * d[1][0] - n[0][1] * n[1][0] * d[0][0] * d[1][1]
        bottom = d[0][0] * d[1][1] * d[0][1] * d[1][0]
        num, den, _ = _reduced(top, bottom)
        return num, den

    def pole_polynomial(self) -> fmpq_poly:
        """The McMillan pole polynomial of a 2×2 matrix: lcm of the denominators of all minors."""
        return lcm(self.common_denominator(), self.determinant()[1])


def from_polynomials(
    nums: Sequence[Sequence[ep.PolyLike]], dens: Sequence[Sequence[ep.PolyLike]]
) -> ExactMatrix:
    """An `ExactMatrix` from unreduced exact numerators and denominators (ascending coefficients)."""
    n = len(nums)
    rn: list[list[fmpq_poly]] = []
    rd: list[list[fmpq_poly]] = []
    cancelled = fmpq_poly([1])
    for i in range(n):
        rn.append([])
        rd.append([])
        for j in range(n):
            num, den = ep.as_poly(nums[i][j]), ep.as_poly(dens[i][j])
            if den.is_zero():
                raise ZeroDivisionError(f"entry {i + 1}{j + 1} has a zero denominator")
            a, b, g = _reduced(num, den)
            rn[i].append(a)
            rd[i].append(b)
            cancelled = lcm(cancelled, g)
    m = ExactMatrix(
        num=tuple(tuple(r) for r in rn), den=tuple(tuple(r) for r in rd), hidden=fmpq_poly([1])
    )
    d = m.common_denominator()
    hidden = cancelled
    g = hidden.gcd(d)
    while g.degree() > 0:
        hidden = hidden // g
        g = hidden.gcd(d)
    return ExactMatrix(num=m.num, den=m.den, hidden=ep.monic(hidden))


def exact_matrix(entries: Sequence[sp.Expr], n: int, values: Mapping[str, float]) -> ExactMatrix:
    """The `ExactMatrix` of ``n*n`` symbolic entries (row-major) at ``values``.

    Each entry is reduced for all parameter values first (FLINT's multivariate
    gcd, [`seapass.ports.ratfunc`][seapass.ports.ratfunc]); then every value is
    substituted as the rational it represents.
    """
    names = variables_of(entries)
    exact = {k: ep.rational(values[k]) for k in names}
    nums: list[list[fmpq_poly]] = [[] for _ in range(n)]
    dens: list[list[fmpq_poly]] = [[] for _ in range(n)]
    for k, expr in enumerate(entries):
        num, den = frac_of(expr).substitute(exact, ())
        nums[k // n].append(to_fmpq_poly(num))
        dens[k // n].append(to_fmpq_poly(den))
    return from_polynomials(nums, dens)
