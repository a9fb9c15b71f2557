"""The exact ``(N, D)`` of a design before the exact path (benchmark reference only).

A frozen copy of ``seapass.analysis.impedance.evaluate_system`` as it was when every
design went through sympy: ``Z_L`` derived symbolically
(``seapass.model.stiffness.load_impedance``, sympy's ``cancel``), its coefficients
compiled once per configuration into exact polynomials in the parameters, then
evaluated at the values.  ``bench_startup.py`` times it against the exact path and
checks that both give the same ``N``, ``D`` and support.  Not part of the package.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping

import sympy as sp
from flint import fmpq, fmpq_poly

from seapass.analysis.impedance import structural_support
from seapass.model.expr import S, to_fraction
from seapass.model.sea import SEA
from seapass.model.stiffness import load_impedance

_Terms = tuple[tuple[tuple[tuple[int, ...], fmpq], ...], ...]


@functools.lru_cache(maxsize=512)
def _compiled(z: sp.Expr) -> tuple[tuple[str, ...], _Terms, _Terms, tuple[bool, ...]]:
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


def evaluate_system(
    sea: SEA, values: Mapping[str, float]
) -> tuple[fmpq_poly, fmpq_poly, tuple[bool, ...]]:
    """``N``, ``D`` and the support of ``Z_L`` of ``sea`` at ``values``, the sympy way.

    As ``is_passive(sea, values=...)`` did: the values make a new model first.
    """
    if values:
        sea = sea.with_values(**values)
    z = load_impedance(sea)
    names, num, den, support = _compiled(z)
    vals = {k: v for k, v in sea.values.items() if v is not None}
    env = []
    for n in names:
        q = to_fraction(vals[n], n)
        env.append(fmpq(q.numerator, q.denominator))
    return _eval_coeffs(num, env), _eval_coeffs(den, env), support
