"""Units of a design's parameters: a small whitelist grammar, defaults and labels.

A unit is a product and quotient of SI symbols, each with an optional prefix and
an integer power: ``N/m``, ``N*s/m``, ``1/s``, ``N*m/rad``, ``kg*m^2``,
``N/(m*s)``.  The grammar (``·`` is accepted for ``*``)::

    unit    := product ('/' product)*
    product := factor ('*' factor)*
    factor  := ('1' | PREFIX? SYMBOL | '(' unit ')') ('^' '-'? DIGITS)?

Anything else (an unknown symbol, ``**``, a space-separated word) is refused at
load time, so a typo never becomes a label.  The standard parameters have a
default unit ([`seapass.model.expr.UNITS`][seapass.model.expr.UNITS]); a design
file's ``[units]`` table and the command line's ``--unit NAME=UNIT`` override it
(`unit_map` spells the defaults in the grammar: ``N*s/m``),
and a parameter without a unit is labelled by its name alone.

Examples
--------
>>> parse_unit("N*s/m"), parse_unit("N·s/m"), parse_unit("1/s")
('N*s/m', 'N*s/m', '1/s')
>>> unit_map({"ki": "1/s"}, ["kd", "ki", "bd", "gain"])
{'kd': 'N/m', 'ki': '1/s', 'bd': 'N*s/m', 'gain': ''}
>>> unit_label("kd", {"kd": "N/m"}), unit_label("g", {})
('kd [N/m]', 'g')
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping

from ..errors import ParameterError
from .expr import UNITS

__all__ = ["MAX_UNIT_CHARS", "PREFIXES", "SYMBOLS", "parse_unit", "unit_label", "unit_map"]

MAX_UNIT_CHARS = 40
"""Longest unit string accepted."""

SYMBOLS: tuple[str, ...] = (
    # SI base units (g for prefixed masses: kg, mg)
    "m", "g", "s", "A", "K", "mol", "cd",
    # SI derived units with special names, and the angle units
    "N", "J", "W", "Pa", "Hz", "C", "V", "Ohm", "F", "T", "Wb", "H", "rad", "sr", "deg",
)  # fmt: skip
"""Unit symbols the grammar knows."""

PREFIXES: tuple[str, ...] = ("p", "n", "u", "µ", "m", "c", "d", "k", "M", "G")
"""SI prefixes the grammar knows (``u`` and ``µ`` are both micro)."""

_TOKEN = re.compile(r"\s*(?:(?P<num>\d+)|(?P<word>[A-Za-zµ]+)|(?P<op>[*·/^()\-]))")


def _tokens(text: str) -> list[str]:
    out: list[str] = []
    pos = 0
    text = text.rstrip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None:
            raise ValueError(f"unexpected {text[pos:].strip()[:1]!r}")
        out.append(m.group(m.lastgroup or "op"))
        pos = m.end()
    return out


def _symbol(word: str) -> str:
    if word in SYMBOLS:
        return word
    for p in PREFIXES:
        if word.startswith(p) and word[len(p) :] in SYMBOLS:
            return word
    raise ValueError(f"unknown unit symbol {word!r}")


class _Parser:
    """Recursive descent over the tokens; returns the canonical text."""

    def __init__(self, tokens: list[str]) -> None:
        self.t = tokens
        self.i = 0

    def peek(self) -> str | None:
        return self.t[self.i] if self.i < len(self.t) else None

    def take(self) -> str:
        tok = self.peek()
        if tok is None:
            raise ValueError("unexpected end")
        self.i += 1
        return tok

    def unit(self) -> str:
        out = self.product()
        while self.peek() == "/":
            self.take()
            out += "/" + self.product()
        return out

    def product(self) -> str:
        out = self.factor()
        while self.peek() in ("*", "·"):
            self.take()
            out += "*" + self.factor()
        return out

    def factor(self) -> str:
        tok = self.take()
        if tok == "(":
            base = "(" + self.unit() + ")"
            if self.take() != ")":
                raise ValueError("missing ')'")
        elif tok == "1":
            base = "1"
        elif tok.isdigit():
            raise ValueError(f"a number ({tok}) is not a unit; only 1 is (as in 1/s)")
        elif tok[0].isalpha():
            base = _symbol(tok)
        else:
            raise ValueError(f"unexpected {tok!r}")
        if self.peek() == "^":
            self.take()
            sign = ""
            if self.peek() == "-":
                sign = self.take()
            power = self.take()
            if not power.isdigit() or len(power) > 2:
                raise ValueError(f"a power is a small whole number, got {sign}{power!r}")
            base += f"^{sign}{power}"
        return base


def parse_unit(text: str, *, argument: str = "unit") -> str:
    """Check ``text`` against the unit grammar; return it in canonical spelling.

    Raises
    ------
    ParameterError
        Naming ``argument``, for text outside the grammar (with the reason).
    """
    if not isinstance(text, str):
        raise ParameterError(f"{argument}: expected text, got {text!r}", argument=argument)
    if len(text) > MAX_UNIT_CHARS:
        raise ParameterError(
            f"{argument}: a unit has at most {MAX_UNIT_CHARS} characters", argument=argument
        )
    try:
        tokens = _tokens(text)
        if not tokens:
            raise ValueError("empty")
        parser = _Parser(tokens)
        out = parser.unit()
        if parser.peek() is not None:
            raise ValueError(f"unexpected {parser.peek()!r}")
    except ValueError as exc:
        raise ParameterError(
            f"{argument}: {text!r} is not a unit ({exc}); write SI symbols with prefixes, "
            "'*', '/' and '^N', e.g. 'N/m', 'N*s/m', '1/s', 'N*m/rad'",
            argument=argument,
        ) from None
    return out


def unit_map(declared: Mapping[str, str] | None, names: Iterable[str]) -> dict[str, str]:
    """The unit of each of ``names``: ``declared`` wins, then the default, else ``""``.

    ``declared`` is checked with `parse_unit` (its errors name ``units['NAME']``).
    """
    given = {k: parse_unit(v, argument=f"units[{k!r}]") for k, v in (declared or {}).items()}
    return {n: given[n] if n in given else _default(n) for n in names}


def _default(name: str) -> str:
    text = UNITS.get(name, "")
    return parse_unit(text) if text else ""


def unit_label(name: str, units: Mapping[str, str]) -> str:
    """``"kd [N/m]"``, or the name alone when it has no unit."""
    unit = units.get(name, "")
    return f"{name} [{unit}]" if unit else name
