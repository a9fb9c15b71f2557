"""Exact high-frequency analysis of the real part ``F(ω; τ)``.

Let ``d`` be the highest power of ``ω`` in the coefficients of ``F`` and ``a_m``, ``b_m``
the coefficients of ``ω^d`` in ``A_m``, ``B_m``.  Then ``F = ω^d h(ωτ) + (lower powers)``
with the trigonometric polynomial ``h(θ) = Σ_m a_m cos mθ + b_m sin mθ`` (only cosines
when ``d`` is even, only sines when ``d`` is odd, by parity).

* ``d`` even: ``h(θ) = H(cos θ)`` with ``H = Σ a_m T_m`` (Chebyshev), an exact polynomial on
  ``[-1, 1]``.  If ``H > 0`` there, with ``h_min`` a rational lower bound and
  ``s_i = Σ_m |A_m,i| + |B_m,i|``, then ``F(ω) ≥ h_min ω^d - Σ_{i<d} s_i ω^i`` for every
  delay, so ``F > 0`` beyond the largest positive root ``ω1`` of that polynomial (exact,
  and the same for every ``τ``).  If ``H < 0`` somewhere, then for **every** ``τ > 0``
  ``F`` is negative at arbitrarily high frequencies: the dangerous band is unbounded and
  the delay margin is 0.  ``H ≥ 0`` with a zero is a tangency: lower powers decide.
* ``d`` odd: ``h`` is a nonzero odd trigonometric polynomial, negative somewhere, so the
  band is unbounded as well.

Examples
--------
The delayed actuator-side PD of the APD design, ``F = k1² (ω² (b + b_d cos θ) - k_d ω sin θ)``:
``H(c) = b + b_d c`` is negative near ``c = -1`` when ``b_d > b``.

>>> from seapass.delay.structure import delayed_impedance
>>> from seapass.delay.trig import real_part
>>> from seapass.model.sea import SEA
>>> apd = SEA(D1="k1", CA="(kd + bd*s)*exp(-tau*s)",
...           values=dict(m=1, b=10, k1=1000, kd=500, bd=25, tau=0.001))
>>> high_frequency(real_part(delayed_impedance(apd))).kind
'unbounded'
"""

from __future__ import annotations

from dataclasses import dataclass

from flint import arb, fmpq, fmpq_poly

from ..exact import poly as ep
from .lowfreq import lower_bound_on
from .trig import TrigRealPart

__all__ = ["HighFrequency", "chebyshev", "high_frequency"]


def chebyshev(coeffs: list[fmpq]) -> fmpq_poly:
    """``Σ_m c_m T_m(x)`` as an exact polynomial."""
    out = fmpq_poly([])
    t_prev, t_cur = fmpq_poly([1]), fmpq_poly([0, 1])
    for m, c in enumerate(coeffs):
        if m == 0:
            tm = t_prev
        elif m == 1:
            tm = t_cur
        else:
            t_prev, t_cur = t_cur, fmpq_poly([0, 2]) * t_cur - t_prev
            tm = t_cur
        out += tm * c
    return out


def _chebyshev_u(coeffs: list[fmpq]) -> fmpq_poly:
    """``U`` with ``Σ_m b_m sin mθ = sin θ · U(cos θ)`` (``U_{m-1}``, second kind)."""
    out = fmpq_poly([])
    u_prev, u_cur = fmpq_poly([1]), fmpq_poly([0, 2])  # U_0, U_1
    for m, c in enumerate(coeffs):
        if m == 0:
            continue
        if m == 1:
            um = u_prev
        elif m == 2:
            um = u_cur
        else:
            u_prev, u_cur = u_cur, fmpq_poly([0, 2]) * u_cur - u_prev
            um = u_cur
        out += um * c
    return out


@dataclass(frozen=True, kw_only=True)
class HighFrequency:
    """What ``ω → ∞`` says, for every delay ``τ > 0`` at once.

    ``kind``: ``"positive"`` (``F > 0`` for ``ω > omega1``, every delay), ``"unbounded"``
    (for every ``τ > 0``, ``F < 0`` at arbitrarily high ``ω``; ``theta`` is an angle with
    ``h(theta) < 0`` given as ``(cos theta, sin-sign)``), ``"tangent"`` (``h ≥ 0`` with a
    zero: undecided by the leading term) or ``"zero"`` (``F ≡ 0``).
    """

    kind: str
    degree: int = -1
    omega1: fmpq | None = None
    h_min: fmpq | None = None
    cos_theta: fmpq | None = None
    upper_half: bool = True

    @property
    def theta(self) -> arb:
        """The angle with ``h < 0`` (a ball; call under a working precision)."""
        if self.cos_theta is None:
            raise ValueError("no angle: the high-frequency term is not negative anywhere")
        t = arb(self.cos_theta).acos()
        return t if self.upper_half else 2 * arb.pi() - t


