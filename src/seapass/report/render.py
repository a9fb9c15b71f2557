"""Renderings of a [`Report`][seapass.report.document.Report]: ``report.html`` and ``report.md``.

``report.html`` embeds every figure as a base64 ``data:`` URI, has inline CSS
only, and a Content-Security-Policy that forbids any network access.  A tiny
inline script records, on load, how many images decoded (``data-images-*``
attributes on ``<body>``) so a headless browser can check the page.
"""

from __future__ import annotations

import base64
import html
import re
from collections.abc import Sequence
from typing import Any

from .document import Finding, Report, Table, format_cell

__all__ = ["render_html", "render_markdown"]


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


_TAG = re.compile(r"<(?=[A-Za-z/!?])")


def _md_safe(text: str) -> str:
    """Neutralize HTML tags outside code spans: user text (a design title) is shown, never run.

    ``<script>`` becomes ``&lt;script>``, which every Markdown viewer shows as
    typed; ``x < 0`` is left alone.
    """
    parts = re.split(r"(`[^`]*`)", text)
    return "".join(p if i % 2 else _TAG.sub("&lt;", p) for i, p in enumerate(parts))


def _md_plain(text: str) -> str:
    """Markdown-escape ``*`` outside code spans (data such as ``w**2`` is not emphasis)."""
    parts = re.split(r"(`[^`]*`)", _md_safe(text))
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


def _md_cell(value: Any) -> str:
    return _md_plain(format_cell(value)).replace("|", "\\|").replace("\n", " ")


def _table_md(t: Table) -> list[str]:
    lines = [f"### {_md_safe(t.title)}", ""]
    if t.note:
        lines += [_md_safe(t.note), ""]
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
    lines = [f"# {_md_safe(report.title)}", "", _md_safe(report.intro.strip()), ""]
    for s in report.sections:
        lines += [f"## {_md_safe(s.title)}", ""]
        if s.status != "ok":
            lines += [f"*{s.status}*", ""]
        if s.text.strip():
            lines += [_md_safe(s.text.strip()), ""]
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
            cap = _md_safe(fig.caption)
            lines += [f"![{cap}](figures/{fig.name}.png)", "", f"*{cap}*", ""]
        if s.files:
            lines += ["more data: " + ", ".join(f"`data/{n}`" for n in s.files), ""]
    return "\n".join(lines).rstrip() + "\n"
