"""Deployable discrete-time controllers: discretization and difference equations.

A controller element ``C(s)`` of an [`SEA`][seapass.model.sea.SEA] is split into

* its polynomial part ``c0 + c1 s + c2 s^2 + ...``: the constant acts on the
  error ``θ − x``; the derivative terms act on the *measurement* only
  (``−x``, "derivative on measurement", no kick on reference steps) and use a
  backward-difference velocity ``(1 − z^-1)/T``, optionally low-pass filtered
  by ``(1 − a)/(1 − a z^-1)``, ``a = exp(−2π f_c T)``;
* its strictly proper part, discretized by Tustin, ZOH or backward difference
  and applied to the error.

Both paths are realized as exact rational transfer functions in ``z^-1``
(`DiscreteTF`, coefficients `fractions.Fraction`) and run as
direct-form-II-transposed difference equations.  With constant references the
closed loop equals ``u = K(z)(θ − x)`` with ``K`` the sum of the two paths, which
is what [`seapass.sampled.passivity`][seapass.sampled.passivity] analyses.

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
from dataclasses import dataclass, field
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import numpy as np
from flint import fmpq_poly

from ..errors import ParameterError, UnrealizableError
from ..model.expr import STANDARD_SYMBOLS, exact_expression
from ..model.loop import METHODS, Method, SampledLoop
from ..model.rational import RatFunc, context, variables
from ..model.sea import SEA, exact_values
from .emulation import emulate, in_lowest_terms

if TYPE_CHECKING:
    import sympy as sp

__all__ = [
    "APDController",
    "DifferenceEquation",
    "DiscreteController",
    "DiscreteTF",
    "LPController",
    "OursController",
    "controller_tfs",
    "discrete_paths",
    "discretize",
    "filter_pole",
    "state_space",
    "zoh_discretize",
]


def _zinv() -> sp.Symbol:
    """The sympy symbol ``q`` that stands for ``z^-1`` in the symbolic paths of this module."""
    import sympy as sp

    return sp.Symbol("q")


def _check_period(period: float) -> Fraction:
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


@dataclass(frozen=True)
class DiscreteTF:
    """``K(z) = (n0 + n1 z^-1 + ...)/(1 + d1 z^-1 + ...)``: exact, causal.

    Attributes
    ----------
    num, den : tuple of Fraction
        Ascending powers of ``z^-1``; ``den[0] == 1``.
    period : Fraction
        Sampling period (s).
    """

    num: tuple[Fraction, ...]
    den: tuple[Fraction, ...]
    period: Fraction

    def __post_init__(self) -> None:
        num = tuple(Fraction(c) for c in self.num) or (Fraction(0),)
        den = tuple(Fraction(c) for c in self.den)
        if not den or den[0] == 0:
            raise UnrealizableError("discrete transfer function is not causal (den[0] = 0)")
        lead = den[0]
        object.__setattr__(self, "num", tuple(c / lead for c in num))
        object.__setattr__(self, "den", tuple(c / lead for c in den))
        object.__setattr__(self, "period", Fraction(self.period))

    @property
    def is_zero(self) -> bool:
        return all(c == 0 for c in self.num)

    def __call__(self, z: complex) -> complex:
        """Evaluate at a complex ``z`` (any numeric type supporting ``**``)."""
        zi = 1 / z
        n = sum(float(c) * zi**i for i, c in enumerate(self.num))
        d = sum(float(c) * zi**i for i, c in enumerate(self.den))
        return n / d

    def evaluate(self, zinv: Any) -> Any:
        """Evaluate with ``z^-1`` given (keeps the numeric type, e.g. mpmath)."""
        n = sum((c.numerator * zinv**i / c.denominator for i, c in enumerate(self.num)), 0)
        d = sum((c.numerator * zinv**i / c.denominator for i, c in enumerate(self.den)), 0)
        return n / d

    def __add__(self, other: DiscreteTF) -> DiscreteTF:
        n = _padd(_pmul(self.num, other.den), _pmul(other.num, self.den))
        return DiscreteTF(n, _pmul(self.den, other.den), self.period)

    def delayed(self, samples: int) -> DiscreteTF:
        """``z^-samples K(z)``."""
        return DiscreteTF((Fraction(0),) * int(samples) + self.num, self.den, self.period)

    def poles(self) -> np.ndarray:
        """Poles in the ``z`` plane (floating point)."""
        den = [float(c) for c in self.den]
        while len(den) > 1 and den[-1] == 0:
            den.pop()
        return np.roots(den) if len(den) > 1 else np.zeros(0)

    def dc_gain(self) -> float:
        d = sum(self.den)
        return math.inf if d == 0 else float(sum(self.num) / d)

    def to_dict(self) -> dict[str, object]:
        return {
            "num": [float(c) for c in self.num],
            "den": [float(c) for c in self.den],
            "period": float(self.period),
        }


def _pmul(p: Sequence[Fraction], q: Sequence[Fraction]) -> tuple[Fraction, ...]:
    out = [Fraction(0)] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        for j, b in enumerate(q):
            out[i + j] += a * b
    return tuple(out)


def _padd(p: Sequence[Fraction], q: Sequence[Fraction]) -> tuple[Fraction, ...]:
    n = max(len(p), len(q))
    return tuple(
        (p[i] if i < len(p) else Fraction(0)) + (q[i] if i < len(q) else Fraction(0))
        for i in range(n)
    )


def zoh_discretize(proper: sp.Expr, period: Fraction) -> sp.Expr:
    """ZOH equivalent of a strictly proper ``C(s)`` in ``q = z⁻¹`` (scipy, floats made exact)."""
    import sympy as sp
    from scipy.signal import cont2discrete

    from ..model.expr import S

    _ZINV = _zinv()

    num, den = sp.fraction(sp.cancel(sp.together(proper)))
    n = [float(c) for c in sp.Poly(num, S).all_coeffs()]
    d = [float(c) for c in sp.Poly(den, S).all_coeffs()]
    nd, dd, _ = cont2discrete((n, d), float(period), method="zoh")
    nd = np.atleast_1d(np.squeeze(nd))
    # descending powers of z with equal length -> ascending powers of z^-1
    k = max(len(nd), len(dd))
    nd = np.concatenate([np.zeros(k - len(nd)), nd])
    dd = np.concatenate([np.zeros(k - len(dd)), dd])
    qn = sum(sp.Rational(Fraction(float(c))) * _ZINV**i for i, c in enumerate(nd))
    qd = sum(sp.Rational(Fraction(float(c))) * _ZINV**i for i, c in enumerate(dd))
    return qn / qd


def discrete_paths(
    coeffs: Sequence[sp.Expr],
    proper: sp.Expr,
    period: Fraction,
    *,
    method: Method,
    velocity_filter: float | None,
) -> tuple[sp.Expr, sp.Expr]:
    """``(error path, measurement path)`` in ``q = z⁻¹`` of ``C(s)`` split into its polynomial
    part ``coeffs`` (ascending) and strictly proper part ``proper`` (see the module docstring).

    Works with symbolic coefficients too (a free parameter of a bound); only the ZOH of a
    proper part needs numbers.  Numeric controllers take the exact path of
    [`seapass.sampled.emulation`][seapass.sampled.emulation] instead (no sympy).
    """
    import sympy as sp

    from ..model.expr import S

    q = _zinv()
    Tq = sp.Rational(period.numerator, period.denominator)
    a = filter_pole(velocity_filter, float(period))
    aq = sp.Rational(a.numerator, a.denominator)
    delta = (1 - q) / Tq * (1 - aq) / (1 - aq * q)
    deriv = sum((c * delta**i for i, c in enumerate(coeffs) if i >= 1), sp.Integer(0))
    const = coeffs[0] if coeffs else sp.Integer(0)
    if proper == 0:
        return const, deriv
    if method == "tustin":
        return const + proper.subs(S, 2 / Tq * (1 - q) / (1 + q)), deriv
    if method == "backward":
        return const + proper.subs(S, (1 - q) / Tq), deriv
    return const + zoh_discretize(proper, period), deriv


def _paths(
    c: RatFunc,
    values: Mapping[str, float | None],
    period: Fraction,
    *,
    method: Method,
    velocity_filter: float | None,
) -> tuple[DiscreteTF, DiscreteTF]:
    """``(error path, measurement path)`` of the exact controller ``c`` at ``values``."""
    env = exact_values(values)
    leftover = sorted(c.parameters() - set(env))
    if leftover:
        raise ParameterError(
            f"controller has parameters without values: {', '.join(leftover)}; give them"
        )
    num, den = in_lowest_terms(*c.evaluate(env))
    a = filter_pole(velocity_filter, float(period))
    err, meas = emulate(num, den, period, method=method, filter_pole=a)
    return (
        DiscreteTF(_ascending(err[0]), _ascending(err[1]), period),
        DiscreteTF(_ascending(meas[0]), _ascending(meas[1]), period),
    )


def _ascending(p: fmpq_poly) -> tuple[Fraction, ...]:
    return tuple(Fraction(int(c.p), int(c.q)) for c in p.coeffs())


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
    T = _check_period(period)
    vals = dict(values or {})
    if isinstance(expr, str):
        c = exact_expression(expr, set(vals) | set(STANDARD_SYMBOLS))
    elif isinstance(expr, int | float | Fraction) and not isinstance(expr, bool):
        c = RatFunc.constant(context(variables(())), Fraction(expr))
    else:
        from ..model.symbolic import exact_from_sympy

        c = exact_from_sympy(expr, "controller")
    err, meas = _paths(c, vals, T, method=method, velocity_filter=velocity_filter)
    if split:
        return err, meas
    return err + meas


class DifferenceEquation:
    """Run a `DiscreteTF` sample by sample (direct form II transposed, float64)."""

    def __init__(self, tf: DiscreteTF) -> None:
        n = max(len(tf.num), len(tf.den))
        self.b = np.array([float(c) for c in tf.num] + [0.0] * (n - len(tf.num)))
        self.a = np.array([float(c) for c in tf.den] + [0.0] * (n - len(tf.den)))
        self.z = np.zeros(max(n - 1, 0))

    def reset(self) -> None:
        self.z[:] = 0.0

    def step(self, x: float) -> float:
        y = self.b[0] * x + (self.z[0] if self.z.size else 0.0)
        for i in range(self.z.size):
            nxt = self.z[i + 1] if i + 1 < self.z.size else 0.0
            self.z[i] = nxt + self.b[i + 1] * x - self.a[i + 1] * y
        return float(y)


@dataclass
class DiscreteController:
    """``u = K_A(θ_A − x_A) + K_L(θ_L − x_L)`` at a fixed period, ready to deploy.

    Derivative terms act on the measurement only (see module docstring).  Build
    from an SEA with `from_sea` or use `LPController`,
    `APDController`, `OursController`.

    Parameters
    ----------
    CA, CL : tuple of DiscreteTF
        ``(error_path, measurement_path)`` for each side.
    period : float
    """

    CA: tuple[DiscreteTF, DiscreteTF]
    CL: tuple[DiscreteTF, DiscreteTF]
    period: float
    name: str = ""
    _filters: list[DifferenceEquation] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self._filters = [DifferenceEquation(tf) for tf in (*self.CA, *self.CL)]

    @classmethod
    def from_sea(
        cls,
        sea: SEA,
        period: float,
        *,
        method: Method = "tustin",
        velocity_filter: float | None = None,
        values: Mapping[str, float] | None = None,
    ) -> DiscreteController:
        """Discretize ``sea.CA`` and ``sea.CL`` with the model's parameter values."""
        if method not in METHODS:
            raise ParameterError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
        T = _check_period(period)
        vals = {k: v for k, v in sea.values.items() if v is not None}
        vals.update(values or {})
        exact = sea.exact_elements()
        parts = [
            _paths(exact[attr], vals, T, method=method, velocity_filter=velocity_filter)
            for attr in ("CA", "CL")
        ]
        return cls(parts[0], parts[1], float(period), sea.name)

    @classmethod
    def for_loop(
        cls, sea: SEA, loop: SampledLoop, *, values: Mapping[str, float] | None = None
    ) -> DiscreteController:
        """`from_sea` at the period, discretization and velocity filter of ``loop``."""
        return cls.from_sea(
            sea,
            loop.period,
            method=loop.method,
            velocity_filter=loop.velocity_filter,
            values=values,
        )

    def transfer_functions(self) -> tuple[DiscreteTF, DiscreteTF]:
        """Total ``(K_A(z), K_L(z))`` acting on ``−x`` when references are zero."""
        return self.CA[0] + self.CA[1], self.CL[0] + self.CL[1]

    def reset(self) -> None:
        for f in self._filters:
            f.reset()

    def step(
        self,
        measurement: tuple[float, float],
        reference: tuple[float, float] = (0.0, 0.0),
    ) -> float:
        """One control period: ``(x_A, x_L)`` and ``(θ_A, θ_L)`` in, force command out."""
        xa, xl = measurement
        ta, tl = reference
        fa_e, fa_m, fl_e, fl_m = self._filters
        return fa_e.step(ta - xa) + fa_m.step(-xa) + fl_e.step(tl - xl) + fl_m.step(-xl)


