"""Declarative checks of TOML documents: one `Field` per key, one `check_table` for every file.

Design files ([`seapass.model.design_file`][seapass.model.design_file]) and rig
files ([`seapass.rig.schema`][seapass.rig.schema]) describe each table as a
mapping of key to `Field` (type, range, default, sub-table); `check_table`
checks a parsed document against it and returns the checked values.  Every
error is a [`FileFormatError`][seapass.errors.FileFormatError] naming the key
(``damper.k1``, ``simulation.load_masses[1]``), in the same words for every
file: an unknown key lists the allowed ones, a missing key or section says so,
a wrong type names the type found, a value out of its range gives the range.
Rules between keys (the actuator mass is positive, a rig file or a preset)
stay with the file's own loader.

Examples
--------
>>> fields = {"rate": Field(float, 1.0, 1e6), "delay": Field(int, 0, 100, required=False)}
>>> check_table({"rate": 500}, fields, where="control")
{'rate': 500.0}
>>> check_table({"rate": 500, "dealy": 1}, fields, where="control")
Traceback (most recent call last):
...
seapass.errors.FileFormatError: unknown key control.dealy; allowed keys: rate, delay
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ..errors import FileFormatError
from .limits import MAX_LIST_LENGTH

__all__ = ["Field", "check_table", "check_value"]


@dataclass(frozen=True)
class Field:
    """One key of a TOML table: what it holds and the values it may take.

    Attributes
    ----------
    kind : type
        ``float``, ``int``, ``str``, ``list`` (a list of numbers), ``tuple``
        (a pair ``[lo, hi]`` of numbers) or ``dict`` (a table: of the keys in
        ``fields``, or of any key matching ``keys`` with values like ``item``).
    lo, hi : float
        Range of a number (of each number of a list or pair); for ``str`` the
        most characters ``hi``.
    lo_open : bool
        ``lo`` itself is excluded.
    required : bool
        A missing key is an error; else it takes ``default`` (left out when None).
    default : object
        The value of a missing optional key.
    nonzero : bool
        A number must not be 0.
    line : bool
        A string is one line of printable text.
    choices : tuple of str
        A string must be one of these.
    min_items : int
        Fewest numbers of a list.
    order : str
        ``"<"`` or ``"<="``: how the two numbers of a pair must compare.
    fields : mapping of str to Field, optional
        The keys of a ``dict`` table.
    keys : str, optional
        For a ``dict`` of free keys: the regular expression every key matches.
    item : Field, optional
        For a ``dict`` of free keys: the field of every value.
    hint : str
        Said after "missing ..." (``"the sampling rate in Hz"``).
    """

    kind: type
    lo: float = -math.inf
    hi: float = math.inf
    lo_open: bool = False
    required: bool = True
    default: Any = None
    nonzero: bool = False
    line: bool = False
    choices: tuple[str, ...] = ()
    min_items: int = 0
    order: str = ""
    fields: Mapping[str, Field] | None = field(default=None, compare=False)
    keys: str | None = None
    item: Field | None = None
    hint: str = ""


def check_table(
    table: Any, fields: Mapping[str, Field], *, where: str = "", what: str = ""
) -> dict[str, Any]:
    """The checked values of ``table`` (a parsed TOML table) by the keys of ``fields``.

    Parameters
    ----------
    table : object
        The parsed table (a dict from `tomllib`).
    fields : mapping of str to Field
        Every allowed key.
    where : str
        The table's dotted name (``"control"``), ``""`` for a whole document.
    what : str
        For a whole document: what it is (``"a rig"``), said when it is not a table.

    Raises
    ------
    FileFormatError
        Naming the key: unknown, missing, of the wrong type or out of range.
    """
    if not isinstance(table, dict):
        head = f"{what} must be a TOML table" if not where else f"[{where}] must be a table"
        raise FileFormatError(f"{head}, got {type(table).__name__}")
    unknown = sorted(set(table) - set(fields))
    if unknown:
        raise FileFormatError(
            f"unknown key {_key(where, unknown[0])}; allowed keys: {', '.join(fields)}"
        )
    out: dict[str, Any] = {}
    for name, spec in fields.items():
        key = _key(where, name)
        if name in table:
            out[name] = check_value(key, spec, table[name])
        elif spec.required:
            missing = f"section [{key}]" if spec.kind is dict else f"key {key}"
            raise FileFormatError(
                f"missing required {missing}" + (f" ({spec.hint})" if spec.hint else "")
            )
        elif spec.default is not None:
            out[name] = spec.default
    return out


def check_value(key: str, spec: Field, value: Any) -> Any:
    """``value`` of ``key`` checked against ``spec``; numbers come back as ``float``/``int``."""
    if spec.kind is dict:
        if spec.fields is not None:
            return check_table(value, spec.fields, where=key)
        return _free_table(key, spec, value)
    if spec.kind is str:
        return _string(key, spec, value)
    if spec.kind is list:
        if not isinstance(value, list):
            raise FileFormatError(f"{key}: expected a list of numbers, got {type(value).__name__}")
        if len(value) > MAX_LIST_LENGTH:
            raise FileFormatError(
                f"{key}: {len(value):,} entries; the limit is {MAX_LIST_LENGTH:,}"
            )
        if len(value) < spec.min_items:
            raise FileFormatError(
                f"{key}: expected at least {spec.min_items} number(s), got {len(value)}"
            )
        return tuple(_number(f"{key}[{i}]", spec, v, float) for i, v in enumerate(value))
    if spec.kind is tuple:
        if not isinstance(value, list) or len(value) != 2:
            raise FileFormatError(f"{key}: expected [lo, hi], got {value!r}")
        lo, hi = (_number(f"{key}[{i}]", spec, v, float) for i, v in enumerate(value))
        if (spec.order == "<" and not lo < hi) or (spec.order == "<=" and not lo <= hi):
            raise FileFormatError(f"{key}: need lo {spec.order} hi, got [{lo:g}, {hi:g}]")
        return (lo, hi)
    return _number(key, spec, value, spec.kind)


def _key(where: str, name: str) -> str:
    return f"{where}.{name}" if where else name


def _free_table(key: str, spec: Field, value: Any) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise FileFormatError(f"[{key}] must be a table, got {type(value).__name__}")
    assert spec.item is not None, "a table of free keys needs its item field"
    out = {}
    for name, v in value.items():
        if spec.keys is not None and not re.fullmatch(spec.keys, name):
            raise FileFormatError(f"{key}.{name}: not a valid name")
        out[name] = check_value(f"{key}.{name}", spec.item, v)
    return out


def _string(key: str, spec: Field, value: Any) -> str:
    if not isinstance(value, str):
        raise FileFormatError(f"{key}: expected a string, got {type(value).__name__} {value!r}")
    if len(value) > spec.hi:
        raise FileFormatError(f"{key}: {len(value):,} characters; the limit is {spec.hi:g}")
    if spec.line:
        bad = next((ch for ch in value if not (ch.isprintable() or ch == "\t")), None)
        if bad is not None:
            raise FileFormatError(
                f"{key}: contains the control character U+{ord(bad):04X}; use one line of "
                "plain text"
            )
    if spec.choices and value not in spec.choices:
        known = " or ".join(repr(c) for c in spec.choices)
        raise FileFormatError(f"{key}: expected {known}, got {value!r}")
    return value


def _number(key: str, spec: Field, value: Any, kind: type) -> Any:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise FileFormatError(f"{key}: expected a number, got {type(value).__name__} {value!r}")
    if kind is int and not isinstance(value, int):
        raise FileFormatError(f"{key}: expected an integer, got {value!r}")
    if not math.isfinite(value):
        raise FileFormatError(f"{key}: must be finite, got {value!r}")
    if spec.nonzero and value == 0:
        raise FileFormatError(f"{key}: must be nonzero, got {value!r}")
    too_low = value <= spec.lo if spec.lo_open else value < spec.lo
    if too_low or value > spec.hi:
        if spec.hi == math.inf:
            raise FileFormatError(
                f"{key}: must be {'>' if spec.lo_open else '>='} {spec.lo:g}, got {value!r}"
            )
        lo = "(" if spec.lo_open else "["
        raise FileFormatError(f"{key}: {value!r} is out of range {lo}{spec.lo:g}, {spec.hi:g}]")
    return kind(value)
