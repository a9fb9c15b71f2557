"""Hostile design files: mutated documents fail with file-format errors; every size, rate,
horizon, delay, list and title is bounded at load time (issue 12, items 1, 7 and 9)."""

from __future__ import annotations

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
from seapass.errors import (
    FileFormatError,
    SeapassError,
)
from seapass.model.design_file import load_design
from seapass.rig.rigfile import load_rig

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
