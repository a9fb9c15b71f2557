"""Strict TOML in and out: one loader for design and rig files, every error naming the
file, and a writer for the flat tables seapass writes back (a fitted rig, ``rig show``).

The file is read with a size cap (`seapass.files.textfile.read_text_file`),
deep nesting is refused in one line (the standard parser is recursive), and a
number that underflows to zero (``1e-400``) is an error instead of a silent 0.
"""

from __future__ import annotations

import math
import os
import re
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from ..errors import FileFormatError
from .limits import MAX_TEXT_FILE_BYTES, MAX_TOML_DEPTH
from .textfile import read_text_file

__all__ = ["dump_toml", "load_toml_file", "loads_strict", "nesting_depth", "update_toml_text"]

T = TypeVar("T")

_NONZERO_MANTISSA = re.compile(r"^[+-]?[0_.]*[1-9]")


class _Underflow(ValueError):
    pass


def _parse_float(text: str) -> float:
    """``float(text)``, refusing a nonzero literal that underflows to 0."""
    value = float(text.replace("_", ""))
    if value == 0.0 and _NONZERO_MANTISSA.match(text.split("e")[0].split("E")[0]):
        raise _Underflow(text)
    return value


def nesting_depth(obj: Any, limit: int = MAX_TOML_DEPTH) -> int:
    """Depth of nested dicts and lists (a scalar is 0); stops counting beyond ``limit``.

    >>> nesting_depth({"a": [[1]]})
    3
    """
    depth = 0
    level: list[Any] = [obj]
    while level and depth <= limit:
        nxt: list[Any] = []
        for item in level:
            if isinstance(item, dict):
                nxt.extend(item.values())
            elif isinstance(item, list):
                nxt.extend(item)
        if not any(isinstance(x, dict | list) for x in level):
            break
        depth += 1
        level = nxt
    return depth


def _open_brackets(text: str) -> int:
    """Upper bound of the bracket nesting of ``text`` (strings are not skipped)."""
    depth = best = 0
    for ch in text:
        if ch in "[{":
            depth += 1
            best = max(best, depth)
        elif ch in "]}" and depth:
            depth -= 1
    return best


def loads_strict(text: str) -> dict[str, Any]:
    """Parse TOML text like `tomllib.loads`, within the nesting limit.

    Raises
    ------
    FileFormatError
        For invalid TOML, nesting deeper than `MAX_TOML_DEPTH`, or a number
        that underflows to zero.
    """
    try:
        data = tomllib.loads(text, parse_float=_parse_float)
    except tomllib.TOMLDecodeError as exc:
        raise FileFormatError(f"invalid TOML: {exc}") from None
    except _Underflow as exc:
        raise FileFormatError(
            f"the number {exc} is too small for a float (it would become 0); write 0 "
            "or a value above 1e-308"
        ) from None
    except RecursionError:
        raise FileFormatError(
            f"nested too deeply (about {_open_brackets(text)} levels of arrays or tables; "
            f"the limit is {MAX_TOML_DEPTH})"
        ) from None
    except ValueError as exc:  # e.g. an integer with more than 4300 digits
        raise FileFormatError(f"invalid TOML value: {exc}") from None
    depth = nesting_depth(data)
    if depth > MAX_TOML_DEPTH:
        raise FileFormatError(
            f"nested too deeply ({depth} or more levels of arrays or tables; "
            f"the limit is {MAX_TOML_DEPTH})"
        )
    return data


def load_toml_file(
    path: str | os.PathLike[str],
    parse: Callable[[dict[str, Any]], T],
    *,
    what: str = "TOML file",
) -> T:
    """Read a TOML file and ``parse`` its table; every error names the file.

    The file must be a regular file of at most `MAX_TEXT_FILE_BYTES`.

    Raises
    ------
    FileFormatError
        For a file that is too large or not a regular file, invalid TOML,
        non-UTF-8 text, nesting beyond `MAX_TOML_DEPTH`, or content ``parse`` rejects.
    OSError
        If the file does not exist or cannot be read.
    """
    p = Path(path)
    text = read_text_file(p, max_bytes=MAX_TEXT_FILE_BYTES, what=what)
    try:
        data = loads_strict(text)
        return parse(data)
    except FileFormatError as exc:
        raise FileFormatError(f"{p}: {exc}") from None


def _toml_char(c: str) -> str:
    if c in '"\\':
        return "\\" + c
    if ord(c) < 0x20 or ord(c) == 0x7F:
        return f"\\u{ord(c):04x}"
    return c


def _toml_value(value: Any, key: str) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{key}: TOML files written by seapass hold finite numbers only")
        return repr(value)  # shortest text that reads back as the same float
    if isinstance(value, str):
        return '"' + "".join(_toml_char(c) for c in value) + '"'
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml_value(v, key) for v in value) + "]"
    raise TypeError(f"{key}: cannot write {type(value).__name__} to TOML")


