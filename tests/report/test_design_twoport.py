"""The two-port section of ``seapass analyze``: the library's verdicts, shown and checked.

The section must say what `seapass.ports` decides (the same JSON as
``seapass twoport check`` on the same file), and its witness pair must
destabilize the SEA's *physical* equations, written out here by hand
(independent of the two-port derivation).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from seapass.cli import main
from seapass.exact.rounding import decimal_down
from seapass.model.design_file import load_design
from seapass.report.analyze import analyze
from seapass.report.document import SectionStatus, Verdict

DESIGN = """\
name = "coupling"
title = "Damped spring, actuator PD, load-side P"

[model]
D1 = "k1 + b1*s"
CA = "kd + bd*s"
CL = "kl"

[parameters]
m = 1.0
b = 10.0
k1 = 1000.0
b1 = 20.0
kd = 500.0
bd = 25.0
kl = {kl}

[ranges]
kl = [0.0, 10000.0]
"""
#: The exact absolutely-stable set of kl in [0, 1e4] (`seapass twoport bound kl`), rounded.
KL_EDGE = 1523.919


def _file(tmp_path: Path, kl: float) -> Path:
    path = tmp_path / f"coupling_{kl:g}.toml"
    path.write_text(DESIGN.format(kl=kl))
    return path


def _csv(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as fh:
        return list(csv.DictReader(fh))


def physical_poles(par: dict[str, float], person: dict, env: dict) -> np.ndarray:
    """Poles of the SEA held by a person (port 1) and a virtual environment (port 2).

    ``q = (x_A, x_L, θ)``: ``m ẍ_A + b ẋ_A = f_A + k1 (x_L − x_A) + b1 (ẋ_L − ẋ_A)``,
    ``m_h ẍ_L + b_h ẋ_L + k_h x_L = −k1 (x_L − x_A) − b1 (ẋ_L − ẋ_A)``,
    ``m_v θ̈ + b_v θ̇ + k_v θ = −f_A``, ``f_A = kd (θ − x_A) + bd (θ̇ − ẋ_A) + kl (θ − x_L)``.
    """
    m, b, k1, b1, kd, bd, kl = (par[k] for k in ("m", "b", "k1", "b1", "kd", "bd", "kl"))
    mass = np.array([m, person["mass"], env["mass"]])
    damp = np.array(
        [
            [b + b1 + bd, -b1, -bd],
            [-b1, person["damping"] + b1, 0.0],
            [-bd, 0.0, env["damping"] + bd],
        ]
    )
    stiff = np.array(
        [
            [k1 + kd, -k1 + kl, -(kd + kl)],
            [-k1, person["stiffness"] + k1, 0.0],
            [-kd, -kl, env["stiffness"] + kd + kl],
        ]
    )
    a = np.zeros((6, 6))
    a[:3, 3:] = np.eye(3)
    a[3:, :3] = -stiff / mass[:, None]
    a[3:, 3:] = -damp / mass[:, None]
    return np.linalg.eigvals(a)


def test_absolutely_stable_design(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _file(tmp_path, 300.0)
    out = tmp_path / "stable"
    rc = main(["analyze", str(path), "--out", str(out), "--stages", "twoport", "--no-progress"])
    assert rc == 0
    capsys.readouterr()
    verdicts = {r["question"]: r for r in _csv(out / "data/twoport_verdicts.csv")}
    assert verdicts["absolutely stable (Llewellyn)"]["answer"] == "True"
    ranges = {r["parameter"]: r for r in _csv(out / "data/twoport_ranges.csv")}["kl"]
    assert ranges["value is absolutely stable"] == "True"
    assert ranges["exact absolutely-stable set"] == f"[0, {decimal_down(KL_EDGE, 6)}]"
    for name in ("twoport_eta", "twoport_minors"):
        assert (out / f"figures/{name}.png").is_file() and (out / f"figures/{name}.svg").is_file()
    # the section's data is what `seapass twoport check FILE --json` prints, key for key
    assert main(["twoport", "check", str(path), "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert json.loads((out / "data/twoport.json").read_text()) == cli
    assert cli["absolutely_stable"] is True and cli["witness"] is None
    friction = json.loads((out / "data/friction.json").read_text())
    assert set(friction) == {"actuator", "transmission"}
    assert "Two-port: any passive person" in (out / "report.md").read_text()


def test_not_absolutely_stable_design_has_a_physical_witness(tmp_path: Path) -> None:
    kl = 5000.0
    design = load_design(_file(tmp_path, kl))
    (sec,) = analyze(design, stages=["twoport"]).sections[:1]
    assert sec.key == "twoport" and sec.status is SectionStatus.OK
    assert sec.findings[0].verdict is Verdict.DIFFERS
    assert "NOT absolutely stable" in sec.text
    tables = {t.name: t for t in sec.tables}
    assert tables["twoport_verdicts"].rows[0][1] is False
    witness = tables["twoport_witness"]
    assert witness.columns[1:5] == (
        "mass [kg]", "damping [N·s/m]", "stiffness [N/m]", "growth rate [1/s]"
    )  # fmt: skip
    person, env = (
        dict(zip(("mass", "damping", "stiffness"), r[1:4], strict=True)) for r in witness.rows
    )
    assert min(*person.values(), *env.values()) >= 0  # passive terminations
    poles = physical_poles(dict(design.values), person, env)
    assert poles.real.max() > 0  # the physical SEA, so held, is unstable
    assert poles.real.max() == pytest.approx(witness.rows[0][4], rel=1e-6)
    ranges = {r[0]: r for r in tables["twoport_ranges"].rows}["kl"]
    assert ranges[3] is False and ranges[4] == f"[0, {decimal_down(KL_EDGE, 6)}]"


def test_without_coupling_eta_does_not_exist(tmp_path: Path) -> None:
    """No controller: ``z12 = z21 = 0``, absolutely stable, η undefined and not drawn."""
    path = tmp_path / "spring.toml"
    path.write_text(
        'name = "spring"\n[model]\nD1 = "k1"\n[parameters]\nm = 1.0\nb = 10.0\nk1 = 1000.0\n'
    )
    (sec,) = analyze(load_design(path), stages=["twoport"]).sections[:1]
    assert sec.status is SectionStatus.OK and sec.findings[0].verdict is Verdict.AGREES
    assert [f.name for f in sec.figures] == ["twoport_minors"]
    assert "undefined" in sec.text


def test_analyze_help_names_the_stage(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["analyze", "--help"])
    assert "twoport" in capsys.readouterr().out
    path = _file(tmp_path, 300.0)
    assert main(["analyze", str(path), "--out", str(tmp_path / "o"), "--stages", "twoports"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and "twoport" in err[0]


def test_a_box_adds_the_robust_two_port_verdict_as_twoport_check_prints_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """With ``[uncertainty]`` the section also decides both criteria over the box; its
    ``twoport_robust.json`` is what ``seapass twoport check FILE --json`` prints for that
    file, and a box reaching past the kl edge at some plant gives a verified worst plant."""
    path = tmp_path / "boxed.toml"
    path.write_text(DESIGN.format(kl=300.0) + "\n[uncertainty]\nm = [0.9, 1.1]\n")
    out = tmp_path / "boxed"
    rc = main(["analyze", str(path), "--out", str(out), "--stages", "twoport", "--no-progress"])
    assert rc == 0
    capsys.readouterr()
    robust = json.loads((out / "data/twoport_robust.json").read_text())
    assert main(["twoport", "check", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == robust
    assert robust["robust"] is True and robust["status"] == "passive"
    assert "Over the `[uncertainty]` box" in (out / "report.md").read_text()
    hot = tmp_path / "hot.toml"
    hot.write_text(DESIGN.format(kl=1500.0) + "\n[uncertainty]\nm = [0.9, 1.1]\nb = [8.0, 12.0]\n")
    (sec,) = analyze(load_design(hot), stages=["twoport"]).sections[:1]
    assert "Worst plant" in sec.text and sec.findings[-1].verdict is Verdict.DIFFERS
