"""``seapass check`` on the numeric path: no sympy, and real SEA controllers answered.

* A numeric ``check`` (model or ``--Z``) imports neither sympy nor python-control nor
  matplotlib: the exact path parses straight to exact polynomials (issue 21, item 11).
* The most common SEA controller, a PID force loop with a filtered derivative on the
  spring force inside an impedance loop, with numbers for every parameter, is checked
  (the symbolic size budget once refused it: issue 22, item 4).  Its verdict is
  cross-checked by a numeric solve of the free-body equations (numpy, complex
  arithmetic): the witness really has ``Re Z(jω) < 0``, and the passive one has
  ``Re Z(jω) ≥ 0`` on a dense grid with every pole in the left half-plane.
"""

from __future__ import annotations

import contextlib
import io
import json
import subprocess
import sys

import numpy as np
import pytest

from seapass.cli import main
from seapass.errors import SymbolicLimitError
from seapass.model.sea import SEA
from seapass.model.stiffness import load_impedance

HEAVY = ("sympy", "control", "matplotlib", "scipy")

CF = "(kp + ki/s + kdf*s/(1 + s/wf))"  # the force-loop compensator C_f
PID_IMPEDANCE = {  # C_A = C_f k1 + ba s, C_L = (1 + C_f)(kv + bv s) - C_f k1
    "D1": "k1 + b1*s",
    "CA": f"{CF}*k1 + ba*s",
    "CL": f"(1 + {CF})*(kv + bv*s) - {CF}*k1",
}
VALUES = {"m": 0.4, "b": 3.0, "k1": 2500.0, "b1": 2.0, "kp": 2.0, "ki": 20.0,
          "kdf": 0.01, "wf": 300.0, "ba": 50.0, "kv": 1000.0, "bv": 20.0}  # fmt: skip


def _argv(values: dict[str, float]) -> list[str]:
    model = [f"--{k}={v}" for k, v in PID_IMPEDANCE.items()]
    return ["check", *model, *[f"--set={k}={v!r}" for k, v in values.items()], "--json"]


def _run(argv: list[str]) -> tuple[int, dict]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(argv)
    return code, json.loads(out.getvalue())


def _loaded_after(argv: list[str]) -> list[str]:
    """The heavy modules a fresh interpreter holds after running ``seapass ARGV``."""
    code = (
        "import json, sys; from seapass.cli import main; code = main(sys.argv[1:]); "
        f"print(json.dumps([code, [m for m in {HEAVY!r} if m in sys.modules]]))"
    )
    run = subprocess.run(
        [sys.executable, "-c", code, *argv], capture_output=True, text=True, check=True
    )
    exit_code, loaded = json.loads(run.stdout.strip().splitlines()[-1])
    assert exit_code in (0, 1), run.stderr
    return loaded


@pytest.mark.parametrize(
    "argv",
    [
        ["check", "--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "m=1", "--set", "b=10",
         "--set", "k1=1000", "--set", "b1=20", "--set", "bd=25", "--set", "kd=5000", "--json"],
        ["check", "--Z", "(s + 1)/(s + 2)"],
        _argv(VALUES),
    ],
    ids=["model", "raw Z", "PID in impedance loop"],
)  # fmt: skip
def test_a_numeric_check_imports_no_symbolic_or_plotting_library(argv):
    assert _loaded_after(argv) == []


def _z_free_body(values: dict[str, float], omegas: np.ndarray) -> np.ndarray:
    """``Z(jω)`` from a numeric solve of the three free-body equations (numpy)."""
    v = values
    out = []
    for w in omegas:
        s = 1j * w
        cf = v["kp"] + v["ki"] / s + v["kdf"] * s / (1 + s / v["wf"])
        ca = cf * v["k1"] + v["ba"] * s
        cl = (1 + cf) * (v["kv"] + v["bv"] * s) - cf * v["k1"]
        d1 = v["k1"] + v["b1"] * s
        alpha = v["m"] * s**2 + v["b"] * s
        # unknowns (X_A, F_A, F_L) for X_L = 1
        a = np.array([[alpha + d1, -1, 0], [d1, 0, 1], [ca, 1, 0]], dtype=complex)
        rhs = np.array([d1, d1, -cl], dtype=complex)
        out.append(np.linalg.solve(a, rhs)[2] / s)
    return np.array(out)


def test_the_pid_force_loop_in_an_impedance_loop_is_checked():
    # the symbolic derivation refuses it; check answers on the exact path
    with pytest.raises(SymbolicLimitError, match="model too large"):
        load_impedance(SEA(**PID_IMPEDANCE, values=dict.fromkeys(VALUES)))
    code, res = _run(_argv(VALUES))
    assert code == 0 and res["passive"] and res["realizable"]
    num, den = np.array(res["num"]), np.array(res["den"])
    omegas = np.logspace(-2, 5, 400)
    z = np.polyval(num, 1j * omegas) / np.polyval(den, 1j * omegas)
    np.testing.assert_allclose(z, _z_free_body(VALUES, omegas), rtol=1e-7)
    assert z.real.min() >= 0  # the passive verdict, on a dense grid
    poles = np.roots(den)
    assert poles.real.max() <= 1e-9 * max(1.0, np.abs(poles).max())


def test_too_little_motor_damping_is_not_passive_with_a_real_witness():
    values = {**VALUES, "ba": 5.0}
    code, res = _run(_argv(values))
    assert code == 1 and not res["passive"] and res["reason"] == "negative_real_part"
    assert _z_free_body(values, np.array([res["omega"]]))[0].real < 0


def test_bad_input_is_one_error_line(capsys):
    code = main(["check", *_argv(VALUES)[1:4], "--set", "kp=nan"])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error:") and err.count("\n") == 1
