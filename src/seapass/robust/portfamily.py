"""The two-port conditions of a family over a box, as polynomials that must be positive on it.

With the uncertain parameters ``p`` symbolic and every other parameter an exact
rational, the entries of a [`TwoPort`][seapass.ports.twoport.TwoPort] are
``P_ij = N_ij(s; p)/D_ij(s; p)`` (the generic reduced forms, as the exact test
sees them).  Over the common denominator ``D = lcm D_ij = s^j D̃`` (sign chosen so
that ``D̃(0) > 0`` at the centre of the box), ``P = N'/D``.  Every plant of the box
passes the exact verdict of [`seapass.ports`][seapass.ports] if, on the whole box:

* **stability** (``stable_entries``): every coefficient of ``D̃`` and every Hurwitz
  determinant ``Δ_2 … Δ_{n−1}`` of ``D̃`` is positive (no pole or hidden mode in the
  closed right half-plane but the one at 0), and ``j <= 1``;
* **the pole at 0** (``j = 1``): the residue matrix ``K_0 = N'(0)/D̃(0)`` satisfies
  the criterion's sign conditions (passivity: symmetric, ``k11, k22, det K_0 ≥ 0``;
  absolute stability: ``k11, k22 ≥ 0``, ``k12 k21 ≥ 0``, ``k11 k22 − k12 k21 ≥ 0``),
  and some entry of ``K_0`` keeps a strict sign (the pole never cancels, which would
  leave a hidden mode at 0);
* **the pole at infinity**: every relative degree is ``≥ −1`` and the matrix of the
  coefficients of ``s^{deg D + 1}`` satisfies the same sign conditions;
* **frequency**: with ``G = N'(jω)·conj(D(jω))``
  ([`seapass.ports.onaxis`][seapass.ports.onaxis]), passivity needs the principal
  minors of ``G + G^H`` to be ``≥ 0``; absolute stability ``Re G11, Re G22 ≥ 0`` and
  Llewellyn's ``a ≥ 0``, ``a² − |G12 G21|² ≥ 0`` (the modulus squared away exactly:
  ``a ≥ |q|`` iff ``a ≥ 0`` and ``a² ≥ |q|²``).  Each is a polynomial ``P(x; p)`` in
  ``x = ω²``; without its generic factor ``x^k`` and compactified by
  ``x = t/(1 − t)`` it must be positive on ``[0, 1] × box``.

A condition identically zero holds; any other must be **proven positive** by
[`seapass.robust.bernstein`][seapass.robust.bernstein].  The conditions are
sufficient; each is also necessary pointwise for the exact condition it names, so a
point where one fails is a candidate worst plant, checked by the ordinary exact test.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

import numpy as np
from flint import fmpq, fmpq_mpoly, fmpz

from ..exact import poly as ep
from ..model.expr import to_fraction
from ..ports.bound import Criterion
from ..ports.onaxis import (
    axis_matrix,
    hermitian_part,
    llewellyn_polynomials,
    principal_minors,
    to_x,
)
from ..ports.ratfunc import context, frac_of
from ..ports.twoport import TwoPort
from .bernstein import from_terms
from .box import UncertainBox

__all__ = ["PortCondition", "PortConditionKind", "PortFamily", "port_family"]


class PortConditionKind(StrEnum):
    """What a two-port condition guards."""

    STABILITY = "stability"
    RESIDUE_ZERO = "residue_zero"
    RESIDUE_INFINITY = "residue_infinity"
    FREQUENCY = "frequency"


@dataclass(frozen=True, kw_only=True)
class PortCondition:
    """One polynomial that must be positive on ``[0, 1] × box`` (axes ``t, p_1, …``).

    ``exact`` names the condition of the exact verdict it guards (``stable_entries``,
    ``re_p11``, ``llewellyn``, ``minor_12``, ...).
    """

    kind: PortConditionKind
    label: str
    exact: str
    coeffs: np.ndarray


@dataclass(frozen=True, kw_only=True)
class PortFamily:
    """The conditions of a two-port family for one criterion, or its structural defect.

    ``keeps_pole``: candidates of which at least one must be proven positive (an entry
    of ``K_0`` with a strict sign); empty when there is no pole at 0.
    ``generic_failure``: a defect that no box-wide proof can remove (a repeated pole
    at 0, a relative degree below −1, a residue matrix that is not symmetric, a
    coefficient or Hurwitz determinant identically zero); then ``conditions`` is empty.
    """

    names: tuple[str, ...]
    criterion: Criterion
    conditions: tuple[PortCondition, ...] = ()
    keeps_pole: tuple[PortCondition, ...] = ()
    generic_failure: str = ""


def _ctx_polys(
    tp: TwoPort, box: UncertainBox, fixed: Mapping[str, float]
) -> list[tuple[fmpq_mpoly, fmpq_mpoly]]:
    exact = {k: ep.rational(to_fraction(v, k)) for k, v in fixed.items()}
    return [frac_of(e).substitute(exact, box.names) for e in tp.entries]


def _deg_s(p: fmpq_mpoly) -> int:
    return -1 if p.is_zero() else int(p.degrees()[0])


def _coeff_s(p: fmpq_mpoly, i: int) -> fmpq_mpoly:
    """Coefficient of ``s^i`` (variable 0), a polynomial in the parameters."""
    ctx = p.context()
    return ctx.from_dict({(0, *m[1:]): c for m, c in p.to_dict().items() if m[0] == i})


def _value(p: fmpq_mpoly, point: Mapping[str, fmpq]) -> fmpq:
    subs: dict[str | int, int | fmpz | fmpq] = {k: v for k, v in point.items()}
    q = p.subs(subs) if subs else p
    return fmpq(q.to_dict().get((0,) * p.context().nvars(), 0))


def _bareiss_minors(h: list[list[fmpq_mpoly]], upto: int) -> list[fmpq_mpoly] | None:
    """Leading principal minors ``Δ_1 … Δ_upto`` of ``h`` (fraction-free Gaussian
    elimination, exact divisions); None when a pivot is identically zero."""
    n = len(h)
    m = [row[:] for row in h]
    prev: Any = 1
    out: list[fmpq_mpoly] = []
    for k in range(min(upto, n)):
        piv = m[k][k]
        if piv.is_zero():
            return None
        out.append(piv)
        for i in range(k + 1, n):
            for j in range(k + 1, n):
                m[i][j] = (m[i][j] * piv - m[i][k] * m[k][j]) / prev
        prev = piv
    return out


def _dense(p: fmpq_mpoly, nvars: int) -> np.ndarray:
    return from_terms(dict(p.to_dict()), nvars)


def _compactified(px: fmpq_mpoly) -> fmpq_mpoly | None:
    """``(1 − t)^{d−k} P(t/(1 − t))/x^k`` in the same context (variable 0 is ``t``); None if ``P ≡ 0``."""
    if px.is_zero():
        return None
    ctx = px.context()
    nv = ctx.nvars()
    cx = {i: _coeff_s(px, i) for i in range(_deg_s(px) + 1)}
    nz = [i for i, c in cx.items() if not c.is_zero()]
    k, d = nz[0], nz[-1]
    t = ctx.from_dict({(1,) + (0,) * (nv - 1): 1})
    one = ctx.from_dict({(0,) * nv: 1})
    total = ctx.from_dict({})
    for i in nz:
        total += cx[i] * t ** (i - k) * (one - t) ** (d - i)
    return total


def _sign_conditions(
    k: list[list[fmpq_mpoly]], criterion: Criterion
) -> list[tuple[str, str, fmpq_mpoly]] | str:
    """``(label, exact name, polynomial ≥ 0)`` of a residue matrix, or why it fails generically."""
    k11, k12, k21, k22 = k[0][0], k[0][1], k[1][0], k[1][1]
    if criterion is Criterion.PASSIVE:
        if not (k12 - k21).is_zero():
            return "not symmetric"
        return [
            ("k11 >= 0", "axis_poles", k11),
            ("k22 >= 0", "axis_poles", k22),
            ("k11 k22 - k12^2 >= 0", "axis_poles", k11 * k22 - k12 * k21),
        ]
    return [
        ("k11 >= 0", "p11_poles", k11),
        ("k22 >= 0", "p22_poles", k22),
        ("k12 k21 >= 0", "axis_residues", k12 * k21),
        ("k11 k22 - k12 k21 >= 0", "axis_residues", k11 * k22 - k12 * k21),
    ]


def port_family(
    tp: TwoPort,
    box: UncertainBox,
    fixed: Mapping[str, float],
    criterion: Criterion,
) -> PortFamily:
    """The conditions (module docstring) of ``tp`` over ``box`` for ``criterion``."""
    names = box.names
    nv = 1 + len(names)
    ctx = context(names)
    nd = _ctx_polys(tp, box, fixed)
    den = ctx.from_dict({(0,) * nv: 1})
    for _n, d in nd:
        den = den * (d / den.gcd(d))
    nmat = [[nd[2 * i + j][0] * (den / nd[2 * i + j][1]) for j in (0, 1)] for i in (0, 1)]
    centre = {k: ep.rational(to_fraction(v, k)) for k, v in box.center().items()}
    j = next(i for i in range(_deg_s(den) + 1) if not _coeff_s(den, i).is_zero())
    if _value(_coeff_s(den, j), centre) < 0:
        den = -den
        nmat = [[-p for p in row] for row in nmat]

    def fail(why: str) -> PortFamily:
        return PortFamily(names=names, criterion=criterion, generic_failure=why)

    if j >= 2:
        return fail("repeated pole at s = 0")
    dd = _deg_s(den)
    conds: list[PortCondition] = []

    def add(kind: PortConditionKind, label: str, exact: str, p: fmpq_mpoly) -> None:
        if not p.is_zero():
            conds.append(PortCondition(kind=kind, label=label, exact=exact, coeffs=_dense(p, nv)))

    desc = [_coeff_s(den, i) for i in range(dd, j - 1, -1)]  # a_0 s^n + ... + a_n of D̃
    n = len(desc) - 1
    for i, c in enumerate(desc):
        if c.is_zero():
            return fail(f"coefficient of s^{n - i} of the denominator is zero")
        add(PortConditionKind.STABILITY, f"coefficient of s^{n - i} of D", "stable_entries", c)
    if n >= 3:
        zero = ctx.from_dict({})
        h = [
            [desc[ix] if 0 <= (ix := 2 * (col + 1) - (row + 1)) <= n else zero for col in range(n)]
            for row in range(n)
        ]
        minors = _bareiss_minors(h, n - 1)
        if minors is None:
            return fail("a Hurwitz determinant of the denominator is identically zero")
        for k, delta in enumerate(minors[1:], start=2):
            add(
                PortConditionKind.STABILITY,
                f"Hurwitz determinant {k} of D",
                "stable_entries",
                delta,
            )
    keeps: list[PortCondition] = []
    if j == 1:
        k0 = [[_coeff_s(p, 0) for p in row] for row in nmat]
        signs = _sign_conditions(k0, criterion)
        if isinstance(signs, str):
            return fail(f"the residue matrix at s = 0 is {signs}")
        for label, exact, p in signs:
            add(PortConditionKind.RESIDUE_ZERO, f"residue at s = 0: {label}", exact, p)
        for i, row in enumerate(k0):
            for jj, p in enumerate(row):
                for sign in (1, -1) if i != jj else (1,):
                    if not p.is_zero():
                        keeps.append(
                            PortCondition(
                                kind=PortConditionKind.RESIDUE_ZERO,
                                label=f"{'-' if sign < 0 else ''}k{i + 1}{jj + 1} at s = 0",
                                exact="stable_entries",
                                coeffs=_dense(sign * p, nv),
                            )
                        )
    for i, row in enumerate(nmat):
        for jj, p in enumerate(row):
            if _deg_s(p) > dd + 1:
                return fail(f"entry {i + 1}{jj + 1} has a relative degree below -1")
    kinf = [[_coeff_s(p, dd + 1) for p in row] for row in nmat]
    signs = _sign_conditions(kinf, criterion)
    if isinstance(signs, str):
        return fail(f"the residue matrix at infinity is {signs}")
    for label, exact, p in signs:
        add(PortConditionKind.RESIDUE_INFINITY, f"residue at infinity: {label}", exact, p)
    g = axis_matrix(nmat, den)
    if criterion is Criterion.PASSIVE:
        freq = [
            (
                f"minor_{''.join(str(i + 1) for i in sub)} of P + P^H >= 0",
                f"minor_{''.join(str(i + 1) for i in sub)}",
                m,
            )
            for sub, m in principal_minors(hermitian_part(g)).items()
        ]
    else:
        r11, r22, a, disc = llewellyn_polynomials(g)
        freq = [
            ("Re p11(jw) >= 0", "re_p11", r11),
            ("Re p22(jw) >= 0", "re_p22", r22),
            ("2 Re p11 Re p22 - Re(p12 p21) >= 0", "llewellyn", a),
            ("(2 Re p11 Re p22 - Re(p12 p21))^2 - |p12 p21|^2 >= 0", "llewellyn", disc),
        ]
    for label, exact, p in freq:
        q = _compactified(to_x(p))
        if q is not None:
            add(PortConditionKind.FREQUENCY, label, exact, q)
    return PortFamily(
        names=names, criterion=criterion, conditions=tuple(conds), keeps_pole=tuple(keeps)
    )
