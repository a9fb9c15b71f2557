"""Short text and HTML summaries of models and results, for the REPL and notebooks.

Every model and result object of seapass has a ``repr`` of one short line (the
few numbers that identify it, never whole arrays or long sentences) and a
``_repr_html_`` card that Jupyter shows.  These two helpers build both, so they
look the same everywhere.  Nothing here computes anything: an object's summary
uses only what it already holds.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["Shown", "format_value", "html_card", "poly_text", "short_repr"]

_MAX_TEXT = 60


class Shown(str):
    """Text that `short_repr` shows as it is, without quotes (``omega=[0.1, 1e+04]``)."""

    __slots__ = ()


def format_value(value: Any) -> str:
    """A number with 6 significant digits, a short string, or the ``repr`` of anything else."""
    if isinstance(value, Shown):
        return str(value)
    if isinstance(value, bool) or value is None:
        return repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return f"{value:.6g}" if math.isfinite(value) else str(value)
    if isinstance(value, str):
        text = value if len(value) <= _MAX_TEXT else value[: _MAX_TEXT - 1] + "…"
        return repr(text)
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{k!r}: {format_value(v)}" for k, v in value.items()) + "}"
    return str(value)


def short_repr(name: str, fields: Mapping[str, Any]) -> str:
    """``Name(key=value, ...)`` over the fields that are not None.

    Examples
    --------
    >>> short_repr("Result", {"passive": True, "omega": None, "margin": 0.0123456789})
    'Result(passive=True, margin=0.0123457)'
    """
    parts = [f"{k}={format_value(v)}" for k, v in fields.items() if v is not None]
    return f"{name}({', '.join(parts)})"


def html_card(title: str, rows: Sequence[tuple[str, Any]], *, note: str = "") -> str:
    """A small HTML table: a bold title, one row per ``(label, value)``, an optional note.

    Values are escaped; strings are shown as they are, other values through
    `format_value`.
    """
    body = "".join(
        f"<tr><th style='text-align:left;padding-right:1em'>{html.escape(str(k))}</th>"
        f"<td style='text-align:left'>{html.escape(v if isinstance(v, str) else format_value(v))}"
        "</td></tr>"
        for k, v in rows
    )
    foot = f"<p style='margin:0.3em 0;color:#555'>{html.escape(note)}</p>" if note else ""
    return f"<div><strong>{html.escape(title)}</strong><table>{body}</table>{foot}</div>"


def poly_text(coeffs: Sequence[float], var: str = "s") -> str:
    """Descending coefficients as ``a s^n + ... + c`` (6 significant digits).

    Examples
    --------
    >>> poly_text([1.0, 0.0, -2.5, 3.0])
    '1 s^3 - 2.5 s + 3'
    """
    n = len(coeffs) - 1
    terms = []
    for i, c in enumerate(coeffs):
        if c == 0:
            continue
        k = n - i
        power = "" if k == 0 else (var if k == 1 else f"{var}^{k}")
        terms.append(f"{c:.6g}" + (f" {power}" if power else ""))
    return " + ".join(terms).replace("+ -", "- ") or "0"
