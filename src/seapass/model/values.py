"""Numbers and names as people give them: checked, exact, never guessed.

A value (``--set kd=5000``, a design file's number, ``values={"kd": 5e3}``) must be
finite, ASCII, and not underflow to zero; a float converts to the rational it
represents exactly.  A parameter name must be a plain identifier that is not reserved.

What lives here: `check_ascii`, `check_name`, `parse_value`,
`to_fraction`, `validate_values`, `finite_number`, `underflows` (all re-exported by
[`seapass.model.expr`][seapass.model.expr]).  May import: [`seapass.errors`][seapass.errors].
"""

from __future__ import annotations

import math
import numbers
import re
import unicodedata
from collections.abc import Mapping
from fractions import Fraction
from typing import Any

from ..errors import ExpressionError, ParameterError

__all__ = [
    "RESERVED",
    "check_ascii",
    "check_name",
    "finite_number",
    "parse_value",
    "to_fraction",
    "underflows",
    "validate_values",
]

RESERVED = frozenset({"s", "w", "I", "E", "pi", "oo", "nan", "zoo"})
"""Names a parameter may not have (the Laplace variable, ω, and sympy's constants)."""


def check_ascii(text: str, what: str) -> None:
    """Refuse non-ASCII input, saying what a lookalike character would have become.

    Python folds ``ｓ`` and ``𝑠`` into ``s`` and reads ``٣`` as 3; seapass does not
    guess: it names the character and its ASCII look-alike.

    >>> check_ascii("ｓ + 1", "CA")
    Traceback (most recent call last):
    ...
    seapass.errors.ExpressionError: CA: non-ASCII character 'ｓ' (U+FF53 FULLWIDTH LATIN SMALL LETTER S) in 'ｓ + 1'; write 's' instead
    """
    bad = next((ch for ch in text if ord(ch) > 127), None)
    if bad is None:
        return
    name = unicodedata.name(bad, "unnamed character")
    digit = unicodedata.digit(bad, None)
    folded = str(digit) if digit is not None else unicodedata.normalize("NFKC", bad)
    hint = (
        f"; write {folded!r} instead"
        if folded.isascii() and folded.strip()
        else "; use plain ASCII letters, digits and operators"
    )
    shown = bad if bad.isprintable() else ""
    where = f"{what}: " if what else ""
    raise ExpressionError(
        f"{where}non-ASCII character {shown!r} (U+{ord(bad):04X} {name}) in {text!r}{hint}"
    )


def check_name(name: str) -> None:
    """Refuse a parameter name that is not a plain identifier (or is reserved)."""
    check_ascii(name, "parameter name")
    if not name.isidentifier() or name.startswith("_") or name in RESERVED:
        raise ExpressionError(
            f"invalid parameter name {name!r}: use a plain identifier other than "
            f"{', '.join(sorted(RESERVED))}"
        )


_NONZERO_MANTISSA = re.compile(r"^\s*[+-]?[0_.]*[1-9]")


def underflows(literal: str) -> bool:
    """True if the decimal ``literal`` is nonzero but rounds to 0.0 as a float.

    >>> underflows("1e-400"), underflows("0.0e5"), underflows("4.9e-324")
    (True, False, False)
    """
    mantissa = re.split("[eE]", literal, maxsplit=1)[0]
    try:
        zero = float(literal) == 0.0
    except ValueError:
        return False
    return zero and bool(_NONZERO_MANTISSA.match(mantissa))


def parse_value(text: str, name: str = "value") -> float:
    """Parse a finite real number, rejecting NaN, infinities, non-ASCII digits and underflow."""
    if isinstance(text, str):
        try:
            check_ascii(text, name)
        except ExpressionError as exc:
            raise ParameterError(str(exc)) from None
    try:
        val = float(text)
    except (TypeError, ValueError):
        raise ParameterError(f"{name}: {text!r} is not a number") from None
    if not math.isfinite(val):
        raise ParameterError(f"{name}: {text!r} is not finite; give a finite number")
    if isinstance(text, str) and underflows(text):
        raise ParameterError(
            f"{name}: {text.strip()} is too small for a float (it would become 0); "
            "give 0 or a value above 1e-308"
        )
    return val


def to_fraction(value: float | int | Fraction | numbers.Real, name: str = "value") -> Fraction:
    """Exact rational value of a finite number (floats convert exactly).

    Any rational number type (``fractions.Fraction``, ``flint.fmpq``, sympy's
    ``Rational``) converts exactly.
    """
    if isinstance(value, Fraction):
        return value
    if isinstance(value, bool):
        raise ParameterError(f"{name}: expected a number, got a boolean")
    if isinstance(value, int):
        return Fraction(value)
    if isinstance(value, numbers.Rational):
        return Fraction(int(value.numerator), int(value.denominator))
    if type(value).__name__ == "fmpq":  # flint's rationals are not registered as numbers
        flint_q: Any = value
        return Fraction(int(flint_q.p), int(flint_q.q))
    try:
        f = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name}: {value!r} is not a number") from None
    if not math.isfinite(f):
        raise ParameterError(f"{name}: {value!r} is not finite")
    return Fraction(f)


def validate_values(values: Mapping[str, object]) -> dict[str, float]:
    """Check parameter names and values; return a plain ``{name: float}`` dict."""
    out: dict[str, float] = {}
    for name, val in values.items():
        check_name(name)
        out[name] = float(to_fraction(val, name))  # type: ignore[arg-type,unused-ignore]
    return out


def finite_number(
    value: float, name: str, *, positive: bool = False, nonzero: bool = False
) -> float:
    """``value`` as a finite float, or a `ParameterError` naming ``name``."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name}: expected a number, got {value!r}") from None
    if not math.isfinite(v):
        raise ParameterError(f"{name} must be finite, got {v}")
    if positive and v <= 0:
        raise ParameterError(f"{name} must be positive, got {v:g}")
    if nonzero and v == 0:
        raise ParameterError(f"{name} must be nonzero")
    return v
