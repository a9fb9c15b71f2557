"""MuJoCo cross-check of the twin (skipped when mujoco is not installed)."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from seapass.errors import MissingExtraError, ParameterError
from seapass.rig.rigfile import paper_rig

RIG = paper_rig()


def test_missing_mujoco_gives_install_hint(monkeypatch):
    from seapass.rig import mujoco_model as mujoco_rig

    monkeypatch.setitem(sys.modules, "mujoco", None)
    with pytest.raises(MissingExtraError, match=r"pip install .seapass\[mujoco\]."):
        mujoco_rig.simulate_mujoco(RIG, load_mass=0.1, duration=0.1)


mujoco = pytest.importorskip("mujoco")

from seapass.rig.mujoco_model import build_mjcf, compare_with_twin, simulate_mujoco  # noqa: E402


def test_mjcf_structure():
    model = mujoco.MjModel.from_xml_string(build_mjcf(RIG, load_mass=0.6))
    assert model.njnt == 2 and model.ntendon == 1 and model.nu == 1
    assert model.tendon_stiffness[0] == pytest.approx(RIG.damper.k1)
    assert model.tendon_damping[0] == pytest.approx(RIG.damper.b1)
    total = model.body_mass.sum()
    assert total == pytest.approx(RIG.actuator_mass + RIG.load_side_mass(0.6))
    with pytest.raises(ParameterError):
        build_mjcf(RIG, load_mass=-1.0)


@pytest.mark.parametrize(
    "gains",
    [
        {"kp_actuator": 500.0, "kv_actuator": 25.0},
        {"kp_actuator": 2000.0, "kv_actuator": 25.0},
        {"kp_load": 800.0},
    ],
)
@pytest.mark.parametrize("ml", [0.1, 0.6])
def test_closed_loop_step_agrees_with_linear_twin(gains, ml):
    cmp = compare_with_twin(RIG, load_mass=ml, duration=0.6, **gains)
    # documented tolerance: 1 % of the 20 mm step
    assert cmp.tolerance == pytest.approx(2e-4)
    assert cmp.agree, cmp.max_error
    assert cmp.mujoco.x_L.shape == cmp.twin_x_L.shape


def test_open_loop_force_step_agrees():
    cmp = compare_with_twin(RIG, load_mass=0.1, force=5.0, x0=0.0, duration=0.5)
    assert cmp.agree
    assert cmp.twin_x_L[-1] > 0.1


def test_mujoco_detects_a_different_plant():
    # The comparison can fail: a stiffer spring in MuJoCo only breaks agreement.
    other = RIG.replace(damper={"k1": 3000.0})
    run = simulate_mujoco(
        other, load_mass=0.1, duration=0.6, kp_actuator=500.0, kv_actuator=25.0, x0=0.02
    )
    ref = compare_with_twin(RIG, load_mass=0.1, duration=0.6, kp_actuator=500.0, kv_actuator=25.0)
    assert np.max(np.abs(run.x_L - ref.twin_x_L)) > ref.tolerance
