"""The exact structure of a delayed impedance: ``Z = N(s, E)/D(s, E)`` with ``E = e^{-sτ}``.

The parser turns ``exp(-tau*s)`` into the exact variable ``E``
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

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, TypeAlias

from flint import fmpq, fmpq_poly

from ..errors import DelayError, ParameterError
from ..exact import poly as ep
from ..files.limits import MAX_DELAY_SECONDS
from ..model.delayatom import delay_variable, model_delays
from ..model.expr import to_fraction
from ..model.freebody import exact_impedance
from ..model.rational import S_NAME
from ..model.sea import SEA, Impedance

__all__ = [
    "MAX_DELAY_SECONDS",
    "DelayedImpedance",
    "coefficients_in",
    "controller_delay",
    "delay_parameter",
    "delayed_impedance",
    "has_model_delay",
]


SystemLike: TypeAlias = "SEA | Impedance | str | Any"
"""An `SEA`, an `Impedance`, or a raw impedance as text or a sympy expression."""


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


def _as_model(system: SystemLike) -> SEA | Impedance:
    """``system`` as a model: a raw expression becomes an `Impedance` with its names free."""
    if isinstance(system, SEA | Impedance):
        return system
    if isinstance(system, str) or type(system).__module__.startswith("sympy"):
        return Impedance(expr=system, values=_declare(system))
    raise TypeError(f"expected an SEA, an Impedance or an expression, got {type(system).__name__}")


def _declare(expr: Any) -> dict[str, float | None]:
    """Names of a raw expression, declared free (so that they parse) - values come later."""
    if not isinstance(expr, str):  # sympy
        return {str(x): None for x in expr.free_symbols if str(x) != "s"}
    import ast

    try:
        tree = ast.parse(expr.replace("^", "**"), mode="eval")
    except SyntaxError:
        return {}
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    return {n: None for n in names - {"s", "exp"} if n.isidentifier() and not n.startswith("_")}


def has_model_delay(system: Any) -> bool:
    """True if ``system`` (an SEA, Impedance or expression) contains a delay factor."""
    if isinstance(system, SEA | Impedance):
        return bool(model_delays(system))
    if isinstance(system, str):
        return "exp" in system
    if type(system).__module__.startswith("sympy"):
        from ..model.symbolic import delay_atoms

        return bool(delay_atoms(system))
    return False


def delay_parameter(system: Any) -> str:
    """The one delay parameter of a model; `DelayError` for none or for two."""
    names = model_delays(system)
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

    The impedance comes from the exact free-body derivation
    ([`seapass.model.freebody`][seapass.model.freebody]; no sympy), in which the delay is
    the variable ``E``.

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
    model = _as_model(system)
    z = exact_impedance(model)
    name = delay_parameter(z)
    merged: dict[str, float | None] = dict(model.values)
    merged.update(values or {})
    evar = delay_variable(name)
    params = sorted(z.names() - {S_NAME, evar})
    if name in params:
        raise DelayError(
            f"the delay parameter {name} also appears outside exp(-{name}*s); give that "
            "quantity its own parameter"
        )
    missing = [n for n in params if merged.get(n) is None]
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
    env = {n: ep.rational(to_fraction(merged[n], n)) for n in params}  # type: ignore[arg-type,unused-ignore]
    num = _in_s_and_e(z.num, env, evar)
    den = _in_s_and_e(z.den, env, evar)
    num, den = _normalized(num, den)
    return DelayedImpedance(name=name, tau=tau, num=num, den=den, label=getattr(system, "name", ""))


def coefficients_in(
    p: Any, env: Mapping[str, fmpq], variables: Sequence[str]
) -> dict[tuple[int, ...], fmpq]:
    """The coefficients of ``p`` (an exact multivariate polynomial) by its powers of
    ``variables``, every other name replaced by its value in ``env``.

    The key of a coefficient is the tuple of exponents of ``variables``, in their order.
    """
    names = p.context().names()
    where = {n: i for i, n in enumerate(variables)}
    coeffs: dict[tuple[int, ...], fmpq] = {}
    for exps, c in zip(p.monoms(), p.coeffs(), strict=True):
        t = fmpq(c)
        key = [0] * len(variables)
        for n, e in zip(names, exps, strict=True):
            if not e:
                continue
            if n in where:
                key[where[n]] = e
            else:
                t *= env[n] ** e
        coeffs[tuple(key)] = coeffs.get(tuple(key), fmpq(0)) + t
    return coeffs


def _in_s_and_e(p: Any, env: Mapping[str, fmpq], evar: str) -> tuple[fmpq_poly, ...]:
    """``p(s, E, params)`` at the parameter values, as ``N_k(s)`` for ascending ``E^k``."""
    coeffs = coefficients_in(p, env, (S_NAME, evar))
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
    names = set(model_delays(sea))
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
    from ..model.zcontroller import continuous_only

    continuous_only(sea, "the delay margin")
    exact = sea.exact_elements()
    if exact["CA"].is_zero and exact["CL"].is_zero:
        raise DelayError("the design has no controller to delay; write the delay into an element, e.g. --CA 'kd*exp(-tau*s)'")  # fmt: skip
    from ..model.expr import check_name

    check_name(delay)
    vals = dict(sea.values)
    vals[delay] = None
    given = sea.describe()  # the elements as parseable text (sympy's printing)

    def delayed(text: str) -> str:
        return "0" if text == "0" else f"({text})*exp(-{delay}*s)"

    return SEA(D1=given["D1"], D2=given["D2"], CA=delayed(given["CA"]),
               CL=delayed(given["CL"]), m=given["m"], b=given["b"], values=vals,
               name=sea.name)  # fmt: skip
