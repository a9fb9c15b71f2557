"""Renderings of a [`Report`][seapass.report.document.Report]: ``report.html`` and ``report.md``.

Both come from jinja2 templates shipped with the package
(``seapass/report/templates/``); ``report.html`` is autoescaped, and section
text is Markdown rendered by markdown-it-py with raw HTML disabled, so no text
of a report (a design name from a user's file included) can inject markup.

``report.html`` is one self-contained file: every figure is embedded as a
base64 ``data:`` URI, CSS and script are inline, formulas are MathML (rendered
by the browser, no font or script download), and a Content-Security-Policy
forbids any network access.  Links to ``data/`` and ``figures/`` (PNG and
SVG) are relative; a link with a scheme or a host in section text is shown as
text, never as a link.  A tiny inline script records, on load, how many images
decoded and how many formulas were laid out (``data-*`` attributes on
``<body>``), so a headless browser can check the page.

Text markup, beyond CommonMark: ``$formula$`` inline and a fenced block with
the info string ``math`` hold formulas as plain text; ``report.html`` shows
them as MathML ([`seapass.report.formula`][seapass.report.formula]), ``report.md`` as code.
"""

from __future__ import annotations

import base64
import html
import re
from functools import cache
from importlib import resources
from typing import Any, cast

from .document import Finding, Math, Report, Section, Table, format_cell, plain_text
from .formula import formula_mathml

__all__ = ["CSP", "render_html", "render_markdown"]

CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'; script-src 'unsafe-inline'"
"""The Content-Security-Policy of ``report.html``: no network access of any kind."""


# ------------------------------------------------------------------ markdown-it


def _math_inline(state: Any, silent: bool) -> bool:
    """``$...$`` on one line: a formula token (``$`` is a markdown-it terminator character)."""
    src, pos = state.src, state.pos
    if src[pos] != "$":
        return False
    end = src.find("$", pos + 1)
    if end <= pos + 1 or "\n" in src[pos + 1 : end]:
        return False
    if not silent:
        token = state.push("math_inline", "math", 0)
        token.content = src[pos + 1 : end]
    state.pos = end + 1
    return True


def _render_math_inline(self: Any, tokens: Any, idx: int, options: Any, env: Any) -> str:
    return _math_html(tokens[idx].content, display=False)


def _math_html(text: str, *, display: bool) -> str:
    ml = formula_mathml(text, display=display)
    if ml is not None:
        return ml
    code = f"<code>{html.escape(text)}</code>"
    return f"<pre>{code}</pre>" if display else code


_ABSOLUTE = re.compile(r"^\s*([a-z][a-z0-9+.-]*:|//|\\\\)", re.I)


def _relative_link(url: str) -> bool:
    return not _ABSOLUTE.match(url)


@cache
def _markdown(inline_only: bool) -> Any:
    """CommonMark without raw HTML (block text), or code spans and formulas only (cells)."""
    from markdown_it import MarkdownIt

    if inline_only:
        md = MarkdownIt("zero", {"html": False}).enable(["backticks", "escape"])
    else:
        md = MarkdownIt("commonmark", {"html": False})
    # links stay inside the report directory: a URL with a scheme or host is shown as text
    setattr(md, "validateLink", _relative_link)  # noqa: B010 (an instance attribute by design)
    md.inline.ruler.before("escape", "math_inline", _math_inline)
    md.add_render_rule("math_inline", _render_math_inline)
    if not inline_only:
        fence = cast(Any, md.renderer).rules["fence"]

        def render_fence(self: Any, tokens: Any, idx: int, options: Any, env: Any) -> str:
            tok = tokens[idx]
            if tok.info.strip() == "math":
                block = _math_html(" ".join(tok.content.split()), display=True)
                return f'<div class="math-block">{block}</div>\n'

            return str(fence(tokens, idx, options, env))

        md.add_render_rule("fence", render_fence)
    return md


def _md_block(text: str) -> Any:
    from markupsafe import Markup

    return Markup(_markdown(False).render(text.strip("\n")))


def _md_inline(text: Any) -> Any:
    from markupsafe import Markup

    return Markup(_markdown(True).renderInline(str(text)))


def _cell_html(value: Any) -> Any:
    from markupsafe import Markup

    if isinstance(value, Math):
        return Markup(_math_html(value.text, display=False))
    return _md_inline(format_cell(value))


# -------------------------------------------------------------- markdown output

_CODE_SPAN = re.compile(r"(`+)(.+?)(?<!`)\1(?!`)", re.S)
_MATH_SPAN = re.compile(r"(?<![\\$])\$([^$\n]+)\$")


