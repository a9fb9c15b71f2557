"""The first delay at which each frequency fails, ``g(ω)``, with certified enclosures.

For a delay to the first power, ``F(ω; τ) = A + B cos θ + C sin θ`` with ``θ = ωτ`` is
negative exactly on the arcs ``θ ∈ (γ - δ, γ + δ) + 2πk`` with ``γ = π + atan2(C, B)`` and
``δ = acos(A/R)``, ``R = sqrt(B² + C²)``, at the frequencies of the dangerous band
(``A < R``).  If the design is passive at ``τ = 0`` (``A + B ≥ 0``), the arc never holds
``θ = 0``, so the first one starts at ``θ_lo = γ - δ ∈ [0, 2π)`` and

``g(ω) = (γ(ω) - δ(ω))/ω``

is the smallest delay with ``F(ω; τ) < 0`` just above it.  Hence ``F(ω; τ) ≥ 0`` for every
``τ ∈ [0, T]`` and every ``ω`` in a set ``Ω`` exactly when ``g ≥ T`` on ``Ω``, and the
delay margin of the real part is ``inf g``: a one-dimensional problem, decided here by
branch and bound on arb balls (natural interval extension and mean-value form).

Examples
--------
A delayed virtual spring, ``Re Z = b - K sin(ωτ)/ω``: ``g(ω) = arcsin(bω/K)/ω``, which
increases from ``b/K`` at ``ω → 0``.

>>> from flint import fmpq
>>> from seapass.delay.structure import delayed_impedance
>>> from seapass.delay.trig import real_part
>>> g = FirstDelay(real_part(delayed_impedance("m*s + b + K*exp(-tau*s)/s",
...                                            values=dict(m=1, b=2, K=50), free_delay=True)))
>>> with precision(128):
...     round(float(g.at(fmpq(10)).mid()), 6)     # asin(0.4)/10
0.041152
"""

from __future__ import annotations

from flint import arb, arb_poly, fmpq

from .balls import arb_of, ball, lower, precision, upper
from .trig import TrigRealPart

__all__ = ["FirstDelay", "precision"]


def _clamped_acos(u: arb) -> arb:
    """``acos`` of ``u`` clamped to ``[-1, 1]`` (``δ = 0`` where ``A ≥ R``: outside the band)."""
    if not u.is_finite():
        return arb.nan()
    lo, hi = max(lower(u), fmpq(-1)), min(upper(u), fmpq(1))
    if lo > hi:  # the whole ball lies beyond 1 (or below -1)
        return arb(0) if lo >= 1 else arb.pi()
    return arb(hi).acos().union(arb(lo).acos())


class FirstDelay:
    """``g(ω)`` of a first-order real part (see the module docstring); call under a precision."""

    def __init__(self, f: TrigRealPart) -> None:
        if f.order != 1:
            raise ValueError("g(w) is defined for a delay to the first power")
        self.f = f
        self._bits = -1

    def _polys(self) -> None:
        from flint import ctx

        if self._bits == ctx.prec:
            return
        self._bits = ctx.prec
        a, b, c = self.f.cos[0], self.f.cos[1], self.f.sin[1]
        self.a, self.b, self.c = arb_poly(a), arb_poly(b), arb_poly(c)
        self.da, self.db, self.dc = (p.derivative() for p in (self.a, self.b, self.c))

    def _parts(self, w: arb) -> tuple[arb, arb, arb]:
        self._polys()
        return self.a(w), self.b(w), self.c(w)

    def safe(self, w: arb) -> bool:
        """Every frequency in the ball is outside the dangerous band (``A > R``)."""
        a, b, c = self._parts(w)
        return bool(a > 0 and a * a - b * b - c * c > 0)

    def at(self, w: fmpq) -> arb:
        """``g`` at a rational frequency inside the band (a ball)."""
        return self._value(arb_of(w))

    def _value(self, w: arb) -> arb:
        a, b, c = self._parts(w)
        r2 = b * b + c * c
        gamma = arb.pi() + arb.atan2(c, b)
        delta = _clamped_acos(a / r2.sqrt())
        return (gamma - delta) / w

    def _arc(self, w: arb) -> arb:
        """``θ_lo(ω) = γ - δ`` (clamped outside the band)."""
        a, b, c = self._parts(w)
        r2 = b * b + c * c
        return arb.pi() + arb.atan2(c, b) - _clamped_acos(a / r2.sqrt())

    def gap(self, w: fmpq, bound: fmpq) -> arb:
        """``θ_lo(ω) - bound·ω`` at a rational frequency: negative iff ``g(ω) < bound``."""
        x = arb_of(w)
        return self._arc(x) - arb_of(bound) * x

    def gap_bound(self, lo: fmpq, hi: fmpq, bound: fmpq) -> arb | None:
        """An enclosure of ``θ_lo(ω) - bound·ω`` over ``[lo, hi]`` (None: the piece is safe).

        ``g ≥ bound`` on the piece iff this is ``≥ 0`` there (``ω > 0``); proving it on the
        arc instead of on ``g = θ_lo/ω`` avoids the cancellation of dividing by ``ω`` near 0.
        Natural interval extension, intersected with the mean-value form where ``θ_lo'`` is
        bounded.  Where part of the piece is safe the formula continues with ``δ = 0``,
        below the (infinite) constraint there, so the enclosure stays a valid lower bound.
        """
        w = ball(lo, hi)
        if self.safe(w):
            return None
        t = arb_of(bound)
        natural = self._arc(w) - t * w
        mv = self._mean_value(lo, hi, t)
        if mv is None or not mv.is_finite():
            return natural
        if not natural.is_finite():
            return mv
        return natural.intersection(mv) if natural.overlaps(mv) else mv

    def _mean_value(self, lo: fmpq, hi: fmpq, t: arb) -> arb | None:
        """``H(c) + H'(W)(W - c)`` for ``H = θ_lo - tω``; None where ``δ'`` is unbounded."""
        self._polys()
        w = ball(lo, hi)
        a, b, c = self._parts(w)
        da, db, dc = self.da(w), self.db(w), self.dc(w)
        r2 = b * b + c * c
        if not r2 > 0:
            return None
        r = r2.sqrt()
        u = a / r
        one_minus = 1 - u * u
        if not one_minus > 0:
            return None
        dgamma = (b * dc - c * db) / r2
        du = (da * r2 - a * (b * db + c * dc)) / (r2 * r)
        slope = dgamma + du / one_minus.sqrt() - t
        c0 = (lo + hi) / 2
        center = self._arc(arb_of(c0)) - t * arb_of(c0)
        if not center.is_finite():
            return None
        return center + slope * ball(-(hi - lo) / 2, (hi - lo) / 2)
