"""Strict TOML input: one loader for design and rig files; every error names the file."""

from __future__ import annotations

import os
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from ..errors import FileFormatError

__all__ = ["load_toml_file"]

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
