"""Haddadi and Hashtrudi-Zaad's absolute-stability parameter η and its exact infimum over ω.

For a two-port ``P`` with ``q = p12 p21 ≢ 0``,

``η(ω) = −cos∠q(jω) + 2 Re p11(jω) Re p22(jω) / |q(jω)| = A/|q|``,
``A = 2 Re p11 Re p22 − Re q``,

and, with ``p11`` stable and ``Re p11 ≥ 0``, the two-port is absolutely stable
exactly when ``η(ω) ≥ 1`` for every ``ω``; η is invariant to scaling the ports,
so ``inf η`` measures how far a design is from losing absolute stability.

With ``P = N/d`` and ``G = N(jω) conj(d(jω))`` (see
[`seapass.ports.onaxis`][seapass.ports.onaxis]) ``η = a/√Q`` where
``a = 2 Re G11 Re G22 − Re(G12 G21)`` and ``Q = |G12 G21|²`` are exact
polynomials in ``x = ω²``.  On each open cell between consecutive real roots of
``a``, ``Q``, ``R = a²/Q`` (reduced) and of the numerator of ``R'``, η is
continuous and monotone, so its infimum over ``[0, ∞)`` is the least of its
values or one-sided limits at the cell ends: at ``x = 0``, at those roots and
as ``x → ∞``.  Each is ``σ √r`` with an exact sign ``σ`` and ``r`` the value
(or limit) of ``R`` there, an algebraic number enclosed by exact interval
arithmetic on a refined isolating interval; the square root is bounded by
integer square roots.  So the infimum comes as a certified rational enclosure,
with the frequency where it is attained, or the limit (``ω → 0``, ``ω → ∞``, or
next to a pole) where it is not.

References
----------
.. [1] A. Haddadi and K. Hashtrudi-Zaad, "Bounded-impedance absolute stability
   of bilateral teleoperation control systems", IEEE Trans. Haptics 3(1), 2010.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from flint import fmpq, fmpq_poly, fmpz

from ..exact.halfline import HalfLinePoint, enclose
from .bands import half_line_points, minimal_point, omega_of

__all__ = ["EtaKind", "EtaMinimum", "eta_infimum", "sqrt_bounds"]

#: Relative width of the enclosure of ``R`` at a candidate (below double precision).
RTOL = fmpq(1, 2**56)
#: Refinement rounds spent separating candidates whose enclosures overlap.
MAX_ROUNDS = 8


def sqrt_bounds(q: fmpq, bits: int = 80) -> tuple[fmpq, fmpq]:
    """Rationals ``lo <= √q <= hi`` (``q >= 0``), ``hi − lo <= 2^-bits · (1 + √q)``.

    >>> lo, hi = sqrt_bounds(fmpq(2))
    >>> lo * lo <= 2 <= hi * hi, float(hi - lo) < 1e-20
    (True, True)
    """
    if q < 0:
        raise ValueError("square root of a negative number")
    if q == 0:
        return fmpq(0), fmpq(0)
    scale = fmpz(2) ** (2 * bits)
    n = int(q.p * scale) // int(q.q)  # floor(q · 4^bits)
    r = math.isqrt(n)
    lo = fmpq(r, 2**bits)
    hi = fmpq(r + 1, 2**bits) if r * r != n or n * int(q.q) != int(q.p * scale) else lo
    if hi * hi < q:  # pragma: no cover - isqrt of the floor is never above the root
        hi = fmpq(r + 2, 2**bits)
    return lo, hi


class EtaKind(StrEnum):
    """How ``inf η`` is reached (the JSON value ``eta_min_kind`` is the string)."""

    ATTAINED = "attained"
    """Attained at a frequency (``omega``)."""
    LIMIT = "limit"
    """Approached as ``ω → limit`` (``0``, ``∞`` or next to a pole), not attained."""
    UNBOUNDED = "unbounded"
    """``−∞``, next to ``limit``."""
    UNDEFINED = "undefined"
    """``p12 p21 ≡ 0``: η does not exist."""


@dataclass(frozen=True, kw_only=True)
class EtaMinimum:
    """``inf_ω η(ω)`` with a certified enclosure.

    Attributes
    ----------
    lower, upper : flint.fmpq or None
        ``lower <= inf η <= upper``; both None when ``inf η = −∞`` or η is undefined.
    kind : EtaKind
        ``ATTAINED`` (at ``omega``), ``LIMIT`` (approached as ``ω → limit``,
        not attained), ``UNBOUNDED`` (``−∞``, next to ``limit``) or
        ``UNDEFINED`` (``p12 p21 ≡ 0``: η does not exist).
    omega : float or None
        Where the infimum is attained [rad/s] (``kind == "attained"``).
    limit : float or None
        The frequency approached (``inf`` for ``ω → ∞``) when it is a limit.
    """

    lower: fmpq | None
    upper: fmpq | None
    kind: EtaKind
    omega: float | None = None
    limit: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "kind", EtaKind(self.kind))

    @property
    def value(self) -> float:
        """The infimum as a float (``-inf`` when unbounded, ``nan`` when undefined)."""
        if self.kind is EtaKind.UNDEFINED:
            return math.nan
        if self.lower is None or self.upper is None:
            return -math.inf
        return float((self.lower + self.upper) / 2)

    def to_dict(self) -> dict[str, Any]:
        return {
            "eta_min": self.value,
            "eta_min_frequency": self.omega if self.kind is EtaKind.ATTAINED else None,
            "eta_min_kind": self.kind.value,
            "eta_min_limit": self.limit,
            "eta_min_enclosure": None
            if self.lower is None or self.upper is None
            else [float(self.lower), float(self.upper)],
        }


@dataclass(frozen=True, kw_only=True)
class _Candidate:
    sigma: int  # sign of η there (−1, 0, 1)
    point: HalfLinePoint | None  # None: x → ∞
    infinite: bool  # R → ∞ there
    attained: bool  # η is defined at the point (not a limit)
    r_at_inf: fmpq | None = None


#: A candidate with the enclosure ``[lo, hi]`` of ``R`` there (its point refined as needed).
_Enclosed = tuple[_Candidate, fmpq, fmpq]


def _reduced(p: fmpq_poly, q: fmpq_poly) -> tuple[fmpq_poly, fmpq_poly]:
    g = p.gcd(q)
    if g.degree() > 0:
        p, q = p // g, q // g
    return p, q


def _sign_of_cell(a: fmpq_poly, cell: HalfLinePoint) -> int:
    return cell.sign(a)


def _enclose_r(rn: fmpq_poly, rd: fmpq_poly, c: _Candidate, rtol: fmpq) -> _Enclosed:
    """``R`` at ``c`` enclosed to ``rtol``; the candidate comes back with its refined point."""
    if c.point is None:
        assert c.r_at_inf is not None
        return c, c.r_at_inf, c.r_at_inf
    pt = minimal_point(c.point)
    if pt.is_rational:
        v = rn(pt.lower) / rd(pt.lower)
        return dataclasses.replace(c, point=pt), v, v
    width = pt.upper - pt.lower
    while True:
        lo_d, hi_d = enclose(rd, pt.lower, pt.upper)
        if lo_d > 0 or hi_d < 0:
            lo_n, hi_n = enclose(rn, pt.lower, pt.upper)
            corners = [lo_n / lo_d, lo_n / hi_d, hi_n / lo_d, hi_n / hi_d]
            lo, hi = max(min(corners), fmpq(0)), max(corners)
            if hi - lo <= rtol * max(hi, fmpq(1, 2**200)):
                return dataclasses.replace(c, point=pt), lo, hi
        width /= 2**16
        pt = pt.refined(width)
        if pt.is_rational:
            v = rn(pt.lower) / rd(pt.lower)
            return dataclasses.replace(c, point=pt), v, v


def eta_infimum(a: fmpq_poly, q: fmpq_poly) -> EtaMinimum:
    """``inf_{x ≥ 0} a(x)/√Q(x)`` for exact polynomials ``a`` and ``Q ≥ 0`` in ``x = ω²``.

    Examples
    --------
    >>> x = fmpq_poly([0, 1])
    >>> m = eta_infimum(x + 2, x * 0 + 1)          # η = x + 2: least value 2 at ω = 0
    >>> m.kind.value, float(m.lower), m.omega
    ('attained', 2.0, 0.0)
    >>> eta_infimum(fmpq_poly([1]), x).kind        # η = 1/√x → 0 as ω → ∞
    <EtaKind.LIMIT: 'limit'>
    """
    if q.is_zero():
        return EtaMinimum(lower=None, upper=None, kind=EtaKind.UNDEFINED)
    if a.is_zero():
        return EtaMinimum(lower=fmpq(0), upper=fmpq(0), kind=EtaKind.ATTAINED, omega=0.0)
    rn, rd = _reduced(a * a, q)
    crit = rn.derivative() * rd - rn * rd.derivative()
    points = half_line_points([a, q, rn, rd, crit])
    cands: list[_Candidate] = []
    n = len(points)
    for i in range(0, n, 2):  # x = 0 and every root (even indices)
        pt = points[i]
        sides = [points[j] for j in (i - 1, i + 1) if 0 <= j < n]
        if pt.sign(q) != 0:
            cands.append(_Candidate(sigma=pt.sign(a), point=pt, infinite=False, attained=True))
            continue
        infinite = pt.sign(rd) == 0
        for side in sides:
            cands.append(
                _Candidate(
                    sigma=_sign_of_cell(a, side), point=pt, infinite=infinite, attained=False
                )
            )
    last = points[-1]
    sigma_inf = last.sign(a)
    if rn.degree() > rd.degree():
        cands.append(_Candidate(sigma=sigma_inf, point=None, infinite=True, attained=False))
    else:
        lim = (
            rn.leading_coefficient() / rd.leading_coefficient()
            if rn.degree() == rd.degree()
            else fmpq(0)
        )
        cands.append(
            _Candidate(sigma=sigma_inf, point=None, infinite=False, attained=False, r_at_inf=lim)
        )
    sigma = min(c.sigma for c in cands)
    if sigma < 0 and any(c.sigma < 0 and c.infinite for c in cands):
        c = next(c for c in cands if c.sigma < 0 and c.infinite)
        return EtaMinimum(
            lower=None,
            upper=None,
            kind=EtaKind.UNBOUNDED,
            limit=math.inf if c.point is None else omega_of(c.point),
        )
    pool = [c for c in cands if c.sigma == sigma and not (sigma > 0 and c.infinite)]
    if sigma == 0:
        c = next(c for c in pool)
        return _result(fmpq(0), fmpq(0), c)
    encl: list[_Enclosed] = [_enclose_r(rn, rd, c, RTOL) for c in pool]
    # the best candidate: largest R for σ = −1, smallest for σ = +1
    for _ in range(MAX_ROUNDS):
        if sigma < 0:
            best = max(encl, key=lambda e: e[2])
            rivals = [e for e in encl if e is not best and e[2] >= best[1]]
        else:
            best = min(encl, key=lambda e: e[1])
            rivals = [e for e in encl if e is not best and e[1] <= best[2]]
        if not rivals:
            break
        tighter = RTOL / 2**32
        encl = [
            _enclose_r(rn, rd, e[0], tighter) if e is best or any(e is r for r in rivals) else e
            for e in encl
        ]
    if sigma < 0:
        r_lo = max(e[1] for e in encl)
        r_hi = max(e[2] for e in encl)
        best = max(encl, key=lambda e: e[2])
        lo = -sqrt_bounds(r_hi)[1]
        hi = -sqrt_bounds(r_lo)[0]
    else:
        r_lo = min(e[1] for e in encl)
        r_hi = min(e[2] for e in encl)
        best = min(encl, key=lambda e: e[1])
        lo = sqrt_bounds(r_lo)[0]
        hi = sqrt_bounds(r_hi)[1]
    return _result(lo, hi, best[0])


def _result(lo: fmpq, hi: fmpq, c: _Candidate) -> EtaMinimum:
    if c.point is None:
        return EtaMinimum(lower=lo, upper=hi, kind=EtaKind.LIMIT, limit=math.inf)
    w = omega_of(c.point)
    if c.attained:
        return EtaMinimum(lower=lo, upper=hi, kind=EtaKind.ATTAINED, omega=w)
    return EtaMinimum(lower=lo, upper=hi, kind=EtaKind.LIMIT, limit=w)
