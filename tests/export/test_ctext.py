"""User text in generated C (issue 20, item 1): one escaping mechanism, checked by a compiler.

A design title like ``t */ #define double float /*`` used to close the banner
comment of ``seapass_ctrl.h`` and turn the controller into single precision
while the export still said "certified".  Every value the C templates print
goes through `seapass.export.ctext`; here hostile texts are escaped, compiled
under the strict flags, and the preprocessor's macros and the controller's
commands are compared with those of a plain title, bit for bit.
"""

from __future__ import annotations

import dataclasses
import re
import shutil
import subprocess
from pathlib import Path

import jinja2
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from seapass.cli import main
from seapass.errors import FileFormatError, ParameterError
from seapass.export import compile_c, equivalence_inputs, export_c
from seapass.export.c_code import HEADER, SOURCE, ExportResult, render_c
from seapass.export.compiled import CFLAGS, find_c_compiler
from seapass.export.ctext import (
    CText,
    c_comment,
    c_identifier,
    c_number,
    c_string,
    finalize,
)
from seapass.export.deployment import plan_deployment
from seapass.model.design_file import load_design

ROOT = Path(__file__).resolve().parents[2]
CC = find_c_compiler()
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler (cc, gcc or clang) on PATH")

HOSTILE = [
    "t */ #define double float /*",  # the attack: close the comment, define a macro
    "*/",
    "/* nested",
    "a ??/",  # a trigraph backslash at the end of the line
    "??= ??( ??) ??' ??< ??> ??! ??-",
    "ends with a backslash \\",
    "back\\\nslash-newline continuation",
    "carriage\rreturn */ #define x 1",
    "NUL\x00byte",
    "vertical\x0btab\x0cform feed\ttab",
    "non-ASCII: Fédération, 東京, 🦾, \u202e bidi override \u2028 line sep",
    "\"quoted\" and 'single' // line comment",
    "#define SEAPASS_CTRL_CERTIFIED 0",
    "/",
    "*",
    "*/*/*/",
]


def decode_comment(text: str) -> str:
    """Inverse of c_comment: every backslash starts \\xHH, \\uHHHH or \\UHHHHHHHH."""
    return re.sub(
        r"\\(?:x([0-9a-f]{2})|u([0-9a-f]{4})|U([0-9a-f]{8}))",
        lambda m: chr(int(next(g for g in m.groups() if g), 16)),
        text,
    )


@given(st.text())
def test_comment_text_cannot_end_or_nest_a_comment(text: str) -> None:
    out = c_comment(text)
    assert isinstance(out, CText)
    assert all(" " <= ch <= "~" for ch in out)  # printable ASCII: no newline, CR, NUL
    assert "*/" not in out and "/*" not in out and "??" not in out
    assert re.fullmatch(r"(?:[^\\]|\\x[0-9a-f]{2}|\\u[0-9a-f]{4}|\\U[0-9a-f]{8})*", out)
    assert decode_comment(out) == text


@given(st.text())
def test_string_text_is_printable_and_closed(text: str) -> None:
    out = c_string(text)
    assert all(" " <= ch <= "~" for ch in out)
    assert re.fullmatch(r'(?:[^\\"?]|\\[\\"?]|\\[0-7]{3})*', out)


def test_plain_text_is_unchanged() -> None:
    for text in ("Pure spring, load-side P (paper baseline)", "1/500 rounded to 0.002", "x/y*z"):
        assert c_comment(text) == text


@pytest.mark.parametrize(
    ("name", "why"),
    [
        ("double", "C keyword"),
        ("bool", "C keyword"),
        ("new", "C\\+\\+ keyword"),
        ("class", "C\\+\\+ keyword"),
        ("_Kd", "reserve"),
        ("k__d", "reserve"),
        ("NULL", "standard headers"),
        ("DBL_MAX", "standard headers"),
        ("seapass_ctrl_step", "seapass_"),
        ("SEAPASS_CTRL_MAGIC", "seapass_"),
        ("k d", "not a C identifier"),
        ("1kd", "not a C identifier"),
        ("kd*/", "not a C identifier"),
        ("x" * 64, "not a C identifier"),
    ],
)
def test_identifiers_that_c_cannot_take_are_refused(name: str, why: str) -> None:
    with pytest.raises(ParameterError, match=why):
        c_identifier(name, "gain name")


def test_identifiers_and_numbers_pass() -> None:
    assert c_identifier("kd") == "kd" and c_identifier("K_1x") == "K_1x"
    assert c_number("-0x1.8p+1") == "-0x1.8p+1" and c_number("1e-05") == "1e-05"
    for bad in ("inf", "nan", "1; x", "0x1p+0 /*"):
        with pytest.raises(ParameterError):
            c_number(bad)


def test_templates_print_nothing_unfiltered() -> None:
    env = jinja2.Environment(finalize=finalize, undefined=jinja2.StrictUndefined)
    assert env.from_string("{{ n }}").render(n=3) == "3"
    with pytest.raises(TypeError, match="without a filter"):
        env.from_string("/* {{ title }} */").render(title="*/ evil")


# ------------------------------------------------------------------ compiled


