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

__all__ = ["dump_toml", "load_toml_file", "loads_strict", "nesting_depth"]

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
