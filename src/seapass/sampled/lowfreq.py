"""The low-frequency condition of a sampled-data SEA port, in closed form.

A port velocity ``v(t) = Re(V e^{jωt})`` (one alias only) meets the *fundamental-harmonic*
impedance of the sampled loop.  As ``ω → 0`` the sample-and-hold acts on the slow signal
like the controller's DC gain ``κ`` and the half-sample lag of the zero-order hold (plus
``d`` samples of delay): to first order in ``s``,

``K(e^{sT}) · (1 − e^{−sT})/(sT) = κ + β s``,  ``β = T (K'(1) − κ/2)``,

(``K'`` = ``dK/dz``; for Tustin or backward-difference controllers ``β = C'(0) − κ (d + ½) T``),
and the low-frequency resistance of the port is

``R_lf = d/ds [D2 + D1 (α + K_A + K_L)/(α + D1 + K_A)] at s = 0``

with ``K_X = κ_X + β_X s``.  ``R_lf ≥ 0`` is *necessary* for sampled passivity (a slow
sinusoid would otherwise extract energy).  For load-side P control (``C_L = kd``) it is
``b − kd T/2 − b kd/k1 ≥ 0``, i.e. ``kd ≤ 2 b k1/(2b + k1 T)`` whatever ``b1`` is.  The exact
value at ``θ = 0`` also contains the aliases' share (``N(0)`` in the passivity module),
which the certified verdict decides; this module gives the closed form a user can read.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from flint import fmpq, fmpq_poly

if TYPE_CHECKING:
    import sympy as sp

__all__ = [
    "LowFrequency",
    "closed_form",
    "closed_form_expr",
    "dc_expansion",
    "low_frequency_limit",
    "low_frequency_of",
    "low_frequency_resistance",
]


@dataclass(frozen=True, kw_only=True)
class LowFrequency:
    """``R_lf`` (N·s/m), its closed form, and whether it is violated (``R_lf < 0``)."""

    resistance: Fraction | None
    closed_form: str = ""
    explanation: str = ""

    @property
    def violated(self) -> bool:
        return self.resistance is not None and self.resistance < 0

    def to_dict(self) -> dict[str, Any]:
        return {
            "resistance": None if self.resistance is None else float(self.resistance),
            "closed_form": self.closed_form,
            "violated": self.violated,
        }


def low_frequency_of(
    sea: Any, ka: Any, kl: Any, *, delay: int, method: str, explain: bool
) -> LowFrequency | None:
    """``R_lf`` of a numeric design; its closed form only when ``explain`` (sympy is slow)."""
    from .plant import numeric_element

    try:
        m, b = (numeric_element(sea, k) for k in ("m", "b"))
        r = low_frequency_resistance(
            m[0][0] / m[1][0],
            b[0][0] / b[1][0],
            numeric_element(sea, "D1"),
            numeric_element(sea, "D2"),
            ka,
            kl,
        )
    except (TypeError, ValueError, ZeroDivisionError):
        return None
    if r is None:
        return None
    text = ""
    if explain:
        continuous = method != "zoh" and getattr(sea, "discrete", None) is None
        expr = closed_form(sea, delay) if continuous else ""  # no closed form for z
        form = f"R_lf = {expr} = {float(r):.6g} N*s/m" if expr else f"R_lf = {float(r):.6g} N*s/m"
        if r < 0:
            text = f"low-frequency resistance {form} < 0"
        else:
            text = f"{form} >= 0, but the aliases' share makes N(0) negative"
        return LowFrequency(resistance=r, closed_form=expr, explanation=text)
    return LowFrequency(resistance=r)


def dc_expansion(tf: Any) -> tuple[Fraction, Fraction] | None:
    """``(κ, β)`` of a discrete controller (``None`` with a pole at ``z = 1``)."""
    num = [Fraction(c) for c in tf.num]
    den = [Fraction(c) for c in tf.den]
    n1, d1 = sum(num), sum(den)
    if d1 == 0:
        return None
    # K(z) = N(q)/D(q), q = 1/z: dK/dz at z = 1 is -dK/dq at q = 1
    dn = sum(i * c for i, c in enumerate(num))
    dd = sum(i * c for i, c in enumerate(den))
    kappa = n1 / d1
    dk_dz = -(dn * d1 - n1 * dd) / (d1 * d1)
    return kappa, Fraction(tf.period) * (dk_dz - kappa / 2)


def _derivative_at_zero(num: fmpq_poly, den: fmpq_poly) -> fmpq | None:
    d0 = den(0)
    if d0 == 0:
        return None
    return (num.derivative()(0) * d0 - num(0) * den.derivative()(0)) / (d0 * d0)


def low_frequency_resistance(
    m: fmpq,
    b: fmpq,
    d1: tuple[fmpq_poly, fmpq_poly],
    d2: tuple[fmpq_poly, fmpq_poly],
    ka: Any,
    kl: Any,
) -> Fraction | None:
    """Exact ``R_lf`` (``None`` if a controller integrates or the expression is singular)."""
    ea, el = dc_expansion(ka), dc_expansion(kl)
    if ea is None or el is None:
        return None
    alpha = fmpq_poly([0, b, m])
    kA = fmpq_poly(
        [fmpq(ea[0].numerator, ea[0].denominator), fmpq(ea[1].numerator, ea[1].denominator)]
    )
    kL = fmpq_poly(
        [fmpq(el[0].numerator, el[0].denominator), fmpq(el[1].numerator, el[1].denominator)]
    )
    n1, den1 = d1
    n2, den2 = d2
    # D1 (α + KA + KL)/(α + D1 + KA) = n1 (α + KA + KL) / (den1 (α + KA) + n1)
    y_num, y_den = n1 * (alpha + kA + kL), den1 * (alpha + kA) + n1
    ry = _derivative_at_zero(y_num, y_den)
    r2 = _derivative_at_zero(n2, den2)
    if ry is None or r2 is None:
        return None
    r = ry + r2
    return Fraction(int(r.p), int(r.q))


def closed_form_expr(sea: Any, delay: int) -> sp.Expr:
    """``R_lf`` as an expression in the model's symbols and ``T`` (Tustin/backward).

    Uses ``κ = C(0)`` and ``β = C'(0) − κ (d + ½) T`` of the continuous controllers.
    """
    import sympy as sp

    from ..model.expr import S

    period_symbol = sp.Symbol("T", positive=True)
    e = sea.elements()
    alpha = e["m"] * S**2 + e["b"] * S

    def first_order(c: sp.Expr) -> sp.Expr:
        c = sp.cancel(c)
        c0 = c.subs(S, 0)
        c1 = sp.diff(c, S).subs(S, 0)
        return c0 + S * (c1 - c0 * (delay + sp.Rational(1, 2)) * period_symbol)

    kA, kL = first_order(e["CA"]), first_order(e["CL"])
    y = e["D2"] + e["D1"] * (alpha + kA + kL) / (alpha + e["D1"] + kA)
    return sp.simplify(sp.cancel(sp.diff(y, S).subs(S, 0)))


def closed_form(sea: Any, delay: int) -> str:
    """[`closed_form_expr`][seapass.sampled.lowfreq.closed_form_expr] as text."""
    return str(closed_form_expr(sea, delay))


def low_frequency_limit(
    sea: Any, param: str, *, delay: int, period: float, lo: float, hi: float
) -> str | None:
    """The values of ``param`` in ``[lo, hi]`` where ``R_lf = 0``, in closed form, as a sentence."""
    import sympy as sp

    from ..model.expr import symbol

    expr = closed_form_expr(sea, delay)
    lam = symbol(param)
    T = sp.Symbol("T", positive=True)
    subs = {
        symbol(k): sp.Rational(Fraction(v))
        for k, v in sea.values.items()
        if v is not None and k != param
    }
    subs[T] = sp.Rational(Fraction(repr(float(period))))
    numer = sp.numer(sp.together(expr))
    if lam not in numer.free_symbols:
        return None
    parts = []
    for root in sp.solve(numer, lam):
        value = root.xreplace(subs)
        if not value.is_real:
            continue
        v = float(value)
        if lo <= v <= hi:
            parts.append(f"{param} = {root} = {v:.10g}")
    if not parts:
        return None
    return f"R_lf = {expr} >= 0 (necessary) changes sign at " + "; ".join(parts)
