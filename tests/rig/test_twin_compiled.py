"""The twin runs the generated C like the Python controller (issue 22, item 6), step by step.

The rig twin (friction, encoder quantization, saturation, the loop's delay) is run twice on
the same seeded encoders: once with the design's Python controller
([`DiscreteController`][seapass.sampled.controllers.DiscreteController], batched difference
equations) and once with the exported C compiled by the system compiler and loaded through
ctypes ([`compile_c`][seapass.export.compiled.compile_c]), stepped one call per period.  The
trajectories must agree to round-off over a counted number of periods, for a continuous
design (discretized by seapass) and for a controller given in z (run as is).  The C has no
delay line of its own here (``hardware_delay`` = the loop's delay): the twin delays.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from seapass.export import compile_c, export_c, find_c_compiler
from seapass.model.design_file import Design, parse_design
from seapass.rig.design_sweep import design_loop
from seapass.rig.rigfile import paper_rig
from seapass.rig.twin import simulate_loop
from seapass.sampled.controllers import DiscreteController

RIG = paper_rig()
BENCH = RIG.model_values()
STEPS = 400  # control periods of each run (0.8 s at the bench's 500 Hz)
needs_cc = pytest.mark.skipif(
    find_c_compiler() is None,
    reason="no C compiler (cc, gcc or clang) on PATH and CC unset: install gcc to run these",
)

HEAD = f"""
name = "{{name}}"
[model]
D1 = "k1 + b1*s"
{{model}}
[parameters]
m = {BENCH["m"]!r}
b = {BENCH["b"]!r}
k1 = {BENCH["k1"]!r}
b1 = {BENCH["b1"]!r}
kd = 600.0
bd = 8.0
kl = 150.0
[rig]
preset = "paper"
"""
CONTINUOUS = HEAD.format(name="pdl", model='CA = "kd + bd*s"\nCL = "kl/(1 + s/40)"') + (
    "[control]\nrate = 500.0\ndelay = 1\nvelocity_filter = 50.0\n"
)
# a PD with a first-order roll-off on the actuator and a lag on the load, as flashed at 500 Hz
IN_Z = HEAD.format(name="zpdl", model="") + (
    '[discrete]\nrate = 500.0\nCA = "kd + bd*500*(1 - z^-1)/(1 + z^-1/4)"\n'
    'CL = "kl*(1 + z^-1)/2/(1 - z^-1/2)"\n[control]\ndelay = 1\n'
)


def design(text: str) -> Design:
    return parse_design(tomllib.loads(text))


def twin(dsg: Design, controller: object, load_mass: float) -> object:
    return simulate_loop(
        RIG, load_mass=load_mass, duration=STEPS * RIG.period, x0=0.02, deflection0=0.004,
        load_force=-3.0, seed=11, loop=design_loop(dsg, RIG), controllers=[controller],
    )  # fmt: skip


@needs_cc
@pytest.mark.parametrize("text", [CONTINUOUS, IN_Z], ids=["continuous", "in_z"])
@pytest.mark.parametrize("load_mass", [0.1, 0.6])
def test_twin_with_generated_c_matches_python_controller(
    text: str, load_mass: float, tmp_path: Path
) -> None:
    dsg = design(text)
    loop = design_loop(dsg, RIG)
    assert loop.delay == 1
    py = DiscreteController.for_loop(dsg.sea(), loop)
    res = export_c(dsg, tmp_path, hardware_delay=loop.delay)
    assert res.deployment.code_delay == 0
    c = compile_c(res)
    want, got = twin(dsg, py, load_mass), twin(dsg, c, load_mass)
    assert want.t.size == got.t.size == STEPS + 1
    for name in ("x_A", "x_L", "x_A_measured", "x_L_measured", "command", "force"):
        a, b = getattr(want, name), getattr(got, name)
        scale = max(1.0, float(np.abs(a).max()))
        assert np.allclose(a, b, rtol=0, atol=1e-12 * scale), name
    # the runs did something: the controller pushed (and saturated or not) and the load moved
    assert np.abs(want.command).max() > 1.0 and np.ptp(want.x_L) > 1e-3
    assert not want.diverged.any()


def test_z_design_on_twin_runs_as_is_and_refuses_another_rate() -> None:
    dsg = design(IN_Z)
    loop = design_loop(dsg, RIG)
    ctrl = DiscreteController.for_loop(dsg.sea(), loop)
    ka, kl = ctrl.transfer_functions()
    (na, da), (nl, dl) = dsg.discrete.coefficients(dsg.values)  # type: ignore[union-attr]
    assert (ka.num, ka.den, kl.num, kl.den) == (na, da, nl, dl)  # nothing re-discretized
    r = twin(dsg, ctrl, 0.1)
    assert r.t.size == STEPS + 1
    fast = dsg.sea()
    with pytest.raises(ValueError, match="runs at 500 Hz but the sampled loop at 1000 Hz"):
        DiscreteController.for_loop(fast, loop.replace(period=0.001))
