"""The real part of a delayed impedance on the imaginary axis, exactly.

With ``s = jω`` and ``E = e^{-jθ}``, ``θ = ωτ``,

``F(ω) = Re N(jω, E) · conj D(jω, E) = Σ_m A_m(ω) cos(mθ) + B_m(ω) sin(mθ)``,

a trigonometric polynomial in ``θ`` whose coefficients ``A_m`` (even) and ``B_m`` (odd)
are polynomials in ``ω`` with exact rational coefficients.  ``F = |D|² Re Z``, so its sign
is the sign of ``Re Z(jω)`` wherever ``D(jω) ≠ 0``.  For a delay to the first power
(``m ≤ 1``) this is ``A(ω) + B(ω) cos ωτ + C(ω) sin ωτ``; at ``τ = 0`` it is the delay-free
real part ``Σ_m A_m``.

Derivation: ``N_k(jω) conj D_l(jω) = u_kl + j v_kl`` (``u`` even, ``v`` odd in ``ω``) and
``Re[(u + jv) e^{-j(k-l)θ}] = u cos((k-l)θ) + v sin((k-l)θ)``; terms with ``k - l = ±m``
collect into ``A_m`` and ``B_m``.

Examples
--------
>>> from seapass.delay.structure import delayed_impedance
>>> f = real_part(delayed_impedance("m*s + b + K*exp(-tau*s)/s",
...                                 values=dict(m=1, b=2, K=50, tau=0.01)))
>>> [str(p) for p in f.cos], [str(p) for p in f.sin]   # 2ω² and -50ω sin(ωτ)
(['2*x^2', '0'], ['0', '(-50)*x'])
"""

from __future__ import annotations

from dataclasses import dataclass

from flint import arb, arb_poly, fmpq_poly

from ..exact.axis import at_j_omega, even_to_x
from .structure import DelayedImpedance

__all__ = ["TrigRealPart", "real_part"]


@dataclass(frozen=True, kw_only=True)
class TrigRealPart:
    """``F(ω) = Σ_m A_m(ω) cos(mωτ) + B_m(ω) sin(mωτ)``; ``cos[m] = A_m``, ``sin[m] = B_m``.

    Polynomials are in ``ω`` (ascending, exact); ``B_0 = 0``.
    """

    cos: tuple[fmpq_poly, ...]
    sin: tuple[fmpq_poly, ...]

    @property
    def order(self) -> int:
        """Highest harmonic ``m`` with a nonzero coefficient (0: no delay left)."""
        for m in range(len(self.cos) - 1, -1, -1):
            if not self.cos[m].is_zero() or not self.sin[m].is_zero():
                return m
        return 0

    @property
    def is_zero(self) -> bool:
        """``F ≡ 0``: the impedance is lossless at every delay."""
        return all(p.is_zero() for p in (*self.cos, *self.sin))

    @property
    def degree(self) -> int:
        """Highest power of ``ω`` among the coefficients (-1 for ``F ≡ 0``)."""
        return max((p.degree() for p in (*self.cos, *self.sin) if not p.is_zero()), default=-1)

    def at_zero_delay(self) -> fmpq_poly:
        """``F`` at ``τ = 0`` (``Σ_m A_m``), as a polynomial in ``ω``."""
        out = fmpq_poly([])
        for a in self.cos:
            out += a
        return out

    def in_x(self) -> tuple[tuple[fmpq_poly, ...], tuple[fmpq_poly, ...]]:
        """``A_m(ω) = a_m(x)`` and ``B_m(ω) = ω b_m(x)`` with ``x = ω²``: ``(a, b)``."""
        a = tuple(even_to_x(p) for p in self.cos)
        b = tuple(even_to_x(_div_omega(p)) for p in self.sin)
        return a, b

    # ------------------------------------------------------------ ball evaluation

    def balls(self) -> _BallForm:
        """The coefficients as ball polynomials at the current working precision."""
        return _BallForm(self)


def _div_omega(p: fmpq_poly) -> fmpq_poly:
    c = p.coeffs()
    if c and c[0] != 0:
        raise ArithmeticError("an odd coefficient with a constant term")
    return fmpq_poly(c[1:])


class _BallForm:
    """``F``, ``∂F/∂ω`` and ``∂F/∂τ`` on balls (build one per working precision)."""

    def __init__(self, f: TrigRealPart) -> None:
        self.m = range(len(f.cos))
        self.a = [arb_poly(p) for p in f.cos]
        self.b = [arb_poly(p) for p in f.sin]
        self.da = [p.derivative() for p in self.a]
        self.db = [p.derivative() for p in self.b]

    def value(self, w: arb, tau: arb) -> arb:
        """``F(ω; τ)``."""
        out = self.a[0](w)
        for m in self.m[1:]:
            s, c = (w * tau * m).sin_cos()
            out += self.a[m](w) * c + self.b[m](w) * s
        return out

    def d_omega(self, w: arb, tau: arb) -> arb:
        """``∂F/∂ω`` at fixed ``τ``."""
        out = self.da[0](w)
        for m in self.m[1:]:
            s, c = (w * tau * m).sin_cos()
            am, bm = self.a[m](w), self.b[m](w)
            out += self.da[m](w) * c + self.db[m](w) * s + tau * m * (bm * c - am * s)
        return out

    def d_tau(self, w: arb, tau: arb) -> arb:
        """``∂F/∂τ`` at fixed ``ω``."""
        out = arb(0)
        for m in self.m[1:]:
            s, c = (w * tau * m).sin_cos()
            out += w * m * (self.b[m](w) * c - self.a[m](w) * s)
        return out


def real_part(z: DelayedImpedance) -> TrigRealPart:
    """The exact trigonometric real part ``F`` of ``z`` (see the module docstring)."""
    order = max(len(z.num), len(z.den)) - 1
    a = [fmpq_poly([]) for _ in range(order + 1)]
    b = [fmpq_poly([]) for _ in range(order + 1)]
    dparts = [at_j_omega(d) for d in z.den]
    for k, n in enumerate(z.num):
        if n.is_zero():
            continue
        nr, ni = at_j_omega(n)
        for l_, (dr, di) in enumerate(dparts):
            if dr.is_zero() and di.is_zero():
                continue
            u = nr * dr + ni * di
            v = ni * dr - nr * di
            m = k - l_
            if m >= 0:
                a[m] += u
                b[m] += v
            else:
                a[-m] += u
                b[-m] -= v
    b[0] = fmpq_poly([])
    return TrigRealPart(cos=tuple(a), sin=tuple(b))
