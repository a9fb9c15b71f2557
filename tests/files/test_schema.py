"""One declarative checker for design and rig files: the same words for the same mistakes."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from seapass.errors import FileFormatError
from seapass.files.schema import Field, check_table
from seapass.model.design_file import parse_design
from seapass.rig.rigfile import paper_rig, parse_rig

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _design(**changes: object) -> dict:
    doc = tomllib.loads((EXAMPLES / "ours.toml").read_text())
    for path, value in changes.items():
        section, _, key = path.partition("__")
        if key:
            doc[section][key] = value
        else:
            doc[section] = value
    return doc


def _rig(section: str, key: str, value: object) -> dict:
    doc = paper_rig().to_dict()
    doc[section][key] = value
    return doc


@pytest.mark.parametrize(
    ("design", "rig", "says"),
    [
        (_design(control__hz=1), _rig("control", "hz", 1), r"unknown key control\.hz; allowed keys: rate, "),
        (_design(control__rate="500"), _rig("control", "rate", "500"), r"control\.rate: expected a number, got str '500'"),
        (_design(control__rate=0.5), _rig("control", "rate", 0.5), r"control\.rate: 0\.5 is out of range \[1, 1e\+06\]"),
        (_design(control__rate=float("nan")), _rig("control", "rate", float("nan")), r"control\.rate: must be finite"),
        (_design(control__delay=1.5), _rig("control", "delay", 1.5), r"control\.\w+: expected an integer, got 1\.5"),
        (_design(simulation__load_masses=[1.0] * 100), _rig("experiment", "load_masses", [1.0] * 100), r"load_masses: 100 entries; the limit is 64"),
    ],
)  # fmt: skip
def test_design_and_rig_files_say_the_same(design: dict, rig: dict, says: str) -> None:
    for parse, doc in ((parse_design, design), (parse_rig, rig)):
        with pytest.raises(FileFormatError, match=says):
            parse(doc)


def test_missing_keys_and_sections() -> None:
    fields = {"a": Field(float, hint="in Hz"), "t": Field(dict, fields={"b": Field(int)})}
    with pytest.raises(FileFormatError, match=r"missing required key a \(in Hz\)"):
        check_table({"t": {"b": 1}}, fields)
    with pytest.raises(FileFormatError, match=r"missing required section \[t\]"):
        check_table({"a": 1.0}, fields)
    with pytest.raises(FileFormatError, match=r"missing required key t\.b"):
        check_table({"a": 1.0, "t": {}}, fields)
    with pytest.raises(FileFormatError, match=r"\[t\] must be a table, got int"):
        check_table({"a": 1.0, "t": 3}, fields)
    with pytest.raises(FileFormatError, match="a thing must be a TOML table, got list"):
        check_table([], fields, what="a thing")
    assert check_table({"a": 2, "t": {"b": 3}}, fields) == {"a": 2.0, "t": {"b": 3}}


def test_pairs_free_keys_and_text() -> None:
    fields = {
        "p": Field(dict, keys=r"[a-z]+", item=Field(tuple, 0.0, order="<="), required=False),
        "s": Field(str, hi=5, line=True, choices=("ab", "a\tb"), required=False),
        "x": Field(float, -1.0, 1.0, nonzero=True, required=False, default=0.5),
    }
    assert check_table({"p": {"m": [1, 2]}}, fields) == {"p": {"m": (1.0, 2.0)}, "x": 0.5}
    for doc, says in (
        ({"p": {"M": [1, 2]}}, r"p\.M: not a valid name"),
        ({"p": {"m": [2, 1]}}, r"p\.m: need lo <= hi, got \[2, 1\]"),
        ({"p": {"m": [-1, 1]}}, r"p\.m\[0\]: must be >= 0, got -1"),
        ({"p": {"m": [1]}}, r"p\.m: expected \[lo, hi\], got \[1\]"),
        ({"s": "abcdef"}, r"s: 6 characters; the limit is 5"),
        ({"s": "a\nb"}, r"s: contains the control character U\+000A"),
        ({"s": "abc"}, r"s: expected 'ab' or 'a\\tb', got 'abc'"),
        ({"x": 0}, r"x: must be nonzero"),
        ({"x": True}, r"x: expected a number, got bool True"),
    ):
        with pytest.raises(FileFormatError, match=says):
            check_table(doc, fields)
