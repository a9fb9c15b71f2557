"""The controller as one system, realized once and minimally: ``K(s) = [C_A(s)  C_L(s)]``.

An SEA controller has two measured inputs, the errors ``e_A = θ_A − x_A`` and
``e_L = θ_L − x_L``, and one output, the actuator force ``f_A``.  Realizing ``C_A`` and
``C_L`` as two separate filters doubles every pole they share: a force loop's one
integrator, which appears in both, becomes two integrators, one of them an
uncontrollable mode at ``s = 0`` that no feedback can move.  Here the row is realized
once, with exactly its McMillan degree:

* each element is split into its polynomial part ``p0 + p1 s`` (the constant acts on the
  error, the derivative on the measured velocity only: *derivative on measurement*) and a
  strictly proper remainder ``r = N/D``, reduced exactly (gcd, python-flint);
* the common denominator is ``D = lcm(D_A, D_L)`` (monic) and the row
  ``[N_A D/D_A,  N_L D/D_L]/D`` is realized in observable canonical form.

For one output the observable form is observable by construction, and it is controllable
iff ``gcd(D, N_A D/D_A, N_L D/D_L) = 1``.  That holds: a root ``p`` of ``D`` of
multiplicity ``μ`` is a root of the ``D_i`` of largest multiplicity at ``p`` with the same
``μ``, so ``D/D_i`` does not vanish at ``p`` and neither does the reduced ``N_i``.  The order
``deg D`` is therefore the McMillan degree of the row (for one output, the degree of the
least common denominator of its entries).  `ControllerRealization.is_minimal` checks both
Kalman ranks exactly anyway.

The discrete counterpart (the same row after discretization, run as one difference
equation) is [`seapass.sampled.controllers.DiscreteController`][seapass.sampled.controllers.DiscreteController];
it builds on `common_denominator` here.

References
----------
.. [1] T. Kailath, *Linear Systems*, Prentice-Hall, 1980, §6.3 (McMillan degree, minimal
   realizations of a row by the observable form).
.. [2] K. J. Åström, T. Hägglund, *Advanced PID Control*, ISA, 2006, §3.4 (derivative on
   measurement).

Examples
--------
A PI force loop inside an impedance loop: the integrator ``ki/s`` is in both elements and
is realized once.

>>> k = controller_realization(
...     SEA(D1="k1", CA="2500*(0.5 + 10/s)", CL="(1.5 + 10/s)*1000 - 2500*(0.5 + 10/s)",
...         values=dict(m=0.4, b=3, k1=2500)))
>>> k.order, k.is_minimal()
(1, True)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np
from flint import fmpq, fmpq_mat, fmpq_poly

from ..errors import ParameterError, UnrealizableError
from .display import html_card, short_repr
from .expr import validate_values
from .sea import SEA, exact_values

__all__ = [
    "ControllerRealization",
    "RationalFunction",
    "common_denominator",
    "controller_realization",
    "exact_rational",
    "is_controllable",
    "is_observable",
    "numeric_controllers",
    "observable_form",
    "realize_row",
    "reduce_rational",
    "split_proper",
]

RationalFunction = tuple[fmpq_poly, fmpq_poly]
"""``(numerator, denominator)``, reduced, with a monic denominator."""

_ONE = fmpq_poly([1])
_ZERO = fmpq_poly([0])


def _fq(c: Any) -> fmpq:
    import sympy as sp

    r = sp.Rational(c)
    return fmpq(int(r.p), int(r.q))


def _as_fraction(c: fmpq) -> Fraction:
    return Fraction(int(c.p), int(c.q))


def reduce_rational(num: fmpq_poly, den: fmpq_poly) -> RationalFunction:
    """``num/den`` in lowest terms with a monic denominator (``0`` is ``0/1``)."""
    if den.is_zero():
        raise ParameterError("a controller has a denominator that is zero for these values")
    if num.is_zero():
        return fmpq_poly([0]), _ONE
    g = num.gcd(den)
    num, den = num // g, den // g
    lead = den.leading_coefficient()
    return num / lead, den / lead


def exact_rational(expr: Any, var: Any = None) -> RationalFunction:
    """Exact reduced ``(num, den)`` of a sympy rational function of ``var`` (default ``s``)
    with numeric coefficients (the numeric path, no sympy, is `numeric_controllers`).

    >>> exact_rational("(s + 1)/(s**2 + s)")
    (1, x)
    """
    import sympy as sp

    from .expr import S

    var = S if var is None else var
    e = sp.sympify(expr)
    num, den = sp.fraction(sp.together(e))
    pn, pd = sp.Poly(sp.expand(num), var), sp.Poly(sp.expand(den), var)
    if pn.free_symbols - {var} or pd.free_symbols - {var}:
        names = sorted(str(x) for x in (pn.free_symbols | pd.free_symbols) - {var})
        raise ParameterError(f"the controller needs values for {', '.join(names)}")
    return reduce_rational(
        fmpq_poly([_fq(c) for c in reversed(pn.all_coeffs())]),
        fmpq_poly([_fq(c) for c in reversed(pd.all_coeffs())]),
    )


def split_proper(f: RationalFunction) -> tuple[fmpq_poly, RationalFunction]:
    """``f = q + r`` with ``q`` a polynomial and ``r`` strictly proper (reduced)."""
    num, den = f
    q, r = divmod(num, den)
    return q, reduce_rational(r, den)


def common_denominator(entries: Sequence[RationalFunction]) -> tuple[list[fmpq_poly], fmpq_poly]:
    """``([N_i D/D_i], D)`` with ``D`` the monic lcm of the (reduced) denominators ``D_i``.

    The entries must be reduced (as `reduce_rational` leaves them); then the numerators and
    ``D`` have no common root, so the row ``[N_i D/D_i]/D`` realized over ``D`` is minimal.
    """
    den = _ONE
    for _n, d in entries:
        den = den * d // den.gcd(d)
    den = den / den.leading_coefficient()
    return [n * (den // d) for n, d in entries], den


def observable_form(
    nums: Sequence[fmpq_poly], den: fmpq_poly
) -> tuple[fmpq_mat, fmpq_mat, fmpq_mat]:
    """Observable canonical form ``(A, B, C)`` of the strictly proper row ``[N_i]/D`` (exact).

    ``A`` has ones below the diagonal and ``−a_0 … −a_{n−1}`` in its last column, ``B[:, i]``
    holds the coefficients of ``N_i`` (ascending), ``C = [0 … 0 1]``.
    """
    if den.leading_coefficient() != 1:
        raise ValueError("observable_form needs a monic denominator")
    n = den.degree()
    a = den.coeffs()
    A = fmpq_mat(n, n)
    for i in range(1, n):
        A[i, i - 1] = 1
    for i in range(n):
        A[i, n - 1] = -a[i]
    B = fmpq_mat(n, len(nums))
    for j, p in enumerate(nums):
        c = p.coeffs()
        if len(c) > n:
            raise ValueError("observable_form needs strictly proper entries")
        for i, x in enumerate(c):
            B[i, j] = x
    C = fmpq_mat(1, n)
    if n:
        C[0, n - 1] = 1
    return A, B, C


def _kalman_rank(A: fmpq_mat, B: fmpq_mat) -> int:
    n = A.nrows()
    if n == 0:
        return 0
    blocks = [B]
    for _ in range(n - 1):
        blocks.append(A * blocks[-1])
    cols = sum(b.ncols() for b in blocks)
    K = fmpq_mat(n, cols)
    c0 = 0
    for blk in blocks:
        for i in range(n):
            for j in range(blk.ncols()):
                K[i, c0 + j] = blk[i, j]
        c0 += blk.ncols()
    return int(K.rank())


def is_controllable(A: fmpq_mat, B: fmpq_mat) -> bool:
    """Kalman rank ``rank [B, AB, …, A^{n−1}B] = n``, decided exactly."""
    return _kalman_rank(A, B) == A.nrows()


def is_observable(A: fmpq_mat, C: fmpq_mat) -> bool:
    """``(Cᵀ, Aᵀ)`` controllable, decided exactly."""
    return _kalman_rank(A.transpose(), C.transpose()) == A.nrows()


def realize_row(
    entries: Sequence[RationalFunction],
) -> tuple[list[fmpq_poly], list[fmpq_poly], fmpq_poly]:
    """``(polynomial parts, numerators over D, D)`` of a row of rational functions."""
    polys, proper = [], []
    for f in entries:
        q, r = split_proper(reduce_rational(*f))
        polys.append(q)
        proper.append(r)
    nums, den = common_denominator(proper)
    return polys, nums, den


def _tuple(p: fmpq_poly, n: int) -> tuple[Fraction, ...]:
    c = [_as_fraction(x) for x in p.coeffs()]
    return tuple(c + [Fraction(0)] * (n - len(c)))


@dataclass(frozen=True, kw_only=True, repr=False)
class ControllerRealization:
    """``K(s) = [C_A  C_L]`` as one minimal state space (see the module docstring).

    ``f_A = Σ_i (p0_i e_i − p1_i v_i) + C ξ`` and ``ξ̇ = A ξ + B e`` with the errors
    ``e = (θ_A − x_A, θ_L − x_L)`` and the measured velocities ``v = (v_A, v_L)``.

    Attributes
    ----------
    proportional, derivative : (Fraction, Fraction)
        ``p0`` and ``p1`` of ``C_A`` and ``C_L``.
    numerators : (tuple of Fraction, tuple of Fraction)
        ``N_A D/D_A`` and ``N_L D/D_L``, ascending, each of length ``order``.
    denominator : tuple of Fraction
        The monic ``D = lcm(D_A, D_L)``, ascending (length ``order + 1``).
    """

    proportional: tuple[Fraction, Fraction]
    derivative: tuple[Fraction, Fraction]
    numerators: tuple[tuple[Fraction, ...], tuple[Fraction, ...]]
    denominator: tuple[Fraction, ...]

    @property
    def order(self) -> int:
        """Number of states: the McMillan degree of the strictly proper row."""
        return len(self.denominator) - 1

    def exact_matrices(self) -> tuple[fmpq_mat, fmpq_mat, fmpq_mat]:
        """``(A, B, C)`` in exact rationals (observable canonical form)."""
        den = fmpq_poly([fmpq(c.numerator, c.denominator) for c in self.denominator])
        nums = [fmpq_poly([fmpq(c.numerator, c.denominator) for c in n]) for n in self.numerators]
        return observable_form(nums, den)

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(A, B, C)`` as float arrays of shapes ``(n, n)``, ``(n, 2)``, ``(n,)``."""
        return observable_arrays(
            [float(c) for c in self.denominator],
            [[float(c) for c in n] for n in self.numerators],
        )

    def is_minimal(self) -> bool:
        """Controllable and observable, both decided exactly (Kalman ranks in rationals)."""
        A, B, C = self.exact_matrices()
        return is_controllable(A, B) and is_observable(A, C)

    def entry(self, i: int) -> RationalFunction:
        """``C_A`` (``i = 0``) or ``C_L`` (``i = 1``) back from the realization, exactly.

        ``p0 + p1 s + C (sI − A)^{-1} B_i``: the cross-check that the realization is the row.
        """
        A, B, C = self.exact_matrices()
        n = self.order
        den = fmpq_poly([fmpq(c.numerator, c.denominator) for c in self.denominator])
        if n:
            # C (sI − A)^{-1} b = [det(sI − A + b C) − det(sI − A)] / det(sI − A)
            bc = fmpq_mat(n, n)
            for r in range(n):
                for c in range(n):
                    bc[r, c] = B[r, i] * C[0, c]
            num = (A - bc).charpoly() - A.charpoly()
            den = A.charpoly()
        else:
            num = _ZERO
        p0, p1 = self.proportional[i], self.derivative[i]
        poly = fmpq_poly([fmpq(p0.numerator, p0.denominator), fmpq(p1.numerator, p1.denominator)])
        return reduce_rational(num + poly * den, den)

    def to_dict(self) -> dict[str, Any]:
        return {
            "order": self.order,
            "proportional": [float(c) for c in self.proportional],
            "derivative": [float(c) for c in self.derivative],
            "numerators": [[float(c) for c in n] for n in self.numerators],
            "denominator": [float(c) for c in self.denominator],
        }

    def __repr__(self) -> str:
        return short_repr("ControllerRealization", {"order": self.order})

    def _repr_html_(self) -> str:
        return html_card(
            "Controller K(s) = [C_A  C_L] (one minimal realization)",
            [
                ("states", str(self.order)),
                (
                    "proportional (on the errors)",
                    ", ".join(f"{float(c):.6g}" for c in self.proportional),
                ),
                (
                    "derivative (on the measurements)",
                    ", ".join(f"{float(c):.6g}" for c in self.derivative),
                ),
                (
                    "common denominator (ascending)",
                    ", ".join(f"{float(c):.6g}" for c in self.denominator),
                ),
            ],
        )


