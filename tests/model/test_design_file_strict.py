"""Strict loading of design TOML files."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers import (
    OURS_TEXT,
    PAPER_RIG_TEXT,
    one_error,
    write_file,
)
from hostile import (
    design_doc,
    mutate,
    no_marker,  # noqa: F401 (a fixture)
)
from seapass.cli import main
from seapass.errors import (
    FileFormatError,
    SeapassError,
)
from seapass.model.design_file import Design, load_design, parse_design
from seapass.rig.rigfile import load_rig

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


# -------------------------------------------------- mutated design documents (moved from test_fuzz)


@pytest.mark.usefixtures("no_marker")
@settings(max_examples=200, deadline=3000)
@given(data=st.data())
def test_design_documents_fail_with_file_format_errors(data):
    design = pytest.importorskip("seapass.model.design_file")
    doc = mutate(data.draw, design_doc())
    try:
        d = design.parse_design(doc)
    except SeapassError:
        return
    # a document that parses is a usable design: its model builds and its values are exact
    sea = d.sea()
    assert set(sea.free_parameters) == set()
    assert d.to_dict()["name"] == d.name


# ------------------------- bounded design files (moved from test_hardening, issue 12 items 1, 7, 9)


def test_design_delay_is_capped_at_load_time(tmp_path: Path) -> None:
    f = write_file(tmp_path, OURS_TEXT.replace("delay = 1 ", "delay = 1000000000 "))
    with pytest.raises(FileFormatError, match=r"control\.delay"):
        load_design(f)
    one_error(["analyze", str(f), "--out", str(tmp_path / "o")], "control.delay", "100")


def test_design_load_masses_list_is_capped(tmp_path: Path) -> None:
    masses = ", ".join(["1.0"] * 200_000)
    f = write_file(
        tmp_path, OURS_TEXT.replace("load_masses = [1.0, 10.0, 25.0]", f"load_masses = [{masses}]")
    )
    one_error(["analyze", str(f), "--out", str(tmp_path / "o")], "load_masses", "200,000")


def test_design_rig_file_must_be_a_small_regular_file(tmp_path: Path) -> None:
    for target in ("/dev/zero", str(tmp_path / "missing.toml")):
        f = write_file(tmp_path, OURS_TEXT.replace('preset = "paper"', f'file = "{target}"'))
        one_error(["analyze", str(f), "--out", str(tmp_path / "o")], "rig.file", target)


@pytest.mark.parametrize(
    ("old", "new", "key"),
    [
        ("rate = 500.0", "rate = 1e-300", "control.rate"),
        ("horizon = 10.0", "horizon = 1e12", "simulation.horizon"),
        ("step = 0.5", "step = 1e9", "simulation.step"),
        ("velocity_filter = 50.0", "velocity_filter = 1e300", "control.velocity_filter"),
        ("tune_mass = 10.0", "tune_mass = 1e300", "simulation.tune_mass"),
        ("kd = 1708.0", "kd = 1e-400", "too small for a float"),
    ],
)
def test_design_values_out_of_range_are_refused(
    tmp_path: Path, old: str, new: str, key: str
) -> None:
    assert old in OURS_TEXT
    f = write_file(tmp_path, OURS_TEXT.replace(old, new))
    with pytest.raises(FileFormatError, match=key):
        load_design(f)


def test_title_length_is_capped(tmp_path: Path) -> None:
    f = write_file(tmp_path, OURS_TEXT.replace('title = "', 'title = "' + "x" * 300))
    with pytest.raises(FileFormatError, match="title: 3"):
        load_design(f)
    rig = write_file(
        tmp_path,
        PAPER_RIG_TEXT.replace('description = "', 'description = "' + "y" * 5000),
        "rig.toml",
    )
    with pytest.raises(FileFormatError, match="description"):
        load_rig(rig)


def test_huge_title_file_is_refused_by_size(tmp_path: Path) -> None:
    f = write_file(tmp_path, OURS_TEXT.replace('title = "', 'title = "' + "x" * 20_000_000))
    one_error(["analyze", str(f), "--out", str(tmp_path / "o")], "larger than the limit")