def _negative_point(p: fmpq_poly) -> fmpq | None:
    """A rational ``c ∈ [-1, 1]`` with ``p(c) < 0``, or None if none was found.

    Tests ``±1`` and one point strictly between consecutive sign changes in ``(-1, 1)``;
    a miss (a test point on a root of even multiplicity) is safe: the caller then sees a
    root and reports a tangency, never "positive".
    """
    for c in (fmpq(-1), fmpq(1)):
        if p(c) < 0:
            return c
    if p.degree() <= 0:
        return None
    odd = ep.positive_roots_odd_multiplicity(p)
    if odd.degree() <= 0:
        return None
    prev = fmpq(-1)
    points = []
    for iv in ep.isolate_real_roots(odd, -1, 1):
        a, b = ep.refine_past(odd, iv, prev) if iv[0] <= prev < iv[1] else iv
        if a > prev:
            points.append((prev + a) / 2)
        prev = b
    for c in points:
        if p(c) < 0:
            return c
    return None


def high_frequency(f: TrigRealPart) -> HighFrequency:
    """Classify ``ω → ∞`` (see the module docstring)."""
    d = f.degree
    if d < 0:
        return HighFrequency(kind="zero")
    a = [p[d] if p.degree() >= d else fmpq(0) for p in f.cos]
    b = [p[d] if p.degree() >= d else fmpq(0) for p in f.sin]
    if d % 2 == 1:
        u = _chebyshev_u(b)
        # u is nonzero of degree < len(b): one of len(b) + 1 distinct points is not a root
        c = next(x for x in (fmpq(k, len(b) + 1) for k in range(len(b) + 1)) if u(x) != 0)
        # sin θ U(cos θ) < 0: θ in (0, π) where U < 0, or in (π, 2π) where U > 0
        return HighFrequency(kind="unbounded", degree=d, cos_theta=c, upper_half=u(c) < 0)
    h = chebyshev(a)
    neg = _negative_point(h)
    if neg is not None:
        return HighFrequency(kind="unbounded", degree=d, cos_theta=neg, upper_half=True)
    if ep.count_real_roots(h, -1, 1) > 0 or h(fmpq(-1)) == 0:
        return HighFrequency(kind="tangent", degree=d)
    h_min = lower_bound_on(h, fmpq(-1), fmpq(1))
    if h_min <= 0:  # pragma: no cover - h > 0 on a compact set: refinement always ends
        return HighFrequency(kind="tangent", degree=d)
    return HighFrequency(kind="positive", degree=d, omega1=_omega1(f, d, h_min), h_min=h_min)


def _last_root(p: fmpq_poly) -> fmpq:
    """A rational above every positive root of ``p`` (0 if it has none)."""
    if p.is_zero() or p.degree() <= 0:
        return fmpq(0)
    roots = ep.isolate_real_roots(p, 0)
    if not roots:
        return fmpq(0)
    a, b = roots[-1]
    if a < b:  # the isolating interval may be as wide as the root bound: tighten it
        a, b = ep.refine(p, (a, b), max(a, fmpq(0)) / 64 + (b - a) / 2**40)
        while b > 2 * a and a < b:
            a, b = ep.refine(p, (a, b), (b - a) / 4)
    return b


def _omega1(f: TrigRealPart, d: int, h_min: fmpq) -> fmpq:
    """A frequency beyond which ``F > 0`` for every delay (the tightest exact bound at hand).

    One harmonic: ``F ≥ A - sqrt(B² + C²)``, positive beyond the last positive root of ``A``
    and of ``A² - B² - C²`` (exact).  Several: ``F ≥ A_0 - Σ_m |A_m| + |B_m|``, a polynomial
    beyond the last root of every ``A_m``, ``B_m``.  Else the coefficient-wise bound.
    """
    if f.order == 1:
        a, b, c = f.cos[0], f.cos[1], f.sin[1]
        gap = a * a - b * b - c * c
        if a.leading_coefficient() > 0 and gap.leading_coefficient() > 0:
            return max(_last_root(a), _last_root(gap))
    parts = [p for m in range(1, len(f.cos)) for p in (f.cos[m], f.sin[m]) if not p.is_zero()]
    g = f.cos[0]
    for p in parts:
        g -= p if p.leading_coefficient() > 0 else -p
    if not g.is_zero() and g.leading_coefficient() > 0:
        return max([_last_root(g), *(_last_root(p) for p in parts)])
    s = [fmpq(0)] * d
    for poly in (*f.cos, *f.sin):
        for i, coeff in enumerate(poly.coeffs()[:d]):
            s[i] += abs(coeff)
    return _last_root(fmpq_poly([-v for v in s] + [h_min]))