@pytest.fixture(scope="module")
def lp_deployment():
    """LP on a damped spring, certified once; the titles below only change text."""
    return plan_deployment(_parse(damped_lp()), force_limit=100.0)


def damped_lp() -> str:
    """examples/lp.toml on a damped spring (passive at its 500 Hz rate)."""
    text = (ROOT / "examples" / "lp.toml").read_text()
    text = text.replace('D1 = "k1"', 'D1 = "k1 + b1*s"')
    return text.replace("k1 = 1000.0", "k1 = 1000.0\nb1 = 20.0")


def _parse(text: str):
    import tomllib

    from seapass.model.design_file import parse_design

    return parse_design(tomllib.loads(text))


def with_title(dep, title: str):
    """``dep`` with its design's title forced to ``title`` (the loader would refuse some)."""
    design = dataclasses.replace(dep.design, title="x")
    object.__setattr__(design, "title", title)  # past validation: the escaping must hold alone
    return dataclasses.replace(dep, design=design)


def write(dep, folder: Path) -> ExportResult:
    folder.mkdir()
    for name, text in render_c(dep).items():
        (folder / name).write_text(text, encoding="utf-8")
    return ExportResult(header=folder / HEADER, source=folder / SOURCE, deployment=dep)


def macros(header: Path) -> set[str]:
    proc = subprocess.run(
        [CC, "-std=c99", "-E", "-dM", "-x", "c", str(header)], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    return set(proc.stdout.splitlines())


@needs_cc
def test_hostile_titles_compile_to_the_same_controller(lp_deployment, tmp_path: Path) -> None:
    base = write(lp_deployment, tmp_path / "base")
    base_macros = macros(base.header)
    inputs = equivalence_inputs(3000, seed=3)
    base_u = compile_c(base).run(*inputs)
    assert np.any(base_u != 0.0)
    for i, title in enumerate(HOSTILE):
        res = write(with_title(lp_deployment, title), tmp_path / f"t{i}")
        header = res.header.read_text(encoding="utf-8")
        assert header.isascii() and "\r" not in header and "\x00" not in header
        banner = next(line for line in header.splitlines() if line.startswith(" * Design: "))
        assert decode_comment(banner) == f" * Design: LP -- {title}"
        assert macros(res.header) == base_macros, title  # no #define got in
        # -Werror: no trigraph, nested-comment or multi-line-comment warning either
        u = compile_c(res).run(*inputs)  # compiles under CFLAGS
        assert np.array_equal(u, base_u), title  # bit for bit
        assert res.source.read_text() == base.source.read_text().replace(
            '"LP".', f'"{c_comment("LP")}".'
        )


@needs_cc
@pytest.mark.skipif(shutil.which("c++") is None, reason="no C++ compiler for the header check")
def test_hostile_titles_keep_the_header_valid_cpp(lp_deployment, tmp_path: Path) -> None:
    res = write(with_title(lp_deployment, " | ".join(HOSTILE)), tmp_path / "h")
    sketch = tmp_path / "sketch.cpp"
    sketch.write_text('#include "seapass_ctrl.h"\nint main() { return SEAPASS_CTRL_CERTIFIED; }\n')
    flags = ["-std=c++11", "-Wall", "-Wextra", "-Werror", "-pedantic", "-fsyntax-only"]
    proc = subprocess.run(
        ["c++", *flags, f"-I{res.header.parent}", str(sketch)], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr


@needs_cc
def test_cli_export_of_the_attack_title(tmp_path: Path, capsys) -> None:
    text = damped_lp()
    evil = tmp_path / "evil.toml"
    evil.write_text(re.sub(r'title = ".*"', 'title = "t */ #define double float /*"', text))
    out = tmp_path / "fw"
    argv = ["export", "c", str(evil), "--out", str(out), "--force-limit", "100", "--verify"]
    assert main(argv) == 0
    assert "identical to the Python controller" in capsys.readouterr().out
    assert not any(m.startswith("#define double") for m in macros(out / HEADER))
    proc = subprocess.run(
        [CC, *CFLAGS, "-c", "-o", str(tmp_path / "c.o"), str(out / SOURCE)],
        capture_output=True, text=True,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr


def test_titles_with_control_characters_are_refused_at_load(tmp_path: Path) -> None:
    base = (ROOT / "examples" / "lp.toml").read_text()
    for bad in ("a\\rb", "a\\u0000b", "a\\u202eb"):
        f = tmp_path / "d.toml"
        f.write_text(base.replace(base.split("\n")[3], f'title = "{bad}"'))
        with pytest.raises(FileFormatError, match="title"):
            load_design(f)


def test_a_gain_c_cannot_name_is_refused_before_any_work(tmp_path: Path, capsys) -> None:
    text = (ROOT / "examples" / "lp.toml").read_text().replace("kd", "new")
    f = tmp_path / "d.toml"
    f.write_text(text)
    assert main(["export", "c", str(f), "--out", str(tmp_path / "o"), "--force-limit", "5"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "gain name 'new' is a C++ keyword" in err
    assert not (tmp_path / "o").exists()
    with pytest.raises(ParameterError, match="C\\+\\+ keyword"):
        export_c(load_design(f), tmp_path / "o", force_limit=5.0)
