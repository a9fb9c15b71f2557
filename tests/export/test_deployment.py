"""The gain envelope of ``export c`` covers the controller gains, never the plant (issue 22)."""

from __future__ import annotations

import contextlib
import io
import tomllib
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.errors import ParameterError
from seapass.export.deployment import plan_deployment
from seapass.model.design_file import parse_design

# an impedance loop around a P force loop: k1 turns deflection into force inside C_A, C_L
P_FORCE = """
name = "p-force"
[model]
D1 = "k1 + b1*s"
[controller]
kind = "impedance"
force = "kp"
impedance = "kv + bv*s"
damping = "ba"
feedforward = true
[parameters]
m = 0.4
b = 3.0
k1 = 2500.0
b1 = 2.0
kp = 2.0
kv = 1000.0
bv = 5.0
ba = 20.0
[ranges]
kv = [0.0, 5000.0]
[control]
rate = 1000.0
"""


def test_the_envelope_holds_the_gains_and_not_k1() -> None:
    design = parse_design(tomllib.loads(P_FORCE))
    assert design.CA == "kp*k1 + ba*s"
    dep = plan_deployment(design, force_limit=100.0, set_gains=True, tunable=["kv"])
    assert [g.name for g in dep.gains] == ["ba", "bv", "kp", "kv"]
    kv = next(g for g in dep.gains if g.name == "kv")
    assert kv.low == 0.0 and 1000.0 < kv.high < 5000.0
    with pytest.raises(ParameterError, match="'k1' is a plant parameter of 'p-force'"):
        plan_deployment(design, force_limit=100.0, set_gains=True, tunable=["k1"])


def test_export_c_refuses_a_plant_parameter_as_tunable(tmp_path: Path) -> None:
    path = tmp_path / "p.toml"
    path.write_text(P_FORCE, encoding="utf-8")
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["export", "c", str(path), "--out", str(tmp_path / "c"), "--force-limit",
                     "100", "--set-gains", "--tunable", "k1"])  # fmt: skip
    lines = err.getvalue().splitlines()
    assert code == 2 and len(lines) == 1 and "'k1' is a plant parameter" in lines[0]
    assert not (tmp_path / "c").exists()
