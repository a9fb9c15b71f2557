"""Strict JSON: the one conversion of results to JSON text that any reader accepts.

Python's ``json`` writes ``NaN`` and ``Infinity``, which are not JSON, and
cannot write numpy scalars or arrays.  `strict_json` turns a result's
``to_dict()`` into plain JSON data: a non-finite float becomes ``null``, a
numpy scalar or array becomes the Python number or list, a tuple becomes a
list and a mapping a dict with string keys.  `json_text` writes it; every
``--json`` output, report data file and paper data file goes through it.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from typing import Any

__all__ = ["json_text", "strict_json"]


def strict_json(obj: Any) -> Any:
    """``obj`` as plain JSON data (non-finite floats ``None``, numpy values plain, tuples lists).

    Examples
    --------
    >>> strict_json({"a": (1.5, float("nan")), 2: [float("-inf"), "x", None, True]})
    {'a': [1.5, None], '2': [None, 'x', None, True]}
    """
    if isinstance(obj, str | bool | int) or obj is None:
        return obj
    if hasattr(obj, "tolist"):  # a numpy scalar or array: its plain Python value
        return strict_json(obj.tolist())
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, Mapping):
        return {k if isinstance(k, str) else str(k): strict_json(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [strict_json(v) for v in obj]
    return obj


def json_text(obj: Any) -> str:
    """Strict JSON text of ``obj`` (see `strict_json`), indented by 2, with a final newline.

    >>> print(json_text({"x": float("inf")}), end="")
    {
      "x": null
    }
    """
    return json.dumps(strict_json(obj), indent=2, allow_nan=False) + "\n"
