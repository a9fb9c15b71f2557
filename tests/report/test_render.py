"""User text in report.md stays text (issue 20, items 1 and 5): no live link, image or markup.

The rendered Markdown is read back by an independent CommonMark parser
(markdown-it-py, the reference algorithm) and by the GitHub-flavoured one
where installed: the title must come out as the same text, with no link,
image, emphasis or HTML.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from markdown_it import MarkdownIt

from seapass.cli import main
from seapass.report.document import Report, Section
from seapass.report.render import render_markdown

ROOT = Path(__file__).resolve().parents[2]

TITLES = [
    "[click me](https://evil.example/steal)",
    "![pixel](https://evil.example/track.png)",
    "[ref][1] and [1]: https://evil.example",
    "a\\[b\\](https://evil.example) c",  # a user's backslash must not undo the escape
    "<https://evil.example> and <b>bold</b>",
    "*em* _em_ **strong** \\*x\\*",
    "pipe | in a title",
]


def tokens_of(md: str, title_line: str) -> list:
    """Inline tokens of the first line of ``md`` that starts with ``title_line``."""
    line = next(x for x in md.splitlines() if x.startswith(title_line))
    return MarkdownIt("commonmark").parseInline(line[len(title_line) :])[0].children


def shown_text(children: list) -> str:
    return "".join(t.content for t in children if t.type in ("text", "text_special", "code_inline"))


@pytest.mark.parametrize("title", TITLES)
def test_title_in_markdown_is_plain_text(title: str) -> None:
    md = render_markdown(Report(title=title, intro="intro", sections=(Section("a", "A", "t"),)))
    children = tokens_of(md, "# ")
    kinds = {t.type for t in children}
    assert not kinds & {"link_open", "image", "em_open", "strong_open", "html_inline"}, kinds
    assert shown_text(children) == title  # every character shown as typed
    html = MarkdownIt("commonmark").render(md)
    assert "evil.example" not in "".join(re.findall(r'(?:href|src)="([^"]*)"', html))


def test_design_title_with_a_link_through_analyze(tmp_path: Path, capsys) -> None:
    text = (ROOT / "examples" / "lp.toml").read_text()
    text = re.sub(r'title = ".*"', 'title = "see [docs](https://evil.example)"', text)
    f = tmp_path / "d.toml"
    f.write_text(text)
    out = tmp_path / "r"
    assert main(["analyze", str(f), "--out", str(out), "--stages", "passivity", "--quick"]) == 0
    md = (out / "report.md").read_text()
    html = MarkdownIt("commonmark").render(md)
    assert "evil.example" in md and 'href="https://evil.example' not in html
    assert "https://evil.example" not in "".join(re.findall(r'href="([^"]*)"', html))
    page = (out / "report.html").read_text()
    assert 'href="https://evil.example' not in page