def _pd(kd: float, bd: float) -> str:
    return f"({Fraction(kd)}) + ({Fraction(bd)})*s"


class LPController(DiscreteController):
    """Load-side proportional control ``C_L = kd`` (the paper's LP)."""

    def __init__(self, kd: float, period: float, **kw: object) -> None:
        sea = SEA(D1="k1", CL=_pd(kd, 0.0), values={"k1": 1.0}, name="LP")
        base = DiscreteController.from_sea(sea, period, **kw)  # type: ignore[arg-type]
        super().__init__(base.CA, base.CL, float(period), "LP")


class APDController(DiscreteController):
    """Actuator-side PD ``C_A = kd + bd s`` (the paper's APD, pure-spring hardware)."""

    def __init__(self, kd: float, bd: float, period: float, **kw: object) -> None:
        sea = SEA(D1="k1", CA=_pd(kd, bd), values={"k1": 1.0}, name="APD")
        base = DiscreteController.from_sea(sea, period, **kw)  # type: ignore[arg-type]
        super().__init__(base.CA, base.CL, float(period), "APD")


class OursController(DiscreteController):
    """Actuator-side PD ``C_A = kd + bd s`` for the damped transmission (the paper's Ours)."""

    def __init__(self, kd: float, bd: float, period: float, **kw: object) -> None:
        sea = SEA(D1="k1 + b1*s", CA=_pd(kd, bd), values={"k1": 1.0, "b1": 1.0}, name="Ours")
        base = DiscreteController.from_sea(sea, period, **kw)  # type: ignore[arg-type]
        super().__init__(base.CA, base.CL, float(period), "Ours")


def state_space(tf: DiscreteTF) -> tuple[np.ndarray, ...]:
    """Direct-form-II-transposed state space ``(A, B, C, D)`` of ``tf``, as it runs."""
    n = max(len(tf.num), len(tf.den))
    b = np.array([float(c) for c in tf.num] + [0.0] * (n - len(tf.num)))
    a = np.array([float(c) for c in tf.den] + [0.0] * (n - len(tf.den)))
    k = n - 1
    A = np.zeros((k, k))
    if k:
        A[:, 0] = -a[1:]
        A[:-1, 1:] = np.eye(k - 1)
    B = (b[1:] - a[1:] * b[0]).reshape(k, 1)
    C = np.zeros((1, k))
    if k:
        C[0, 0] = 1.0
    return A, B, C, np.array([[b[0]]])


def controller_tfs(sea: SEA, loop: SampledLoop) -> tuple[DiscreteTF, DiscreteTF]:
    """``(z^-d K_A(z), z^-d K_L(z))`` in ``loop`` exactly as `DiscreteController` runs them."""
    ka, kl = DiscreteController.for_loop(sea, loop).transfer_functions()
    return ka.delayed(loop.delay), kl.delayed(loop.delay)
