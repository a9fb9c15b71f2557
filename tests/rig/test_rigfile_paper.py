"""Rig files: packaged paper rig, strict validation, derived quantities."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers import (
    PAPER_RIG_TEXT,
    REPO,
    forbid,
    one_error,
    write_file,
)
from hostile import (
    mutate,
    no_marker,  # noqa: F401 (a fixture)
)
from seapass.cli import main
from seapass.errors import (
    FileFormatError,
    SeapassError,
)
from seapass.rig.rigfile import Rig, load_rig, paper_rig, parse_rig

PAPER = Path(__file__).resolve().parents[2] / "src" / "seapass" / "data" / "paper_rig.toml"


def _doc() -> dict:
    return tomllib.loads(PAPER.read_text())


def _dump(d: dict) -> str:
    """Tiny TOML writer for the two-level rig layout (tests only)."""

    def val(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace('"', '\\"') + '"'
        if isinstance(v, list | tuple):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return repr(v)

    lines = [f"{k} = {val(v)}" for k, v in d.items() if not isinstance(v, dict)]
    for k, v in d.items():
        if isinstance(v, dict):
            lines.append(f"[{k}]")
            lines += [f"{kk} = {val(vv)}" for kk, vv in v.items()]
    return "\n".join(lines) + "\n"


def test_paper_rig_values_from_the_paper():
    rig = paper_rig()
    assert isinstance(rig, Rig)
    assert rig.damper.k1 == 1005.0
    assert rig.transmission.gear_ratio == 4.8
    assert rig.control.rate == 500.0
    assert rig.experiment.load_masses == (0.1, 0.6)
    assert rig.experiment.bd_ours == 25.0
    # 500 lines/inch in quadrature: 2000 counts per inch.
    assert rig.linear_resolution == pytest.approx(12.7e-6)
    # 1000 cpt x4 through 4.8:1 and a 10 mm pulley.
    assert rig.motor_resolution == pytest.approx(2 * math.pi * 0.01 / (4000 * 4.8))
    j = rig.motor.rotor_inertia * (4.8 / 0.01) ** 2
    assert rig.actuator_mass == pytest.approx(rig.transmission.carriage_mass + j)
    assert rig.force_limit == pytest.approx(rig.motor.peak_torque * 4.8 / 0.01)
    assert rig.period == pytest.approx(0.002)


def test_round_trip_through_dict():
    rig = paper_rig()
    assert parse_rig(rig.to_dict()) == rig


def test_load_rig_from_file(tmp_path):
    p = tmp_path / "r.toml"
    p.write_text(PAPER.read_text())
    assert load_rig(p) == paper_rig()


@pytest.mark.parametrize(
    ("mutate", "needle"),
    [
        (lambda d: d["damper"].update(k2=3.0), "damper.k2"),
        (lambda d: d.update(extra={"a": 1}), "extra"),
        (lambda d: d["damper"].pop("k1"), "damper.k1"),
        (lambda d: d.pop("motor"), "[motor]"),
        (lambda d: d["damper"].update(k1="1005"), "damper.k1"),
        (lambda d: d["damper"].update(k1=True), "damper.k1"),
        (lambda d: d["damper"].update(k1=-1.0), "damper.k1"),
        (lambda d: d["damper"].update(k1=0.0), "damper.k1"),
        (lambda d: d["encoders"].update(motor_cpt=1000.5), "encoders.motor_cpt"),
        (lambda d: d["encoders"].update(motor_quadrature=8), "encoders.motor_quadrature"),
        (lambda d: d["control"].update(delay=2), "control.delay"),
        (lambda d: d["experiment"].update(load_masses=[0.1, "x"]), "experiment.load_masses[1]"),
        (lambda d: d["experiment"].update(load_masses=0.1), "experiment.load_masses"),
        (lambda d: d["motor"].update(peak_torque=0.01), "motor.peak_torque"),
        (lambda d: d.update(name=3), "name"),
        (lambda d: d.update(damper=5), "[damper]"),
    ],
)
def test_strict_validation_names_the_key(mutate, needle):
    d = _doc()
    mutate(d)
    with pytest.raises(FileFormatError) as exc:
        parse_rig(d)
    assert needle in str(exc.value)


def test_bad_toml_and_file_name_in_message(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text("[damper\nk1 = 3")
    with pytest.raises(FileFormatError, match=r"bad\.toml"):
        load_rig(p)
    d = _doc()
    d["load"]["travl"] = 0.1
    q = tmp_path / "typo.toml"
    q.write_text(_dump(d))
    with pytest.raises(FileFormatError, match=r"typo\.toml.*load\.travl"):
        load_rig(q)


@settings(max_examples=40, deadline=None)
@given(st.floats(allow_nan=True, allow_infinity=True).filter(lambda x: not (0 < x <= 1e8)))
def test_out_of_range_spring_rejected(k1):
    d = _doc()
    d["damper"]["k1"] = k1
    with pytest.raises(FileFormatError, match=r"damper\.k1"):
        parse_rig(d)


@settings(max_examples=40, deadline=None)
@given(st.floats(min_value=1.0, max_value=1e6), st.floats(min_value=0.0, max_value=1e3))
def test_valid_values_accepted(k1, b1):
    d = _doc()
    d["damper"].update(k1=k1, b1=b1)
    rig = parse_rig(d)
    assert rig.damper.k1 == k1 and rig.damper.b1 == b1


def test_replace_revalidates_cross_field_rules():
    rig = paper_rig()
    assert rig.replace(damper={"b1": 0.0}).damper.b1 == 0.0
    with pytest.raises(FileFormatError, match="horizon"):
        rig.replace(experiment={"horizon": 1.0})
    with pytest.raises(FileFormatError, match=r"damper\.k9"):
        rig.replace(damper={"k9": 1.0})
    with pytest.raises(FileFormatError, match=r"damper\.k1"):
        rig.replace(damper={"k1": -5.0})


def test_cli_show_and_bad_file(tmp_path, capsys):
    assert main(["rig", "show"]) == 0
    assert "k1 = 1005.0" in capsys.readouterr().out
    d = _doc()
    d["spring"] = {"k1": 1.0}
    p = tmp_path / "bad.toml"
    p.write_text(_dump(d))
    assert main(["rig", "show", "--rig", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "spring" in err
    assert main(["rig", "sweep", "--rig", str(tmp_path / "missing.toml")]) == 2


# ----------------------------------------------------- mutated rig documents (moved from test_fuzz)


@pytest.mark.usefixtures("no_marker")
@settings(max_examples=200, deadline=3000)
@given(data=st.data())
def test_rig_documents_fail_with_file_format_errors(data):
    rig = pytest.importorskip("seapass.rig.rigfile")
    base = tomllib.loads((REPO / "src" / "seapass" / "data" / "paper_rig.toml").read_text())
    doc = mutate(data.draw, base)
    try:
        r = rig.parse_rig(doc)
    except SeapassError:
        return
    assert r.period > 0


# ----------------------------------------- step counts (moved from test_hardening, issue 12 item 3)


def test_rig_step_counts_are_capped_at_load_time(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    text = (
        PAPER_RIG_TEXT.replace("rate = 500.0", "rate = 1000000.0")
        .replace("substeps = 10", "substeps = 10000")
        .replace("horizon = 3.0", "horizon = 10000.0")
        .replace("settle_cap = 2.0", "settle_cap = 2.0")
    )
    f = write_file(tmp_path, text, "rig.toml")
    with pytest.raises(FileFormatError, match=r"experiment\.horizon"):
        load_rig(f)
    forbid(monkeypatch, "seapass.rig.experiment.run_experiment")
    one_error(["rig", "sweep", "--rig", str(f)], "control periods per run")
