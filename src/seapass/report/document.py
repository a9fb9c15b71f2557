"""The report's document model: sections of text, tables, figures and findings.

A `Report` is a sequence of `Section` objects, each holding
short text (a small Markdown subset: paragraphs, ``- `` lists, fenced code,
```code``` and ``**bold**``), `Table` objects, `FigureData`
(PNG bytes) and `Finding` objects (a claim of the paper checked
against seapass).  The stages of [`seapass.report.reproduce`][seapass.report.reproduce] and
[`seapass.report.analyze`][seapass.report.analyze] build them; [`seapass.report.render`][seapass.report.render] renders
them and [`seapass.report.output`][seapass.report.output] writes them.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from types import MappingProxyType
from typing import Any

from ..errors import ParameterError

__all__ = [
    "FigureData",
    "Finding",
    "Report",
    "Section",
    "SectionStatus",
    "Table",
    "Verdict",
    "format_cell",
    "format_intervals",
    "to_json",
]


class SectionStatus(StrEnum):
    """How a report stage ended."""

    OK = "ok"
    SKIPPED = "skipped"
    """An optional input or extra is missing; the reason is in the section's text."""
    FAILED = "failed"
    """The stage raised; the error is in the section's text."""


class Verdict(StrEnum):
    """What seapass finds about a claim."""

    AGREES = "agrees"
    DIFFERS = "differs"
    INFO = "info"
    """A number or observation, not a comparison."""


_FILE = re.compile(r"^[A-Za-z0-9_.-]+$")


def format_cell(value: Any) -> str:
    """Human-readable cell: floats to 4 significant digits, booleans as yes/NO."""
    if value is None:
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "NO"
    if isinstance(value, float):
        if math.isnan(value):
            return "–"
        if math.isinf(value):
            return "∞" if value > 0 else "−∞"
        return f"{value:.4g}"
    return str(value)


def format_intervals(intervals: Sequence[tuple[float, float]], hi: float) -> str:
    """``[a, b] ∪ {c}`` with 6 significant digits; an end at ``hi`` is marked as the search limit."""
    if not intervals:
        return "none"
    parts = []
    for a, b in intervals:
        end = f"{b:.6g}" + (" (search limit)" if b >= hi else "")
        parts.append(f"[{a:.6g}, {end}]" if a != b else f"{{{a:.6g}}}")
    return " ∪ ".join(parts)


def to_json(obj: Any) -> str:
    """Strict, stable JSON text (non-finite floats become null, numpy scalars plain)."""

    def clean(o: Any) -> Any:
        if isinstance(o, float) and not math.isfinite(o):
            return None
        if isinstance(o, Mapping):
            return {str(k): clean(v) for k, v in o.items()}
        if isinstance(o, list | tuple):
            return [clean(v) for v in o]
        if hasattr(o, "item") and callable(o.item) and not isinstance(o, str | bytes):
            return clean(o.item())
        return o

    return json.dumps(clean(obj), indent=2, allow_nan=False) + "\n"


def _csv_cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ("" if math.isnan(value) else str(value))
    return str(value)


@dataclass(frozen=True)
class Table:
    """A table of values; written as ``data/<name>.csv`` and shown in the report.

    ``highlight`` lists ``(row, column)`` cells to flag (discrepancies); a
    ``False`` cell is always flagged.  ``views`` optionally splits a wide
    table for display into ``(subtitle, column indices)`` parts; the CSV
    always has every column.
    """

    name: str
    title: str
    columns: tuple[str, ...]
    rows: tuple[tuple[Any, ...], ...]
    highlight: frozenset[tuple[int, int]] = frozenset()
    note: str = ""
    views: tuple[tuple[str, tuple[int, ...]], ...] = ()

    def __post_init__(self) -> None:
        if not _FILE.match(self.name):
            raise ParameterError(f"table name {self.name!r} is not a plain file stem")
        object.__setattr__(self, "columns", tuple(self.columns))
        object.__setattr__(self, "rows", tuple(tuple(r) for r in self.rows))
        object.__setattr__(self, "highlight", frozenset(self.highlight))
        for _sub, cols in self.views:
            if not cols or not all(0 <= j < len(self.columns) for j in cols):
                raise ParameterError(f"table {self.name!r}: a view has bad column indices {cols}")
        for i, r in enumerate(self.rows):
            if len(r) != len(self.columns):
                raise ParameterError(
                    f"table {self.name!r}: row {i} has {len(r)} cells, expected {len(self.columns)}"
                )

    def flagged(self, i: int, j: int) -> bool:
        return (i, j) in self.highlight or self.rows[i][j] is False

    def to_csv(self) -> str:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(self.columns)
        for r in self.rows:
            w.writerow([_csv_cell(v) for v in r])
        return buf.getvalue()


