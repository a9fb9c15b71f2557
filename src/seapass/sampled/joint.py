"""The discrete controller as one system: one common denominator, one difference equation.

After discretization the controller is a row of exact transfer functions in ``z⁻¹``, one
per input signal (``θ_A − x_A``, ``−x_A``, ``θ_L − x_L``, ``−x_L``: error and measurement
paths of ``C_A`` and ``C_L``, see [`seapass.sampled.controllers`][seapass.sampled.controllers]).
`JointRealization` puts the row over the exact least common denominator and runs it as
*one* multi-input direct-form-II-transposed difference equation (the observable form)::

    y  = Σ_j b_j[0] x_j + z_0
    z_i = z_{i+1} + Σ_j b_j[i+1] x_j − a[i+1] y      (i = 0 … n−1, z_n = 0)

Every entry is reduced first (exact gcd), so a pole the entries share (a force loop's
integrator, the velocity filter of both derivative paths) is one state and the order ``n``
is the McMillan degree of the row; `JointRealization.is_minimal` checks controllability
and observability exactly.  The float update above is the one order of operations that the
Python runner (`JointDifferenceEquation`), the batched runner of the twin
(`BatchDifferenceEquation`) and the exported C code all use, so they agree bit for bit.

References
----------
.. [1] A. V. Oppenheim, R. W. Schafer, *Discrete-Time Signal Processing*, 3rd ed., 2010,
   §6.5 (transposed direct form II).
.. [2] T. Kailath, *Linear Systems*, Prentice-Hall, 1980, §6.3 (minimal realizations).

Examples
--------
Two integrators ``1/(1 − z⁻¹)`` on two inputs are one state:

>>> from fractions import Fraction as F
>>> r = JointRealization.of(
...     [((F(1),), (F(1), F(-1))), ((F(2), F(1)), (F(1), F(-1)))], ("a", "b"), F(1, 1000))
>>> r.order, r.is_minimal()
(1, True)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from flint import fmpq, fmpq_mat, fmpq_poly

from ..errors import UnrealizableError
from ..model.minimal import is_controllable, is_observable

__all__ = [
    "BatchDifferenceEquation",
    "DiscreteTF",
    "JointDifferenceEquation",
    "JointRealization",
    "Poly",
    "poly_add",
    "poly_mul",
    "q_gcd",
    "q_lcm",
    "q_reduce",
]

Poly = tuple[Fraction, ...]
"""Coefficients of a polynomial in ``q = z⁻¹``, ascending."""


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
        n = poly_add(poly_mul(self.num, other.den), poly_mul(other.num, self.den))
        return DiscreteTF(n, poly_mul(self.den, other.den), self.period)

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


def poly_mul(p: Sequence[Fraction], q: Sequence[Fraction]) -> tuple[Fraction, ...]:
    out = [Fraction(0)] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        for j, b in enumerate(q):
            out[i + j] += a * b
    return tuple(out)


def poly_add(p: Sequence[Fraction], q: Sequence[Fraction]) -> tuple[Fraction, ...]:
    n = max(len(p), len(q))
    return tuple(
        (p[i] if i < len(p) else Fraction(0)) + (q[i] if i < len(q) else Fraction(0))
        for i in range(n)
    )


def _poly(c: Sequence[Fraction]) -> fmpq_poly:
    return fmpq_poly([fmpq(Fraction(x).numerator, Fraction(x).denominator) for x in c])


def _tuple(p: fmpq_poly) -> Poly:
    return tuple(Fraction(int(x.p), int(x.q)) for x in p.coeffs()) or (Fraction(0),)


def _unit(p: fmpq_poly) -> fmpq_poly:
    """``p`` scaled to constant term 1 (every denominator here has ``p(0) ≠ 0``)."""
    c0 = p.coeffs()[0] if p.coeffs() else fmpq(0)
    if c0 == 0:
        raise ValueError("a discrete denominator vanishes at z^-1 = 0 (not causal)")
    return p / c0


def q_reduce(num: Sequence[Fraction], den: Sequence[Fraction]) -> tuple[Poly, Poly]:
    """``num/den`` in lowest terms with ``den[0] = 1`` (``0`` is ``0/1``)."""
    n, d = _poly(num), _poly(den)
    _unit(d)  # refuses a non-causal denominator
    if n.is_zero():
        return (Fraction(0),), (Fraction(1),)
    g = n.gcd(d)
    n2, d2 = n // g, d // g
    c0 = d2.coeffs()[0]
    return _tuple(n2 / c0), _tuple(d2 / c0)


def q_gcd(p: Sequence[Fraction], r: Sequence[Fraction]) -> Poly:
    """Exact gcd of two denominators in ``q``, with constant term 1."""
    return _tuple(_unit(_poly(p).gcd(_poly(r))))


def q_lcm(p: Sequence[Fraction], r: Sequence[Fraction]) -> Poly:
    """Exact lcm of two denominators in ``q``, with constant term 1."""
    a, b = _poly(p), _poly(r)
    return _tuple(_unit(a * b // a.gcd(b)))


def _pad(c: Sequence[Fraction], n: int) -> Poly:
    return tuple(c) + (Fraction(0),) * (n - len(c))


@dataclass(frozen=True, repr=False, kw_only=True)
class JointRealization:
    """``y = Σ_j N_j(z⁻¹)/D(z⁻¹) x_j`` with one exact common denominator.

    Attributes
    ----------
    numerators : tuple of Poly
        ``N_j``, each of length ``order + 1`` (ascending powers of ``z⁻¹``).
    denominator : Poly
        ``D`` with ``D[0] = 1``, length ``order + 1``.
    inputs : tuple of str
        Name of each input signal (entries that are identically zero are left out).
    period : Fraction
    """

    numerators: tuple[Poly, ...]
    denominator: Poly
    inputs: tuple[str, ...]
    period: Fraction

    @classmethod
    def of(
        cls, entries: Sequence[tuple[Sequence[Fraction], Sequence[Fraction]]],
        inputs: Sequence[str], period: Fraction,
    ) -> JointRealization:  # fmt: skip
        """The minimal joint realization of the row ``entries`` (``(num, den)`` each)."""
        kept = []
        for (num, dnm), name in zip(entries, inputs, strict=True):
            n, d = q_reduce(num, dnm)
            if any(c != 0 for c in n):
                kept.append((n, d, name))
        den: Poly = (Fraction(1),)
        for _n, d, _name in kept:
            den = q_lcm(den, d)
        D = _poly(den)
        nums = [_tuple(_poly(n) * (D // _poly(d))) for n, d, _name in kept]
        order = max([len(den) - 1, *(len(n) - 1 for n in nums)])
        return cls(
            numerators=tuple(_pad(n, order + 1) for n in nums),
            denominator=_pad(den, order + 1),
            inputs=tuple(name for _n, _d, name in kept),
            period=Fraction(period),
        )

    @property
    def order(self) -> int:
        """Number of states (the McMillan degree of the row)."""
        return len(self.denominator) - 1

    def entry(self, name: str) -> tuple[Poly, Poly]:
        """``(num, den)`` of input ``name`` (``0/1`` for an input that is not used), reduced."""
        if name not in self.inputs:
            return (Fraction(0),), (Fraction(1),)
        return q_reduce(self.numerators[self.inputs.index(name)], self.denominator)

    def exact_state_space(self) -> tuple[fmpq_mat, fmpq_mat, fmpq_mat, fmpq_mat]:
        """``(A, B, C, D)`` of the difference equation as it runs, in exact rationals."""
        n, k = self.order, len(self.inputs)
        a = [fmpq(c.numerator, c.denominator) for c in self.denominator]
        b = [[fmpq(c.numerator, c.denominator) for c in num] for num in self.numerators]
        A, B, C, D = fmpq_mat(n, n), fmpq_mat(n, k), fmpq_mat(1, n), fmpq_mat(1, k)
        for i in range(n):
            A[i, 0] = -a[i + 1]
            if i + 1 < n:
                A[i, i + 1] = 1
            for j in range(k):
                B[i, j] = b[j][i + 1] - a[i + 1] * b[j][0]
        if n:
            C[0, 0] = 1
        for j in range(k):
            D[0, j] = b[j][0]
        return A, B, C, D

    def is_minimal(self) -> bool:
        """Controllable and observable, decided exactly (Kalman ranks in rationals)."""
        A, B, C, _D = self.exact_state_space()
        return is_controllable(A, B) and is_observable(A, C)

    def state_space(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(A, B, C, D)`` as floats, shapes ``(n, n)``, ``(n, k)``, ``(n,)``, ``(k,)``."""
        A, B, C, D = self.exact_state_space()

        def arr(m: fmpq_mat) -> np.ndarray:
            return np.array(
                [[float(int(m[i, j].p)) / float(int(m[i, j].q)) if m[i, j] != 0 else 0.0
                  for j in range(m.ncols())] for i in range(m.nrows())],
                dtype=float,
            ).reshape(m.nrows(), m.ncols())  # fmt: skip

        return arr(A), arr(B), arr(C).reshape(-1), arr(D).reshape(-1)

    def coefficients(self) -> tuple[np.ndarray, np.ndarray]:
        """``(b, a)`` as floats: ``b`` of shape ``(k, n + 1)``, ``a`` of shape ``(n + 1,)``."""
        b = np.array([[float(c) for c in num] for num in self.numerators], dtype=float)
        a = np.array([float(c) for c in self.denominator], dtype=float)
        return b.reshape(len(self.numerators), self.order + 1), a

    def to_dict(self) -> dict[str, Any]:
        return {
            "order": self.order,
            "inputs": list(self.inputs),
            "numerators": [[float(c) for c in n] for n in self.numerators],
            "denominator": [float(c) for c in self.denominator],
            "period": float(self.period),
        }

    def __repr__(self) -> str:
        return f"JointRealization(order={self.order}, inputs={list(self.inputs)})"


