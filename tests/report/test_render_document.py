"""The report's document model and renderings: formulas as MathML, escaping, summary, links."""

from __future__ import annotations

import html
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from markupsafe import escape

from helpers import OURS_TEXT, tiny_report, write_file
from seapass.model.design_file import load_design
from seapass.report.document import (
    Discrepancy,
    FigureData,
    Finding,
    Math,
    Report,
    Section,
    Table,
    Verdict,
    code,
    formula,
    literal,
    plain_text,
)
from seapass.report.formula import decimal_rational, formula_mathml
from seapass.report.output import write_report
from seapass.report.render import CSP, render_html, render_markdown

MATHML_TAGS = {"math", "mrow", "mi", "mn", "mo", "msub", "msup", "mfrac", "msqrt", "mtext"}


def _elements(ml: str) -> set[str]:
    # MathML as the browser gets it, with the one named entity the printer may emit
    root = ET.fromstring(ml.replace("&#x2062;", "\u2062").replace("&#x2061;", "\u2061"))
    return {el.tag for el in root.iter()}


# ------------------------------------------------------------------------------ formulas


@pytest.mark.parametrize(
    ("text", "pieces"),
    [
        ("kd <= k1", ["<msub><mi>k</mi><mi>d</mi></msub>", "<mo>≤</mo>",
                      "<msub><mi>k</mi><mn>1</mn></msub>"]),
        ("b*k1**2*(w - 1)*(w + 1)", ["<msup><msub><mi>k</mi><mn>1</mn></msub><mn>2</mn></msup>",
                                     "<mi>ω</mi>", "<mo>(</mo>"]),
        ("(k1 + b1*s)/(m*s**2 + b*s + k1)", ["<mfrac>", "<msup><mi>s</mi><mn>2</mn></msup>"]),
        ("(kd <= k1) & (kd <= (b**2 + b*b1)/m)", ["<mo>∧</mo>", "<mfrac>"]),
        ("(a >= 0) | (c >= 0)", ["<mo>∨</mo>"]),
        ("x_A - 1e-05*kd", ["<msub><mi>x</mi><mi>A</mi></msub>", "<mn>−5</mn>"]),
        ("k1^2", ["<msup>"]),
        ("True", ["<mtext>true</mtext>"]),
        ("sqrt(m)*Abs(x)", ["<msqrt>", "<mo>|</mo>"]),
    ],
)  # fmt: skip
def test_formulas_become_mathml(text: str, pieces: list[str]) -> None:
    ml = formula_mathml(text)
    assert ml is not None and ml.startswith(f'<math alttext="{html.escape(text)}"')
    for piece in pieces:
        assert piece in ml
    assert _elements(ml) <= MATHML_TAGS


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ("a - (b + c)", "<mo>−</mo><mrow><mo>(</mo>"),  # the parentheses stay
        ("a*(-b)", "<mo>(</mo><mrow><mo>−</mo>"),
        ("-b**4*b1", "<mrow><mrow><mo>−</mo><msup>"),  # no spurious parentheses
        ("2*b**3*b1", "<mrow><mrow><mn>2</mn><mo>&#x2062;</mo><msup>"),
        ("(a + b)**2", "<msup><mrow><mo>(</mo>"),
    ],
)
def test_parentheses_follow_precedence(text: str, shown: str) -> None:
    ml = formula_mathml(text)
    assert ml is not None and shown in ml


@pytest.mark.parametrize(
    "text",
    ["", "import os", "__import__('os').system('x')", "a.b", "lambda: 1", "f(x)", "x[0]",
     "'<script>'", "a if b else c", "x" * 5000, "+".join(["x"] * 2000), "a = 1"],
)  # fmt: skip
def test_non_formulas_are_refused(text: str) -> None:
    assert formula_mathml(text) is None


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet="ab12+-*/()<>=&|^ ._$`", max_size=40))
def test_any_text_gives_wellformed_mathml_or_none(text: str) -> None:
    ml = formula_mathml(text)
    if ml is not None:
        assert _elements(ml) <= MATHML_TAGS


def test_decimal_coefficients() -> None:
    s = sp.Symbol("s")
    noisy = (sp.Rational(1152921504606847, 10**12) * s**3 + 2 * s) / (2 * s**2 + 4)
    assert decimal_rational(noisy, s) == "(576.461*s**3 + s)/(s**2 + 2)"
    assert decimal_rational(sp.Integer(3), s) == "3"
    assert decimal_rational(s - 2, s) == "s - 2"
    assert decimal_rational(sp.Symbol("k") * s, s) == "k*s"  # not numeric: unchanged


# ------------------------------------------------------------------------ document model


