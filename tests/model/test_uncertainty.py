"""A design file's ``[uncertainty]`` table: checked at load, kept on the `Design` (issue 26)."""

from __future__ import annotations

import tomllib

import pytest

from seapass.errors import FileFormatError
from seapass.model.design_file import Design, parse_design
from seapass.model.uncertainty import NONNEGATIVE, POSITIVE
from seapass.robust.box import NONNEGATIVE as BOX_NONNEGATIVE
from seapass.robust.box import POSITIVE as BOX_POSITIVE

BASE = """
name = "lpbox"
[model]
D1 = "k1"
CL = "kd"
[parameters]
m = 1.0
b = 10.0
k1 = 1000.0
kd = 500.0
"""


def _load(table: str) -> Design:
    return parse_design(tomllib.loads(BASE + "[uncertainty]\n" + table))


def test_the_table_is_read_sorted_and_written_back() -> None:
    d = _load("m = [0.9, 1.1]\nb = [8, 12]\n")
    assert dict(d.uncertainty) == {"b": (8.0, 12.0), "m": (0.9, 1.1)}
    assert list(d.uncertainty) == ["b", "m"]
    assert d.to_dict()["uncertainty"] == {"b": [8.0, 12.0], "m": [0.9, 1.1]}
    assert parse_design(tomllib.loads(BASE)).uncertainty == {}


def test_the_physical_rules_are_the_box_rules() -> None:
    assert POSITIVE == BOX_POSITIVE and NONNEGATIVE == BOX_NONNEGATIVE


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ("q = [1.0, 2.0]", "uncertainty.q: not a parameter of the model"),
        ("m = [1.1, 0.9]", "uncertainty.m: [1.1, 0.9] is empty"),
        ("m = [0.0, 1.1]", "uncertainty.m: [0, 1.1] includes non-physical values"),
        ("b = [-1.0, 12.0]", "uncertainty.b: [-1, 12] includes non-physical values"),
        ("m = [1.1, 1.2]", "does not contain the file's value m = 1"),
        ("k1 = [1e-3, 1e4]", "spans more than 6 decades"),
        ("kd = [0.0, 1e13]", "exceeds |value| <= 1e+12"),
        ("m = [0.9]", "uncertainty.m"),
        ('m = [0.9, "x"]', "uncertainty.m[1]"),
        ("m = [0.9, nan]", "uncertainty.m"),
    ],
)
def test_a_bad_entry_names_the_key(table: str, message: str) -> None:
    with pytest.raises(FileFormatError, match="uncertainty") as info:
        _load(table + "\n")
    assert message in str(info.value)


def test_too_many_entries_are_refused_before_any_work() -> None:
    text = BASE.replace("[model]", "[model]").replace('CL = "kd"', 'CL = "kd + a1 + a2 + a3 + a4"')
    text = text.replace("kd = 500.0", "kd = 500.0\na1 = 1.0\na2 = 1.0\na3 = 1.0\na4 = 1.0")
    table = "".join(f"{n} = [0.5, 2.0]\n" for n in ("m", "b", "k1", "a1", "a2", "a3", "a4"))
    table = table.replace("m = [0.5, 2.0]", "m = [0.5, 1.5]").replace(
        "b = [0.5, 2.0]", "b = [5, 20]"
    )
    table = table.replace("k1 = [0.5, 2.0]", "k1 = [500, 2000]")
    with pytest.raises(FileFormatError, match=r"\[uncertainty\]: 7 entries exceed the limit of 6"):
        parse_design(tomllib.loads(text + "[uncertainty]\n" + table))


def test_a_design_built_in_python_may_hold_a_box_away_from_its_nominal_values() -> None:
    """Only a file ties the box to its nominal values (a fitted rig's box may move away)."""
    d = Design(name="x", D1="k1", CL="kd", values={"m": 1.0, "b": 10.0, "k1": 1e3, "kd": 500.0},
               uncertainty={"m": (1.1, 1.2)})  # fmt: skip
    assert d.uncertainty == {"m": (1.1, 1.2)}
    with pytest.raises(FileFormatError, match="non-physical"):
        Design(name="x", D1="k1", CL="kd", values={"m": 1.0, "b": 10.0, "k1": 1e3, "kd": 5e2},
               uncertainty={"m": (-1.0, 1.2)})  # fmt: skip
