"""Exact emulation of a numeric continuous controller ``C(s)`` at a sampling period (no sympy).

The scheme of [`seapass.sampled.controllers`][seapass.sampled.controllers]: ``C`` is
split into its polynomial part ``c0 + c1 s + ...`` and its strictly proper part; the
constant and the proper part (Tustin ``s = (2/T)(1 − q)/(1 + q)``, backward
``s = (1 − q)/T``, or ZOH) act on the error, the derivative terms on the measurement
through the filtered backward difference ``δ = (1 − q)/T · (1 − a)/(1 − a q)``, with
``q = z⁻¹``.  Everything is exact rational arithmetic on ``flint.fmpq_poly`` (ZOH
only rounds where scipy's ``cont2discrete`` does, from the same floats as before).

What lives here: `emulate`, `in_lowest_terms`.  May import: [`seapass.errors`][seapass.errors],
[`seapass.model`][seapass.model] and the modules of this package below it.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Literal

from flint import fmpq, fmpq_poly, fmpz

from ..errors import ParameterError
from ..exact.poly import as_poly, rational

__all__ = ["Rational", "emulate", "in_lowest_terms", "sympy_scaled"]

Rational = tuple[fmpq_poly, fmpq_poly]
"""``(num, den)``, univariate."""

_ONE = fmpq_poly([1])


def in_lowest_terms(num: fmpq_poly, den: fmpq_poly) -> Rational:
    """``num/den`` divided by their gcd (``den`` nonzero)."""
    if den.is_zero():
        raise ZeroDivisionError("denominator is identically zero")
    if num.is_zero():
        return fmpq_poly([]), _ONE
    g = num.gcd(den)
    return (num // g, den // g) if g.degree() > 0 else (num, den)


def sympy_scaled(num: fmpq_poly, den: fmpq_poly) -> Rational:
    """``num/den`` (coprime) scaled as sympy's ``fraction(cancel(.))`` scales them.

    Integer coefficients without a common factor, ``den``'s leading coefficient positive
    (the floats handed to scipy then equal those of the sympy path, bit for bit).
    """
    coeffs = [*num.coeffs(), *den.coeffs()]
    lcm = fmpz(1)
    for c in coeffs:
        lcm = lcm * c.q // lcm.gcd(c.q)
    content = fmpz(0)
    for c in coeffs:
        content = content.gcd(c.p * (lcm // c.q))
    scale = fmpq(lcm) / content
    if den.leading_coefficient() < 0:
        scale = -scale
    return num * scale, den * scale


def _add(a: Rational, b: Rational) -> Rational:
    return in_lowest_terms(a[0] * b[1] + b[0] * a[1], a[1] * b[1])


def _mul(a: Rational, b: Rational) -> Rational:
    return in_lowest_terms(a[0] * b[0], a[1] * b[1])


def _substitute(p: fmpq_poly, sub: Rational, degree: int) -> fmpq_poly:
    """``p(n/d) d^degree`` for ``sub = (n, d)``, ``degree >= deg p``."""
    n, d = sub
    out = fmpq_poly([])
    for i, c in enumerate(p.coeffs()):
        if c:
            out += c * n**i * d ** (degree - i)
    return out


def _zoh(num: fmpq_poly, den: fmpq_poly, period: Fraction) -> Rational:
    """ZOH equivalent of a strictly proper ``num/den`` in ``q`` (scipy, floats made exact)."""
    import numpy as np
    from scipy.signal import cont2discrete

    n_s, d_s = sympy_scaled(num, den)
    n = [float(c) for c in reversed(n_s.coeffs())]
    d = [float(c) for c in reversed(d_s.coeffs())]
    nd, dd, _ = cont2discrete((n, d), float(period), method="zoh")
    nd = np.atleast_1d(np.squeeze(nd))
    k = max(len(nd), len(dd))  # descending powers of z, equal length -> ascending in q
    nd = np.concatenate([np.zeros(k - len(nd)), nd])
    dd = np.concatenate([np.zeros(k - len(dd)), dd])
    return (
        as_poly([float(c) for c in nd]),
        as_poly([float(c) for c in dd]),
    )


def emulate(
    num: fmpq_poly,
    den: fmpq_poly,
    period: Fraction,
    *,
    method: Literal["tustin", "zoh", "backward"],
    filter_pole: Fraction,
) -> tuple[Rational, Rational]:
    """``(error path, measurement path)`` of ``C = num/den`` in ``q = z⁻¹``, in lowest terms.

    Parameters
    ----------
    num, den : flint.fmpq_poly
        ``C(s)`` with numeric coefficients.
    period : Fraction
        Sampling period ``T`` (s).
    method : {"tustin", "zoh", "backward"}
        Discretization of the strictly proper part.
    filter_pole : Fraction
        Pole ``a`` of the velocity filter (0: none).

    Examples
    --------
    >>> e, m = emulate(fmpq_poly([100, 2]), fmpq_poly([1]), Fraction(1, 100),
    ...                method="backward", filter_pole=Fraction(0))
    >>> e[0] / e[1][0], m[0] / m[1][0]  # 100 on the error, 2 (1 - q)/T on the measurement
    (100, (-200)*x + 200)
    """
    num, den = in_lowest_terms(num, den)
    quo, rem = divmod(num, den)
    T = rational(period)
    a = rational(filter_pole)
    coeffs = quo.coeffs()
    const: Rational = (fmpq_poly([coeffs[0]]) if coeffs else fmpq_poly([]), _ONE)
    # δ = (1 − q)/T · (1 − a)/(1 − a q)
    delta = in_lowest_terms(fmpq_poly([1 - a, a - 1]), fmpq_poly([T, -a * T]))
    deriv: Rational = (fmpq_poly([]), _ONE)
    power = delta
    for c in coeffs[1:]:
        if c:
            deriv = _add(deriv, (power[0] * c, power[1]))
        power = _mul(power, delta)
    if rem.is_zero():
        return const, deriv
    if method == "zoh":
        proper = _zoh(*in_lowest_terms(rem, den), period)
    elif method in ("tustin", "backward"):
        sub = (
            (fmpq_poly([2, -2]), fmpq_poly([T, T]))  # s = 2(1 − q)/(T(1 + q))
            if method == "tustin"
            else (fmpq_poly([1, -1]), fmpq_poly([T]))  # s = (1 − q)/T
        )
        k = den.degree()
        proper = in_lowest_terms(_substitute(rem, sub, k), _substitute(den, sub, k))
    else:
        raise ParameterError(f"method must be tustin, zoh or backward, got {method!r}")
    return _add(const, proper), deriv
