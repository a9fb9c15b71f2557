"""The exact structure of a delayed impedance: ``Z = N(s, E)/D(s, E)`` with ``E = e^{-sτ}``.

The parser turns ``exp(-tau*s)`` into the atom ``Delay(tau)``
([`seapass.model.delayatom`][seapass.model.delayatom]); the free-body derivation treats
it as a constant generator.  Here it becomes the symbol ``E`` and the impedance a quotient
of two polynomials in ``s`` and ``E`` with exact rational coefficients, kept as the
tuples ``N_k(s)``, ``D_k(s)`` of the powers ``E^k`` (`DelayedImpedance`).

Refused clearly (`DelayError`): two different delays, a prediction ``e^{+sτ}`` (the
denominator vanishes at ``E = 0``), a delay parameter that is negative or beyond
`MAX_DELAY_SECONDS`.

Examples
--------
>>> z = delayed_impedance("m*s + b + K*exp(-tau*s)/s", values=dict(m=1, b=2, K=50, tau=0.01))
>>> z.name, z.tau, [str(p) for p in z.num], [str(p) for p in z.den]
('tau', 1/100, ['x^2 + 2*x', '50'], ['x'])
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, TypeAlias

import sympy as sp
from flint import fmpq, fmpq_poly

from ..errors import DelayError, ParameterError
from ..exact import poly as ep
from ..files.limits import MAX_DELAY_SECONDS
from ..model.delayatom import Delay, delay_atoms
from ..model.expr import S, to_fraction
from ..model.sea import SEA, Impedance
from ..model.stiffness import load_impedance

__all__ = [
    "MAX_DELAY_SECONDS",
    "DelayedImpedance",
    "controller_delay",
    "delay_parameter",
    "delayed_impedance",
    "has_model_delay",
    "model_expression",
]


_E = sp.Symbol("E_delay")  # the generator E = e^{-sτ}; never a user name (underscore)

SystemLike: TypeAlias = SEA | Impedance | str | sp.Expr


@dataclass(frozen=True, kw_only=True)
class DelayedImpedance:
    """``Z(s) = Σ_k N_k(s) E^k / Σ_k D_k(s) E^k`` with ``E = e^{-sτ}``, exactly.

    Attributes
    ----------
    name : str
        The delay parameter (``"tau"``).
    tau : flint.fmpq or None
        Its value in seconds (exact), or None when it is left free (a delay margin).
    num, den : tuple of flint.fmpq_poly
        ``N_k`` and ``D_k`` in ascending powers of ``E``; ``D_0 ≠ 0`` and the leading
        coefficient of the delay-free part is positive.
    """

    name: str
    tau: fmpq | None
    num: tuple[fmpq_poly, ...]
    den: tuple[fmpq_poly, ...]
    label: str = field(default="", compare=False)

    @property
    def order(self) -> int:
        """Highest power of ``E`` in ``N`` or ``D``."""
        return max(len(self.num), len(self.den)) - 1

    def at(self, e_value: fmpq) -> tuple[fmpq_poly, fmpq_poly]:
        """``N(s, e)`` and ``D(s, e)`` for a rational ``e`` (``e = 1`` is the delay-free loop)."""
        return _collapse(self.num, e_value), _collapse(self.den, e_value)

    def with_tau(self, tau: Any) -> DelayedImpedance:
        """The same impedance at another delay (seconds, a rational or float)."""
        return DelayedImpedance(
            name=self.name, tau=check_tau(tau, self.name), num=self.num, den=self.den,
            label=self.label,
        )  # fmt: skip

    def __repr__(self) -> str:
        return f"DelayedImpedance(name={self.name!r}, tau={self.tau}, order={self.order})"


def _collapse(parts: Sequence[fmpq_poly], e_value: fmpq) -> fmpq_poly:
    out = fmpq_poly([])
    for k, p in enumerate(parts):
        out += p * e_value**k
    return out


def check_tau(value: Any, name: str) -> fmpq:
    """An exact delay in ``[0, MAX_DELAY_SECONDS]`` from a number, or a `ParameterError`.

    A float is the decimal it was written as (``0.001`` is ``1/1000``).
    """
    key = f"values[{name!r}]"
    if isinstance(value, fmpq):
        q = value
    else:
        exact = to_fraction(value, key)  # raises for nan, inf, booleans and non-numbers
        # a float delay is the decimal it was written as (0.001 is 1/1000), as the
        # sampled period is; Fractions and ints stay exact
        q = ep.rational(Fraction(repr(float(value))) if isinstance(value, float) else exact)
    if q < 0:
        raise ParameterError(
            f"{key}: a delay must be >= 0 s, got {float(q):g}; exp(-{name}*s) with "
            f"{name} < 0 is a prediction",
            argument=key,
        )
    if q > fmpq(int(MAX_DELAY_SECONDS)):
        raise ParameterError(
            f"{key}: a delay of {float(q):g} s is beyond the limit of {MAX_DELAY_SECONDS:g} s "
            f"(delays are in seconds: 1 ms is {name}=0.001)",
            argument=key,
        )
    return q


def model_expression(system: SystemLike) -> tuple[sp.Expr, Mapping[str, float | None]]:
    """The symbolic impedance of ``system`` (``Z_L`` of an SEA) and its stored values."""
    if isinstance(system, str | sp.Expr):
        system = Impedance(expr=system, values=_declare(system))
    if isinstance(system, SEA):
        return load_impedance(system), system.values
    if isinstance(system, Impedance):
        return system.expr, system.values
    raise TypeError(f"expected an SEA, an Impedance or an expression, got {type(system).__name__}")


def _declare(expr: str | sp.Expr) -> dict[str, float | None]:
    """Names of a raw expression, declared free (so that they parse) - values come later."""
    if isinstance(expr, sp.Expr):
        return {str(x): None for x in expr.free_symbols if x != S}
    import ast

    try:
        tree = ast.parse(expr.replace("^", "**"), mode="eval")
    except SyntaxError:
        return {}
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    return {n: None for n in names - {"s", "exp"} if n.isidentifier() and not n.startswith("_")}


def has_model_delay(system: Any) -> bool:
    """True if ``system`` (an SEA, Impedance or expression) contains a delay factor."""
    if isinstance(system, SEA):
        return any(delay_atoms(getattr(system, a)) for a in ("D1", "D2", "CA", "CL"))
    if isinstance(system, Impedance):
        return bool(delay_atoms(system.expr))
    if isinstance(system, sp.Expr):
        return bool(delay_atoms(system))
    if isinstance(system, str):
        return "exp" in system
    return False


def delay_parameter(expr: sp.Expr) -> str:
    """The one delay parameter of ``expr``; `DelayError` for none or for two."""
    names = sorted({str(a.args[0]) for a in delay_atoms(expr)})
    if not names:
        raise DelayError("the model has no delay: write one as exp(-NAME*s), e.g. 'kd*exp(-tau*s)'")
    if len(names) > 1:
        raise DelayError(
            f"two different delays ({', '.join(names)}); seapass supports one delay parameter "
            "per model: exp(-NAME*s) and its whole multiples exp(-2*NAME*s)"
        )
    return names[0]


def delayed_impedance(
    system: SystemLike,
    values: Mapping[str, float | None] | None = None,
    *,
    free_delay: bool = False,
) -> DelayedImpedance:
    """Exact ``N(s, E)`` and ``D(s, E)`` of a delayed ``system`` at its parameter values.

    Parameters
    ----------
    system : SEA, Impedance, str or sympy.Expr
        The design (its load impedance ``Z_L``) or a raw impedance with one delay factor.
    values : mapping, optional
        Values overriding the stored ones (also the delay, in seconds).
    free_delay : bool, default False
        Leave the delay without a value (``tau`` is then None): a delay margin.

    Raises
    ------
    DelayError
        No delay, two different delays, or a prediction ``e^{+sτ}``.
    ParameterError
        A missing value, or a delay that is negative or beyond `MAX_DELAY_SECONDS`.
    """
    expr, stored = model_expression(system)
    name = delay_parameter(expr)
    merged: dict[str, float | None] = dict(stored)
    merged.update(values or {})
    others = sorted(str(x) for x in expr.free_symbols if x != S and str(x) != name)
    missing = [n for n in others if merged.get(n) is None]
    if missing:
        raise ParameterError(
            f"no value for parameter(s) {', '.join(missing)}: give them, "
            f"e.g. values={{{missing[0]!r}: 1.0}}"
        )
    tau: fmpq | None = None
    if not free_delay:
        if merged.get(name) is None:
            raise ParameterError(
                f"no value for the delay {name}: give it in seconds, e.g. values={{{name!r}: 0.001}}"
            )
        tau = check_tau(merged[name], name)
    else:
        merged.pop(name, None)
    names, num_terms, den_terms = _compiled(expr, name)
    env = [ep.rational(to_fraction(merged[n], n)) for n in names]  # type: ignore[arg-type,unused-ignore]
    num = _evaluate(num_terms, env)
    den = _evaluate(den_terms, env)
    num, den = _normalized(num, den)
    return DelayedImpedance(name=name, tau=tau, num=num, den=den, label=getattr(system, "name", ""))


_Terms = tuple[tuple[int, int, tuple[int, ...], fmpq], ...]


@functools.lru_cache(maxsize=256)
def _compiled(expr: sp.Expr, name: str) -> tuple[tuple[str, ...], _Terms, _Terms]:
    """Coefficients of ``s^i E^k`` of ``N`` and ``D`` as exact polynomials in the parameters."""
    z = expr.xreplace({a: _E for a in delay_atoms(expr)})
    num, den = sp.fraction(sp.cancel(sp.together(z)))
    params = sorted((x for x in (num.free_symbols | den.free_symbols) if x not in (S, _E)), key=str)
    if any(str(x) == name for x in params):
        raise DelayError(
            f"the delay parameter {name} also appears outside exp(-{name}*s); give that "
            "quantity its own parameter"
        )

    def terms(e: sp.Expr) -> _Terms:
        poly = sp.Poly(sp.expand(e), S, _E, *params, domain="QQ")
        out = []
        for mon, c in zip(poly.monoms(), poly.coeffs(), strict=True):
            out.append((int(mon[0]), int(mon[1]), tuple(mon[2:]), fmpq(int(c.p), int(c.q))))
        return tuple(out)

    return tuple(str(x) for x in params), terms(num), terms(den)


def _evaluate(terms: _Terms, env: list[fmpq]) -> tuple[fmpq_poly, ...]:
    coeffs: dict[tuple[int, int], fmpq] = {}
    for i, k, mon, q in terms:
        t = q
        for v, e in zip(env, mon, strict=False):
            if e:
                t *= v**e
        coeffs[(i, k)] = coeffs.get((i, k), fmpq(0)) + t
    order = max((k for (_, k) in coeffs), default=0)
    out = []
    for k in range(order + 1):
        deg = max((i for (i, kk) in coeffs if kk == k), default=-1)
        out.append(fmpq_poly([coeffs.get((i, k), fmpq(0)) for i in range(deg + 1)]))
    return tuple(out)


def _normalized(
    num: tuple[fmpq_poly, ...], den: tuple[fmpq_poly, ...]
) -> tuple[tuple[fmpq_poly, ...], tuple[fmpq_poly, ...]]:
    """Trim zero top powers of ``E``, cancel a common power of ``E``, and sign-normalize."""

    def trim(parts: tuple[fmpq_poly, ...]) -> tuple[fmpq_poly, ...]:
        p = list(parts)
        while len(p) > 1 and p[-1].is_zero():
            p.pop()
        return tuple(p)

    num, den = trim(num), trim(den)
    if all(p.is_zero() for p in den):
        raise ParameterError("the impedance has a zero denominator for these values")
    while den[0].is_zero() and (num[0].is_zero() or all(p.is_zero() for p in num)):
        num, den = (num[1:] or (fmpq_poly([]),)), den[1:]
    if den[0].is_zero():
        raise DelayError(
            "the model contains exp(+NAME*s) (a delay in a denominator that does not cancel): "
            "that is a prediction, not a delay; seapass supports delays exp(-NAME*s) only"
        )
    if all(p.is_zero() for p in num):
        num = (fmpq_poly([]),)
    lead = den[0].leading_coefficient()
    if lead < 0:
        num, den = tuple(-p for p in num), tuple(-p for p in den)
    return num, den


def controller_delay(
    design: Any, delay: str, values: Mapping[str, float | None] | None = None
) -> SEA:
    """The design with the delay ``exp(-delay*s)`` on its controllers (if it has none yet).

    ``design`` is an `SEA`, a catalog key (``"LP"``, ``"APD"``, ``"ours"``: the paper's
    plant ``m = 1, b = 10, k1 = 1000`` with the gains from ``values``), a
    `CatalogDesign` or a design file's `Design`.  A design that already has the delay
    ``delay`` is returned as it is; the delay's own value is left free.  The controllers
    ``C_A`` and ``C_L`` both act on measured positions, so both are delayed (a loop
    latency: bus, computation, a remote master).

    Examples
    --------
    >>> controller_delay("LP", "tau", dict(kd=500)).CL
    kd*exp(-tau*s)
    """
    from ..model.catalog import PAPER_VALUES, CatalogDesign
    from ..model.catalog import design as catalog_design
    from ..model.design_file import Design

    if isinstance(design, str):
        design = catalog_design(design)
    extra = dict(values or {})
    if isinstance(design, CatalogDesign):
        base: dict[str, float | None] = {g: None for g in design.gains}
        base.update(PAPER_VALUES)
        base.update(extra)
        sea = SEA(D1=design.D1, D2=design.D2, CA=design.CA, CL=design.CL, values=base,
                  name=design.key)  # fmt: skip
    elif isinstance(design, Design):
        sea = design.sea().with_values(**extra) if extra else design.sea()
    elif isinstance(design, SEA):
        sea = design.with_values(**extra) if extra else design
    else:
        raise TypeError(
            f"design: expected an SEA, a Design or a catalog name, got {type(design).__name__}"
        )
    names = {
        str(a.args[0]) for attr in ("D1", "D2", "CA", "CL") for a in delay_atoms(getattr(sea, attr))
    }
    if names:
        if names != {delay}:
            raise DelayError(
                f"the design's delay is exp(-{sorted(names)[0]}*s), not exp(-{delay}*s); "
                "give that name"
            )
        return sea
    if delay in sea.parameters:
        raise ParameterError(
            f"delay: {delay!r} is already a parameter of the design; name the delay "
            "something else, e.g. 'tau'",
            argument="delay",
        )
    if sea.CA == 0 and sea.CL == 0:
        raise DelayError("the design has no controller to delay; write the delay into an element, e.g. --CA 'kd*exp(-tau*s)'")  # fmt: skip
    e = Delay(sp.Symbol(delay, positive=True))
    vals = dict(sea.values)
    vals[delay] = None
    return SEA(D1=sea.D1, D2=sea.D2, CA=sea.CA * e, CL=sea.CL * e, m=sea.m, b=sea.b,
               values=vals, name=sea.name)  # fmt: skip
