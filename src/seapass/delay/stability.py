"""Right-half-plane roots of the characteristic quasi-polynomial ``P(s) + Q(s) e^{-sτ}``.

The loop with the port held is stable when the denominator ``D(s, e^{-sτ})`` of the
impedance has no root in ``Re s ≥ 0`` (a root at ``s = 0`` that is a polynomial factor of
``D`` is the impedance's pole at 0 and is handled with the residues).  With
``D = s^k g(s) (p(s) + q(s) E)``, ``g = gcd`` (roots that do not move with ``τ``):

* ``q = 0``: a rational loop, decided by the exact root count `rhp_count`;
* ``deg q > deg p`` (advanced): infinitely many roots in ``Re s > 0`` for every ``τ > 0``;
* ``deg q = deg p`` (neutral): with ``r = |q_n/p_n|``, ``r > 1`` gives infinitely many roots in
  ``Re s > 0`` for every ``τ > 0``, ``r = 1`` chains of roots approaching the axis
  (undecided), ``r < 1`` is handled like the retarded case;
* ``deg q < deg p`` (retarded): at ``τ = 0`` the roots are those of ``p + q``, counted
  exactly.  As ``τ`` grows roots cross the imaginary axis only at ``s = ±jω`` with
  ``W(ω²) = |p(jω)|² - |q(jω)|² = 0`` (exact roots), at the crossing delays
  ``τ_{i,k} = (φ_i + 2πk)/ω_i`` where ``e^{-jω_iφ_i/ω_i} = -p(jω_i)/q(jω_i)``, and in the
  direction ``sign W'(ω_i²)`` (Cooke & van den Driessche), a pair each time.  So
  ``n(τ) = n(0) + 2 Σ_i sign W'(ω_i²) · #{k : τ_{i,k} < τ}``.

Crossing delays are arb balls; a delay whose ball meets a crossing delay is undecided at
that precision (and the precision is raised).

References
----------
.. [1] K. L. Cooke and P. van den Driessche, "On zeroes of some transcendental equations",
   Funkcialaj Ekvacioj 29, 1986, pp. 77-90.
.. [2] J. K. Hale and S. M. Verduyn Lunel, *Introduction to Functional Differential
   Equations*, Springer, 1993, ch. 12 (neutral equations).
.. [3] W. Michiels and S.-I. Niculescu, *Stability and Stabilization of Time-Delay
   Systems*, SIAM, 2007, ch. 1 and 4.

Examples
--------
``s + 2 + e^{-sτ}``: ``|p|² - |q|² = ω² + 3 > 0``, no crossing: stable for every delay.

>>> from flint import fmpq, fmpq_poly
>>> ch = characteristic((fmpq_poly([2, 1]), fmpq_poly([1])))
>>> str(ch.kind), stability_at(ch, fmpq(5)).stable, delay_independent_stability(ch)
('retarded', True, True)

``s + 1/2 + 2 e^{-sτ}`` crosses at ``ω = √15/2`` and is unstable from ``τ ≈ 0.94``:

>>> ch = characteristic((fmpq_poly([fmpq(1, 2), 1]), fmpq_poly([2])))
>>> [round(float(c.delay.mid()), 6) for c in crossings(ch)]
[0.941639]
>>> stability_at(ch, fmpq(9, 10)).stable, stability_at(ch, fmpq(1)).stable
(True, False)
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from enum import StrEnum

from flint import acb, arb, arb_poly, fmpq, fmpq_poly

from ..exact import poly as ep
from ..exact.axis import at_j_omega, squared_magnitude_polynomial
from .balls import PRECISIONS, arb_of, ball, precision

__all__ = [
    "Characteristic",
    "Crossing",
    "LoopKind",
    "Stability",
    "characteristic",
    "crossings",
    "delay_independent_stability",
    "first_crossing",
    "rhp_count",
    "stability_at",
]


# ---------------------------------------------------------------- exact root count


def _quadrant(re: fmpq, im: fmpq) -> int:
    if re > 0:
        return 0 if im > 0 else 3
    return 1 if im > 0 else 2


def _gap_points(sf: fmpq_poly) -> list[fmpq]:
    """One rational point before, between and after the real roots of a squarefree ``sf``."""
    ivs = [list(iv) for iv in ep.isolate_real_roots(sf)]
    for i in range(1, len(ivs)):
        prev, cur = ivs[i - 1], ivs[i]
        while cur[0] <= prev[1]:  # separate the closed intervals (an end may be a root)
            if cur[0] < cur[1]:
                cur[0], cur[1] = ep.refine_past(sf, (cur[0], cur[1]), prev[1])
            else:
                prev[0], prev[1] = ep.refine(sf, (prev[0], prev[1]), (prev[1] - prev[0]) / 2)
    points = [ivs[0][0] - 1]
    points += [(ivs[i - 1][1] + ivs[i][0]) / 2 for i in range(1, len(ivs))]
    points.append(ivs[-1][1] + 1)
    if any(sf(x) == 0 for x in points):
        raise ArithmeticError("a sample point is a root")  # pragma: no cover
    return points


def rhp_count(p: fmpq_poly) -> int | None:
    """Number of roots of ``p`` with ``Re s > 0`` (exact), or None if ``p`` has a root on the
    imaginary axis.

    The argument of ``p(jω)`` is followed from ``ω = -∞`` to ``∞`` by the quadrants it visits
    between consecutive real roots of ``Re p(jω)`` and ``Im p(jω)`` (exact isolation); its
    total change is ``π (n_left - n_right)``.

    >>> x = fmpq_poly([0, 1])
    >>> rhp_count((x - 1) * (x**2 + x + 1)), rhp_count(x**2 + 1), rhp_count((x + 2) * (x - 3) ** 2)
    (1, None, 2)
    """
    n = p.degree()
    if n <= 0:
        return 0
    re, im = at_j_omega(p)
    if re.is_zero() or p[0] == 0:
        return None  # a root at s = 0
    g = re.gcd(im) if not im.is_zero() else re
    if g.degree() > 0 and ep.count_real_roots(g) > 0:
        return None
    if im.is_zero():  # p(s) = h(s²) with no axis root: roots in pairs ±s
        return n // 2
    prod = ep.squarefree_part(re * im)
    samples = _gap_points(prod) if prod.degree() > 0 else [fmpq(0)]
    quads = [_quadrant(re(w), im(w)) for w in samples]
    unwrapped = [quads[0]]
    for q_prev, q in itertools.pairwise(quads):
        step = (q - q_prev) % 4
        if step == 2:
            raise ArithmeticError("the curve jumped two quadrants; refusing to guess")
        unwrapped.append(unwrapped[-1] + (1 if step == 1 else -1 if step == 3 else 0))
    neg = 2 if p.leading_coefficient() < 0 else 0
    d_minus, d_plus = (neg + 3 * n) % 4, (neg + n) % 4

    def adjacent(u: int, direction: int) -> int:
        if u % 4 == direction:
            return u
        if (u + 1) % 4 == direction:
            return u + 1
        raise ArithmeticError("asymptote not adjacent to the last quadrant")

    delta = adjacent(unwrapped[-1], d_plus) - adjacent(unwrapped[0], d_minus)
    if delta % 2:
        raise ArithmeticError("the argument change is not a multiple of pi")
    n_right = (n - delta // 2) // 2
    if not 0 <= n_right <= n or (n - delta // 2) % 2:
        raise ArithmeticError("inconsistent root count")
    return n_right


# ---------------------------------------------------------------- the quasi-polynomial


class LoopKind(StrEnum):
    """The type of the characteristic equation ``p(s) + q(s) e^{-sτ} = 0``."""

    RATIONAL = "rational"
    """No delay in ``D``."""
    RETARDED = "retarded"
    """``deg q < deg p``."""
    NEUTRAL = "neutral"
    """``deg q = deg p``."""
    ADVANCED = "advanced"
    """``deg q > deg p``: unstable for every delay ``> 0``."""
    UNSUPPORTED = "unsupported"
    """``E²`` or higher in ``D``."""


@dataclass(frozen=True, kw_only=True)
class Characteristic:
    """``D(s, E) = s^k · common(s) · (p(s) + q(s) E)``; ``kind`` as in the module docstring
    (``"unsupported"``: ``E²`` or higher in ``D``)."""

    p: fmpq_poly
    q: fmpq_poly
    s_power: int
    common: fmpq_poly
    kind: LoopKind

    @property
    def neutral_ratio(self) -> fmpq | None:
        """``|q_n/p_n|`` of a neutral equation (None otherwise)."""
        if self.kind is not LoopKind.NEUTRAL:
            return None
        return abs(self.q.leading_coefficient() / self.p.leading_coefficient())


def _s_order(p: fmpq_poly) -> int:
    c = p.coeffs()
    return next((i for i, v in enumerate(c) if v != 0), len(c))


def characteristic(den: tuple[fmpq_poly, ...]) -> Characteristic:
    """Split the denominator ``Σ_k D_k(s) E^k`` of a delayed impedance."""
    parts = list(den)
    while len(parts) > 1 and parts[-1].is_zero():
        parts.pop()
    if len(parts) > 2:
        return Characteristic(
            p=parts[0], q=fmpq_poly([]), s_power=0, common=fmpq_poly([1]), kind=LoopKind.UNSUPPORTED
        )
    big_p = parts[0]
    big_q = parts[1] if len(parts) > 1 else fmpq_poly([])
    k = min(_s_order(big_p), _s_order(big_q) if not big_q.is_zero() else _s_order(big_p))
    shift = fmpq_poly([0, 1]) ** k
    big_p, big_q = big_p // shift, big_q // shift
    if big_q.is_zero():
        return Characteristic(
            p=big_p, q=big_q, s_power=k, common=fmpq_poly([1]), kind=LoopKind.RATIONAL
        )
    g = big_p.gcd(big_q)
    p, q = big_p // g, big_q // g
    if q.degree() > p.degree():
        kind = LoopKind.ADVANCED
    elif q.degree() == p.degree():
        kind = LoopKind.NEUTRAL
    else:
        kind = LoopKind.RETARDED
    return Characteristic(p=p, q=q, s_power=k, common=g, kind=kind)


@dataclass(frozen=True, kw_only=True)
class Crossing:
    """Where roots cross the imaginary axis as ``τ`` grows.

    ``x``: isolating interval of ``ω²`` (a root of ``W``); ``omega``, ``phase`` (``φ`` in
    ``(0, 2π)``) and ``delay`` (``φ/ω``, the first crossing delay) are balls; ``direction``:
    ``+1`` into the right half-plane, ``-1`` out of it, ``0`` touching (``W`` has a multiple
    root there).
    """

    x: tuple[fmpq, fmpq]
    omega: arb
    phase: arb
    delay: arb
    direction: int
    precision: int = field(default=0, compare=False)

    def count_below(self, tau: fmpq) -> int | None:
        """``#{k ≥ 0 : (φ + 2πk)/ω < τ}``, or None when ``τ`` is too close to a crossing delay."""
        with precision(max(self.precision, 128)):
            t = (arb_of(tau) * self.omega - self.phase) / (2 * arb.pi())
            if t < 0:
                return 0
            if t.contains_integer():
                return None
            k = t.floor().unique_fmpz()
            return None if k is None else int(k) + 1


