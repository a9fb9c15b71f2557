"""The unit grammar and the units of a design file's ``[units]`` table."""

from __future__ import annotations

import pytest

from seapass.errors import FileFormatError, ParameterError
from seapass.model.design_file import parse_design
from seapass.model.units import parse_unit, unit_label, unit_map

DOC = {
    "name": "u",
    "model": {"D1": "k1", "CA": "kd + ki/s"},
    "parameters": {"m": 1.0, "b": 10.0, "k1": 1000.0, "kd": 100.0, "ki": 5.0},
}


@pytest.mark.parametrize(
    ("text", "canonical"),
    [
        ("N/m", "N/m"),
        ("N*s/m", "N*s/m"),
        ("N·s/m", "N*s/m"),
        ("1/s", "1/s"),
        ("N*m/rad", "N*m/rad"),
        ("kg*m^2", "kg*m^2"),
        ("N/(m*s)", "N/(m*s)"),
        ("mN/mm", "mN/mm"),
        ("kHz", "kHz"),
        ("s^-1", "s^-1"),
        (" N / m ", "N/m"),
    ],
)
def test_units_in_the_grammar(text: str, canonical: str) -> None:
    assert parse_unit(text) == canonical


@pytest.mark.parametrize(
    "text", ["", "sec", "N**2", "N/", "2/s", "N m", "N/(m*s", "m^x", "import os", "N" * 41]
)
def test_text_outside_the_grammar_is_refused(text: str) -> None:
    with pytest.raises(ParameterError, match="unit"):
        parse_unit(text)


def test_declared_units_override_the_defaults() -> None:
    units = unit_map({"ki": "1/s"}, ["kd", "ki", "bd", "other"])
    assert units == {"kd": "N/m", "ki": "1/s", "bd": "N*s/m", "other": ""}
    assert unit_label("ki", units) == "ki [1/s]" and unit_label("other", units) == "other"


def test_a_design_file_declares_units() -> None:
    design = parse_design({**DOC, "units": {"ki": "1/s", "m_L": "g"}})
    assert design.units == {"ki": "1/s", "m_L": "g"}
    assert design.unit_map()["ki"] == "1/s" and design.unit_map()["kd"] == "N/m"
    assert design.to_dict()["units"] == {"ki": "1/s", "m_L": "g"}


@pytest.mark.parametrize(
    ("units", "needle"),
    [
        ({"ki": "1/sec"}, "units.ki: '1/sec' is not a unit"),
        ({"kx": "N/m"}, "units.kx: not a parameter of the model"),
        ({"ki": 3}, "units.ki"),
        ("N/m", "units"),
    ],
)
def test_bad_units_tables_name_the_key(units: object, needle: str) -> None:
    with pytest.raises(FileFormatError, match=needle.replace("(", r"\(").replace("'", "'")):
        parse_design({**DOC, "units": units})
