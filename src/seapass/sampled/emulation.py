"""Emulation: continuous controllers ``C(s)`` turned into exact discrete transfer functions.

A controller element ``C(s)`` is split into

* its polynomial part ``c0 + c1 s + c2 s^2 + ...``: the constant acts on the
  error ``θ − x``; the derivative terms act on the *measurement* only
  (``−x``, "derivative on measurement", no kick on reference steps) and use a
  backward-difference velocity ``(1 − z^-1)/T``, optionally low-pass filtered
  by ``(1 − a)/(1 − a z^-1)``, ``a = exp(−2π f_c T)``;
* its strictly proper part, discretized by Tustin, ZOH or backward difference
  and applied to the error.  Tustin and backward differences are exact
  substitutions; the ZOH of a row of controllers is taken from their one minimal
  realization (`zoh_row`), so poles the elements share stay shared.

Everything is exact (`fractions.Fraction` coefficients in ``q = z⁻¹``) except the
matrix exponential of the ZOH, whose floats are then taken as the rationals they are.
The deployable controller built from these paths is
[`seapass.sampled.controllers.DiscreteController`][seapass.sampled.controllers.DiscreteController].

References
----------
.. [1] G. F. Franklin, J. D. Powell, M. Workman, *Digital Control of Dynamic
   Systems*, 3rd ed., Addison-Wesley, 1998, ch. 6 (emulation: Tustin, ZOH,
   backward difference).
.. [2] K. J. Åström, T. Hägglund, *Advanced PID Control*, ISA, 2006, §3.4
   (derivative on measurement, derivative filtering).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from fractions import Fraction

import numpy as np
import sympy as sp
from flint import fmpq, fmpq_mat, fmpq_poly

from ..errors import ParameterError
from ..model.expr import S, to_fraction
from ..model.loop import METHODS, Method
from .joint import DiscreteTF, q_reduce

__all__ = [
    "ZINV",
    "check_period",
    "coeffs_in_q",
    "discrete_paths",
    "discretize",
    "exact_paths",
    "filter_pole",
    "split_polynomial",
    "zoh_discretize",
    "zoh_row",
    "zoh_row_exact",
]

ZINV = sp.Symbol("q")
"""The symbol that stands for ``z⁻¹`` in the discrete expressions."""


def check_period(period: float) -> Fraction:
    if not (isinstance(period, int | float | Fraction) and math.isfinite(float(period))):
        raise ParameterError(f"period must be a finite number of seconds, got {period!r}")
    if float(period) <= 0:
        raise ParameterError(f"period must be positive, got {float(period):g} s")
    # shortest decimal form: 0.002 means 1/500, not the nearest binary float
    return Fraction(period) if isinstance(period, Fraction) else Fraction(repr(float(period)))


def filter_pole(cutoff_hz: float | None, period: float) -> Fraction:
    """Pole ``a = exp(−2π f_c T)`` of the first-order velocity filter (0 = no filter).

    The float is converted to a Fraction exactly, so analysis and runtime use
    the very same number.
    """
    if cutoff_hz is None:
        return Fraction(0)
    fc = float(cutoff_hz)
    if not (math.isfinite(fc) and fc > 0):
        raise ParameterError(f"velocity_filter must be a positive cutoff in Hz, got {cutoff_hz!r}")
    return Fraction(math.exp(-2.0 * math.pi * fc * float(period)))


def coeffs_in_q(expr: sp.Expr) -> tuple[tuple[Fraction, ...], tuple[Fraction, ...]]:
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    pn = sp.Poly(sp.expand(num), ZINV)
    pd = sp.Poly(sp.expand(den), ZINV)

    def asc(p: sp.Poly) -> tuple[Fraction, ...]:
        c = p.all_coeffs()[::-1]
        return tuple(Fraction(int(sp.Rational(x).p), int(sp.Rational(x).q)) for x in c)

    return asc(pn), asc(pd)


def split_polynomial(expr: sp.Expr) -> tuple[list[sp.Rational], sp.Expr]:
    """Polynomial coefficients (ascending) and strictly proper remainder of ``expr(s)``."""
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    pn, pd = sp.Poly(num, S), sp.Poly(den, S)
    quo, rem = sp.div(pn, pd)
    coeffs = [sp.Rational(c) for c in quo.all_coeffs()[::-1]]
    return coeffs, sp.cancel(rem.as_expr() / pd.as_expr())


def zoh_discretize(proper: sp.Expr, period: Fraction) -> sp.Expr:
    """ZOH equivalent of a strictly proper ``C(s)`` in ``q = z⁻¹`` (scipy, floats made exact)."""
    from scipy.signal import cont2discrete

    num, den = sp.fraction(sp.cancel(sp.together(proper)))
    n = [float(c) for c in sp.Poly(num, S).all_coeffs()]
    d = [float(c) for c in sp.Poly(den, S).all_coeffs()]
    nd, dd, _ = cont2discrete((n, d), float(period), method="zoh")
    nd = np.atleast_1d(np.squeeze(nd))
    # descending powers of z with equal length -> ascending powers of z^-1
    k = max(len(nd), len(dd))
    nd = np.concatenate([np.zeros(k - len(nd)), nd])
    dd = np.concatenate([np.zeros(k - len(dd)), dd])
    qn = sum(sp.Rational(Fraction(float(c))) * ZINV**i for i, c in enumerate(nd))
    qd = sum(sp.Rational(Fraction(float(c))) * ZINV**i for i, c in enumerate(dd))
    return qn / qd


def zoh_row(propers: Sequence[sp.Expr], period: Fraction) -> list[sp.Expr]:
    """ZOH equivalents in ``q = z⁻¹`` of a row of strictly proper ``C(s)``, from ONE realization.

    The row is realized minimally ([`seapass.model.minimal`][seapass.model.minimal]:
    a pole the entries share is one state), discretized once by the matrix exponential
    (floats made exact), and each entry's pulse transfer function is read off that one
    discrete realization exactly, so shared poles stay identical in every entry.
    """
    from ..model.minimal import exact_rational

    out = []
    for num, den in zoh_row_exact([exact_rational(p) for p in propers], period):
        qn = sum((_rat(c) * ZINV**i for i, c in enumerate(num.coeffs())), sp.Integer(0))
        qd = sum((_rat(c) * ZINV**i for i, c in enumerate(den.coeffs())), sp.Integer(0))
        out.append(qn / qd)
    return out


def zoh_row_exact(
    rows: Sequence[tuple[fmpq_poly, fmpq_poly]], period: Fraction
) -> list[tuple[fmpq_poly, fmpq_poly]]:
    """`zoh_row` on exact strictly proper ``(num, den)`` in ``s``; ``(num, den)`` in ``q`` out."""
    from scipy.linalg import expm

    from ..model.minimal import common_denominator, observable_form

    nums, den = common_denominator(list(rows))
    n = den.degree()
    if n == 0:
        return [(fmpq_poly([0]), fmpq_poly([1])) for _ in rows]
    A, B, _C = observable_form(nums, den)
    k = len(rows)
    big = np.zeros((n + k, n + k))
    big[:n, :n] = [[float(A[i, j]) for j in range(n)] for i in range(n)]
    big[:n, n:] = [[float(B[i, j]) for j in range(k)] for i in range(n)]
    E = expm(big * float(period))
    Ad = fmpq_mat(n, n, [_exact(x) for x in E[:n, :n].ravel()])
    base = Ad.charpoly()  # det(zI − Ad), monic of degree n
    out = []
    for j in range(k):
        if rows[j][0].is_zero():
            out.append((fmpq_poly([0]), fmpq_poly([1])))
            continue
        # C (zI − Ad)^{-1} b = [det(zI − Ad + b C) − det(zI − Ad)] / det(zI − Ad), C = e_n
        bc = fmpq_mat(n, n)
        for i in range(n):
            bc[i, n - 1] = _exact(E[i, n + j])
        num = (Ad - bc).charpoly() - base
        # in q = 1/z: multiply both by z^-n (coefficients reversed, padded to degree n)
        cn = [num.coeffs()[i] if i < len(num.coeffs()) else 0 for i in range(n + 1)]
        out.append((fmpq_poly(cn[::-1]), fmpq_poly(base.coeffs()[::-1])))
    return out


def exact_paths(
    expr: sp.Expr,
    period: Fraction,
    *,
    method: Method,
    velocity_filter: float | None,
    proper_q: tuple[fmpq_poly, fmpq_poly] | None = None,
) -> tuple[DiscreteTF, DiscreteTF]:
    """``(error path, measurement path)`` of a numeric ``C(s)``, in exact rational arithmetic.

    The scheme of `discrete_paths` carried out on python-flint polynomials (much faster than
    the symbolic route, same exact result); ``proper_q`` is the proper part already
    discretized in ``q`` (the joint ZOH, `zoh_row_exact`).
    """
    from ..model.minimal import exact_rational, split_proper

    T = fmpq(period.numerator, period.denominator)
    poly, (rn, rd) = split_proper(exact_rational(expr))
    c = poly.coeffs()
    a = filter_pole(velocity_filter, float(period))
    af = fmpq(a.numerator, a.denominator)
    one_minus_q = fmpq_poly([1, -1])
    K = len(c) - 1
    if K >= 1:
        dnum = one_minus_q * ((1 - af) / T)
        dden = fmpq_poly([1, -af])
        mnum = sum((dnum**k * dden ** (K - k) * c[k] for k in range(1, K + 1)), fmpq_poly([0]))
        meas = (mnum, dden**K)
    else:
        meas = (fmpq_poly([0]), fmpq_poly([1]))
    c0 = c[0] if c else fmpq(0)
    if proper_q is not None:
        pn, pd = proper_q
    elif rn.is_zero():
        pn, pd = fmpq_poly([0]), fmpq_poly([1])
    else:
        n = rd.degree()
        rc, dc = rn.coeffs(), rd.coeffs()
        if method == "tustin":
            w, one_plus_q = one_minus_q * (2 / T), fmpq_poly([1, 1])
            pn = sum((w**i * one_plus_q ** (n - i) * x for i, x in enumerate(rc)), fmpq_poly([0]))
            pd = sum((w**i * one_plus_q ** (n - i) * x for i, x in enumerate(dc)), fmpq_poly([0]))
        elif method == "backward":
            w = one_minus_q / T
            pn = sum((w**i * x for i, x in enumerate(rc)), fmpq_poly([0]))
            pd = sum((w**i * x for i, x in enumerate(dc)), fmpq_poly([0]))
        else:
            ((pn, pd),) = zoh_row_exact([(rn, rd)], period)
    err = (pd * c0 + pn, pd)
    return (
        DiscreteTF(*q_reduce(_fractions(err[0]), _fractions(err[1])), period),
        DiscreteTF(*q_reduce(_fractions(meas[0]), _fractions(meas[1])), period),
    )


def _fractions(p: fmpq_poly) -> tuple[Fraction, ...]:
    return tuple(Fraction(int(x.p), int(x.q)) for x in p.coeffs()) or (Fraction(0),)


def _exact(x: float) -> fmpq:
    f = Fraction(float(x))
    return fmpq(f.numerator, f.denominator)


def _rat(c: fmpq) -> sp.Rational:
    return sp.Rational(int(c.p), int(c.q))


def discrete_paths(
    coeffs: Sequence[sp.Expr],
    proper: sp.Expr,
    period: Fraction,
    *,
    method: Method,
    velocity_filter: float | None,
    proper_q: sp.Expr | None = None,
) -> tuple[sp.Expr, sp.Expr]:
    """``(error path, measurement path)`` in ``q = z⁻¹`` of ``C(s)`` split into its polynomial
    part ``coeffs`` (ascending) and strictly proper part ``proper`` (see the module docstring).

    Works with symbolic coefficients too (a free parameter of a bound); only the ZOH of a
    proper part needs numbers.  ``proper_q`` is the proper part already discretized (the
    joint ZOH of both controllers, `zoh_row`).
    """
    q = ZINV
    Tq = sp.Rational(period.numerator, period.denominator)
    a = filter_pole(velocity_filter, float(period))
    aq = sp.Rational(a.numerator, a.denominator)
    delta = (1 - q) / Tq * (1 - aq) / (1 - aq * q)
    deriv = sum((c * delta**i for i, c in enumerate(coeffs) if i >= 1), sp.Integer(0))
    const = coeffs[0] if coeffs else sp.Integer(0)
    if proper_q is not None:
        return const + proper_q, deriv
    if proper == 0:
        return const, deriv
    if method == "tustin":
        return const + proper.subs(S, 2 / Tq * (1 - q) / (1 + q)), deriv
    if method == "backward":
        return const + proper.subs(S, (1 - q) / Tq), deriv
    return const + zoh_discretize(proper, period), deriv


def discretize(
    expr: sp.Expr | str | float,
    period: float,
    *,
    method: Method = "tustin",
    velocity_filter: float | None = None,
    values: Mapping[str, float] | None = None,
    split: bool = False,
) -> DiscreteTF | tuple[DiscreteTF, DiscreteTF]:
    """Discretize a controller ``C(s)`` (see the module docstring for the scheme).

    Parameters
    ----------
    expr : sympy.Expr or str or float
        ``C(s)`` with numeric coefficients (or symbols given in ``values``).
    period : float
        Sampling period ``T`` (s).
    method : {"tustin", "zoh", "backward"}
        Discretization of the strictly proper part.
    velocity_filter : float, optional
        Cutoff (Hz) of the first-order low-pass on the finite-difference velocity.
    values : mapping, optional
        Parameter values substituted exactly.
    split : bool, default False
        Return ``(error_path, measurement_path)`` instead of their sum.

    Returns
    -------
    DiscreteTF or (DiscreteTF, DiscreteTF)

    Examples
    --------
    >>> k = discretize("100 + 2*s", 0.01, method="backward")
    >>> [float(c) for c in k.num], [float(c) for c in k.den]
    ([300.0, -200.0], [1.0])
    """
    if method not in METHODS:
        raise ParameterError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    T = check_period(period)
    if isinstance(expr, str):
        from ..model.expr import parse_expression

        expr = parse_expression(expr, set(values or {}) | {"m", "b", "k1", "b1", "kd", "bd", "ki"})
    e = sp.sympify(expr)
    if values:
        from ..model.expr import symbol

        e = e.xreplace({symbol(k): sp.Rational(to_fraction(v, k)) for k, v in values.items()})
    leftover = e.free_symbols - {S}
    if leftover:
        names = ", ".join(sorted(map(str, leftover)))
        raise ParameterError(f"controller has parameters without values: {names}; give them")
    err, meas = exact_paths(e, T, method=method, velocity_filter=velocity_filter)
    if split:
        return err, meas
    return err + meas