def _crossing_at(ch: Characteristic, w_poly: fmpq_poly, iv: tuple[fmpq, fmpq]) -> Crossing:
    direction = ep.sign_at_root(w_poly.derivative(), w_poly, iv)
    pr, pi = at_j_omega(ch.p)
    qr, qi = at_j_omega(ch.q)
    a, b = iv
    for bits in PRECISIONS:
        if a < b:
            a, b = ep.refine(w_poly, (a, b), (b - a) / 2 ** (bits // 2) + a / 2 ** (bits - 16))
        with precision(bits):
            w = ball(a, b).sqrt()
            pv = acb(arb_poly(pr)(w), arb_poly(pi)(w))
            qv = acb(arb_poly(qr)(w), arb_poly(qi)(w))
            phase = -((-pv / qv).arg())
            if phase < 0:
                phase += 2 * arb.pi()
            elif not phase > 0:
                continue  # straddles the branch cut: refine and retry
            if phase.rad() < phase.mid().abs_lower() * arb(2) ** -40 or bits == PRECISIONS[-1]:
                return Crossing(
                    x=(a, b),
                    omega=w,
                    phase=phase,
                    delay=phase / w,
                    direction=direction,
                    precision=bits,
                )
    return Crossing(
        x=(a, b),
        omega=w,
        phase=phase,
        delay=phase / w,
        direction=direction,
        precision=PRECISIONS[-1],
    )


def crossings(ch: Characteristic) -> list[Crossing]:
    """Every frequency at which a root crosses the axis for some ``τ > 0`` (retarded/neutral)."""
    if ch.kind not in (LoopKind.RETARDED, LoopKind.NEUTRAL):
        return []
    w_poly = squared_magnitude_polynomial(ch.p) - squared_magnitude_polynomial(ch.q)
    if w_poly.is_zero():
        raise ArithmeticError("|p(jw)| = |q(jw)| for every w")  # only for r = 1 (handled)
    return [_crossing_at(ch, w_poly, iv) for iv in ep.isolate_real_roots(w_poly, 0)]


def first_crossing(ch: Characteristic) -> Crossing | None:
    """The crossing with the smallest first delay (None if roots never cross)."""
    cands = crossings(ch)
    if not cands:
        return None
    return min(cands, key=lambda c: float(c.delay.mid()))


@dataclass(frozen=True, kw_only=True)
class Stability:
    """``stable``: True / False / None (undecided); ``detail`` says why."""

    stable: bool | None
    detail: str = ""
    rhp_roots: int | None = None


def _common_ok(ch: Characteristic) -> Stability | None:
    if ch.common.degree() <= 0:
        return None
    n = rhp_count(ch.common)
    if n is None:
        return Stability(
            stable=None, detail="a root on the imaginary axis for every delay (common factor)"
        )
    if n > 0:
        return Stability(
            stable=False,
            detail="a right-half-plane root for every delay (common factor)",
            rhp_roots=n,
        )
    return None


def stability_at(ch: Characteristic, tau: fmpq) -> Stability:
    """Decide whether ``p + q e^{-sτ}`` (and the common factor) has no root in ``Re s ≥ 0``."""
    bad = _common_ok(ch)
    if bad is not None:
        return bad
    if ch.kind is LoopKind.UNSUPPORTED:
        return Stability(
            stable=None, detail="the characteristic equation has e^{-2s tau} or higher: unsupported"
        )
    if ch.kind is LoopKind.RATIONAL or tau == 0:
        n = rhp_count(ch.p + ch.q)
        if n is None:
            return Stability(stable=None, detail="a root on the imaginary axis")
        return Stability(
            stable=n == 0, detail="" if n == 0 else f"{n} right-half-plane roots", rhp_roots=n
        )
    if ch.kind is LoopKind.ADVANCED:
        return Stability(
            stable=False, detail="advanced type (deg Q > deg P): infinitely many unstable roots"
        )
    ratio = ch.neutral_ratio
    if ratio is not None and ratio > 1:
        return Stability(
            stable=False, detail="neutral type with |q_n/p_n| > 1: infinitely many unstable roots"
        )
    if ratio is not None and ratio == 1:
        return Stability(
            stable=None, detail="neutral type with |q_n/p_n| = 1: root chains approach the axis"
        )
    n0 = rhp_count(ch.p + ch.q)
    if n0 is None:
        return Stability(stable=None, detail="a root on the imaginary axis at zero delay")
    n = n0
    for c in crossings(ch):
        k = c.count_below(tau)
        if k is None:
            return Stability(stable=None, detail=f"the delay is within rounding of a crossing delay at w = {float(c.omega.mid()):.6g} rad/s")  # fmt: skip
        if k and c.direction == 0:
            return Stability(
                stable=None, detail="a root touches the imaginary axis (W has a multiple root)"
            )
        n += 2 * c.direction * k
    if n < 0:
        raise ArithmeticError("negative number of right-half-plane roots")
    return Stability(
        stable=n == 0, detail="" if n == 0 else f"{n} right-half-plane roots", rhp_roots=n
    )


def delay_independent_stability(ch: Characteristic) -> bool | None:
    """Stable for every delay ``τ ≥ 0`` (exact); None when undecided."""
    if ch.common.degree() > 0:
        n = rhp_count(ch.common)
        if n is None:
            return None
        if n > 0:
            return False
    if ch.kind is LoopKind.UNSUPPORTED:
        return None
    n0 = rhp_count(ch.p + ch.q)
    if n0 is None:
        return None
    if n0 > 0:
        return False
    if ch.kind is LoopKind.RATIONAL:
        return True
    if ch.kind is LoopKind.ADVANCED:
        return False
    ratio = ch.neutral_ratio
    if ratio is not None and ratio >= 1:
        return False if ratio > 1 else None
    w_poly = squared_magnitude_polynomial(ch.p) - squared_magnitude_polynomial(ch.q)
    return ep.count_real_roots(w_poly, 0) == 0