@dataclass
class JointDifferenceEquation:
    """Run a `JointRealization` sample by sample in float64 (the order of the module docstring)."""

    realization: JointRealization
    b: np.ndarray = field(init=False, repr=False)
    a: np.ndarray = field(init=False, repr=False)
    z: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self.b, self.a = self.realization.coefficients()
        self.z = np.zeros(self.realization.order)

    def reset(self) -> None:
        self.z[:] = 0.0

    def step(self, x: Sequence[float]) -> float:
        """One sample: the inputs in `JointRealization.inputs` order in, the output out."""
        b, a, z = self.b, self.a, self.z
        k, n = b.shape[0], z.size
        if k == 0:
            return 0.0
        acc = float(b[0, 0]) * x[0]
        for j in range(1, k):
            acc = acc + float(b[j, 0]) * x[j]
        y = acc + float(z[0]) if n else acc
        for i in range(n):
            t = float(z[i + 1]) if i + 1 < n else 0.0
            for j in range(k):
                t = t + float(b[j, i + 1]) * x[j]
            z[i] = t - float(a[i + 1]) * y
        return float(y)


class BatchDifferenceEquation:
    """Many `JointRealization` s of one input set at once (axis ``run``), as the twin runs them.

    Realizations of lower order are padded with zero coefficients (their extra states stay
    zero), so every run does the arithmetic of `JointDifferenceEquation`, elementwise.
    """

    def __init__(self, realizations: Sequence[JointRealization], inputs: Sequence[str]) -> None:
        n = max((r.order for r in realizations), default=0)
        k = len(inputs)
        self.inputs = tuple(inputs)
        self.b = np.zeros((k, n + 1, len(realizations)))
        self.a = np.zeros((n + 1, len(realizations)))
        for r, real in enumerate(realizations):
            b, a = real.coefficients()
            self.a[: a.size, r] = a
            for j, name in enumerate(real.inputs):
                self.b[self.inputs.index(name), : b.shape[1], r] = b[j]
        used = [j for j in range(k) if np.any(self.b[j] != 0)]
        self.used = used
        self.z = np.zeros((n, len(realizations)))

    def reset(self) -> None:
        self.z[:] = 0.0

    def step(self, x: Sequence[np.ndarray]) -> np.ndarray:
        """Inputs (one ``(B,)`` array per name of ``inputs``) in, outputs ``(B,)`` out."""
        b, a, z = self.b, self.a, self.z
        n = z.shape[0]
        if not self.used:
            return np.zeros(self.a.shape[1])
        first, *rest = self.used
        acc = b[first, 0] * x[first]
        for j in rest:
            acc = acc + b[j, 0] * x[j]
        y = acc + z[0] if n else acc
        for i in range(n):
            t = z[i + 1] if i + 1 < n else np.zeros_like(y)
            for j in self.used:
                t = t + b[j, i + 1] * x[j]
            z[i] = t - a[i + 1] * y
        return np.asarray(y, dtype=float)