# an HTML tag opener outside code: user text (a design title) is shown, never run;
# ``<script>`` becomes ``&lt;script>``, which every Markdown viewer shows as typed
_TAG = re.compile(r"<(?=[A-Za-z/!?])")


def _code_span(text: str) -> str:
    from .document import code

    return code(text)


def _split_code(text: str) -> list[tuple[bool, str]]:
    """``text`` in (is code span, part) pieces."""
    out, pos = [], 0
    for m in _CODE_SPAN.finditer(text):
        out += [(False, text[pos : m.start()]), (True, m.group(0))]
        pos = m.end()
    out.append((False, text[pos:]))
    return out


def _md_text(text: str) -> str:
    """Section text for ``report.md``: formulas as code (```math`` fences as plain fences)."""
    lines, fenced = [], False
    for line in str(text).strip("\n").splitlines():
        if line.startswith("```"):
            fenced = not fenced
            lines.append("```" if line.strip() == "```math" else line)
        elif fenced:
            lines.append(line)
        else:
            parts = _split_code(line)
            lines.append(
                "".join(
                    p
                    if is_code
                    else _MATH_SPAN.sub(lambda m: _code_span(m.group(1)), _TAG.sub("&lt;", p))
                    for is_code, p in parts
                )
            )
    return "\n".join(lines)


# ``*`` always, ``_`` unless inside a word (where CommonMark never reads it as emphasis),
# ``[ ]`` (links and images: a title's ``[x](https://...)`` stays text, as in report.html)
# and ``\`` (so that a user's backslash cannot undo one of these escapes)
_LITERAL = re.compile(r"[*\[\]\\]|(?<![A-Za-z0-9])_|_(?![A-Za-z0-9])")


def _md_inline_text(text: Any) -> str:
    """One line of inline Markdown (titles, cells): formulas as code, ``* _ [ ] \\ |`` literal."""
    out = []
    for is_code, part in _split_code(" ".join(str(text).split())):
        if is_code:
            out.append(part)
            continue
        pieces = _MATH_SPAN.split(part)
        for k, piece in enumerate(pieces):
            if k % 2:
                out.append(_code_span(piece))
            else:
                out.append(_LITERAL.sub(r"\\\g<0>", _TAG.sub("&lt;", piece)))
    return "".join(out).replace("|", "\\|")


def _md_cell(value: Any, flagged: bool) -> str:
    if isinstance(value, Math):
        return _code_span(value.text).replace("|", "\\|")
    text = _md_inline_text(format_cell(value))
    return f"**{text}**" if flagged and "`" not in text and text else text


# -------------------------------------------------------------------- templates


def _views(t: Table) -> list[tuple[str, tuple[int, ...]]]:
    return t.view_indices()


def _indexed(section: Section) -> list[tuple[Section, int, Finding]]:
    return [(section, i, f) for i, f in enumerate(section.findings)]


def _all_findings(report: Report) -> list[tuple[Section, int, Finding]]:
    return [item for s in report.sections for item in _indexed(s)]


def _resource(name: str) -> str:
    return resources.files("seapass.report").joinpath("templates", name).read_text("utf-8")


@cache
def _environment(as_html: bool) -> Any:
    import jinja2

    env = jinja2.Environment(
        loader=jinja2.PackageLoader("seapass.report", "templates"),
        autoescape=as_html,
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
    )
    env.filters.update(
        plain=plain_text,
        slug=lambda v: re.sub(r"[^a-z0-9]+", "-", str(v).lower()).strip("-"),
    )
    env.globals.update(views=_views)
    if as_html:
        env.filters.update(
            md=_md_block,
            inline=_md_inline,
            cell=_cell_html,
            b64=lambda b: base64.b64encode(b).decode("ascii"),
        )
        env.globals.update(indexed=_indexed, all_findings=_all_findings)
    else:
        env.filters.update(md_text=_md_text, md_inline=_md_inline_text)
        env.globals.update(md_cell=_md_cell)
    return env


def render_html(report: Report) -> str:
    """The whole report as one self-contained HTML page (figures as data URIs)."""
    from markupsafe import Markup

    template = _environment(True).get_template("report.html.j2")
    page = template.render(
        report=report,
        summary=report.summary(),
        csp=CSP,
        css=Markup(_resource("report.css")),
        script=Markup(_resource("report.js")),
    )
    return page.rstrip("\n") + "\n"


def render_markdown(report: Report) -> str:
    """The report as Markdown; figures and data files are linked."""
    template = _environment(False).get_template("report.md.j2")
    titles = {s.key: s.title for s in report.sections}
    text = template.render(report=report, summary=report.summary(), titles=titles)
    # at most one blank line between blocks, whatever the template's branches left
    return re.sub(r"\n{3,}", "\n\n", text).strip() + "\n"
