"""Interaction objectives of a controller given in z (``seapass.tuning.sampled_objectives``).

Independent cross-checks, written here:

* the rendered stiffness against a lock-in measurement on a fine run: the port moved
  sinusoidally, the actuator integrated exactly at T/20 (scipy's ZOH), the PD difference
  equation by hand with one sample of delay, the force's first Fourier coefficient over
  whole cycles;
* the clamped-force response against python-control: both plant transfers sampled by
  ``sample_system(..., "zoh")``, the controller and the delay as discrete transfer
  functions, closed by ``feedback``; the bandwidth by a dense grid and bisection;
* the Z-width against ``sampled_passivity`` at the value and just above it.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import control
import numpy as np
import pytest
from scipy.signal import cont2discrete

from seapass.cli import main
from seapass.errors import ParameterError
from seapass.model.design_file import load_design
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.model.zcontroller import ZController
from seapass.sampled.passivity import sampled_passivity
from seapass.tuning import InteractionObjective, tune_objective
from seapass.tuning.sampled_objectives import SampledObjectiveFunction

PLANT = {"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 2.0}
RATE = 500.0
T = 1.0 / RATE
ZC = ZController(CA="kd + bd*500*(1 - z^-1)", rate=RATE)
SEA_Z = SEA(D1="k1 + b1*s", values={**PLANT, "kd": None, "bd": None}, discrete=ZC)
LOOP = SampledLoop(rate=RATE, delay=1)
FILE = """
name = "zpd"
[model]
D1 = "k1 + b1*s"
[parameters]
m = 1.02
b = 10.0
k1 = 1005.0
b1 = 2.0
kd = 2000.0
bd = 25.0
[ranges]
{ranges}
[discrete]
rate = 500.0
CA = "kd + bd*500*(1 - z^-1)"
[control]
delay = 1
[simulation]
load_masses = [1.0]
"""
RANGES = "kd = [0.0, 40000.0]\nbd = [0.0, 60.0]"


def _file(tmp_path: Path, ranges: str = RANGES) -> Path:
    p = tmp_path / "zpd.toml"
    p.write_text(FILE.format(ranges=ranges), encoding="utf-8")
    return p


def _fn(kind: str, **kw: object) -> SampledObjectiveFunction:
    return SampledObjectiveFunction(
        InteractionObjective(kind=kind, **kw),  # type: ignore[arg-type]
        SEA_Z, ["kd", "bd"], load_masses=[1.0], loop=LOOP,
    )  # fmt: skip


def _lock_in_stiffness(kd: float, bd: float, omega: float, sub: int = 20) -> complex:
    """``F/X`` at ``omega`` measured on a fine run (see the module docstring)."""
    m, b, k1, b1 = (PLANT[k] for k in ("m", "b", "k1", "b1"))
    A = np.array([[0, 1, 0, 0], [-k1 / m, -(b + b1) / m, k1 / m, b1 / m], [0, 0, 0, 1],
                  [0, 0, -(omega**2), 0]])  # fmt: skip  # the port: x_L = X sin(ωt)
    B = np.array([[0.0], [1 / m], [0.0], [0.0]])
    Ad, Bd, *_ = cont2discrete((A, B, np.eye(4), np.zeros((4, 1))), T / sub, method="zoh")
    X = 1e-3
    x = np.array([0.0, 0.0, 0.0, X * omega])
    cycle = round(2 * math.pi / omega / T)  # samples per cycle (ω divides the rate here)
    settle = 12 * cycle
    e_prev, pending = 0.0, 0.0
    t, F, P = [], [], []
    for k in range(settle + cycle):
        e = -x[0]  # θ = 0
        u = kd * e + bd * RATE * (e - e_prev)
        e_prev, applied, pending = e, pending, u  # one sample of delay
        for i in range(sub):
            if k >= settle:
                t.append((k * sub + i) * T / sub)
                F.append(k1 * (x[2] - x[0]) + b1 * (x[3] - x[1]))
                P.append(x[2])
            x = Ad @ x + Bd[:, 0] * applied
    ph = np.exp(-1j * omega * np.array(t))
    return complex(np.mean(np.array(F) * ph) / np.mean(np.array(P) * ph))


@pytest.mark.parametrize("hz", [5.0, 25.0])
def test_rendered_stiffness_is_the_fundamental_harmonic_of_a_fine_run(hz: float) -> None:
    fn = _fn("rendering", target="600", band=(1.0, 10.0))
    omega = 2 * math.pi * hz
    got = complex(fn.stiffness_response((2000.0, 25.0), np.array([omega]))[0])
    want = _lock_in_stiffness(2000.0, 25.0, omega)
    assert abs(got - want) <= 2e-3 * abs(want)
    # at low frequency the sampled PD renders the springs in series, k1 kd/(k1 + kd)
    low = complex(fn.stiffness_response((2000.0, 25.0), np.array([1e-3]))[0])
    assert low.real == pytest.approx(1005 * 2000 / 3005, rel=1e-5)


def _python_control_force(kd: float, bd: float) -> control.TransferFunction:
    m, b, k1, b1 = (PLANT[k] for k in ("m", "b", "k1", "b1"))
    held = [m, b + b1, k1]  # the load clamped: m s² + (b + b1) s + k1
    gp = control.sample_system(control.tf([1.0], held), T, method="zoh")
    ga = control.sample_system(control.tf([b1, k1], held), T, method="zoh")
    k = control.tf([kd + bd * RATE, -bd * RATE], [1.0, 0.0], T)
    delay = control.tf([1.0], [1.0, 0.0], T)
    return ga * control.feedback(delay * k, gp)


def test_clamped_force_response_and_bandwidth_agree_with_python_control() -> None:
    fn = _fn("force-bandwidth")
    for kd, bd in ((2000.0, 25.0), (500.0, 10.0)):
        g = _python_control_force(kd, bd)
        dc = abs(float(np.real(control.dcgain(g))))
        w = np.array([1.0, 30.0, 100.0, 400.0, 1200.0])
        want = np.abs(g(np.exp(1j * w * T))) / dc
        got = fn.force_magnitude((kd, bd))
        assert callable(got) and np.allclose(got(w), want, rtol=1e-7)
        grid = np.geomspace(0.01, 0.999 * math.pi / T, 20001)
        mag = np.abs(g(np.exp(1j * grid * T))) / dc
        i = int(np.argmax(mag <= 1 / math.sqrt(2)))
        assert 0 < i and fn.force_bandwidth((kd, bd)) == pytest.approx(grid[i], rel=1e-3)
    assert fn.band[1] < math.pi / T  # the default band ends below the Nyquist frequency


def test_zwidth_value_is_certified_and_the_edge() -> None:
    fn = SampledObjectiveFunction(
        InteractionObjective(kind="zwidth", max_boxes=200), SEA_Z, ["bd"], load_masses=[1.0],
        loop=LOOP, stiffness="kd", stiffness_box=(0.0, 40000.0),
    )  # fmt: skip
    value = fn.zwidth((25.0,))
    assert 1000 < value < 40000 and fn.boxes_exhausted == 0
    at = SEA_Z.with_values(bd=25.0)
    assert sampled_passivity(at.with_values(kd=value), loop=LOOP).passive
    assert not sampled_passivity(at.with_values(kd=value * 1.01), loop=LOOP).passive


def test_tune_objective_on_a_z_design_end_to_end(tmp_path: Path) -> None:
    design = load_design(_file(tmp_path))
    r = tune_objective(design, InteractionObjective(kind="force-bandwidth"), maxiter=3,
                       popsize=4, seed=1, loop=design.loop)  # fmt: skip
    assert r.options.loop == LOOP  # the file's [control]: delay 1
    c = r.constrained
    assert r.feasible and c.stable and r.passivity_checks == 0 and r.sampled_checks >= 1
    again = sampled_passivity(r.sea, loop=LOOP)  # certified again at the printed gains
    assert again.passive and c.outcome.passive and c.sampled_outcome is c.outcome
    fn = r.function
    assert isinstance(fn, SampledObjectiveFunction)
    assert c.value == pytest.approx(fn.force_bandwidth(tuple(c.gains[g] for g in fn.full_gains)))
    start = fn.force_bandwidth(tuple({"kd": 2000.0, "bd": 25.0}[g] for g in fn.full_gains))
    assert c.value >= start  # the search saw better than the file's gains
    d = r.to_dict()
    assert d["controller_in_z"] is True and d["period"] == T and d["passive"] is True
    assert set(r.response(points=20)["curves"]) == {"passive optimum", "unconstrained"}


def test_rendering_tune_on_a_z_design(tmp_path: Path) -> None:
    design = load_design(_file(tmp_path))
    spec = InteractionObjective(kind="rendering", target="600", band=(1.0, 10.0))
    r = tune_objective(design, spec, maxiter=3, popsize=4, seed=1, loop=design.loop)
    assert r.feasible and r.constrained.at is not None
    kd = r.gains["kd"]
    assert abs(1005 * kd / (1005 + kd) - 600) < 0.2 * 600  # near the target's stiffness
    assert r.value < 0.2 and sampled_passivity(r.sea, loop=LOOP).passive


def test_bad_input(tmp_path: Path) -> None:
    design = load_design(_file(tmp_path))
    with pytest.raises(ParameterError, match=r"Nyquist frequency pi/T = 1570\.8") as exc:
        tune_objective(design, InteractionObjective(kind="rendering", target="600",
                       band=(1.0, 2000.0)), maxiter=1, popsize=2)  # fmt: skip
    assert exc.value.argument == "band"
    no_kd = load_design(_file(tmp_path, ranges="bd = [0.0, 60.0]"))
    with pytest.raises(ParameterError, match="kd: a controller in z has no default box"):
        tune_objective(no_kd, "zwidth", maxiter=1, popsize=2)
    with pytest.raises(ParameterError, match="not a gain of the controller in z"):
        tune_objective(design, "force-bandwidth", tune={"b1": (0.0, 5.0)}, allow_plant=True,
                       maxiter=1, popsize=2)  # fmt: skip


def _cli(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_objectives_on_a_z_design(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = str(_file(tmp_path))
    code, out, err = _cli(["tune", f, "--objective", "zwidth", "--tune", "bd", "--max-boxes",
                           "60", "--maxiter", "1", "--popsize", "2", "--no-progress", "--json"],
                          capsys)  # fmt: skip
    d = json.loads(out)
    assert code == 0 and d["controller_in_z"] and d["stiffness"] == "kd" and d["passive"]
    kd = d["gains"]["kd"]
    sea = SEA_Z.with_values(kd=kd, bd=d["gains"]["bd"])
    assert d["objective"] == kd and sampled_passivity(sea, loop=LOOP).passive
    code, out, err = _cli(["tune", f, "--objective", "rendering", "--target", "600", "--band",
                           "1:10", "--maxiter", "2", "--popsize", "3", "--no-progress"],
                          capsys)  # fmt: skip
    assert code == 0 and "controller in z, certified): yes" in out and "note:" not in err
    code, out, err = _cli(["tune", f, "--objective", "rendering", "--target", "600", "--band",
                           "1:2000", "--no-progress"], capsys)  # fmt: skip
    assert code == 2 and out == "" and err.count("\n") == 1 and err.startswith("error: ")
    assert "1570.8 rad/s" in err and "Traceback" not in err
