"""Emulation: continuous controllers ``C(s)`` turned into exact discrete transfer functions.

A controller element ``C(s)`` is split into

* its polynomial part ``c0 + c1 s + c2 s^2 + ...``: the constant acts on the
  error ``θ − x``; the derivative terms act on the *measurement* only
  (``−x``, "derivative on measurement", no kick on reference steps) and use the
  backward-difference velocity ``δ = (1 − q)/T``, optionally low-pass filtered by
  ``(1 − a)/(1 − a q)``, ``a = exp(−2π f_c T)``, with ``q = z⁻¹``;
* its strictly proper part, discretized by Tustin (``s = (2/T)(1 − q)/(1 + q)``),
  backward difference (``s = (1 − q)/T``) or ZOH and applied to the error.  Tustin and
  backward differences are exact substitutions; the ZOH of a row of controllers is taken
  from their one minimal realization (`zoh_row_exact`), so poles the elements share stay
  shared.

Numeric controllers take the exact path, `emulate`, on ``flint.fmpq_poly`` (no sympy);
everything is exact except the matrix exponential of the ZOH, whose floats are then taken
as the rationals they are.  `discrete_paths` is the same scheme on sympy expressions, for
controller families with a free gain ([`seapass.sampled.family`][seapass.sampled.family]);
it shares the ZOH with the exact path.  The deployable controller built from these paths is
[`seapass.sampled.controllers.DiscreteController`][seapass.sampled.controllers.DiscreteController].

What lives here: `emulate`, `discretize`, `discrete_paths`, the ZOH of a row
(`zoh_row_exact`, `zoh_row`, `zoh_discretize`), `check_period`, `filter_pole`,
`as_discrete_tf` and the `Rational` alias of
[`RationalFunction`][seapass.model.minimal.RationalFunction] (exact ``(num, den)``,
reduced by [`reduce_rational`][seapass.model.minimal.reduce_rational]).  May import:
[`seapass.errors`][seapass.errors], [`seapass.exact`][seapass.exact],
[`seapass.model`][seapass.model] and the modules of this package below it.

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
from typing import TYPE_CHECKING

import numpy as np
from flint import fmpq, fmpq_mat, fmpq_poly

from ..errors import ParameterError
from ..exact.poly import rational
from ..model.loop import METHODS, Method
from ..model.minimal import RationalFunction as Rational
from ..model.minimal import common_denominator, observable_form, reduce_rational
from .joint import DiscreteTF, q_reduce

if TYPE_CHECKING:
    import sympy as sp

__all__ = [
    "Rational",
    "as_discrete_tf",
    "check_period",
    "discrete_paths",
    "discretize",
    "emulate",
    "filter_pole",
    "zinv",
    "zoh_discretize",
    "zoh_row",
    "zoh_row_exact",
]

_ONE = fmpq_poly([1])
_ZERO = fmpq_poly([])


def zinv() -> sp.Symbol:
    """The sympy symbol ``q`` that stands for ``z⁻¹`` in the symbolic paths (`discrete_paths`)."""
    import sympy as sp

    return sp.Symbol("q")


def check_period(period: float) -> Fraction:
    """The sampling period as an exact Fraction (its shortest decimal form), checked."""
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


def as_discrete_tf(path: Rational, period: Fraction) -> DiscreteTF:
    """``num/den`` in ``q`` as a reduced `DiscreteTF` (``den[0] = 1``)."""
    return DiscreteTF(*q_reduce(_fractions(path[0]), _fractions(path[1])), period)


def _fractions(p: fmpq_poly) -> tuple[Fraction, ...]:
    return tuple(Fraction(int(x.p), int(x.q)) for x in p.coeffs()) or (Fraction(0),)


def _add(a: Rational, b: Rational) -> Rational:
    return reduce_rational(a[0] * b[1] + b[0] * a[1], a[1] * b[1])


def _mul(a: Rational, b: Rational) -> Rational:
    return reduce_rational(a[0] * b[0], a[1] * b[1])


def _substitute(p: fmpq_poly, sub: Rational, degree: int) -> fmpq_poly:
    """``p(n/d) d^degree`` for ``sub = (n, d)``, ``degree >= deg p``."""
    n, d = sub
    out = fmpq_poly([])
    for i, c in enumerate(p.coeffs()):
        if c:
            out += c * n**i * d ** (degree - i)
    return out


def emulate(
    num: fmpq_poly,
    den: fmpq_poly,
    period: Fraction,
    *,
    method: Method,
    filter_pole: Fraction,
    proper_q: Rational | None = None,
) -> tuple[Rational, Rational]:
    """``(error path, measurement path)`` of ``C = num/den`` in ``q = z⁻¹``, in lowest terms
    with monic denominators.

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
    proper_q : (fmpq_poly, fmpq_poly), optional
        The strictly proper part already discretized in ``q`` (the joint ZOH of both
        controllers, `zoh_row_exact`); ``method`` is then not used for it.

    Examples
    --------
    >>> e, m = emulate(fmpq_poly([100, 2]), fmpq_poly([1]), Fraction(1, 100),
    ...                method="backward", filter_pole=Fraction(0))
    >>> e[0] / e[1][0], m[0] / m[1][0]  # 100 on the error, 2 (1 - q)/T on the measurement
    (100, (-200)*x + 200)
    """
    num, den = reduce_rational(num, den)
    quo, rem = divmod(num, den)
    T = rational(period)
    a = rational(filter_pole)
    coeffs = quo.coeffs()
    const: Rational = (fmpq_poly([coeffs[0]]) if coeffs else _ZERO, _ONE)
    # δ = (1 − q)/T · (1 − a)/(1 − a q)
    delta = reduce_rational(fmpq_poly([1 - a, a - 1]), fmpq_poly([T, -a * T]))
    deriv: Rational = (_ZERO, _ONE)
    power = delta
    for c in coeffs[1:]:
        if c:
            deriv = _add(deriv, (power[0] * c, power[1]))
        power = _mul(power, delta)
    if proper_q is not None:
        return _add(const, reduce_rational(*proper_q)), deriv
    if rem.is_zero():
        return const, deriv
    if method == "zoh":
        ((pn, pd),) = zoh_row_exact([reduce_rational(rem, den)], period)
        proper = reduce_rational(pn, pd)
    elif method in ("tustin", "backward"):
        sub = (
            (fmpq_poly([2, -2]), fmpq_poly([T, T]))  # s = 2(1 − q)/(T(1 + q))
            if method == "tustin"
            else (fmpq_poly([1, -1]), fmpq_poly([T]))  # s = (1 − q)/T
        )
        k = den.degree()
        proper = reduce_rational(_substitute(rem, sub, k), _substitute(den, sub, k))
    else:
        raise ParameterError(f"method must be tustin, zoh or backward, got {method!r}")
    return _add(const, proper), deriv


def zoh_row_exact(rows: Sequence[Rational], period: Fraction) -> list[Rational]:
    """ZOH equivalents in ``q = z⁻¹`` of a row of strictly proper ``C(s) = num/den``, exact in
    and out, from ONE realization.

    The row is realized minimally ([`seapass.model.minimal`][seapass.model.minimal]: a pole
    the entries share is one state), discretized once by the matrix exponential (floats made
    exact), and each entry's pulse transfer function is read off that one discrete
    realization exactly, so shared poles stay identical in every entry.
    """
    from scipy.linalg import expm

    nums, den = common_denominator(list(rows))
    n = den.degree()
    if n == 0:
        return [(_ZERO, _ONE) for _ in rows]
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
            out.append((_ZERO, _ONE))
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


def _exact(x: float) -> fmpq:
    f = Fraction(float(x))
    return fmpq(f.numerator, f.denominator)


def zoh_row(propers: Sequence[sp.Expr], period: Fraction) -> list[sp.Expr]:
    """`zoh_row_exact` for sympy expressions in ``s`` (numeric coefficients): expressions in
    ``q = z⁻¹`` out."""
    import sympy as sp

    from ..model.minimal import exact_rational

    q = zinv()
    out = []
    for num, den in zoh_row_exact([exact_rational(p) for p in propers], period):
        qn = sum((_rat(c) * q**i for i, c in enumerate(num.coeffs())), sp.Integer(0))
        qd = sum((_rat(c) * q**i for i, c in enumerate(den.coeffs())), sp.Integer(0))
        out.append(qn / qd)
    return out


def _rat(c: fmpq) -> sp.Rational:
    import sympy as sp

    return sp.Rational(int(c.p), int(c.q))


def zoh_discretize(proper: sp.Expr, period: Fraction) -> sp.Expr:
    """ZOH equivalent of one strictly proper ``C(s)`` in ``q = z⁻¹`` (`zoh_row` of one)."""
    return zoh_row([proper], period)[0]


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
    joint ZOH of both controllers, `zoh_row`).  Numeric controllers take the exact path,
    `emulate`, instead (no sympy).
    """
    import sympy as sp

    from ..model.expr import S

    q = zinv()
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
    from ..model.elements import exact_values
    from ..model.expr import STANDARD_SYMBOLS, exact_expression
    from ..model.rational import RatFunc, context, variables

    if method not in METHODS:
        raise ParameterError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    T = check_period(period)
    vals = dict(values or {})
    if isinstance(expr, str):
        c = exact_expression(expr, set(vals) | set(STANDARD_SYMBOLS))
    elif isinstance(expr, int | float | Fraction) and not isinstance(expr, bool):
        c = RatFunc.constant(context(variables(())), Fraction(expr))
    else:
        from ..model.symbolic import exact_from_sympy

        c = exact_from_sympy(expr, "controller")
    env = exact_values(vals)
    leftover = sorted(c.parameters() - set(env))
    if leftover:
        raise ParameterError(
            f"controller has parameters without values: {', '.join(leftover)}; give them"
        )
    a = filter_pole(velocity_filter, float(T))
    err, meas = emulate(*c.evaluate(env), T, method=method, filter_pole=a)
    if split:
        return as_discrete_tf(err, T), as_discrete_tf(meas, T)
    return as_discrete_tf(err, T) + as_discrete_tf(meas, T)
