"""`update_toml_text`: a rig or design file's values changed in place, every comment kept."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from helpers import (
    one_error,
    write_file,
)
from seapass.errors import FileFormatError
from seapass.files.toml import loads_strict, update_toml_text
from seapass.rig.packaged import rig_template


def test_values_change_and_comments_stay() -> None:
    text = rig_template()
    out = update_toml_text(
        text, {"transmission.viscous": 12.25, "description": 'fitted "x"', "damper.b1": 31.5}
    )
    assert out is not None
    data = tomllib.loads(out)
    assert data["transmission"]["viscous"] == 12.25 and data["damper"]["b1"] == 31.5
    assert data["description"] == 'fitted "x"'
    comments = [ln[ln.index("#") :] for ln in text.splitlines() if "#" in ln]
    kept = [ln[ln.index("#") :] for ln in out.splitlines() if "#" in ln]
    assert kept == comments and len(out.splitlines()) == len(text.splitlines())


def test_missing_keys_are_added_to_their_table() -> None:
    out = update_toml_text("a = 1\n\n[t]\nb = 2 # two\n\n[u]\n", {"t.c": 3, "u.d": "x", "e": 1.5})
    assert out is not None and tomllib.loads(out) == {
        "a": 1, "e": 1.5, "t": {"b": 2, "c": 3}, "u": {"d": "x"},
    }  # fmt: skip
    assert "b = 2 # two" in out


@pytest.mark.parametrize(
    "text",
    [
        'a = """\nmulti\n"""\n',  # a multi-line string
        "[t]\nb = [\n 1,\n 2]\n",  # a multi-line array
        "not toml = = 1\n",
    ],
)
def test_what_cannot_be_edited_line_by_line_is_refused(text: str) -> None:
    key = "t.b" if text.startswith("[t]") else "a"
    assert update_toml_text(text, {key: 5}) is None


def test_a_missing_table_is_refused() -> None:
    assert update_toml_text("a = 1\n", {"t.b": 2}) is None


# ---------------------------------- deeply nested TOML (moved from test_hardening, issue 12 item 2)


@pytest.mark.parametrize(
    "nest", ["a = " + "[" * 500 + "]" * 500, "a = " + "{b = " * 500 + "1" + "}" * 500]
)
def test_deeply_nested_toml_is_one_line(tmp_path: Path, nest: str) -> None:
    f = write_file(tmp_path, nest + "\n")
    with pytest.raises(FileFormatError, match="nested too deeply"):
        loads_strict(f.read_text())
    one_error(["analyze", str(f), "--out", str(tmp_path / "o")], "nested too deeply")
    one_error(["rig", "show", "--rig", str(f)], "nested too deeply")
    one_error(["rig", "sweep", "--rig", str(f)], "nested too deeply")


def test_moderate_nesting_beyond_the_limit_is_refused() -> None:
    with pytest.raises(FileFormatError, match="limit is 8"):
        loads_strict("a = " + "[" * 20 + "]" * 20)
