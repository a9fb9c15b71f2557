"""The report's document model: sections of text, tables, figures and findings.

A `Report` is a sequence of `Section` objects, each holding
short text (CommonMark, rendered by markdown-it-py: paragraphs, lists, fenced
code, ```code```, emphasis, links; plus ``$formula$`` and ```` ```math ````
blocks for formulas in plain text, shown as MathML), `Table` objects (cells may
be `Math`), `FigureData` (PNG and SVG bytes) and `Finding` objects (a claim,
usually the paper's, checked by seapass; a difference carries its
`Discrepancy` kind).  The stages of [`seapass.report.reproduce`][seapass.report.reproduce] and
[`seapass.report.analyze`][seapass.report.analyze] build them; [`seapass.report.render`][seapass.report.render] renders
them and [`seapass.report.output`][seapass.report.output] writes them.

Text from users (design names, file names) goes into Markdown through `code`,
so it is shown literally.
"""

from __future__ import annotations

import csv
import io
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from types import MappingProxyType
from typing import Any

from ..errors import ParameterError
from ..exact.rounding import decimal_down, inward_text
from ..files.jsontext import json_text as to_json

__all__ = [
    "Discrepancy",
    "FigureData",
    "Finding",
    "Math",
    "Report",
    "Section",
    "SectionStatus",
    "Summary",
    "Table",
    "UpperEnd",
    "Verdict",
    "code",
    "format_cell",
    "format_intervals",
    "formula",
    "literal",
    "plain_text",
    "to_json",
]


class SectionStatus(StrEnum):
    """How a report stage ended."""

    OK = "ok"
    SKIPPED = "skipped"
    """An optional input or extra is missing; the reason is in the section's text."""
    FAILED = "failed"
    """The stage raised; the error is in the section's text."""
    STOPPED_AT_BUDGET = "stopped_at_budget"
    """The stage reached its work budget; the section holds what it had (never a verdict
    it did not reach) and says which budget to raise."""
    NOT_RUN = "not_run"
    """The run was interrupted before the stage finished; the report is incomplete."""

    @property
    def label(self) -> str:
        """In words: ``"stopped at budget"``, ``"not run"``, ``"ok"``..."""
        return self.value.replace("_", " ")


class Verdict(StrEnum):
    """What seapass finds about a claim."""

    AGREES = "agrees"
    DIFFERS = "differs"
    INFO = "info"
    """A number or observation, not a comparison."""


class Discrepancy(StrEnum):
    """What kind of difference a finding with verdict ``differs`` records."""

    PAPER_TYPO = "paper typo"
    """A printed formula differs from the derivation; the conclusion it supports holds."""
    CONSERVATIVE = "conservative bound"
    """The paper's bound is sufficient only: it rejects designs that are passive."""
    UNSAFE = "unsafe bound"
    """The paper's bound admits designs that are not passive."""
    CHECK_FAILED = "check failed"
    """A check of seapass's own (twin, sampled data, a design's verdict) does not hold."""

    @property
    def label(self) -> str:
        """The heading the report's summary uses for this kind."""
        return _KIND_LABELS[self]


_KIND_LABELS = {
    Discrepancy.PAPER_TYPO: "Typos in the paper's printed formulas",
    Discrepancy.CONSERVATIVE: "Bounds that are only conservative (safe, but reject passive designs)",
    Discrepancy.UNSAFE: "Unsafe bounds (admit designs that are not passive)",
    Discrepancy.CHECK_FAILED: "Checks of seapass's own that failed",
}


@dataclass(frozen=True)
class Math:
    """A formula as plain text in Python syntax (``b*k1**2*(w - 1)``).

    ``data/`` and ``report.md`` get the text; ``report.html`` shows it as
    MathML ([`seapass.report.formula.formula_mathml`][seapass.report.formula.formula_mathml]).
    """

    text: str

    def __str__(self) -> str:
        return self.text


def formula(text: Any) -> str:
    """Inline formula markup for section text: ``$text$`` (shown as MathML).

    >>> formula("kd <= k1")
    '$kd <= k1$'
    """
    t = str(text)
    if "$" in t or "\n" in t:
        return code(t)
    return f"${t}$"


def code(text: Any) -> str:
    """``text`` as a Markdown code span, shown literally whatever it contains.

    >>> code("a`b")
    '``a`b``'
    """
    t = " ".join(str(text).split()) or " "
    longest = max((len(r) for r in re.findall(r"`+", t)), default=0)
    fence = "`" * (longest + 1)
    pad = " " if t.startswith("`") or t.endswith("`") else ""
    return f"{fence}{pad}{t}{pad}{fence}"


