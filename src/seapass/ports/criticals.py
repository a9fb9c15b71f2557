"""Critical values of one free parameter ``k``: where a two-port or n-port verdict may change.

With every other parameter fixed, the entries are rational functions of ``s``
and ``k`` (`flint.fmpq_mpoly`).  Each condition of the criterion (Llewellyn's
for ``"absolute"``, Raisbeck's for ``"passive"``) can change its truth value
only at a real root of one of these polynomials in ``k``:

* per entry ``N/D``: the leading coefficients in ``s`` (a pole or zero to or
  from infinity) and ``Res_s(N, D)`` (a cancellation: a mode hidden or shown);
  a factor common to ``N`` and ``D`` for every ``k`` is a hidden mode, and where
  it crosses the imaginary axis is critical too;
* the common denominator ``d``: ``Res_ω(Re d(jω), Im d(jω))`` after removing
  their generic common factor ``g`` (a pole crossing the imaginary axis), and
  the leading and constant coefficients and discriminant of ``g`` (poles on the
  axis appearing, merging or reaching 0);
* residues on the axis: the entries and principal minors of the residue matrix
  ``K̃ = N(jω) conj(d'(jω))`` (and Llewellyn's ``k11 k22 − k12 k21``,
  ``k12 k21``) at ``ω = 0``, their resultants with ``g`` at the other axis
  poles, and the same for ``lim P(s)/s`` at infinity;
* each frequency condition ``f(x, k) ≥ 0`` on ``x = ω² ≥ 0`` (a principal
  minor of ``P + P^H``, or ``Re p11``, ``Re p22``, ``a``, ``a² − |q|²``): for
  every factor of odd multiplicity, its leading coefficient and its value at
  ``x = 0`` (a root through ``∞`` or ``0``), its discriminant in ``x`` (roots
  appearing from a complex pair) and the factors free of ``x``.

Roots of two different factors of one condition crossing each other change the
truth value at that single ``k`` at most, not on an interval; such isolated
values are not critical values (as in
[`seapass.analysis.region`][seapass.analysis.region]).  Between consecutive
critical values every verdict is constant, so one exact decision per cell
settles it ([`seapass.ports.bound`][seapass.ports.bound]).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import Any

from flint import fmpq, fmpq_mpoly, fmpq_poly

from .onaxis import (
    axis_matrix,
    cdet,
    cmul,
    hermitian_part,
    jw,
    llewellyn_polynomials,
    principal_minors,
    to_x,
)
from .poles import residue_matrix
from .ratfunc import Frac

__all__ = ["critical_polynomials", "univariate"]


def _deg(p: fmpq_mpoly) -> int:
    return -1 if p.is_zero() else int(p.degrees()[0])


def _coeff(p: fmpq_mpoly, i: int) -> fmpq_mpoly:
    """Coefficient of ``s^i`` (a polynomial in ``k``)."""
    ctx = p.context()
    return ctx.from_dict({(0, *m[1:]): c for m, c in p.to_dict().items() if m[0] == i})


def _lc(p: fmpq_mpoly) -> fmpq_mpoly:
    return _coeff(p, _deg(p))


def _lcm(a: fmpq_mpoly, b: fmpq_mpoly) -> fmpq_mpoly:
    return a * (b / a.gcd(b))


def _axis_crossings(d: fmpq_mpoly, out: list[fmpq_mpoly]) -> fmpq_mpoly:
    """Append the critical polynomials of the axis poles of ``1/d``; return ``g`` (generic axis part)."""
    re, im = jw(d)
    if im.is_zero():
        g = re
        out.append(_lc(re))
    else:
        g = re.gcd(im)
        r1, r2 = re / g, im / g
        if _deg(r1) > 0 and _deg(r2) > 0:
            out.append(r1.resultant(r2, "s"))
        else:
            out += [_lc(r1), _lc(r2)]
    if _deg(g) > 0:
        out += [_lc(g), _coeff(g, 0)]
        if _deg(g) > 1:
            out.append(g.discriminant("s"))
    return g


def _strip_omega(g: fmpq_mpoly) -> fmpq_mpoly:
    """``g`` without its factors ``ω`` (the pole at 0 is treated separately)."""
    ctx = g.context()
    w = ctx.gens()[0]
    while _deg(g) > 0 and _coeff(g, 0).is_zero():
        g = g / w
    return g


def _residue_quantities(kt: list[list[Any]], absolute: bool) -> list[fmpq_mpoly]:
    """Real polynomials whose signs decide the residue conditions at an axis pole."""
    n = len(kt)
    out = []
    for i, j in itertools.product(range(n), repeat=2):
        out += [kt[i][j][0], kt[i][j][1]]
    if absolute:
        f = cmul(kt[0][1], kt[1][0])
        e = cmul(kt[0][0], kt[1][1])
        out += [f[0], f[1], e[0] - f[0], e[1] - f[1]]
    else:
        for r in range(2, n + 1):
            for subset in itertools.combinations(range(n), r):
                out.append(cdet(kt, subset, subset)[0])
    return [q for q in out if not q.is_zero()]


def _infinity(
    nums: Sequence[Sequence[fmpq_mpoly]], dens: Sequence[Sequence[fmpq_mpoly]], absolute: bool
) -> list[fmpq_mpoly]:
    """Critical polynomials of the residues at infinity, ``lim P(s)/s``."""
    n = len(nums)
    ctx = nums[0][0].context()
    zero = Frac.make(ctx.from_dict({}), ctx.from_dict({(0,) * ctx.nvars(): 1}))
    k = [[zero] * n for _ in range(n)]
    for i, j in itertools.product(range(n), repeat=2):
        num, den = nums[i][j], dens[i][j]
        if not num.is_zero() and _deg(num) - _deg(den) >= 1:
            k[i][j] = Frac.make(_coeff(num, _deg(den) + 1), _lc(den))
    out: list[fmpq_mpoly] = []

    def add(f: Frac) -> None:
        out.extend([f.num, f.den])

    if absolute:
        f12 = k[0][1] * k[1][0]
        add(f12)
        add(k[0][0] * k[1][1] - f12)
    else:
        for r in range(2, n + 1):
            for subset in itertools.combinations(range(n), r):
                add(_det_frac([[k[a][b] for b in subset] for a in subset]))
    return out


def _det_frac(m: list[list[Frac]]) -> Frac:
    if len(m) == 1:
        return m[0][0]
    total = None
    for c in range(len(m)):
        minor = [row[:c] + row[c + 1 :] for row in m[1:]]
        term = m[0][c] * _det_frac(minor)
        total = term if total is None else (total + term if c % 2 == 0 else total - term)
    assert total is not None
    return total


def _frequency(f: fmpq_mpoly, out: list[fmpq_mpoly]) -> None:
    """Critical polynomials of ``f(x, k) ≥ 0 for all x ≥ 0``."""
    if f.is_zero():
        return
    _c, factors = f.factor_squarefree()
    for h, mult in factors:
        if mult % 2 == 0:
            continue
        if _deg(h) <= 0:
            out.append(h)
            continue
        out += [_lc(h), _coeff(h, 0)]
        if _deg(h) > 1:
            out.append(h.discriminant("s"))


def critical_polynomials(
    nums: Sequence[Sequence[fmpq_mpoly]], dens: Sequence[Sequence[fmpq_mpoly]], criterion: str
) -> list[fmpq_mpoly]:
    """Polynomials in ``k`` (context ``("s", k)``, free of ``s``) on whose roots a verdict may change.

    ``nums``, ``dens``: the entries ``N_ij/D_ij`` as polynomials in ``s`` and ``k``;
    ``criterion``: ``"absolute"`` (Llewellyn, 2×2) or ``"passive"`` (Raisbeck, n×n).
    """
    absolute = criterion == "absolute"
    n = len(nums)
    out: list[fmpq_mpoly] = []
    red_n: list[list[fmpq_mpoly]] = []
    red_d: list[list[fmpq_mpoly]] = []
    for i in range(n):
        red_n.append([])
        red_d.append([])
        for j in range(n):
            num, den = nums[i][j], dens[i][j]
            if not num.is_zero():
                g = num.gcd(den)
                if _deg(g) > 0:  # a mode hidden for every k: where it crosses the axis matters
                    _axis_crossings(g, out)
                num, den = num / g, den / g
                out += [_lc(num), _lc(den)]
                if _deg(num) > 0 and _deg(den) > 0:
                    out.append(num.resultant(den, "s"))
            red_n[i].append(num)
            red_d[i].append(den)
    d = red_d[0][0]
    for row in red_d:
        for q in row:
            d = _lcm(d, q)
    for i, j in itertools.product(range(n), repeat=2):  # each entry's own poles, too
        _axis_crossings(red_d[i][j], out)
    g = _axis_crossings(d, out)
    nmat = [[red_n[i][j] * (d / red_d[i][j]) for j in range(n)] for i in range(n)]
    kt = residue_matrix(nmat, d)
    if _coeff(d, 0).is_zero():  # a pole at s = 0 for every k
        ctx = d.context()
        at0 = [
            [
                (ctx.from_dict({}) + p[0].subs({"s": 0}), ctx.from_dict({}) + p[1].subs({"s": 0}))
                for p in row
            ]
            for row in kt
        ]
        out += _residue_quantities(at0, absolute)
    g_nz = _strip_omega(g)
    if _deg(g_nz) > 0:
        out += [g_nz.resultant(q, "s") for q in _residue_quantities(kt, absolute) if _deg(q) >= 0]
    out += _infinity(red_n, red_d, absolute)
    gm = axis_matrix(nmat, d)
    if absolute:
        polys = list(llewellyn_polynomials(gm))
    else:
        polys = list(principal_minors(hermitian_part(gm)).values())
    for f in polys:
        _frequency(to_x(f), out)
    return [p for p in out if not p.is_zero() and not p.is_constant()]


def univariate(p: fmpq_mpoly) -> fmpq_poly:
    """A polynomial of the context ``("s", k)`` that is free of ``s`` as a `flint.fmpq_poly` in ``k``."""
    d = p.to_dict()
    if any(m[0] for m in d):
        raise ArithmeticError("a critical polynomial still depends on s")
    deg = max(m[1] for m in d)
    coeffs = [fmpq(0)] * (deg + 1)
    for m, c in d.items():
        coeffs[m[1]] = c
    return fmpq_poly(coeffs)
