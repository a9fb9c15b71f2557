"""Strict TOML in and out: one loader for design and rig files (every error names the file)
and a writer for the flat tables seapass writes back (a fitted rig, ``rig show``)."""

from __future__ import annotations

import math
import os
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from ..errors import FileFormatError

__all__ = ["dump_toml", "load_toml_file"]

T = TypeVar("T")


def load_toml_file(path: str | os.PathLike[str], parse: Callable[[dict[str, Any]], T]) -> T:
    """Read a TOML file and ``parse`` its table; every error names the file.

    Raises
    ------
    FileFormatError
        For invalid TOML, non-UTF-8 text, or content ``parse`` rejects.
    OSError
        If the file cannot be read.
    """
    p = Path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise FileFormatError(f"{p}: invalid TOML: {exc}") from None
    except UnicodeDecodeError:
        raise FileFormatError(f"{p}: not a UTF-8 text file") from None
    try:
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
