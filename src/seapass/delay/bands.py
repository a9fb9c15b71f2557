"""The dangerous band of a delay to the first power: where some delay makes ``Re Z < 0``.

For ``F = A(ω) + B(ω) cos θ + C(ω) sin θ`` and ``R = sqrt(B² + C²)``,
``min_θ F = A - R``.  So ``F(ω; τ) ≥ 0`` for **every** delay at the frequencies where
``A ≥ 0`` and ``A² ≥ B² + C²`` (polynomials in ``x = ω²``, decided exactly), and the
dangerous band is

``Ω = {ω > 0 : A(ω) < 0 or A(ω)² < B(ω)² + C(ω)²}``,

a finite union of open intervals with exact algebraic end points.  Inside ``Ω``, ``F < 0``
exactly when ``θ = ωτ`` lies in the open arc ``(γ - δ, γ + δ) mod 2π`` with
``γ = π + atan2(C, B)`` and ``δ = acos(A/R)``.

Examples
--------
A rigid device with a delayed spring, ``Re Z = b - K sin(ωτ)/ω``: dangerous below
``ω = K/b``.

>>> from seapass.delay.structure import delayed_impedance
>>> from seapass.delay.trig import real_part
>>> f = real_part(delayed_impedance("m*s + b + K*exp(-tau*s)/s",
...                                 values=dict(m=1, b=2, K=50, tau=0.01)))
>>> [(float(a), round(float(b), 9)) for a, b in dangerous_bands(f)]
[(0.0, 25.0)]
"""

from __future__ import annotations

from dataclasses import dataclass

from flint import fmpq, fmpq_poly

from ..exact import poly as ep
from .balls import sqrt_bounds
from .trig import TrigRealPart

__all__ = ["Band", "band_polynomials", "dangerous_bands"]

Band = tuple[fmpq, fmpq]
"""Rational ``(lo, hi)`` enclosing one open band in ``ω`` (``lo`` may be 0)."""


@dataclass(frozen=True, kw_only=True)
class BandPolynomials:
    """``A``, and ``gap = A² - B² - C²``, as polynomials in ``x = ω²``."""

    a: fmpq_poly
    gap: fmpq_poly


def band_polynomials(f: TrigRealPart) -> BandPolynomials:
    """``A(x)`` and ``A(x)² - B(x)² - x·c(x)²`` of a first-order real part (``C = ω c(x²)``)."""
    if f.order > 1:
        raise ValueError("the dangerous band is defined for a delay to the first power")
    (a0, *a_rest), (_b0, *b_rest) = f.in_x()
    a1 = a_rest[0] if a_rest else fmpq_poly([])
    c1 = b_rest[0] if b_rest else fmpq_poly([])
    x = fmpq_poly([0, 1])
    return BandPolynomials(a=a0, gap=a0 * a0 - a1 * a1 - x * c1 * c1)


def _region_sign(p: fmpq_poly, lo: fmpq, hi: fmpq | None) -> int:
    """The constant sign of ``p`` on a region between consecutive sign changes.

    A test point may hit a root of even multiplicity (``p = 0`` there); then another
    point of the region is tried (``p`` has finitely many roots).
    """
    for k in range(1, p.degree() + 3):
        point = lo + (hi - lo) / (k + 1) if hi is not None else lo * (k + 1) + k
        v = p(point)
        if v != 0:
            return 1 if v > 0 else -1
    raise ArithmeticError("no point off the roots")  # pragma: no cover - deg + 2 points


def _negative_set(p: fmpq_poly) -> list[tuple[fmpq, fmpq]]:
    """Rational enclosures ``(lo, hi)`` in ``x`` of the open sets where ``p(x) < 0``, ``x > 0``."""
    if p.is_zero():
        return []
    odd = ep.positive_roots_odd_multiplicity(p)
    tight: list[tuple[fmpq, fmpq]] = []
    prev = fmpq(0)
    if odd.degree() > 0:
        for iv in ep.isolate_real_roots(odd, 0):
            a, b = ep.refine_past(odd, iv, prev) if iv[0] <= prev < iv[1] else iv
            if a < b:  # edges to a relative width of 2^-32 (the band is scanned, not guessed)
                a, b = ep.refine(odd, (a, b), (b - a) / 2**40 + a / 2**32)
            tight.append((a, b))
            prev = b
    # region i lies between root i-1 and root i; a point strictly inside each:
    edges_lo = [fmpq(0)] + [b for _, b in tight]
    edges_hi = [a for a, _ in tight] + [None]
    out: list[tuple[fmpq, fmpq]] = []
    for i, (lo, hi) in enumerate(zip(edges_lo, edges_hi, strict=True)):
        if _region_sign(p, lo, hi) > 0:
            continue
        # the enclosure reaches out to the neighbouring roots' far ends
        enc_lo = tight[i - 1][0] if i > 0 else fmpq(0)
        enc_hi = tight[i][1] if i < len(tight) else None
        if enc_hi is None:
            raise ArithmeticError("unbounded band")  # the caller handles h < 0 first
        out.append((enc_lo, enc_hi))
    return out


def dangerous_bands(f: TrigRealPart) -> list[Band]:
    """Rational enclosures in ``ω`` of the dangerous band (merged, increasing).

    Requires a bounded band (the high-frequency term positive); each enclosure may be a
    little wider than the band (its ends are isolating intervals of the edges).
    """
    bp = band_polynomials(f)
    sets = _negative_set(bp.gap) + _negative_set(bp.a)
    sets.sort()
    merged: list[tuple[fmpq, fmpq]] = []
    for lo, hi in sets:
        if merged and lo <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(hi, merged[-1][1]))
        else:
            merged.append((lo, hi))
    return [(sqrt_bounds(lo)[0], sqrt_bounds(hi)[1]) for lo, hi in merged]
