"""The exact rational impedance ``Z = N/D`` of a system at given parameter values.

Every float value is converted to the rational it represents, so ``N`` and
``D`` are exact.  ``Z`` is derived once per configuration, without sympy, as an
exact rational function of ``s`` and the parameters
([`seapass.model.freebody`][seapass.model.freebody]) and cached, so repeated
evaluation costs only rational arithmetic.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, TypeAlias

from flint import fmpq, fmpq_mpoly, fmpq_poly

from ..errors import ParameterError
from ..exact import poly as ep
from ..exact.axis import at_j_omega, even_to_x
from ..model.delayatom import delay_refusal, model_delays
from ..model.expr import to_fraction
from ..model.freebody import exact_impedance
from ..model.rational import S_NAME, univariate
from ..model.sea import SEA, Impedance, exact_values
from ..model.zcontroller import continuous_only

if TYPE_CHECKING:
    import sympy as sp

__all__ = [
    "SystemLike",
    "compiled_impedance",
    "evaluate_system",
    "exact_rational_function",
    "exact_support",
    "structural_support",
]

SystemLike: TypeAlias = "SEA | Impedance | str | sp.Expr | tuple[Sequence[Any], Sequence[Any]]"
"""A system the exact analyses accept: an `SEA`, an `Impedance`, an expression in ``s``
(a string or a sympy expression) or a ``(num, den)`` pair of descending coefficients."""


def exact_rational_function(
    system: SystemLike,
    values: Mapping[str, float] | None = None,
) -> tuple[fmpq_poly, fmpq_poly]:
    """Exact ``(N, D)`` of the impedance of ``system``, as `flint.fmpq_poly`.

    ``system`` may be an `SEA` (its load impedance ``Z_L``), an
    `Impedance`, an expression string/sympy expression in ``s``, or a
    ``(num, den)`` pair of descending coefficient sequences.
    """
    num, den, _support = evaluate_system(system, values)
    return num, den


def evaluate_system(
    system: SystemLike,
    values: Mapping[str, float] | None,
) -> tuple[fmpq_poly, fmpq_poly, tuple[bool, ...] | None]:
    """`exact_rational_function` plus the structural support of ``P`` (None for raw coefficients).

    ``N/D`` is ``Z`` in lowest terms *for every parameter value* (the exact
    derivation of [`seapass.model.freebody`][seapass.model.freebody] keeps the
    parameters as variables), then evaluated at the values: a factor that cancels
    only at these values stays in both, and the passivity test reports it as a
    hidden mode.  ``N`` and ``D`` are scaled as sympy's ``cancel`` scales them.
    """
    if isinstance(system, tuple) and len(system) == 2:
        num = ep.as_poly([to_fraction(c, "num") for c in reversed(list(system[0]))])
        den = ep.as_poly([to_fraction(c, "den") for c in reversed(list(system[1]))])
        if den.is_zero():
            raise ParameterError("den: the denominator is identically zero")
        return num, den, None
    if isinstance(system, str) or type(system).__module__.startswith("sympy"):
        system = Impedance(expr=system, values=dict(values or {}))
        values = None
    if values:
        if not isinstance(system, SEA | Impedance):
            raise TypeError("values= applies to SEA and Impedance systems only")
        system = system.with_values(**values)
    if not isinstance(system, SEA | Impedance):
        raise TypeError(f"cannot test passivity of {type(system).__name__}")
    num_c, den_c, support = compiled_impedance(system)
    missing = system.free_parameters
    if missing:
        raise ParameterError(
            f"no value for parameter(s) {', '.join(missing)}: give them, "
            f"e.g. values={{{missing[0]!r}: 1.0}}"
        )
    env = exact_values(system.values)
    n, d = univariate(num_c, env), univariate(den_c, env)
    if d.is_zero():
        raise ParameterError("the impedance has a zero denominator for these values")
    return n, d, support


def compiled_impedance(system: SEA | Impedance) -> tuple[fmpq_mpoly, fmpq_mpoly, tuple[bool, ...]]:
    """``N`` and ``D`` in sympy's normal form and the structural support of ``P``.

    Cached on the parsed elements, so repeated tests of one configuration cost only the
    exact evaluation at the values.
    """
    continuous_only(system, "the continuous-time passivity analysis")
    key = ("sea", system.sources()) if isinstance(system, SEA) else ("z", system.sources())
    with _LOCK:
        found = _CACHE.get(key)
        if found is not None:
            _CACHE.move_to_end(key)
            return found
    z = exact_impedance(system)
    delays = model_delays(z)
    if delays:  # E = e^{-s tau} is no parameter: the exact rational test does not apply
        raise delay_refusal(delays[0])
    num, den = z.canonical()
    found = (num, den, exact_support(num, den))
    with _LOCK:
        _CACHE[key] = found
        if len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    return found


_CACHE: OrderedDict[tuple[Any, ...], tuple[fmpq_mpoly, fmpq_mpoly, tuple[bool, ...]]]
_CACHE = OrderedDict()
_CACHE_SIZE = 512
_LOCK = threading.Lock()


def _in_s(p: fmpq_mpoly) -> dict[int, fmpq_mpoly]:
    """``p`` as ``{k: coefficient of s^k}`` (coefficients polynomials in the parameters)."""
    ctx = p.context()
    i = ctx.variable_to_index(S_NAME)
    parts: dict[int, dict[tuple[int, ...], fmpq]] = {}
    for exps, c in zip(p.monoms(), p.coeffs(), strict=True):
        rest = tuple(0 if j == i else e for j, e in enumerate(exps))
        parts.setdefault(exps[i], {})[rest] = c
    return {k: ctx.from_dict(v) for k, v in parts.items()}


def exact_support(num: fmpq_mpoly, den: fmpq_mpoly) -> tuple[bool, ...]:
    """`structural_support` of ``N/D`` given as polynomials in ``s`` and the parameters.

    A power of ``x`` whose coefficient is nonzero at one point of the parameters is
    nonzero for generic values; only the powers that vanish there are decided by forming
    their coefficient, ``Σ ± n_k d_l`` over ``k + l = 2i``, as a polynomial.
    """
    names = [n for n in num.context().names() if n != S_NAME]
    point = {n: fmpq(2 * j + 3, 5 * j + 7) for j, n in enumerate(names)}  # any point will do
    nr, ni = at_j_omega(univariate(num, point))
    dr, di = at_j_omega(univariate(den, point))
    at_point = even_to_x(nr * dr + ni * di)
    n, d = _in_s(num), _in_s(den)
    zero = num.context().constant(0)
    top = (max(n, default=0) + max(d, default=0)) // 2
    support = []
    for i in range(top + 1):
        if i <= at_point.degree() and at_point[i] != 0:
            support.append(True)
            continue
        coeff = zero
        for k, nk in n.items():
            j = 2 * i - k
            if j in d:  # Re of j^k (−j)^j = (−1)^(j + i)
                coeff = coeff + (-1 if (j + i) % 2 else 1) * nk * d[j]
        support.append(not coeff.is_zero())
    while support and not support[-1]:
        support.pop()
    return tuple(support)


def structural_support(num: sp.Expr, den: sp.Expr) -> tuple[bool, ...]:
    """Which powers ``x^i`` of ``P(x) = Re N(jω) D(−jω)`` are not identically zero.

    Computed with every parameter symbolic.  Terms that cancel for *all*
    parameter values (e.g. the ``ω⁴`` terms of a pure spring with load-side P)
    are structural, not a sign of a nearby boundary, so the margin ignores them.
    """
    import sympy as sp

    from ..model.expr import S

    w = sp.Dummy("w", real=True)
    coeffs_n = sp.Poly(sp.expand(num), S).all_coeffs()[::-1]
    coeffs_d = sp.Poly(sp.expand(den), S).all_coeffs()[::-1]

    def re_im(coeffs: list[sp.Expr]) -> tuple[sp.Expr, sp.Expr]:
        re = sum(
            (c * (-1) ** (k // 2) * w**k for k, c in enumerate(coeffs) if k % 2 == 0), sp.S.Zero
        )
        im = sum(
            (c * (-1) ** (k // 2) * w**k for k, c in enumerate(coeffs) if k % 2 == 1), sp.S.Zero
        )
        return re, im

    nr, ni = re_im(coeffs_n)
    dr, di = re_im(coeffs_d)
    pw = sp.Poly(sp.expand(nr * dr + ni * di), w)
    deg = pw.degree() if not pw.is_zero else -1
    return tuple(pw.coeff_monomial(w ** (2 * i)) != 0 for i in range(deg // 2 + 1))
