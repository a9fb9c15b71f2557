"""The exact rational impedance ``Z = N/D`` of a system at given parameter values.

Every float value is converted to the rational it represents, so ``N`` and
``D`` are exact.  The symbolic coefficients of a configuration are compiled
once (cached), so repeated evaluation costs only rational arithmetic.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from typing import Any

import sympy as sp
from flint import fmpq, fmpq_poly

from ..errors import DelayError, ParameterError
from ..exact import poly as ep
from ..model.delayatom import delay_text, has_delay
from ..model.expr import S, to_fraction
from ..model.sea import SEA, Impedance
from ..model.stiffness import load_impedance

__all__ = ["evaluate_system", "exact_rational_function", "structural_support"]


def exact_rational_function(
    system: SEA | Impedance | str | sp.Expr | tuple[Sequence[Any], Sequence[Any]],
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
    system: SEA | Impedance | str | sp.Expr | tuple[Sequence[Any], Sequence[Any]],
    values: Mapping[str, float] | None,
) -> tuple[fmpq_poly, fmpq_poly, tuple[bool, ...] | None]:
    """`exact_rational_function` plus the structural support of ``P`` (None for raw coefficients)."""
    if isinstance(system, tuple) and len(system) == 2:
        num = ep.as_poly([to_fraction(c, "num") for c in reversed(list(system[0]))])
        den = ep.as_poly([to_fraction(c, "den") for c in reversed(list(system[1]))])
        if den.is_zero():
            raise ParameterError("den: the denominator is identically zero")
        return num, den, None
    if isinstance(system, str | sp.Expr):
        system = Impedance(expr=system, values=dict(values or {}))
        values = None
    if values:
        if not isinstance(system, SEA | Impedance):
            raise TypeError("values= applies to SEA and Impedance systems only")
        system = _with_values(system, values)
    if isinstance(system, SEA):
        z = load_impedance(system)
    elif isinstance(system, Impedance):
        z = system.expr
    else:
        raise TypeError(f"cannot test passivity of {type(system).__name__}")
    if has_delay(z):
        raise DelayError(
            f"{delay_text(z)} in the model: this exact rational test does not apply to a "
            "delayed design; seapass.is_passive, seapass.delay_margin and the commands "
            "'seapass check' and 'seapass delay-margin' decide delayed designs"
        )
    missing = system.free_parameters
    if missing:
        raise ParameterError(
            f"no value for parameter(s) {', '.join(missing)}: give them, "
            f"e.g. values={{{missing[0]!r}: 1.0}}"
        )
    names, num_terms, den_terms, support = _compiled(z)
    vals = {k: ep.rational(to_fraction(v, k)) for k, v in system.values.items() if v is not None}
    env = [vals[n] for n in names]
    n, d = _eval_coeffs(num_terms, env), _eval_coeffs(den_terms, env)
    if d.is_zero():
        raise ParameterError("the impedance has a zero denominator for these values")
    return n, d, support


_Terms = tuple[tuple[tuple[tuple[int, ...], fmpq], ...], ...]


@functools.lru_cache(maxsize=512)
def _compiled(z: sp.Expr) -> tuple[tuple[str, ...], _Terms, _Terms, tuple[bool, ...]]:
    """Coefficients of ``N`` and ``D`` in ``s`` as exact polynomials in the parameters,
    and the structural support of ``P(x)`` (`structural_support`).

    Cached on the symbolic impedance, so repeated tests of one configuration
    cost only exact rational arithmetic.
    """
    num, den = sp.fraction(sp.cancel(sp.together(z)))
    params = sorted((x for x in (num.free_symbols | den.free_symbols) if x != S), key=str)
    names = tuple(str(x) for x in params)

    def terms(expr: sp.Expr) -> _Terms:
        out = []
        for c in sp.Poly(sp.expand(expr), S).all_coeffs()[::-1]:
            pc = sp.Poly(c, *params, domain="QQ") if params else sp.Poly(c, S, domain="QQ")
            out.append(
                tuple(
                    (tuple(mon) if params else (), fmpq(int(q.p), int(q.q)))
                    for mon, q in zip(pc.monoms(), pc.coeffs(), strict=True)
                )
            )
        return tuple(out)

    return names, terms(num), terms(den), structural_support(num, den)


def structural_support(num: sp.Expr, den: sp.Expr) -> tuple[bool, ...]:
    """Which powers ``x^i`` of ``P(x) = Re N(jω) D(−jω)`` are not identically zero.

    Computed with every parameter symbolic.  Terms that cancel for *all*
    parameter values (e.g. the ``ω⁴`` terms of a pure spring with load-side P)
    are structural, not a sign of a nearby boundary, so the margin ignores them.
    """
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


def _eval_coeffs(terms: _Terms, env: list[fmpq]) -> fmpq_poly:
    out = []
    for coeff in terms:
        acc = fmpq(0)
        for mon, q in coeff:
            t = q
            for v, e in zip(env, mon, strict=False):
                if e:
                    t *= v**e
            acc += t
        out.append(acc)
    return fmpq_poly(out)


def _with_values(system: SEA | Impedance, values: Mapping[str, float]) -> SEA | Impedance:
    merged = dict(system.values)
    merged.update(values)
    if isinstance(system, SEA):
        return system.with_values(**merged)
    return Impedance(expr=system.expr, values=merged)
