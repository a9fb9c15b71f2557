"""The elements of a model as given: validation, sources, exact and sympy forms.

An element (``D1``, ``C_A``, ``m``, a coefficient of a raw ``Z``) is given as text, a
number or a sympy expression.  `element_source` validates it (text through the
parser's whitelist) and returns its *source*, a hashable form the caches key on:
``("text", stripped text)``, ``("number", Fraction)`` or ``("sympy", expression)``.
`exact_of` turns a source into an exact rational function
([`seapass.model.rational`][seapass.model.rational]; no sympy); `sympy_of` into a
sympy expression, which the `LazySympy` descriptor builds on first access, so the
numeric path never imports sympy.

What lives here: sources and their two forms, the checks of parameter values.
May import: [`seapass.errors`][seapass.errors] and the modules of
[`seapass.model`][seapass.model] below it (`expr`, `rational`).
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping
from fractions import Fraction
from types import MappingProxyType
from typing import Any, TypeAlias

from flint import fmpq

from ..errors import ExpressionError, ParameterError, did_you_mean
from .expr import check_name, exact_expression, parse_tree, to_fraction, tree_names
from .rational import RatFunc, context, variables

__all__ = [
    "LazySympy",
    "Source",
    "check_used",
    "element_source",
    "exact_of",
    "exact_values",
    "freeze_values",
    "is_sympy",
    "poly_names",
    "source_names",
    "sympy_of",
]

# A source is what an element was given as, in a hashable form that the caches key on:
# ("text", stripped text), ("number", Fraction) or ("sympy", validated expression).
Source: TypeAlias = tuple[str, Any]


def is_sympy(value: Any) -> bool:
    return type(value).__module__.startswith("sympy")


def element_source(value: Any, allowed: frozenset[str], what: str) -> Source:
    """Validate an element as given; return its source."""
    if isinstance(value, str):
        try:
            parse_tree(value, allowed)
        except ExpressionError as exc:
            raise ExpressionError(f"{what}: {exc}", argument=what) from None
        return ("text", value.strip())
    if isinstance(value, bool):
        raise ExpressionError(f"{what}: expected an expression, got a boolean")
    if isinstance(value, int | float | Fraction):
        return ("number", to_fraction(value, what))
    from .symbolic import check_sympy_input

    return ("sympy", _checked_sympy(value, allowed, what, check_sympy_input))


@functools.lru_cache(maxsize=1024)
def _checked_sympy(value: Any, allowed: frozenset[str], what: str, check: Any) -> Any:
    """Validation of sympy input is pure, so it is cached (models are rebuilt often)."""
    return check(value, allowed, what)


def exact_of(source: Source, allowed: frozenset[str], what: str) -> RatFunc:
    """The exact rational function of a source, in the context of its own names."""
    kind, value = source
    if kind == "text":
        return exact_expression(value, allowed)
    if kind == "number":
        return RatFunc.constant(context(variables(())), value)
    return _exact_sympy(value, what)


@functools.lru_cache(maxsize=1024)
def _exact_sympy(expr: Any, what: str) -> RatFunc:
    from .symbolic import exact_from_sympy

    return exact_from_sympy(expr, what)


def sympy_of(source: Source, allowed: frozenset[str]) -> Any:
    """The sympy expression of a source (imports sympy)."""
    kind, value = source
    if kind == "text":
        from .expr import parse_expression

        return parse_expression(value, allowed)
    if kind == "number":
        import sympy as sp

        return sp.Rational(value)
    return value


class LazySympy:
    """A data descriptor for an element field of a frozen dataclass.

    Assigning stores the value as given; reading returns its sympy expression,
    built on first access (the numeric path never reads it, so never imports sympy).
    """

    def __init__(self, default: Any) -> None:
        self.default = default
        self.name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, obj: Any, objtype: Any = None) -> Any:
        if obj is None:
            return self.default
        state = obj.__dict__
        key = f"_sympy_{self.name}"
        if key not in state:
            state[key] = sympy_of(state[f"_source_{self.name}"], state["_allowed"])
        return state[key]

    def __set__(self, obj: Any, value: Any) -> None:
        obj.__dict__[f"_given_{self.name}"] = value


def freeze_values(values: Mapping[str, Any] | None) -> Mapping[str, float | None]:
    """``values`` checked (names, finite numbers or None) and frozen."""
    if values is not None and not isinstance(values, Mapping):
        raise ParameterError(
            f"values: expected a mapping of names to numbers, got {type(values).__name__}",
            argument="values",
        )
    out: dict[str, float | None] = {}
    for name, val in (values or {}).items():
        if not isinstance(name, str):
            raise ParameterError(
                f"values: parameter names must be strings, got {name!r}", argument="values"
            )
        key = f"values[{name!r}]"
        try:
            check_name(name)
        except ExpressionError as exc:
            raise ParameterError(f"{key}: {exc}", argument=key) from None
        out[name] = None if val is None else float(to_fraction(val, key))
    return MappingProxyType(out)


def exact_values(values: Mapping[str, float | None]) -> dict[str, fmpq]:
    """The given values as exact rationals (floats convert exactly); free names left out."""
    out = {}
    for k, v in values.items():
        if v is not None:
            q = to_fraction(v, k)
            out[k] = fmpq(q.numerator, q.denominator)
    return out


def source_names(source: Source, allowed: frozenset[str]) -> frozenset[str]:
    """The parameter names an element uses *as written* (before anything cancels).

    ``k*s/(k*s + k)`` uses ``k`` although ``k`` cancels from it, as sympy's free
    symbols of the expression say; a value given for ``k`` is therefore not a typo.
    """
    kind, value = source
    if kind == "text":
        return tree_names(parse_tree(value, allowed))
    if kind == "number":
        return frozenset()
    return frozenset(str(x) for x in value.free_symbols) - {"s"}  # Delay(tau) holds tau


def poly_names(p: Any) -> set[str]:
    """The variables a polynomial depends on."""
    return {n for n, d in zip(p.context().names(), p.degrees(), strict=True) if d > 0}


def check_used(values: Mapping[str, Any], used: Iterable[str], what: str = "the model") -> None:
    """Raise if a name in ``values`` is not a parameter of the model (a typo, usually).

    The message names the Python argument (``values['kdd']``) and the closest
    parameter the model does use.
    """
    used = sorted(used)
    for name in values:
        if name not in used:
            key = f"values[{name!r}]"
            raise ParameterError(
                f"{key}: {name!r} is not a parameter of {what}{did_you_mean(name, used)}; "
                f"it uses {', '.join(used) or 'no parameters'}",
                argument=key,
            )
