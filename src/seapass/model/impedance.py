"""A raw rational impedance ``Z(s)``: an environment or a load given as one transfer function.

`Impedance` holds ``Z`` as given (text, sympy, or coefficient lists), its exact form
(`Impedance.exact`, on flint, no sympy) and, built on first use, its sympy form.  The
SEA model is [`seapass.model.sea`][seapass.model.sea].

May import: [`seapass.errors`][seapass.errors] and the modules of this package below it.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from ..errors import DegenerateModelError, ExpressionError
from .delayatom import delay_of_variable
from .display import html_card, short_repr
from .elements import (
    LazySympy,
    Source,
    check_used,
    element_source,
    exact_of,
    freeze_values,
    is_sympy,
    source_names,
    sympy_of,
)
from .expr import STANDARD_SYMBOLS, to_fraction
from .rational import RatFunc, context, variables

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["Impedance"]


class _ImpedanceExpr(LazySympy):
    """The ``expr`` field of `Impedance`: reading it gives the cancelled sympy ``Z``."""

    def __init__(self) -> None:
        super().__init__(None)

    def __get__(self, obj: Any, objtype: Any = None) -> Any:
        if obj is None:
            return self.default
        state = obj.__dict__
        if "_sympy_expr" not in state:
            state["_sympy_expr"] = _impedance_sympy(obj)
        return state["_sympy_expr"]


@dataclass(frozen=True, repr=False)
class Impedance:
    """A raw rational impedance ``Z(s)`` with optional parameter values.

    Give either ``expr`` (text or sympy) or ``num`` and ``den``.  Coefficient
    sequences for ``num``/``den`` are in *descending* powers of ``s``, as in
    numpy and python-control.
    """

    expr: Any = _ImpedanceExpr()
    num: Any = None
    den: Any = None
    values: Mapping[str, float | None] = field(default_factory=dict)

    def __post_init__(self) -> None:
        vals = freeze_values(self.values)
        object.__setattr__(self, "values", vals)
        state = self.__dict__
        allowed = frozenset(STANDARD_SYMBOLS) | frozenset(vals)
        state["_allowed"] = allowed
        given = state.get("_given_expr")
        if given is not None:
            if self.num is not None or self.den is not None:
                raise ExpressionError("give either expr or num/den, not both")
            sources: Any = ("expr", element_source(given, allowed, "Z"))
        else:
            if self.num is None or self.den is None:
                raise ExpressionError("give Z as an expression or as both num and den")
            sources = ("coeffs", _coefficients(self.num, allowed, "num"))
            sources += (_coefficients(self.den, allowed, "den"),)
        state["_sources"] = sources
        state["_given"] = (given, self.num, self.den)
        # before cancelling: a parameter that cancels out was still used
        check_used(vals, _impedance_parts(sources, allowed)[1], "Z")
        left = _user_names(self.exact().parameters())
        if set(vals) - left:  # a parameter that cancelled out no longer matters
            object.__setattr__(
                self, "values", MappingProxyType({k: v for k, v in vals.items() if k in left})
            )
        object.__setattr__(self, "num", None)
        object.__setattr__(self, "den", None)

    def __reduce__(self) -> tuple[Any, ...]:
        expr, num, den = self.__dict__["_given"]
        return (_rebuild_impedance, (expr, num, den, dict(self.values)))

    def exact(self) -> RatFunc:
        """``Z`` as an exact rational function in lowest terms (no values substituted)."""
        return _impedance_parts(self.__dict__["_sources"], self.__dict__["_allowed"])[0]

    def sources(self) -> tuple[Any, ...]:
        """``Z`` as parsed, in a hashable form (cache keys)."""
        return tuple(self.__dict__["_sources"])

    def with_values(self, **values: float | None) -> Impedance:
        """A copy with some parameter values changed or added."""
        expr, num, den = self.__dict__["_given"]
        return Impedance(expr=expr, num=num, den=den, values={**self.values, **values})

    @property
    def parameters(self) -> tuple[str, ...]:
        return tuple(sorted(_user_names(self.exact().parameters())))

    @property
    def free_parameters(self) -> tuple[str, ...]:
        return tuple(p for p in self.parameters if self.values.get(p) is None)

    def substitutions(self) -> dict[sp.Symbol, sp.Rational]:
        import sympy as sp

        from .expr import symbol

        return {
            symbol(k): sp.Rational(to_fraction(v, k))
            for k, v in self.values.items()
            if v is not None
        }

    def to_control(self) -> Any:
        """``Z(s)`` as a ``control.TransferFunction`` (input ``v``, output ``F``)."""
        from .pycontrol import impedance_transfer_function

        return impedance_transfer_function(self)

    @classmethod
    def from_control(cls, system: Any) -> Impedance:
        """An `Impedance` from a SISO continuous-time ``control.TransferFunction`` or ``StateSpace``.

        The float coefficients are taken as the exact rationals they represent.

        Examples
        --------
        >>> import control
        >>> Impedance.from_control(control.tf([1, 1], [1, 2]))
        Impedance(Z='(s + 1)/(s + 2)')
        """
        from .pycontrol import impedance_from_control

        return impedance_from_control(system)

    def __repr__(self) -> str:
        return short_repr("Impedance", {"Z": str(self.expr), "values": dict(self.values) or None})

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [("Z(s)", str(self.expr))]
        rows += [(k, "free" if v is None else v) for k, v in self.values.items()]
        return html_card("Impedance", rows)


def _user_names(names: frozenset[str]) -> frozenset[str]:
    """Parameter names as a user writes them: the delay variable ``_E_tau`` is ``tau``."""
    return frozenset(delay_of_variable(n) or n for n in names)


def _coefficients(coeffs: Any, allowed: frozenset[str], what: str) -> tuple[Source, ...]:
    """Sources of a coefficient sequence (descending powers), or of one expression."""
    if isinstance(coeffs, str) or is_sympy(coeffs):
        return (element_source(coeffs, allowed, what),)
    try:
        seq = list(coeffs)
    except TypeError:
        return (element_source(coeffs, allowed, what),)
    if not seq:
        raise ExpressionError(f"{what}: empty coefficient list")
    return tuple(element_source(c, allowed, f"{what}[{i}]") for i, c in enumerate(seq))


@functools.lru_cache(maxsize=512)
def _impedance_parts(
    sources: tuple[Any, ...], allowed: frozenset[str]
) -> tuple[RatFunc, frozenset[str]]:
    """``Z`` in lowest terms and the names its parts use before cancelling (cached)."""
    if sources[0] == "expr":
        whole = exact_of(sources[1], allowed, "Z")
        return whole, source_names(sources[1], allowed)
    parts = {
        what: [exact_of(src, allowed, f"{what}[{i}]") for i, src in enumerate(srcs)]
        for what, srcs in (("num", sources[1]), ("den", sources[2]))
    }
    names: set[str] = set()
    for src in (*sources[1], *sources[2]):
        names |= source_names(src, allowed)
    exact_names: set[str] = set()
    for fs in parts.values():
        for f in fs:
            exact_names |= f.parameters()
    ctx = context(variables(exact_names))
    s = RatFunc.variable(ctx, "s")
    total = {}
    for what, fs in parts.items():
        acc = RatFunc.constant(ctx, 0)
        for i, f in enumerate(fs):
            acc = acc + f.to_context(ctx) * s ** (len(fs) - 1 - i)
        total[what] = acc
    if total["den"].is_zero:
        raise DegenerateModelError("Z has a zero denominator")
    return total["num"] / total["den"], frozenset(names)


def _impedance_sympy(obj: Impedance) -> Any:
    """``Z`` as sympy, cancelled, exactly as it was built before the exact path existed."""
    import sympy as sp

    from .symbolic import S

    sources, allowed = obj.__dict__["_sources"], obj.__dict__["_allowed"]

    def poly(srcs: tuple[Source, ...]) -> Any:
        n = len(srcs) - 1
        return sp.Add(*[sympy_of(src, allowed) * S ** (n - i) for i, src in enumerate(srcs)])

    if sources[0] == "expr":
        z = sympy_of(sources[1], allowed)
    else:
        z = poly(sources[1]) / poly(sources[2])
    num, den = sp.fraction(sp.cancel(sp.together(z)))
    return num / den


def _rebuild_impedance(expr: Any, num: Any, den: Any, values: dict[str, Any]) -> Impedance:
    return Impedance(expr=expr, num=num, den=den, values=values)
