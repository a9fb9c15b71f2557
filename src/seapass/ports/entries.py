"""Validated input of immittance matrices: parameter values, entries, square shapes.

Entries are safe text (through [`seapass.model.expr`][seapass.model.expr], never
``eval``), sympy expressions rational in ``s`` or numbers; each is cancelled for
all parameter values.  The number of ports is capped at load time
([`MAX_PORTS`][seapass.files.limits.MAX_PORTS]).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from types import MappingProxyType
from typing import Any

import sympy as sp

from ..errors import ExpressionError, ModelError, ParameterError
from ..files.limits import MAX_PORTS
from ..model.elements import check_used, freeze_values  # one values check for every model
from ..model.expr import (
    STANDARD_SYMBOLS,
    S,
    check_rational_in_s,
    parse_expression,
    to_fraction,
)
from .ratfunc import cancelled

__all__ = [
    "entry_parameters",
    "freeze_values",
    "merged_values",
    "no_values",
    "parse_entries",
    "parse_entry",
    "square_entries",
]


def no_values() -> Mapping[str, float | None]:
    """A read-only empty mapping of parameter values (the default of the port models)."""
    return MappingProxyType({})


def parse_entry(value: Any, allowed: set[str], what: str) -> sp.Expr:
    """One entry as a cancelled sympy expression (``what`` names it in errors, e.g. ``z12``)."""
    if isinstance(value, bool):
        raise ExpressionError(f"{what}: expected an expression, got a boolean", argument=what)
    if isinstance(value, str):
        try:
            expr = parse_expression(value, allowed)
        except ExpressionError as exc:
            raise ExpressionError(f"{what}: {exc}", argument=what) from None
    elif isinstance(value, int | float):
        expr = sp.Rational(to_fraction(value, what))
    elif isinstance(value, sp.Basic):
        expr = check_rational_in_s(value, allowed, what)
    else:
        raise ExpressionError(
            f"{what}: expected an expression (text, sympy or a number), got {type(value).__name__}",
            argument=what,
        )
    return cancelled(expr)


def entry_parameters(entries: Sequence[sp.Expr]) -> tuple[str, ...]:
    """Names of all parameters the entries use, sorted."""
    return tuple(sorted({str(x) for e in entries for x in e.free_symbols if x != S}))


def parse_entries(
    raw: Sequence[Any], labels: Sequence[str], values: Mapping[str, Any], what: str
) -> tuple[sp.Expr, ...]:
    """Every entry parsed (``labels[i]`` names entry ``i``); every name of ``values`` used."""
    allowed = set(STANDARD_SYMBOLS) | set(values)
    entries = tuple(parse_entry(v, allowed, lab) for v, lab in zip(raw, labels, strict=True))
    check_used(values, entry_parameters(entries), what)
    return entries


def merged_values(
    fixed: Mapping[str, float | None],
    given: Mapping[str, float] | None,
    parameters: Sequence[str],
    what: str,
) -> dict[str, Any]:
    """The values of ``parameters``: ``fixed`` with ``given`` over it; each must have one."""
    merged: dict[str, Any] = {k: v for k, v in fixed.items() if v is not None}
    if given:
        check_used(given, parameters, what)
        merged.update({k: to_fraction(v, k) for k, v in given.items()})
    missing = [p for p in parameters if p not in merged]
    if missing:
        raise ParameterError(
            f"no value for parameter(s) {', '.join(missing)}: give them, "
            f"e.g. values={{{missing[0]!r}: 1.0}}"
        )
    return merged


def _is_row(r: Any) -> bool:
    return isinstance(r, Sequence) and not isinstance(r, str)


def square_entries(matrix: Any, n: int | None = None) -> list[Any]:
    """The entries of a square nested sequence, row-major (``n`` rows if given).

    A flat sequence of ``n²`` entries is accepted too.

    >>> square_entries([["a", "b"], ["c", "d"]])
    ['a', 'b', 'c', 'd']
    """
    want = f"a {n}×{n} matrix" if n else "a square matrix"
    if not _is_row(matrix):
        raise ModelError(
            f"matrix: expected {want} as nested rows [[...], [...]]", argument="matrix"
        )
    rows = list(matrix)
    if n is not None and len(rows) == n * n and not any(_is_row(r) for r in rows):
        return rows
    size = len(rows)
    if size > MAX_PORTS:
        raise ModelError(
            f"matrix: {size} ports; the limit is {MAX_PORTS} (every principal minor is decided)",
            argument="matrix",
        )
    ok = size >= 1 and all(_is_row(r) and len(r) == size for r in rows)
    if not ok or (n is not None and size != n):
        shape = [len(r) if _is_row(r) else 1 for r in rows]
        raise ModelError(
            f"matrix: expected {want}; got {size} rows of lengths {shape}", argument="matrix"
        )
    return [x for r in rows for x in r]
