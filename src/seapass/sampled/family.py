"""Discrete controllers whose coefficients depend on one free parameter ``λ``.

The discretization is the very one of [`seapass.sampled.controllers.discretize`][seapass.sampled.controllers.discretize]
(polynomial part → derivative on the measurement with backward differences and the optional
velocity filter; strictly proper part → Tustin / backward / ZOH), carried out with ``λ``
left symbolic.  Each controller becomes ``n(z⁻¹; λ)/d(z⁻¹; λ)`` with coefficients that are
polynomials in ``λ`` (denominators cleared), equal to the deployed controller at every
``λ`` except finitely many *special values* (a degree of ``C(s)`` drops, a factor cancels,
the discretization is undefined); those are returned so callers decide them one by one.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

import sympy as sp
from flint import fmpq, fmpq_poly

from ..errors import ParameterError
from ..exact.poly import as_poly, rational
from ..model.expr import S, symbol, to_fraction
from ..model.loop import Method, SampledLoop
from ..model.sea import SEA
from .emulation import discrete_paths

__all__ = [
    "ControllerFamily",
    "ControllerPolys",
    "controller_family",
    "joint_polys",
    "poly_product",
]

_Q = sp.Symbol("q")  # z^-1
_LAM = sp.Symbol("lambda_")  # the free parameter in the joint gcd


@dataclass(frozen=True)
class ControllerPolys:
    """``num``/``den`` as ``[coefficient of λ^a]`` of polynomials in ``z⁻¹`` (fmpq)."""

    num: tuple[fmpq_poly, ...]
    den: tuple[fmpq_poly, ...]

    @property
    def is_zero(self) -> bool:
        return all(p.is_zero() for p in self.num)

    def at(self, lam: Fraction) -> tuple[fmpq_poly, fmpq_poly]:
        x = rational(lam)
        return _at(self.num, x), _at(self.den, x)


def _at(coeffs: tuple[fmpq_poly, ...], x: fmpq) -> fmpq_poly:
    out = fmpq_poly([0])
    for c in reversed(coeffs):
        out = out * x + c
    return out


def _split(expr: sp.Expr, lam: sp.Symbol) -> tuple[list[sp.Expr], sp.Expr, list[sp.Expr]]:
    """Polynomial part (ascending), strictly proper remainder, and λ-polynomials whose roots
    change the structure (leading coefficients in ``s``, cancellations)."""
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    field = sp.QQ.frac_field(lam)
    pn, pd = sp.Poly(num, S, domain=field), sp.Poly(den, S, domain=field)
    quo, rem = sp.div(pn, pd)
    special = [pn.LC(), pd.LC()]
    if pn.degree() > 0 and pd.degree() > 0:
        special.append(sp.resultant(pn.as_expr(), pd.as_expr(), S))
    coeffs = [sp.sympify(field.to_sympy(c)) for c in quo.all_coeffs()[::-1]]
    return (
        coeffs,
        sp.cancel(rem.as_expr() / pd.as_expr()),
        [sp.sympify(field.to_sympy(x)) if not isinstance(x, sp.Expr) else x for x in special],
    )


def _in_q(expr: sp.Expr, lam: sp.Symbol) -> tuple[list[fmpq_poly], list[fmpq_poly], list[sp.Expr]]:
    """``expr(q; λ)`` as ``num``/``den`` coefficient lists (in ``λ``) and special polynomials."""
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    pq_num = sp.Poly(sp.expand(num), _Q, lam)
    pq_den = sp.Poly(sp.expand(den), _Q, lam)
    special = [sp.Poly(den, _Q, lam).as_expr().subs(_Q, 0)]
    if sp.Poly(num, _Q).degree() > 0 and sp.Poly(den, _Q).degree() > 0:
        special.append(sp.resultant(sp.expand(num), sp.expand(den), _Q))

    def split(p: sp.Poly) -> list[fmpq_poly]:
        if p.is_zero:
            return [fmpq_poly([0])]
        k = p.degree(lam)
        out = [[fmpq(0)] * (p.degree(_Q) + 1) for _ in range(max(k, 0) + 1)]
        for (i, a), c in p.terms():
            out[a][i] = rational(sp.Rational(c))
        return [fmpq_poly(c) for c in out]

    return split(pq_num), split(pq_den), special


def poly_product(p: list[fmpq_poly], r: list[fmpq_poly]) -> list[fmpq_poly]:
    """Product of two polynomials in ``λ`` whose coefficients are polynomials in ``z⁻¹``."""
    out = [fmpq_poly([0])] * (len(p) + len(r) - 1)
    out = list(out)
    for i, a in enumerate(p):
        for j, b in enumerate(r):
            out[i + j] = out[i + j] + a * b
    return out


def _add(p: list[fmpq_poly], r: list[fmpq_poly]) -> list[fmpq_poly]:
    n = max(len(p), len(r))
    zero = fmpq_poly([0])
    return [(p[i] if i < len(p) else zero) + (r[i] if i < len(r) else zero) for i in range(n)]


def _discretize(
    expr: sp.Expr, lam: sp.Symbol, period: Fraction, method: Method, velocity_filter: float | None
) -> tuple[ControllerPolys, list[sp.Expr]]:
    coeffs, proper, special = _split(expr, lam)
    if method == "zoh" and lam in proper.free_symbols:
        raise ParameterError(
            f"{lam} sits in a strictly proper controller part discretized by ZOH; "
            "bounds need method='tustin' or 'backward' there"
        )
    err, deriv = discrete_paths(
        coeffs, proper, period, method=method, velocity_filter=velocity_filter
    )
    ne, de, s1 = _in_q(sp.sympify(err), lam)
    nm, dm, s2 = _in_q(sp.sympify(deriv), lam)
    # DiscreteTF.__add__: (ne dm + nm de)/(de dm), no cancellation
    num = _add(poly_product(ne, dm), poly_product(nm, de))
    den = poly_product(de, dm)
    return ControllerPolys(tuple(num), tuple(den)), [*special, *s1, *s2]


def _to_sympy(polys: Sequence[fmpq_poly]) -> sp.Expr:
    """``Σ_a λ^a p_a(q)`` as a sympy expression in ``q`` and ``λ`` (the symbol `_LAM`)."""
    out = sp.Integer(0)
    for a, p in enumerate(polys):
        for i, c in enumerate(p.coeffs()):
            if c != 0:
                out += sp.Rational(int(c.p), int(c.q)) * _Q**i * _LAM**a
    return out


def _from_sympy(expr: sp.Expr) -> list[fmpq_poly]:
    return _in_q(sp.expand(expr), _LAM)[0] if expr != 0 else [fmpq_poly([0])]


def joint_polys(
    actuator: ControllerPolys, load: ControllerPolys
) -> tuple[list[list[fmpq_poly]], list[fmpq_poly]]:
    """``v'(λ) = (D, n_A D/d_A, n_L D/d_L)`` and ``d_L/g`` over the common denominator.

    ``g = gcd(d_A, d_L)`` is taken in ``Q[q, λ]`` (exact, sympy): a pole both controllers
    share for generic ``λ`` (a force loop's integrator) is one factor of ``D = d_A d_L/g``.
    At the finitely many ``λ`` where more cancels the family keeps a common factor, which
    only makes a verdict more conservative there (an extra ``|factor|² ≥ 0`` in the power,
    extra roots in the stability test); those values are decided alone anyway when rational.
    Without a shared factor this is ``(d_A d_L, n_A d_L, n_L d_A)`` and ``d_L``.
    """
    da, dl = _to_sympy(actuator.den), _to_sympy(load.den)
    g = sp.gcd(da, dl) if not load.is_zero else sp.Integer(1)
    if _Q not in g.free_symbols:
        return [
            poly_product(list(actuator.den), list(load.den)),
            poly_product(list(actuator.num), list(load.den)),
            poly_product(list(load.num), list(actuator.den)),
        ], list(load.den)
    ra = _from_sympy(sp.cancel(dl / g))  # d_L/g: the poles of K_L that K_A lacks
    rl = _from_sympy(sp.cancel(da / g))
    return [
        poly_product(list(actuator.den), ra),
        poly_product(list(actuator.num), ra),
        poly_product(list(load.num), rl),
    ], ra


@dataclass(frozen=True)
class ControllerFamily:
    """Both controllers as functions of ``λ``; ``special``: rational ``λ`` to decide alone."""

    actuator: ControllerPolys
    load: ControllerPolys
    special: tuple[Fraction, ...]


def _rational_roots(exprs: list[sp.Expr], lam: sp.Symbol) -> set[Fraction]:
    out: set[Fraction] = set()
    for e in exprs:
        e = sp.sympify(e)
        num = sp.fraction(sp.together(e))[0]
        if lam not in num.free_symbols:
            continue
        p = sp.Poly(sp.expand(num), lam)
        poly = as_poly([sp.Rational(c) for c in reversed(p.all_coeffs())])
        for f, _m in poly.factor()[1]:
            if f.degree() == 1:
                r = -f[0] / f[1]
                out.add(Fraction(int(r.p), int(r.q)))
    return out


def controller_family(sea: SEA, param: str, loop: SampledLoop) -> ControllerFamily:
    """``K_A``, ``K_L`` of ``sea`` in ``loop`` with ``param`` free (every other value substituted)."""
    lam = symbol(param)
    if sea.discrete is not None:
        return _z_family(sea, param, loop)
    T = loop.exact_period
    vals = {k: v for k, v in sea.values.items() if v is not None and k != param}
    subs = {symbol(k): sp.Rational(to_fraction(v, k)) for k, v in vals.items()}
    parts = []
    special: list[sp.Expr] = []
    for attr in ("CA", "CL"):
        e = sp.sympify(getattr(sea, attr)).xreplace(subs)
        leftover = e.free_symbols - {S, lam}
        if leftover:
            raise ParameterError(
                "controller has parameters without values: " + ", ".join(sorted(map(str, leftover)))
            )
        polys, sp_ = _discretize(e, lam, T, loop.method, loop.velocity_filter)
        if loop.delay:
            polys = ControllerPolys(tuple(p.left_shift(loop.delay) for p in polys.num), polys.den)
        parts.append(polys)
        special += sp_
    return ControllerFamily(parts[0], parts[1], tuple(sorted(_rational_roots(special, lam))))


def _z_family(sea: SEA, param: str, loop: SampledLoop) -> ControllerFamily:
    """A controller given in ``z`` with ``param`` free: its own coefficients, nothing discretized.

    ``z = 1/q``; the special values are the rational roots of the constant term of the
    denominator (not causal there) and of the resultant (a factor cancels).
    """
    zc = sea.discrete
    zc.check_loop(loop.period)
    lam = symbol(param)
    subs = {
        symbol(k): sp.Rational(to_fraction(v, k))
        for k, v in sea.values.items()
        if v is not None and k != param
    }
    z = symbol("z")
    parts, special = [], []
    for side in ("CA", "CL"):
        e = zc.symbolic(side).xreplace(subs)
        leftover = e.free_symbols - {z, lam}
        if leftover:
            raise ParameterError(
                "controller has parameters without values: " + ", ".join(sorted(map(str, leftover)))
            )
        num, den = sp.fraction(sp.cancel(sp.together(e)))
        n = max(sp.Poly(num, z).degree(), sp.Poly(den, z).degree(), 0)
        nq = sp.expand(num.xreplace({z: 1 / _Q}) * _Q**n)
        dq = sp.expand(den.xreplace({z: 1 / _Q}) * _Q**n)
        if sp.expand(dq.subs(_Q, 0)) == 0:
            raise ParameterError(f"{side}_z is not causal for any value of {param}")
        pn, pd, sp_ = _in_q(nq / dq, lam)
        if loop.delay:
            pn = [p.left_shift(loop.delay) for p in pn]
        parts.append(ControllerPolys(tuple(pn), tuple(pd)))
        special += sp_
    return ControllerFamily(parts[0], parts[1], tuple(sorted(_rational_roots(special, lam))))
