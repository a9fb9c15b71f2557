"""Exact necessary-and-sufficient passivity conditions in symbolic form.

For a model whose parameters are left symbolic (all assumed strictly
positive), `exact_passivity_condition` returns the conditions of the
positive-real test as a sympy boolean:

* stability: the Routh first column of ``D(s)/s^k`` (``k`` generic poles at 0);
* the pole at ``s = 0``: simple, with a positive residue (the static stiffness);
* the relative degree, and the sign at ``s = ∞`` when ``Z ~ c s``;
* ``P(x) = Re N(jω) D(−jω) ≥ 0`` on ``x = ω² ≥ 0``.  With ``P = x^k Q(x)``:
  for ``deg Q ≤ 2`` the condition is ``q2 ≥ 0 ∧ q0 ≥ 0 ∧ (q1 ≥ 0 ∨ 4 q2 q0 − q1² ≥ 0)``,
  i.e. ``q1 ≥ −2√(q2 q0)``;
  for ``deg Q = 3`` it is the sign of ``Q`` at its larger critical point.

Atoms that are provably true or false for positive parameters are decided
and removed.  Conditions are *generic*: they hold outside a measure-zero set
of parameter values (e.g. where a leading coefficient vanishes); the numeric
test [`seapass.analysis.passivity.is_passive`][seapass.analysis.passivity.is_passive] is exact everywhere.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp
from sympy.logic.boolalg import Boolean

from ..errors import SymbolicLimitError
from ..model.budget import symbolic_time_limit
from ..model.expr import S, W
from ..model.sea import SEA, Impedance
from ..model.stiffness import load_impedance, num_den, real_part_polynomial

__all__ = ["ExactCondition", "exact_passivity_condition", "nonnegative_on_halfline"]

_X = sp.Symbol("x", nonnegative=True)
MAX_OPS = 20000


@dataclass(frozen=True, kw_only=True)
class ExactCondition:
    """Symbolic exact passivity condition.

    Attributes
    ----------
    real_part : sympy.Expr
        ``P`` as a polynomial in ``w`` (ω), collected by powers.
    real_part_condition : sympy.Boolean
        ``P(ω) ≥ 0 ∀ω``, exactly.
    pole_conditions : sympy.Boolean
        Stability, simple pole at 0 with positive residue, relative degree.
    condition : sympy.Boolean
        Conjunction of both, simplified for positive parameters.
    explicit : bool
        False when the real-part condition had to be left implicit (degree > 3 in ``x``).
    """

    real_part: sp.Expr
    real_part_condition: Boolean
    pole_conditions: Boolean
    condition: Boolean
    explicit: bool = True

    def to_dict(self) -> dict[str, Any]:
        return {
            "real_part": str(self.real_part),
            "real_part_condition": str(self.real_part_condition),
            "pole_conditions": str(self.pole_conditions),
            "condition": str(self.condition),
            "explicit": self.explicit,
        }


def _sign(e: sp.Expr) -> int | None:
    """+1/-1/0 when provable for positive symbols, else None."""
    e = sp.factor(sp.together(sp.expand(e)))
    if e == 0:
        return 0
    if e.is_positive:
        return 1
    if e.is_negative:
        return -1
    num, den = sp.fraction(e)
    sd = 1 if den.is_positive else (-1 if den.is_negative else None)
    if sd is None:
        return None
    sn = 1 if sp.expand(num).is_positive else (-1 if sp.expand(num).is_negative else None)
    return None if sn is None else sn * sd


def _strip(e: sp.Expr) -> tuple[sp.Expr, int]:
    """Remove factors of provable sign; return the rest and the product of removed signs."""
    e = sp.factor(sp.together(e))
    sign = 1
    keep = []
    for f in sp.Mul.make_args(e):
        s_ = _sign(f)
        if s_ in (1, -1):
            sign *= s_
        else:
            keep.append(f)
    return sp.Mul(*keep), sign


def _ge0(e: sp.Expr, strict: bool = False) -> Boolean:
    """``e >= 0`` (or ``> 0``), decided where provable, else with known factors removed."""
    s_ = _sign(e)
    if s_ is not None:
        return sp.true if (s_ > 0 or (s_ == 0 and not strict)) else sp.false
    rest, sign = _strip(e)
    if sign < 0:
        rest = -rest
    rest = sp.expand(rest) if len(sp.Add.make_args(sp.expand(rest))) <= 12 else rest
    return sp.Gt(rest, 0) if strict else sp.Ge(rest, 0)


def _or_linear(left: sp.Expr, right: sp.Expr) -> bool:
    """Prove ``left >= 0 or right >= 0`` for all positive parameter values when both are
    linear in one shared parameter with opposite slopes and the half-lines overlap."""
    for v in sorted(left.free_symbols & right.free_symbols, key=str):
        pl, pr = sp.Poly(sp.expand(left), v), sp.Poly(sp.expand(right), v)
        if pl.degree() != 1 or pr.degree() != 1:
            continue
        (l1, l0), (r1, r0) = pl.all_coeffs(), pr.all_coeffs()
        if v in (l1 * r1).free_symbols:
            continue
        sl, sr = _sign(l1), _sign(r1)
        if sl == -1 and sr == 1:
            up, down = -l0 / l1, -r0 / r1  # left holds for v <= up, right for v >= down
        elif sl == 1 and sr == -1:
            up, down = -r0 / r1, -l0 / l1
        else:
            continue
        if _sign(up - down) in (1, 0):
            return True
    return False


def nonnegative_on_halfline(coeffs: list[sp.Expr]) -> tuple[Boolean, bool]:
    """Exact condition for ``Σ c_i x^i >= 0`` for all ``x >= 0`` (ascending ``coeffs``).

    Returns the condition and whether it is explicit.
    """
    c = list(coeffs)
    while c and sp.expand(c[-1]) == 0:
        c.pop()
    if not c:
        return sp.true, True
    k = 0
    while sp.expand(c[k]) == 0:
        k += 1
    q = c[k:]
    n = len(q) - 1
    lead, q0 = q[-1], q[0]
    base = sp.And(_ge0(lead), _ge0(q0))
    if n <= 1:
        return sp.And(base, _ge0(q[1]) if n == 1 else sp.true), True
    if n == 2:
        q1 = q[1]
        if _sign(q1) in (1, 0):
            return base, True
        disc = sp.expand(4 * lead * q0 - q1**2)
        if _sign(disc) in (1, 0) or _or_linear(q1, disc):
            return base, True
        # q1 + 2*sqrt(q2*q0) >= 0, written without radicals (q2, q0 >= 0 hold by `base`)
        return sp.And(base, sp.Or(_ge0(q1), _ge0(disc))), True
    if n == 3:
        a, c2, c1 = lead, q[2], q[1]
        if _sign(c2) in (1, 0) and _sign(c1) in (1, 0):
            return base, True
        d = sp.expand(c2**2 - 3 * a * c1)
        xs = (-c2 + sp.sqrt(sp.Max(d, 0))) / (3 * a)  # real even where the d <= 0 branch holds
        qx = a * xs**3 + c2 * xs**2 + c1 * xs + q0
        return sp.And(base, sp.Or(sp.Le(d, 0), sp.Le(xs, 0), sp.Ge(qx, 0))), True
    return base, False


def _routh_first_column(desc: list[sp.Expr]) -> list[sp.Expr]:
    n = len(desc) - 1
    rows = [desc[0::2], desc[1::2]]
    for _ in range(n - 1):
        a, b = rows[-2], rows[-1]
        if not b or sp.expand(b[0]) == 0:
            raise SymbolicLimitError("Routh array has a generic zero pivot; use the numeric test")
        new = []
        for i in range(len(a) - 1):
            bi1 = b[i + 1] if i + 1 < len(b) else 0
            new.append(sp.cancel((b[0] * a[i + 1] - a[0] * bi1) / b[0]))
        rows.append(new)
    return [r[0] for r in rows[: n + 1]]


def exact_passivity_condition(system: SEA | Impedance) -> ExactCondition:
    """Exact symbolic passivity condition of an SEA (or raw impedance), parameters positive.

    Parameters
    ----------
    system : SEA or Impedance
        Parameter values, if any, are ignored: the result is symbolic.

    Returns
    -------
    ExactCondition

    Raises
    ------
    SymbolicLimitError
        If the expressions exceed the size budget (``MAX_OPS`` operations) or the
        derivation runs longer than [`SYMBOLIC_TIME_LIMIT`][seapass.files.limits.SYMBOLIC_TIME_LIMIT] seconds.
    """
    with symbolic_time_limit(what="symbolic passivity condition"):
        return _exact_condition(system)


def _exact_condition(system: SEA | Impedance) -> ExactCondition:
    z = load_impedance(system) if isinstance(system, SEA) else system.expr
    if sp.count_ops(z) > MAX_OPS:
        raise SymbolicLimitError(
            f"impedance expression too large for symbolic analysis (> {MAX_OPS} ops)"
        )
    num, den = num_den(z)
    pn, pd = sp.Poly(num, S), sp.Poly(den, S)
    conds: list[Boolean] = []
    rel = pd.degree() - pn.degree()
    if rel not in (-1, 0, 1):
        conds.append(sp.false)
    elif rel == -1:
        conds.append(_ge0(pn.LC() / pd.LC(), strict=True))
    dc = pd.all_coeffs()[::-1]
    k = 0
    while sp.expand(dc[k]) == 0:
        k += 1
    if k >= 2:
        conds.append(sp.false)
    elif k == 1:
        conds.append(_ge0(num.subs(S, 0) / dc[1], strict=True))
    rest = dc[k:][::-1]
    if len(rest) > 1:
        conds += [_ge0(c, strict=True) for c in _routh_first_column([sp.expand(c) for c in rest])]
    pole = sp.And(*conds)
    pw = real_part_polynomial(z)
    px = sp.Poly(sp.expand(pw), W)
    coeffs = [px.coeff_monomial(W ** (2 * i)) for i in range(px.degree() // 2 + 1)]
    re_cond, explicit = nonnegative_on_halfline(coeffs)
    total = sp.And(pole, re_cond)
    return ExactCondition(
        real_part=sp.collect(sp.expand(pw), W, sp.factor),
        real_part_condition=re_cond,
        pole_conditions=pole,
        condition=total,
        explicit=explicit,
    )
