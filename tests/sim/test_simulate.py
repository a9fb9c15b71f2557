"""Simulation of a real SEA controller: a PI force loop inside an impedance loop (issue 22).

The controller's integrator is in both ``C_A`` and ``C_L``; realized once it is one state,
so the loop is stable and settles where physics says (``F/kv``).  Cross-checked against
python-control's ``forced_response`` on the same minimal realization.
"""

from __future__ import annotations

import contextlib
import io
import json
import warnings

import numpy as np

from seapass.cli import main
from seapass.model.realization import closed_loop
from seapass.model.sea import SEA
from seapass.sim.scenarios import ForceStep
from seapass.sim.simulate import simulate

VALUES = dict(m=0.4, b=3, k1=2500, b1=2, kf=0.5, ki=10, kv=1000, bv=5, ba=5)
CASCADE = SEA(
    D1="k1 + b1*s",
    CA="(kf + ki/s)*k1 + ba*s",
    CL="(1 + kf + ki/s)*(kv + bv*s) - (kf + ki/s)*k1",
    values=VALUES,
)
ARGS = ["--D1", "k1 + b1*s", "--CA", "(kf + ki/s)*k1 + ba*s",
        "--CL", "(1 + kf + ki/s)*(kv + bv*s) - (kf + ki/s)*k1",
        *[a for k, v in VALUES.items() for a in ("--set", f"{k}={v}")]]  # fmt: skip


def test_the_force_loop_settles_at_force_over_stiffness() -> None:
    res = simulate(CASCADE, load_mass=2.0, scenario=ForceStep(20.0))
    assert res.stable and not res.marginal
    assert len(res.system.states) == 5  # plant (4) + ONE integrator
    assert abs(res.target - 20.0 / 1000.0) < 1e-12
    assert abs(res.x_L[-1] - 0.02) < 1e-6


def test_cli_simulate_reports_the_right_target() -> None:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(["simulate", *ARGS, "--load-mass", "2", "--force-step", "20", "--json"])
    assert code == 0
    data = json.loads(out.getvalue())
    assert data["stable"] is True and data["marginal"] is False
    assert abs(data["target"] - 0.02) < 1e-9
    assert data["status"] == "settled"


def test_simulate_agrees_with_python_control_on_the_minimal_realization() -> None:
    import control

    res = simulate(CASCADE, load_mass=2.0, scenario=ForceStep(20.0), horizon=2.0, dt=1e-3)
    sys = closed_loop(CASCADE, load_mass=2.0).to_control()
    u = np.zeros((3, res.time.size))
    u[2] = 20.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        resp = control.forced_response(sys, T=res.time, U=u)
    y = np.asarray(resp.outputs)
    names = list(sys.output_labels)
    for name, ours in (("x_A", res.x_A), ("x_L", res.x_L), ("f_A", res.f_A)):
        theirs = y[names.index(name)]
        scale = float(np.max(np.abs(theirs)))
        assert float(np.max(np.abs(ours - theirs))) <= 1e-6 * scale, name