def test_findings_carry_their_kind() -> None:
    assert Finding("c", Verdict.DIFFERS).kind == Discrepancy.CHECK_FAILED
    f = Finding("bound $kd <= k1$", "differs", "x = $a*b$", kind="unsafe bound")
    assert f.kind is Discrepancy.UNSAFE
    assert f.to_dict() == {"claim": "bound kd <= k1", "verdict": "differs",
                           "kind": "unsafe bound", "detail": "x = a*b"}  # fmt: skip
    with pytest.raises(ValueError, match="only a finding that differs"):
        Finding("c", Verdict.AGREES, kind=Discrepancy.PAPER_TYPO)
    with pytest.raises(ValueError, match="kind must be one of"):
        Finding("c", Verdict.DIFFERS, kind="typo")  # type: ignore[arg-type]


def test_markup_helpers() -> None:
    assert formula("a*b") == "$a*b$" and formula("a$b").startswith("`")
    assert code("x`y") == "``x`y``"
    assert plain_text("p $x$ and `y`") == "p x and `y`"
    assert literal("*a* [b](c)") == "\\*a\\* \\[b\\](c)"


def _png() -> bytes:
    from matplotlib.figure import Figure

    from seapass.plot.style import figure_bytes

    return figure_bytes(Figure(figsize=(1, 1)))


def _report() -> Report:
    table = Table("t", "T <i>", ("a", "formula"), ((1.5, Math("kd <= k1")), ("x|y", Math("?"))))
    sec = Section(
        key="s",
        title="S & co",
        text="Text with $b*w**2$, `code`, **bold**, <script>alert(1)</script>, "
        "[a link](http://example.com) and " + literal("[x](http://evil) <b>") + ".\n\n"
        "```math\nk1 - kd >= 0\n```",
        tables=(table,),
        figures=(FigureData("f", "cap $x$", _png(), b'<svg xmlns="http://www.w3.org/2000/svg"/>'),),
        findings=(
            Finding("claim $kd <= k1$", Verdict.DIFFERS, "d*e*f", kind=Discrepancy.UNSAFE),
            Finding("other", Verdict.AGREES),
        ),
        files={"x.json": "{}\n"},
    )
    return Report("R <1>", "intro", (sec,), headline="**Reproduced:** S")


def test_html_is_escaped_self_contained_and_linked() -> None:
    page = render_html(_report())
    assert f'content="{escape(CSP)}"' in page and "default-src 'none'" in CSP
    assert "<script>alert" not in page and "&lt;script&gt;alert" in page
    assert "R &lt;1&gt;" in page and "T &lt;i&gt;" in page and "S &amp; co" in page
    # no network: no absolute link survives, markdown or literal
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:|//)""", page)
    assert "[x](http://evil) &lt;b&gt;" in page
    # formulas: inline, block, cells; a cell that is not a formula shows as code
    assert page.count("<math alttext") == 7  # text, block, cell, caption, 3 × the claim
    assert '<div class="math-block"><math' in page and "<code>?</code>" in page
    # every data reference is a link; figures link PNG and SVG
    for path in ("data/t.csv", "data/x.json", "figures/f.png", "figures/f.svg",
                 "data/findings.json"):  # fmt: skip
        assert f'<a href="{path}">' in page
    # the summary comes first, with the differences by kind, linked to the findings
    summary = page.index('id="summary"')
    assert summary < page.index("<table") and summary < page.index('id="sec-s"')
    block = page[summary : page.index("</section>", summary)]
    assert "Unsafe bounds" in block and 'href="#finding-s-0"' in block
    assert 'id="finding-s-0"' in page and "differs: unsafe bound" in page


def test_markdown_keeps_formulas_as_code() -> None:
    md = render_markdown(_report())
    assert "`b*w**2`" in md and "```\nk1 - kd >= 0\n```" in md and "$" not in md
    assert "| `kd <= k1` |" in md and "| x\\|y |" in md and "d\\*e\\*f" in md
    assert "**differs: unsafe bound**" in md
    assert "[`data/t.csv`](data/t.csv)" in md and "[SVG](figures/f.svg)" in md
    assert md.index("## Summary") < md.index("## S & co")


def test_written_report_has_svg_and_plain_data(tmp_path: Path) -> None:
    out = tmp_path / "r"
    write_report(_report(), out)
    assert (out / "figures/f.svg").read_bytes().startswith(b"<svg")
    assert (out / "data/t.csv").read_text() == "a,formula\n1.5,kd <= k1\nx|y,?\n"
    assert '"claim": "claim kd <= k1"' in (out / "data/findings.json").read_text()


# --------------------------------- user text in titles (moved from test_hardening, issue 12 item 9)


def test_html_in_a_title_is_shown_not_run_in_markdown(tmp_path: Path) -> None:
    md = render_markdown(
        tiny_report(title="<script>alert(1)</script> ok", text="<img src=x onerror=y>")
    )
    assert "<script>" not in md and "<img" not in md
    assert "&lt;script>alert(1)&lt;/script> ok" in md
    f = write_file(tmp_path, OURS_TEXT.replace('title = "', 'title = "<script>alert(1)</script>'))
    assert load_design(f).title.startswith("<script>")  # accepted as text, escaped on output