def dump_toml(data: dict[str, Any], *, comments: dict[str, str] | None = None) -> str:
    """TOML text of ``data``: top-level keys first, then one ``[table]`` per nested dict.

    Values are strings, booleans, integers, finite floats (written so they read
    back bit for bit) and lists of these; tables nest one level.  ``comments``
    maps a table name (or ``"key"`` / ``"table.key"``) to a comment written
    above it.

    Examples
    --------
    >>> print(dump_toml({"name": "x", "spring": {"k1": 1005.0, "masses": [0.1, 0.6]}}), end="")
    name = "x"
    <BLANKLINE>
    [spring]
    k1 = 1005.0
    masses = [0.1, 0.6]
    >>> tomllib.loads(dump_toml({"a": {"b": 0.1}})) == {"a": {"b": 0.1}}
    True
    """
    notes = comments or {}

    def note(key: str) -> list[str]:
        return [f"# {line}".rstrip() for line in notes[key].splitlines()] if key in notes else []

    lines: list[str] = []
    for key, value in data.items():
        if not isinstance(value, dict):
            lines += [*note(key), f"{key} = {_toml_value(value, key)}"]
    for table, body in data.items():
        if isinstance(body, dict):
            lines += ["", *note(table), f"[{table}]"]
            for key, value in body.items():
                lines += [
                    *note(f"{table}.{key}"),
                    f"{key} = {_toml_value(value, f'{table}.{key}')}",
                ]
    return "\n".join(lines).lstrip("\n") + "\n"


_HEADER = re.compile(r"^\s*\[([A-Za-z0-9_-]+)\]\s*(#.*)?$")
_KEY = re.compile(r"^(\s*)([A-Za-z0-9_-]+)(\s*=\s*)(.*)$")


def _value_end(text: str) -> int:
    """Where the scalar value at the start of ``text`` ends (a string, or a bare token)."""
    if text.startswith('"'):
        i = 1
        while i < len(text):
            if text[i] == "\\":
                i += 2
                continue
            if text[i] == '"':
                return i + 1
            i += 1
        return -1
    if text.startswith("'"):
        j = text.find("'", 1)
        return -1 if j < 0 else j + 1
    m = re.match(r"[^\s#\[\]{}]+", text)
    return m.end() if m else -1


def update_toml_text(text: str, changes: dict[str, Any]) -> str | None:
    """``text`` with the scalar values of ``changes`` replaced, every comment and line kept.

    ``changes`` maps ``"key"`` (top level) or ``"table.key"`` to a value as
    `dump_toml` writes it.  A key the text lacks is added at the end of its
    table (or before the first table).  Returns None when the text cannot be
    edited line by line faithfully (a multi-line value, a quoted or dotted key,
    a missing table): the caller then writes `dump_toml` instead.  The result is
    always re-read and compared with ``text``'s values plus ``changes``.

    Examples
    --------
    >>> print(update_toml_text('a = 1  # one\\n[t]\\nb = "x" # why\\n', {"t.b": "y", "t.c": 2.5}), end="")
    a = 1  # one
    [t]
    b = "y" # why
    c = 2.5
    """
    try:
        before = tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        return None
    lines = text.splitlines()
    table = ""
    ends: dict[str, int] = {
        "": next((i for i, ln in enumerate(lines) if _HEADER.match(ln)), len(lines))
    }
    found: dict[str, int] = {}
    for i, line in enumerate(lines):
        head = _HEADER.match(line)
        if head:
            table = head.group(1)
            ends[table] = i + 1
            continue
        key = _KEY.match(line)
        if key:
            found[f"{table}.{key.group(2)}" if table else key.group(2)] = i
        if line.strip() and not line.lstrip().startswith("#"):
            ends[table] = i + 1
    added: dict[int, list[str]] = {}
    for name, value in changes.items():
        table, _, leaf = name.rpartition(".")
        new = _toml_value(value, name)
        if name in found:
            i = found[name]
            m = _KEY.match(lines[i])
            assert m is not None
            end = _value_end(m.group(4))
            if end < 0:
                return None
            lines[i] = m.group(1) + m.group(2) + m.group(3) + new + m.group(4)[end:]
        elif table in ends:
            added.setdefault(ends[table], []).append(f"{leaf} = {new}")
        else:
            return None
    for at in sorted(added, reverse=True):
        lines[at:at] = added[at]
    out = "\n".join(lines) + "\n"
    expected = {k: (dict(v) if isinstance(v, dict) else v) for k, v in before.items()}
    for name, value in changes.items():
        table, _, leaf = name.rpartition(".")
        (expected.setdefault(table, {}) if table else expected)[leaf] = (
            list(value) if isinstance(value, tuple) else value
        )
    try:
        return out if tomllib.loads(out) == expected else None
    except tomllib.TOMLDecodeError:
        return None
