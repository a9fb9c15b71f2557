"""Design files with a ``[controller]`` table and a ``[plant]`` table; plant parameters vs gains."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from seapass.errors import FileFormatError
from seapass.model.controller import Controller, derive_controller
from seapass.model.design_file import Design, load_design, parse_design

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

CASCADE = """
name = "c"
[model]
D1 = "k1 + b1*s"
[controller]
kind = "impedance"
force = "kp + ki/s"
impedance = "kv + bv*s"
damping = "ba"
feedforward = true
[parameters]
m = 0.4
b = 3.0
k1 = 2500.0
b1 = 2.0
kp = 2.0
ki = 20.0
kv = 1000.0
bv = 5.0
ba = 20.0
"""


def _parse(text: str) -> Design:
    return parse_design(tomllib.loads(text))


def test_controller_table_compiles_into_ca_cl() -> None:
    d = _parse(CASCADE)
    assert d.CA == "(kp + ki/s)*k1 + ba*s"
    assert d.CL == "-(kp + ki/s)*k1 + (kv + bv*s)*((kp + ki/s) + 1)"
    assert d.controller == Controller(kind="impedance", force="kp + ki/s", impedance="kv + bv*s",
                                      damping="ba", feedforward=True)  # fmt: skip
    derivation = d.derivation()
    assert derivation is not None and derivation.general["CA"] == "C_f*K_s + b_a*s"
    # the symptom of issue 22: k1 is the hardware's spring, not a gain
    assert d.gains == ("ba", "bv", "ki", "kp", "kv")
    assert d.plant_parameters == ("b", "b1", "k1", "m")
    assert "k1" not in d.analysis_ranges()
    data = d.to_dict()
    assert data["controller"]["kind"] == "impedance" and data["plant"] == ["b", "b1", "k1", "m"]
    assert "controller" in d._repr_html_()


def test_a_rebuilt_design_keeps_its_controller() -> None:
    from dataclasses import replace

    d = _parse(CASCADE)
    again = replace(d, values={**d.values, "kp": 3.0})
    assert again.CA == d.CA and again.values["kp"] == 3.0


def test_explicit_ranges_make_a_plant_parameter_a_design_variable() -> None:
    d = _parse(CASCADE + "[ranges]\nk1 = [1000.0, 4000.0]\n")
    assert d.analysis_ranges()["k1"] == (1000.0, 4000.0)
    assert "k1" not in d.gains


def test_plant_table() -> None:
    text = CASCADE.replace('force = "kp + ki/s"', 'force = "(kp + ki/s)/kt"').replace(
        "[parameters]", "[plant]\nkt = 0.5\n[parameters]"
    )
    d = _parse(text)
    assert d.plant == ("kt",) and "kt" in d.plant_parameters and "kt" not in d.gains
    assert d.values["kt"] == 0.5 and d.sea().plant == ("kt",)
    assert d.to_dict()["plant"] == ["b", "b1", "k1", "kt", "m"]


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        (CASCADE.replace('D1 = "k1 + b1*s"', 'D1 = "k1 + b1*s"\nCA = "kd"'),
         r"give either \[controller\] or model.CA, not both"),
        (CASCADE.replace('kind = "impedance"', 'kind = "admittance"'),
         "controller.kind: expected 'force' or 'impedance' or 'velocity-sourced'"),
        (CASCADE.replace('force = "kp + ki/s"', 'force = "kp + ki*s"'),
         r"controller.force: the force-loop compensator 'kp \+ ki\*s' is improper"),
        (CASCADE.replace('impedance = "kv + bv*s"\n', ""),
         "controller.impedance: kind 'impedance' needs the target impedance"),
        (CASCADE.replace("bv = 5.0\n", ""),
         r"controller.impedance: unknown symbol 'bv'.*add bv to \[parameters\]"),
        (CASCADE.replace('kind = "impedance"', 'kind = "force"'),
         "controller.impedance: kind 'force' has no target impedance"),
        (CASCADE.replace("feedforward = true", 'feedforward = "yes"'),
         "controller.feedforward: expected true or false"),
        (CASCADE.replace('damping = "ba"', 'dampig = "ba"'), "unknown key controller.dampig"),
        (CASCADE.replace('kind = "impedance"\n', ""), "missing required key controller.kind"),
        (CASCADE + "[plant]\nk1 = 2000.0\n", r"plant.k1 is also in \[parameters\]"),
        (CASCADE + "[plant]\nkt = 2.0\n", "plant.kt: 'kt' is not a parameter of the model"),
    ],
)  # fmt: skip
def test_bad_controller_tables(edit: str, words: str) -> None:
    with pytest.raises(FileFormatError, match=words):
        _parse(edit)


@pytest.mark.parametrize("name", ["cascaded_impedance.toml", "velocity_sourced.toml"])
def test_controller_examples(name: str) -> None:
    d = load_design(EXAMPLES / name)
    assert d.controller is not None and d.loop is not None
    assert set(d.gains) == set(d.ranges)  # every gain has a range; no plant parameter has one
    assert not set(d.plant_parameters) & set(d.analysis_ranges())
    c = derive_controller(d.controller, parameters=d.values)
    assert (c.CA, c.CL) == (d.CA, d.CL)
