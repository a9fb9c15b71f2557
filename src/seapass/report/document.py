"""Report content and its renderings: a self-contained ``report.html`` and ``report.md``.

A :class:`Report` is a sequence of :class:`Section` objects, each holding
short text (a small Markdown subset: paragraphs, ``- `` lists, fenced code,
```code``` and ``**bold**``), :class:`Table` objects, :class:`FigureData`
(PNG bytes) and :class:`Finding` objects (a claim of the paper checked
against seapass).  The stages of :mod:`seapass.report.reproduce` and
:mod:`seapass.report.analyze` build them; this module only renders and writes.

``report.html`` embeds every figure as a base64 ``data:`` URI, has inline CSS
only, and a Content-Security-Policy that forbids any network access.  A tiny
inline script records, on load, how many images decoded (``data-images-*``
attributes on ``<body>``) so a headless browser can check the page.

:func:`write_report` writes the whole directory (``report.html``,
``report.md``, ``data/``, ``figures/``) into a temporary sibling directory and
swaps it in only when complete: an interrupted run leaves the previous
directory untouched.
"""

from __future__ import annotations

import base64
import csv
import html
import io
import json
import math
import os
import re
import shutil
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from ..errors import ParameterError
from ..files.atomic import atomic_write, atomic_write_text

__all__ = [
    "MARKER",
    "FigureData",
    "Finding",
    "Report",
    "Section",
    "Table",
    "check_output_dir",
    "figure_png",
    "format_cell",
    "format_intervals",
    "render_html",
    "render_markdown",
    "to_json",
    "write_report",
]

#: File that marks a directory as written by seapass (safe to replace).
MARKER = ".seapass-report"

_STATUSES = ("ok", "skipped", "failed")
_VERDICTS = ("agrees", "differs", "info")
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
    verdict: str
    detail: str = ""

    def __post_init__(self) -> None:
        if self.verdict not in _VERDICTS:
            raise ParameterError(f"verdict must be one of {_VERDICTS}, got {self.verdict!r}")

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
    status: str = "ok"

    def __post_init__(self) -> None:
        if self.status not in _STATUSES:
            raise ParameterError(f"status must be one of {_STATUSES}, got {self.status!r}")
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
        return [s.key for s in self.sections if s.status == "failed"]

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


def figure_png(fig: Any, *, dpi: int = 110) -> bytes:
    """Render a matplotlib figure to byte-stable PNG (no software/date metadata) and close it."""
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})
    finally:
        plt.close(fig)
    return buf.getvalue()


# ----------------------------------------------------------------------- text


# emphasis only at word boundaries, so "w**2*(k1**2" (sympy output) stays as it is
_BOLD = re.compile(r"(?<![\w*])\*\*(?=\S)(.+?)(?<=\S)\*\*(?![\w*])")
_ITALIC = re.compile(r"(?<![\w*])\*(?=[^\s*])([^*]+?)(?<=\S)\*(?![\w*])")


def _inline_html(text: str, *, emphasis: bool = True) -> str:
    """Escape ``text``; ```code``` spans always, ``**bold**``/``*italic*`` if ``emphasis``."""
    out = []
    for i, part in enumerate(re.split(r"(`[^`]*`)", text)):
        if i % 2:
            out.append(f"<code>{html.escape(part[1:-1])}</code>")
        else:
            esc = html.escape(part)
            if emphasis:
                esc = _BOLD.sub(r"<strong>\1</strong>", esc)
                esc = _ITALIC.sub(r"<em>\1</em>", esc)
            out.append(esc)
    return "".join(out)


def _md_plain(text: str) -> str:
    """Markdown-escape ``*`` outside code spans (data such as ``w**2`` is not emphasis)."""
    parts = re.split(r"(`[^`]*`)", text)
    return "".join(p if i % 2 else p.replace("*", "\\*") for i, p in enumerate(parts))


def _blocks(text: str) -> list[tuple[str, list[str]]]:
    """Split the Markdown subset into ("p" | "ul" | "pre", lines) blocks."""
    blocks: list[tuple[str, list[str]]] = []
    lines = text.strip("\n").splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("```"):
            j = i + 1
            while j < len(lines) and not lines[j].startswith("```"):
                j += 1
            blocks.append(("pre", lines[i + 1 : j]))
            i = j + 1
        elif not line.strip():
            i += 1
        elif line.startswith("- "):
            items: list[str] = []
            while i < len(lines) and (lines[i].startswith("- ") or lines[i].startswith("  ")):
                if lines[i].startswith("- "):
                    items.append(lines[i][2:])
                else:
                    items[-1] += " " + lines[i].strip()
                i += 1
            blocks.append(("ul", items))
        else:
            para = []
            while i < len(lines) and lines[i].strip() and not lines[i].startswith(("- ", "```")):
                para.append(lines[i].strip())
                i += 1
            blocks.append(("p", [" ".join(para)]))
    return blocks