def literal(text: Any) -> str:
    r"""``text`` as Markdown that shows it as is, on one line (for text from users).

    Every character that can open inline markup (emphasis, code, links,
    images, raw HTML, entities, formulas) is backslash-escaped.

    >>> print(literal("[x](http://a) *b*, it's 5 $"))
    \[x\](http://a) \*b\*, it's 5 \$
    """
    return re.sub(r"([\\`*_\[\]<>!&$])", r"\\\1", " ".join(str(text).split()))


_INLINE_MATH = re.compile(r"(?<![\\$])\$([^$\n]+)\$")


def plain_text(text: str) -> str:
    """``text`` without formula markup (``$x$`` becomes ``x``), for ``data/``.

    >>> plain_text("derived - printed = $b*w**2$")
    'derived - printed = b*w**2'
    """
    return _INLINE_MATH.sub(lambda m: m.group(1), text)


_FILE = re.compile(r"^[A-Za-z0-9_.-]+$")


class UpperEnd(float):
    """A table cell that is the upper end of a passive set (a largest passive value): shown
    rounded down, so the printed number is itself passive; data files keep the double."""

    __slots__ = ()


def format_cell(value: Any) -> str:
    """Human-readable cell: floats to 4 significant digits (an `UpperEnd` rounded down),
    booleans as yes/NO."""
    if value is None:
        return "–"
    if isinstance(value, UpperEnd) and math.isfinite(value):
        return decimal_down(float(value), 4)
    if isinstance(value, Math):
        return value.text
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
    """``[a, b] ∪ {c}`` with 6 significant digits, rounded inward (every printed end is in
    its interval); an end at ``hi`` is marked as the search limit."""
    if not intervals:
        return "none"
    parts = []
    for a, b in intervals:
        a_text, b_text = inward_text(a, b, 6)
        end = b_text + (" (search limit)" if b >= hi else "")
        parts.append(f"[{a_text}, {end}]" if a != b else f"{{{a_text}}}")
    return " ∪ ".join(parts)


def _csv_cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, Math):
        return value.text
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ("" if math.isnan(value) else str(value))
    return str(value)


@dataclass(frozen=True)
class Table:
    """A table of values; written as ``data/<name>.csv`` and shown in the report.

    ``highlight`` lists ``(row index, column name)`` cells to flag
    (discrepancies); a ``False`` cell is always flagged.  ``views`` optionally
    splits a wide table for display into ``(subtitle, column names)`` parts;
    the CSV always has every column.
    """

    name: str
    title: str
    columns: tuple[str, ...]
    rows: tuple[tuple[Any, ...], ...]
    highlight: frozenset[tuple[int, str]] = frozenset()
    note: str = ""
    views: tuple[tuple[str, tuple[str, ...]], ...] = ()

    def __post_init__(self) -> None:
        if not _FILE.match(self.name):
            raise ParameterError(f"table name {self.name!r} is not a plain file stem")
        object.__setattr__(self, "columns", tuple(self.columns))
        object.__setattr__(self, "rows", tuple(tuple(r) for r in self.rows))
        object.__setattr__(self, "highlight", frozenset(self.highlight))
        for _i, col in self.highlight:
            if col not in self.columns:
                raise ParameterError(f"table {self.name!r}: no column {col!r} to highlight")
        for _sub, cols in self.views:
            if not cols or not all(c in self.columns for c in cols):
                raise ParameterError(f"table {self.name!r}: a view has unknown columns {cols}")
        for i, r in enumerate(self.rows):
            if len(r) != len(self.columns):
                raise ParameterError(
                    f"table {self.name!r}: row {i} has {len(r)} cells, expected {len(self.columns)}"
                )

    def flagged(self, i: int, j: int) -> bool:
        """Cell ``(i, j)`` (row and column index) is flagged."""
        return (i, self.columns[j]) in self.highlight or self.rows[i][j] is False

    def view_indices(self) -> list[tuple[str, tuple[int, ...]]]:
        """The display parts as ``(subtitle, column indices)`` (one part: every column)."""
        if not self.views:
            return [("", tuple(range(len(self.columns))))]
        return [(sub, tuple(self.columns.index(c) for c in cols)) for sub, cols in self.views]

    def to_csv(self) -> str:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(self.columns)
        for r in self.rows:
            w.writerow([_csv_cell(v) for v in r])
        return buf.getvalue()


