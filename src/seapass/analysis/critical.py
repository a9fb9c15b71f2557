"""Critical values of one free parameter, exactly, on bivariate flint polynomials (no sympy).

With every parameter but one (``λ``) fixed to exact rationals, ``Z = N/D`` has
``N, D ∈ Q[s, λ]``.  The verdict of the positive-real test can change only at a real
root of one of the polynomials in ``λ`` listed in
[`seapass.analysis.region`][seapass.analysis.region] (leading coefficients,
resultants, discriminants, the coefficients of ``P(x) = Re N(jω) D(−jω)``); this module
forms them with ``flint.fmpq_mpoly`` (exact gcd, resultant, discriminant, square-free
factorization), factors them over ``Q`` and isolates their roots in a range.  It
computes the same polynomials as the symbolic version there, up to constant factors,
so the critical values are the same numbers.

What lives here: `CriticalValue`, `critical_polynomials_in`, `critical_values_in`,
`exact_with`.  May import:
[`seapass.errors`][seapass.errors], [`seapass.exact`][seapass.exact],
[`seapass.model`][seapass.model] and the modules of this package below it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction

from flint import fmpq, fmpq_mpoly, fmpq_mpoly_ctx, fmpq_poly

from ..exact import poly as ep
from ..model.rational import S_NAME, RatFunc, on_axis, univariate
from ..model.sea import SEA, Impedance, exact_values
from .impedance import compiled_impedance, exact_support

__all__ = ["CriticalValue", "critical_polynomials_in", "critical_values_in", "exact_with"]

_LAM = "lam"
_CTX = fmpq_mpoly_ctx.get((S_NAME, _LAM), "lex")  # s (or ω, or x = ω²) and the free λ
_S, _L = 0, 1


def _in_var(p: fmpq_mpoly, var: int) -> dict[int, fmpq_mpoly]:
    """``p`` as ``{k: coefficient of var^k}``."""
    parts: dict[int, dict[tuple[int, ...], fmpq]] = {}
    for exps, c in zip(p.monoms(), p.coeffs(), strict=True):
        rest = tuple(0 if j == var else e for j, e in enumerate(exps))
        parts.setdefault(exps[var], {})[rest] = c
    return {k: _CTX.from_dict(v) for k, v in parts.items()}


def _degree(p: fmpq_mpoly, var: int = _S) -> int:
    return -1 if p.is_zero() else int(p.degrees()[var])


def _lc(p: fmpq_mpoly, var: int = _S) -> fmpq_mpoly:
    if p.is_zero():
        return p
    parts = _in_var(p, var)
    return parts[max(parts)]


def _halve(p: fmpq_mpoly) -> fmpq_mpoly:
    """An even polynomial in ω as a polynomial in ``x = ω²``."""
    return _CTX.from_dict(
        {(e[_S] // 2, e[_L]): c for e, c in zip(p.monoms(), p.coeffs(), strict=True)}
    )


def _sqf_part(p: fmpq_mpoly) -> fmpq_mpoly:
    _content, factors = p.factor_squarefree()
    out = _CTX.constant(1)
    for f, _m in factors:
        out = out * f
    return out


def _critical(num: fmpq_mpoly, den: fmpq_mpoly) -> list[fmpq_mpoly]:
    """The critical polynomials of ``N/D`` (coprime, in ``(s, λ)``), as in ``region._critical_polys``."""
    out = [_lc(num), _lc(den)]
    if _degree(num) > 0 and _degree(den) > 0:
        out.append(num.resultant(den, S_NAME))
    else:
        out += [num, den] if _degree(num) <= 0 else [den]
    re_d, im_d = on_axis(den)
    re_n, im_n = on_axis(num)
    g = re_d.gcd(im_d) if not im_d.is_zero() else re_d
    if not im_d.is_zero():
        r1, r2 = re_d / g, im_d / g
        if _degree(r1) > 0 and _degree(r2) > 0:
            out.append(r1.resultant(r2, S_NAME))
        else:
            out += [_lc(r1), _lc(r2)]
    if _degree(g) > 0:
        out += [_lc(g), g.subs({S_NAME: 0})]
        if _degree(g) > 1:
            out.append(g.discriminant(S_NAME))
        ddr, ddi = on_axis(den.derivative(S_NAME))
        for res in (re_n * ddr + im_n * ddi, im_n * ddr - re_n * ddi):
            if not res.is_zero():
                out.append(g.resultant(res, S_NAME))
    pw = re_n * re_d + im_n * im_d
    if not pw.is_zero():
        px = _halve(pw)
        parts = _in_var(px, _S)
        k = min(parts)
        q = _CTX.from_dict(
            {(e[_S] - k, e[_L]): c for e, c in zip(px.monoms(), px.coeffs(), strict=True)}
        )
        q = _sqf_part(q) if _degree(q) > 0 else q
        out += [parts[max(parts)], q.subs({S_NAME: 0})]
        if _degree(q) > 1:
            out.append(q.discriminant(S_NAME))
        out += [c for c in parts.values() if _degree(c, _L) > 0]
    return [e for e in out if not e.is_zero()]


def _in_lambda(e: fmpq_mpoly) -> fmpq_poly:
    """A polynomial of ``(s, λ)`` as one in ``λ``: itself when free of ``s``, else its content
    in ``λ`` (where all its coefficients in ``s`` vanish together)."""
    parts = _in_var(e, _S)
    g = _CTX.constant(0)
    for part in parts.values():
        g = g.gcd(part) if not g.is_zero() else part
    coeffs: dict[int, fmpq] = {}
    for exps, c in zip(g.monoms(), g.coeffs(), strict=True):
        coeffs[exps[_L]] = c
    return fmpq_poly([coeffs.get(i, fmpq(0)) for i in range(max(coeffs, default=-1) + 1)])


def _bivariate(system: SEA | Impedance, param: str, fixed: Mapping[str, fmpq]) -> RatFunc:
    """``Z`` with every parameter but ``param`` replaced by its value, in ``Q[s, λ]``, reduced."""
    num, den, _support = compiled_impedance(system)
    subs: dict[str | int, fmpq] = {k: v for k, v in fixed.items() if k != param}
    if subs:
        num, den = num.subs(subs), den.subs(subs)
    mapping: dict[str | int, str | int] = {S_NAME: S_NAME, param: _LAM}
    n, d = (p.project_to_context(_CTX, mapping=mapping) for p in (num, den))
    return RatFunc.from_polys(n, d)


def critical_polynomials_in(
    system: SEA | Impedance, param: str, fixed: Mapping[str, fmpq]
) -> list[fmpq_poly]:
    """The critical polynomials in ``param`` of ``system`` with the other values ``fixed``."""
    z = _bivariate(system, param, fixed)
    return [p for p in (_in_lambda(e) for e in _critical(z.num, z.den)) if p.degree() > 0]


@dataclass(frozen=True, eq=False, kw_only=True)
class CriticalValue:
    """A critical value: the rational ``lo`` (``lo == hi``) or the only root of the
    irreducible ``poly`` (degree >= 2, so irrational) in ``(lo, hi]``."""

    lo: Fraction
    hi: Fraction
    poly: fmpq_poly | None = None

    def separated(self, other: CriticalValue) -> tuple[CriticalValue, CriticalValue]:
        """Both narrowed until their intervals are disjoint (distinct roots)."""
        a, b = self, other
        for _ in range(ep.MAX_BISECTIONS):
            if a.hi < b.lo or b.hi < a.lo or (a.lo == a.hi and b.lo == b.hi):
                return a, b
            a, b = a.halved(), b.halved()
        raise ArithmeticError("critical values could not be separated")

    def halved(self) -> CriticalValue:
        """The same value with its isolating interval halved (a rational one is exact)."""
        if self.poly is None:
            return self
        lo, hi = (ep.rational(x) for x in (self.lo, self.hi))
        lo, hi = ep.refine(self.poly, (lo, hi), (hi - lo) / 2)
        return CriticalValue(lo=ep.to_fraction(lo), hi=ep.to_fraction(hi), poly=self.poly)


def critical_values_in(polys: list[fmpq_poly], lo: Fraction, hi: Fraction) -> list[CriticalValue]:
    """Sorted critical values in ``[lo, hi]``: rational roots exactly, irrational ones by
    tight isolating intervals ``(a, b]`` (relative width 2^-60) of their irreducible
    factor, pairwise disjoint."""
    factors: dict[tuple[fmpq, ...], fmpq_poly] = {}
    for e in polys:
        _c, fs = e.factor()
        for f, _m in fs:
            monic = f / f.leading_coefficient()
            factors[tuple(monic.coeffs())] = monic
    out: dict[tuple[Fraction, Fraction], CriticalValue] = {}
    for q in factors.values():
        if q.degree() == 1:
            r = ep.to_fraction(-q[0] / q[1])
            if lo <= r <= hi:
                out[r, r] = CriticalValue(lo=r, hi=r)
            continue
        for a, b in ep.isolate_real_roots(q, lo, hi):
            a, b = ep.refine(q, (a, b), max(abs(b), fmpq(1)) / fmpq(2) ** 40)
            scale_ = min(abs(a), abs(b)) or fmpq(1, 2**40)
            a, b = ep.refine(q, (a, b), scale_ / fmpq(2) ** 60)
            lo_, hi_ = ep.to_fraction(a), ep.to_fraction(b)
            out[lo_, hi_] = CriticalValue(lo=lo_, hi=hi_, poly=q)
    points = sorted(out.values(), key=lambda c: (c.lo, c.hi))
    for i in range(len(points) - 1):  # roots closer than 2^-60: narrow both
        if points[i + 1].lo <= points[i].hi:
            points[i], points[i + 1] = points[i].separated(points[i + 1])
    return sorted(points, key=lambda c: (c.lo, c.hi))


def exact_with(
    system: SEA | Impedance, fixed: Mapping[str, float | None], param: str, x: Fraction
) -> tuple[fmpq_poly, fmpq_poly, tuple[bool, ...]]:
    """``N``, ``D`` and the structural support of ``system`` at ``fixed`` and ``param = x``.

    As the values are handed to the model: a value that is a float goes with the others
    (``Z`` reduced for every value of every parameter); a rational that is not a float is
    substituted into ``Z`` first and ``Z`` reduced again in the remaining parameters.
    """
    value = fmpq(x.numerator, x.denominator)
    env = {**exact_values(fixed), param: value}
    num, den, support = compiled_impedance(system)
    if Fraction(float(x)) != x:
        at: dict[str | int, fmpq] = {param: value}
        num, den = RatFunc.from_polys(num.subs(at), den.subs(at)).canonical()
        support = exact_support(num, den)
    return univariate(num, env), univariate(den, env), support