def _text_html(text: str) -> str:
    out = []
    for kind, lines in _blocks(text):
        if kind == "pre":
            out.append(f"<pre>{html.escape(chr(10).join(lines))}</pre>")
        elif kind == "ul":
            out.append("<ul>" + "".join(f"<li>{_inline_html(x)}</li>" for x in lines) + "</ul>")
        else:
            out.append(f"<p>{_inline_html(lines[0])}</p>")
    return "\n".join(out)


# ----------------------------------------------------------------------- HTML

_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",sans-serif;
margin:0 auto;max-width:1100px;padding:1.5em;color:#1f2328;line-height:1.45;font-size:15px}
h1{font-size:1.7em;margin-bottom:.2em}h2{border-bottom:2px solid #d0d7de;padding-bottom:.2em;
margin-top:2em}h3{font-size:1.05em;margin-top:1.4em}
table{border-collapse:collapse;margin:.6em 0 1.2em;font-size:13px;display:block;overflow-x:auto}
th,td{border:1px solid #d0d7de;padding:3px 7px;text-align:left;vertical-align:top}
th{background:#f6f8fa}td.flag{background:#ffebe9;color:#82071e;font-weight:600}
code,pre{font-family:"DejaVu Sans Mono",Menlo,Consolas,monospace;font-size:12.5px}
pre{background:#f6f8fa;padding:.6em;overflow-x:auto}
figure{margin:1em 0}figure img{max-width:100%;height:auto;border:1px solid #eaeef2}
figcaption{font-size:13px;color:#57606a}
.badge{display:inline-block;padding:0 .5em;border-radius:1em;font-size:12px;font-weight:600}
.agrees{background:#dafbe1;color:#116329}.differs{background:#ffebe9;color:#82071e}
.info{background:#ddf4ff;color:#0550ae}.skipped{background:#fff8c5;color:#7d4e00}
.failed{background:#ffebe9;color:#82071e}.ok{background:#dafbe1;color:#116329}
nav ul{columns:2}
"""

_SCRIPT = """
window.addEventListener("error",function(){var b=document.body;
b.dataset.scriptErrors=String(Number(b.dataset.scriptErrors||0)+1);});
window.addEventListener("load",function(){var imgs=document.images,ok=0;
for(var i=0;i<imgs.length;i++){if(imgs[i].complete&&imgs[i].naturalWidth>0){ok++;}}
document.body.dataset.imagesTotal=String(imgs.length);
document.body.dataset.imagesLoaded=String(ok);});
"""

_CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'; script-src 'unsafe-inline'"


def _views(t: Table) -> list[tuple[str, tuple[int, ...]]]:
    return list(t.views) or [("", tuple(range(len(t.columns))))]


def _table_html(t: Table) -> str:
    parts = []
    for sub, cols in _views(t):
        head = "".join(f"<th>{html.escape(t.columns[j])}</th>" for j in cols)
        body = []
        for i, r in enumerate(t.rows):
            cells = []
            for j in cols:
                cls = ' class="flag"' if t.flagged(i, j) else ""
                cells.append(f"<td{cls}>{_inline_html(format_cell(r[j]), emphasis=False)}</td>")
            body.append("<tr>" + "".join(cells) + "</tr>")
        if sub:
            parts.append(f"<p><strong>{html.escape(sub)}</strong></p>")
        parts.append(f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>")
    note = f"<p>{_inline_html(t.note)}</p>" if t.note else ""
    return (
        f'<h3 id="table-{t.name}">{html.escape(t.title)}</h3>{note}{"".join(parts)}'
        f"<p><small>data: <code>data/{t.name}.csv</code></small></p>"
    )


def _findings_html(findings: Sequence[tuple[str, Finding]], with_section: bool) -> str:
    if not findings:
        return ""
    head = "<th>section</th>" if with_section else ""
    rows = []
    for sec, f in findings:
        s = f"<td>{html.escape(sec)}</td>" if with_section else ""
        rows.append(
            f"<tr>{s}<td>{_inline_html(f.claim, emphasis=False)}</td>"
            f'<td><span class="badge {f.verdict}">{f.verdict}</span></td>'
            f"<td>{_inline_html(f.detail, emphasis=False)}</td></tr>"
        )
    return (
        f"<table><thead><tr>{head}<th>claim</th><th>verdict</th><th>detail</th></tr></thead>"
        f"<tbody>{''.join(rows)}</tbody></table>"
    )


def render_html(report: Report) -> str:
    """The whole report as one self-contained HTML page (figures as data URIs)."""
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f'<meta http-equiv="Content-Security-Policy" content="{_CSP}">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{html.escape(report.title)}</title>",
        f"<style>{_CSS}</style>",
        f"<script>{_SCRIPT}</script>",
        "</head><body>",
        f"<h1>{html.escape(report.title)}</h1>",
        _text_html(report.intro),
        "<nav><h2>Contents</h2><ul>",
    ]
    for s in report.sections:
        parts.append(
            f'<li><a href="#sec-{s.key}">{html.escape(s.title)}</a> '
            f'<span class="badge {s.status}">{s.status}</span></li>'
        )
    parts.append('<li><a href="#findings">All findings</a></li></ul></nav>')
    for s in report.sections:
        parts.append(f'<section id="sec-{s.key}"><h2>{html.escape(s.title)}</h2>')
        if s.status != "ok":
            parts.append(f'<p><span class="badge {s.status}">{s.status}</span></p>')
        parts.append(_text_html(s.text))
        if s.findings:
            parts.append("<h3>Findings</h3>")
            parts.append(_findings_html([("", f) for f in s.findings], with_section=False))
        for t in s.tables:
            parts.append(_table_html(t))
        for fig in s.figures:
            b64 = base64.b64encode(fig.png).decode("ascii")
            parts.append(
                f'<figure id="fig-{fig.name}"><img src="data:image/png;base64,{b64}" '
                f'alt="{html.escape(fig.caption)}"><figcaption>{_inline_html(fig.caption)} '
                f"(<code>figures/{fig.name}.png</code>)</figcaption></figure>"
            )
        if s.files:
            names = ", ".join(f"<code>data/{html.escape(n)}</code>" for n in s.files)
            parts.append(f"<p><small>more data: {names}</small></p>")
        parts.append("</section>")
    parts.append('<section id="findings"><h2>All findings</h2>')
    parts.append(_findings_html(report.findings, with_section=True) or "<p>none</p>")
    parts.append("</section></body></html>")
    return "\n".join(parts) + "\n"


# ----------------------------------------------------------------------- Markdown


def _md_cell(value: Any) -> str:
    return _md_plain(format_cell(value)).replace("|", "\\|").replace("\n", " ")


def _table_md(t: Table) -> list[str]:
    lines = [f"### {t.title}", ""]
    if t.note:
        lines += [t.note, ""]
    for sub, cols in _views(t):
        if sub:
            lines += [f"**{sub}**", ""]
        lines.append("| " + " | ".join(t.columns[j].replace("|", "\\|") for j in cols) + " |")
        lines.append("|" + "---|" * len(cols))
        for i, r in enumerate(t.rows):
            cells = []
            for j in cols:
                c = _md_cell(r[j])
                cells.append(f"**{c}**" if t.flagged(i, j) and "`" not in c else c)
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    lines += [f"data: `data/{t.name}.csv`", ""]
    return lines


def render_markdown(report: Report) -> str:
    """The report as Markdown; figures are linked from ``figures/``."""
    lines = [f"# {report.title}", "", report.intro.strip(), ""]
    for s in report.sections:
        lines += [f"## {s.title}", ""]
        if s.status != "ok":
            lines += [f"*{s.status}*", ""]
        if s.text.strip():
            lines += [s.text.strip(), ""]
        if s.findings:
            lines += ["| claim | verdict | detail |", "|---|---|---|"]
            for f in s.findings:
                lines.append(
                    f"| {_md_plain(f.claim).replace('|', '/')} | **{f.verdict}** | "
                    f"{_md_plain(f.detail).replace('|', '/')} |"
                )
            lines.append("")
        for t in s.tables:
            lines += _table_md(t)
        for fig in s.figures:
            lines += [f"![{fig.caption}](figures/{fig.name}.png)", "", f"*{fig.caption}*", ""]
        if s.files:
            lines += ["more data: " + ", ".join(f"`data/{n}`" for n in s.files), ""]
    return "\n".join(lines).rstrip() + "\n"


# ----------------------------------------------------------------------- output


def check_output_dir(out: str | os.PathLike[str]) -> None:
    """Raise unless ``out`` is new, empty or a previous seapass output (call before long work)."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise NotADirectoryError(f"--out {str(out)!r} exists and is not a directory")
    if out.is_dir() and any(out.iterdir()) and not (out / MARKER).exists():
        raise FileExistsError(
            f"--out {str(out)!r} is a non-empty directory that seapass did not write; "
            "choose a new or empty directory (seapass replaces its own output directories only)"
        )


def write_report(report: Report, out: str | os.PathLike[str]) -> list[Path]:
    """Write ``report.html``, ``report.md``, ``data/`` and ``figures/`` into ``out``.

    Everything is written into a temporary sibling directory first; only when
    it is complete does it replace ``out`` (which must be new, empty, or a
    previous seapass output).  Returns the written paths, relative to ``out``.
    """
    target = Path(out)
    check_output_dir(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    files: dict[str, str | bytes] = {
        "report.html": render_html(report),
        "report.md": render_markdown(report),
        **report.files(),
        MARKER: "written by seapass; this directory is replaced as a whole on the next run\n",
    }
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent))
    old: Path | None = None
    try:
        for rel, content in sorted(files.items()):
            path = tmp / rel
            if isinstance(content, bytes):
                with atomic_write(path, "wb") as fh:
                    fh.write(content)
            else:
                atomic_write_text(path, content)
        os.chmod(tmp, 0o777 & ~_umask())
        if target.exists():
            old = Path(
                tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".old", dir=target.parent)
            )
            os.replace(target, old / "previous")
        os.replace(tmp, target)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None and not target.exists() and (old / "previous").exists():
            os.replace(old / "previous", target)
        raise
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    return [Path(rel) for rel in sorted(files)]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