@dataclass(frozen=True)
class FigureData:
    """A rendered figure: ``figures/<name>.png`` and ``figures/<name>.svg``.

    Build it from a matplotlib figure (or its Axes) with `FigureData.of`,
    which renders both formats; every figure of a report has both.
    """

    name: str
    caption: str
    png: bytes = field(repr=False)
    svg: bytes = field(repr=False)

    def __post_init__(self) -> None:
        if not _FILE.match(self.name):
            raise ParameterError(f"figure name {self.name!r} is not a plain file stem")
        if not self.png.startswith(b"\x89PNG"):
            raise ParameterError(f"figure {self.name!r}: not PNG data")
        if b"<svg" not in self.svg[:2000]:
            raise ParameterError(f"figure {self.name!r}: not SVG data")

    @classmethod
    def of(cls, name: str, caption: str, fig: Any) -> FigureData:
        """Render ``fig`` (a figure, or Axes of it) as PNG and SVG, and close it."""
        from ..plot.style import figure_renders

        out = figure_renders(fig, ("png", "svg"))
        return cls(name, caption, out["png"], out["svg"])

    @property
    def files(self) -> dict[str, bytes]:
        """Relative path to content of every file of this figure."""
        return {f"figures/{self.name}.png": self.png, f"figures/{self.name}.svg": self.svg}


@dataclass(frozen=True)
class Finding:
    """A claim (usually the paper's) and what seapass finds: ``agrees``, ``differs`` or ``info``.

    ``claim`` and ``detail`` are inline text (``$formula$`` allowed).  A
    difference has a ``kind`` (`Discrepancy`); given none it is
    ``check failed`` (a check of seapass's own), since the paper stages name
    their kinds explicitly.
    """

    claim: str
    verdict: Verdict
    detail: str = ""
    kind: Discrepancy | None = None

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "verdict", Verdict(self.verdict))
        except ValueError:
            choices = ", ".join(v.value for v in Verdict)
            raise ParameterError(
                f"verdict must be one of {choices}, got {self.verdict!r}"
            ) from None
        if self.verdict != Verdict.DIFFERS:
            if self.kind is not None:
                raise ParameterError(f"only a finding that differs has a kind, got {self.kind!r}")
            return
        try:
            kind = Discrepancy(self.kind or Discrepancy.CHECK_FAILED)
        except ValueError:
            choices = ", ".join(k.value for k in Discrepancy)
            raise ParameterError(f"kind must be one of {choices}, got {self.kind!r}") from None
        object.__setattr__(self, "kind", kind)

    def to_dict(self) -> dict[str, str | None]:
        """Plain text (formula markup removed) for ``data/findings.json``."""
        return {
            "claim": plain_text(self.claim),
            "verdict": self.verdict,
            "kind": self.kind,
            "detail": plain_text(self.detail),
        }


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
class Summary:
    """The headline numbers of a report (`Report.summary`).

    ``counts`` has every `Verdict`; ``differences`` maps every
    `Discrepancy` to its findings as ``(section key, finding index, finding)``;
    ``problems`` are the sections that did not complete (skipped, failed, stopped at
    their budget or not run).
    """

    counts: Mapping[Verdict, int]
    differences: Mapping[Discrepancy, tuple[tuple[str, int, Finding], ...]]
    problems: tuple[Section, ...]


@dataclass(frozen=True)
class Report:
    """A titled sequence of sections.

    ``headline`` is the first line of the summary block (what was checked);
    the renderers add the counts and every difference by kind after it.
    ``incomplete`` says why the report is partial (an interrupted run, or one still
    running when it was written); empty for a complete report.
    """

    title: str
    intro: str
    sections: tuple[Section, ...]
    headline: str = ""
    incomplete: str = ""

    @property
    def findings(self) -> list[tuple[str, Finding]]:
        return [(s.title, f) for s in self.sections for f in s.findings]

    @property
    def failed(self) -> list[str]:
        return [s.key for s in self.sections if s.status == SectionStatus.FAILED]

    def summary(self) -> Summary:
        """Counts of findings by verdict, the differences by kind, the sections with problems."""
        counts = dict.fromkeys(Verdict, 0)
        diffs: dict[Discrepancy, list[tuple[str, int, Finding]]] = {k: [] for k in Discrepancy}
        for s in self.sections:
            for i, f in enumerate(s.findings):
                counts[f.verdict] += 1
                if f.kind is not None:
                    diffs[f.kind].append((s.key, i, f))
        return Summary(
            counts=MappingProxyType(counts),
            differences=MappingProxyType({k: tuple(v) for k, v in diffs.items()}),
            problems=tuple(s for s in self.sections if s.status != SectionStatus.OK),
        )

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
        if self.incomplete:
            out["data/incomplete.json"] = to_json({"complete": False, "why": self.incomplete})
        for s in self.sections:
            for t in s.tables:
                out[f"data/{t.name}.csv"] = t.to_csv()
            for name, text in s.files.items():
                out[f"data/{name}"] = text
            for fig in s.figures:
                out.update(fig.files)
        return out