def observable_arrays(
    den: Sequence[float] | np.ndarray, nums: Sequence[Sequence[float] | np.ndarray]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Float observable form of ``[N_i]/D`` (``D`` ascending and monic, ``N_i`` ascending)."""
    n = len(den) - 1
    A = np.zeros((n, n))
    if n:
        A[1:, :-1] = np.eye(n - 1)
        A[:, -1] = -np.asarray(den[:n], dtype=float)
    B = np.zeros((n, len(nums)))
    for j, c in enumerate(nums):
        B[: len(c), j] = c
    C = np.zeros(n)
    if n:
        C[-1] = 1.0
    return A, B, C


def _excess_error(name: str, excess: int) -> UnrealizableError:
    return UnrealizableError(
        f"{name} is improper with {excess} more zeros than poles: the controller "
        f"measures only positions and velocities, so at most one derivative "
        f"(e.g. 'kd + bd*s') is realizable; add filter poles, "
        f"e.g. 'kd + bd*s/(1 + s/500)'"
    )


def realization_from_rationals(
    ca: RationalFunction, cl: RationalFunction, *, names: Sequence[str] = ("CA", "CL")
) -> ControllerRealization:
    """The minimal `ControllerRealization` of the exact row ``[ca, cl]``.

    Raises
    ------
    UnrealizableError
        For an element whose polynomial part has degree 2 or more.
    """
    polys, nums, den = realize_row([ca, cl])
    for name, q in zip(names, polys, strict=True):
        if q.degree() > 1:
            raise _excess_error(name, q.degree())
    n = den.degree()
    return ControllerRealization(
        proportional=(_tuple(polys[0], 2)[0], _tuple(polys[1], 2)[0]),
        derivative=(_tuple(polys[0], 2)[1], _tuple(polys[1], 2)[1]),
        numerators=(_tuple(nums[0], n), _tuple(nums[1], n)),
        denominator=_tuple(den, n + 1),
    )


def numeric_controllers(
    sea: SEA, values: Mapping[str, float] | None = None
) -> tuple[RationalFunction, RationalFunction]:
    """``(C_A, C_L)`` of ``sea`` at its values (``values`` override them), exact and reduced.

    Built from the model's exact elements (`SEA.exact_elements`, no sympy).

    Raises
    ------
    ParameterError
        For a controller parameter without a value (the message names it).

    Examples
    --------
    >>> numeric_controllers(SEA(D1="k1", CA="kd + ki/s", values=dict(kd=2, ki=3)))[0]
    (2*x + 3, x)
    """
    vals = {k: v for k, v in sea.values.items() if v is not None}
    if values:
        vals.update(validate_values(values))
    env = exact_values(vals)
    exact = sea.exact_elements()
    out = []
    for key in ("CA", "CL"):
        missing = sorted(exact[key].parameters() - set(env))
        if missing:
            raise ParameterError(
                f"{key} needs values for {', '.join(missing)}; give them, "
                f"e.g. values={{{missing[0]!r}: 1.0}}"
            )
        out.append(reduce_rational(*exact[key].evaluate(env)))
    return out[0], out[1]


def controller_realization(
    sea: SEA, *, values: Mapping[str, float] | None = None
) -> ControllerRealization:
    """The one minimal realization of ``K(s) = [C_A  C_L]`` of ``sea`` (every value given).

    Parameters
    ----------
    sea : SEA
    values : mapping, optional
        Parameter values overriding those of ``sea``.

    Raises
    ------
    ParameterError
        For a controller parameter without a value.
    UnrealizableError
        For an element that needs more than one derivative (``kd*s**2``).
    """
    from .zcontroller import continuous_only

    continuous_only(sea, "the continuous controller realization")
    ca, cl = numeric_controllers(sea, values)
    names: tuple[str, ...] = ("CA", "CL")
    if any(n.degree() - d.degree() > 1 for n, d in (ca, cl)):  # the message shows them
        names = tuple(f"{k} = {getattr(sea, k)}" for k in ("CA", "CL"))
    return realization_from_rationals(ca, cl, names=names)