@dataclass(frozen=True)
class FigureData:
    """A rendered figure: PNG bytes, written as ``figures/<name>.png``."""

    name: str
    caption: str
    png: bytes = field(repr=False)

    def __post_init__(self) -> None:
        if not _FILE.match(self.name):
            raise ParameterError(f"figure name {self.name!r} is not a plain file stem")
        if not self.png.startswith(b"\x89PNG"):
            raise ParameterError(f"figure {self.name!r}: not PNG data")


@dataclass(frozen=True)
class Finding:
    """A claim (usually the paper's) and what seapass finds: ``agrees``, ``differs`` or ``info``."""

    claim: str
    verdict: Verdict
    detail: str = ""

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "verdict", Verdict(self.verdict))
        except ValueError:
            choices = ", ".join(v.value for v in Verdict)
            raise ParameterError(
                f"verdict must be one of {choices}, got {self.verdict!r}"
            ) from None

    def to_dict(self) -> dict[str, str]:
        return {"claim": self.claim, "verdict": self.verdict, "detail": self.detail}


@dataclass(frozen=True)
class Section:
    """One stage's contribution to the report.

    ``files`` are extra data files (``data/<name>``, e.g. JSON) as text.
    ``status`` is ``"ok"``, ``"skipped"`` (a module or an input is missing; the
    reason is in ``text``) or ``"failed"`` (the error is in ``text``).
    """

    key: str
    title: str
    text: str = ""
    tables: tuple[Table, ...] = ()
    figures: tuple[FigureData, ...] = ()
    findings: tuple[Finding, ...] = ()
    files: Mapping[str, str] = field(default_factory=dict)
    status: SectionStatus = SectionStatus.OK

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "status", SectionStatus(self.status))
        except ValueError:
            choices = ", ".join(s.value for s in SectionStatus)
            raise ParameterError(f"status must be one of {choices}, got {self.status!r}") from None
        object.__setattr__(self, "tables", tuple(self.tables))
        object.__setattr__(self, "figures", tuple(self.figures))
        object.__setattr__(self, "findings", tuple(self.findings))
        object.__setattr__(self, "files", MappingProxyType(dict(self.files)))
        for name in self.files:
            if not _FILE.match(name):
                raise ParameterError(f"data file name {name!r} is not a plain file name")

    def __reduce__(self) -> tuple[Any, ...]:
        # a mappingproxy does not pickle; sections travel between worker processes
        return (
            Section,
            (self.key, self.title, self.text, self.tables, self.figures, self.findings,
             dict(self.files), self.status),
        )  # fmt: skip


@dataclass(frozen=True)
class Report:
    """A titled sequence of sections."""

    title: str
    intro: str
    sections: tuple[Section, ...]

    @property
    def findings(self) -> list[tuple[str, Finding]]:
        return [(s.title, f) for s in self.sections for f in s.findings]

    @property
    def failed(self) -> list[str]:
        return [s.key for s in self.sections if s.status == SectionStatus.FAILED]

    def files(self) -> dict[str, str | bytes]:
        """Every output file, relative path to content (without the two reports)."""
        out: dict[str, str | bytes] = {
            "data/findings.json": to_json(
                [{"section": s.key, **f.to_dict()} for s in self.sections for f in s.findings]
            ),
            "data/sections.json": to_json(
                [{"key": s.key, "title": s.title, "status": s.status} for s in self.sections]
            ),
        }
        for s in self.sections:
            for t in s.tables:
                out[f"data/{t.name}.csv"] = t.to_csv()
            for name, text in s.files.items():
                out[f"data/{name}"] = text
            for fig in s.figures:
                out[f"figures/{fig.name}.png"] = fig.png
        return out
