"""Strict loading of design TOML files."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.cli import main
from seapass.errors import FileFormatError
from seapass.model.design_file import Design, load_design, parse_design

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

BASE = """
name = "t"
[model]
D1 = "k1 + b1*s"
CA = "kd + bd*s"
[parameters]
m = 1.0
b = 10.0
k1 = 1000.0
b1 = 20.0
kd = 500.0
bd = 25.0
"""


def _parse(text: str) -> Design:
    return parse_design(tomllib.loads(text))


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_examples_load(path: Path) -> None:
    d = load_design(path)
    sea = d.sea()
    assert not sea.free_parameters
    assert set(d.analysis_ranges()) >= set(d.gains)


def test_minimal_design_defaults() -> None:
    d = _parse(BASE)
    assert d.D2 == "0" and d.CL == "0"
    assert d.gains == ("bd", "kd")
    assert d.load_masses == (1.0, 10.0, 25.0)
    assert d.tuning_mass == 10.0
    assert d.period is None
    assert d.analysis_ranges()["kd"] == (0.0, 5000.0)
    assert d.to_dict()["model"]["D1"] == "k1 + b1*s"


def test_control_and_rig_sections(tmp_path: Path) -> None:
    f = tmp_path / "d.toml"
    (tmp_path / "rig.toml").write_text("# checked when the rig stage reads it\n")
    f.write_text(
        BASE + "[control]\nrate = 500\ndelay = 1\nvelocity_filter = 50\n"
        '[rig]\nfile = "rig.toml"\n[simulation]\nload_masses = [0.1, 0.6]\n'
    )
    d = load_design(f)
    assert d.period == pytest.approx(0.002)
    assert d.control_delay == 1 and d.velocity_filter == 50.0
    assert d.rig_file == str(tmp_path / "rig.toml")
    assert d.tuning_mass == 0.6


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (BASE + "colour = 1\n", "colour"),
        (BASE + "[simulation]\nstepp = 1\n", "simulation.stepp"),
        (BASE + "[control]\nrate = 500\nhz = 1\n", "control.hz"),
        (BASE.replace("kd = 500.0", 'kd = "500"'), "parameters.kd"),
        (BASE.replace("kd = 500.0", "kd = true"), "parameters.kd"),
        (BASE.replace("kd = 500.0\n", ""), "parameters.kd"),
        (BASE.replace("m = 1.0\n", ""), "parameters.m"),
        (BASE.replace("m = 1.0", "m = -1.0"), "parameters.m"),
        (BASE + "k2 = 5.0\n", "parameters.k2"),
        (BASE.replace('name = "t"\n', ""), "name"),
        (BASE.replace('name = "t"', 'name = "a b/c"'), "name"),
        (BASE + "[ranges]\nkd = [0, 1, 2]\n", "ranges.kd"),
        (BASE + "[ranges]\nkd = [10, 1]\n", "ranges.kd"),
        (BASE + "[ranges]\nk2 = [0, 1]\n", "ranges.k2"),
        (BASE + "[simulation]\nload_masses = [1, -2]\n", "simulation.load_masses[1]"),
        (BASE + "[simulation]\nload_masses = []\n", "simulation.load_masses"),
        (BASE + "[simulation]\nstep = 0\n", "simulation.step"),
        (BASE + "[control]\ndelay = 1\n", "control.rate"),
        (BASE + "[control]\nrate = 500\ndelay = 1.5\n", "control.delay"),
        (BASE + "[control]\nrate = inf\n", "control.rate"),
        (BASE + '[rig]\npreset = "other"\n', "rig.preset"),
        (BASE + '[rig]\npreset = "paper"\nfile = "x"\n', "rig"),
        (BASE.replace('D1 = "k1 + b1*s"', "D1 = 3"), "model.D1"),
        (BASE.replace('D1 = "k1 + b1*s"', "D1 = \"__import__('os')\""), "model"),
        (BASE.replace('D1 = "k1 + b1*s"', 'D1 = "k1 + q*s"'), "model"),
        (BASE.replace('D1 = "k1 + b1*s"', 'D1 = ""'), "model.D1"),
        (BASE.replace("[model]", '[model]\nD3 = "1"'), "model.D3"),
        (BASE.replace("[parameters]", "[parameters]\ns = 1.0"), "parameters.s"),
    ],
)
def test_errors_name_the_key(edit: str, key: str) -> None:
    with pytest.raises(FileFormatError, match=key.replace("[", r"\[").replace("]", r"\]")):
        _parse(edit)


def test_invalid_toml_and_missing_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "bad.toml"
    f.write_text("name = \n")
    with pytest.raises(FileFormatError, match="invalid TOML"):
        load_design(f)
    assert main(["analyze", str(f), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "bad.toml" in err
    assert main(["analyze", str(tmp_path / "missing.toml"), "--out", str(tmp_path / "o")]) == 2
    assert not (tmp_path / "o").exists()


@settings(max_examples=30, deadline=None)
@given(st.from_regex(r"[a-z][a-z0-9_]{0,12}", fullmatch=True))
def test_any_unknown_top_level_key_is_rejected(key: str) -> None:
    allowed = {"name", "title", "model", "parameters", "ranges", "simulation", "control", "rig"}
    if key in allowed:
        return
    with pytest.raises(FileFormatError, match=f"unknown key {key}"):
        _parse(f"{key} = 1\n" + BASE)
