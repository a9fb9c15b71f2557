"""The loop with its controller output delayed (seapass.sim.delayed).

Independent method: the same loop written out by hand from the free-body equations, with the
delay replaced by python-control's Padé approximation (``control.pade``, order 6: higher
orders realized through ``tf`` lose accuracy in double precision), simulated by
``control.forced_response`` on the same grid.  Stated tolerance: 2e-5 m on a 0.5 m step
(the Padé error; the method of steps itself agrees with a 8x finer grid to 1e-8 m).
"""

from __future__ import annotations

import control
import numpy as np
import pytest

from seapass.errors import ParameterError, SimulationError
from seapass.files.limits import MAX_SIM_STEPS
from seapass.model.sea import SEA
from seapass.sim.delayed import (
    DelayedSimulationResult,
    controller_latency,
    simulate_delayed,
)
from seapass.sim.metrics import tracking_metrics
from seapass.sim.scenarios import LoadDisplaced, Step
from seapass.sim.simulate import simulate

PLANT = {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 30.0}
OURS = {**PLANT, "kd": 300.0, "bd": 40.0}


def _pade_loop(v: dict[str, float], load_mass: float, tau: float, order: int = 6) -> object:
    """x_L of the loop with f_A = pade(tau) * [ka(θ−x_A) − ba v_A + kl(θ−x_L) − bl v_L]."""
    m, b, k1, b1 = v["m"], v["b"], v["k1"], v["b1"]
    ka, ba, kl, bl = (v.get(k, 0.0) for k in ("kd", "bd", "kl", "bl"))
    A = np.array([[0, 1, 0, 0],
                  [-k1 / m, -(b + b1) / m, k1 / m, b1 / m],
                  [0, 0, 0, 1],
                  [k1 / load_mass, b1 / load_mass, -k1 / load_mass, -b1 / load_mass]])  # fmt: skip
    bf = np.array([0.0, 1.0 / m, 0.0, 0.0])
    cy, dy = np.array([-ka, -ba, -kl, -bl]), ka + kl
    num, den = control.pade(tau, order)
    p = control.ss(control.tf(num, den))
    ad, bd, cd, dd = (np.asarray(x, float) for x in (p.A, p.B, p.C, p.D))
    nd = ad.shape[0]
    a = np.zeros((4 + nd, 4 + nd))
    a[:4, :4] = A + dd[0, 0] * np.outer(bf, cy)
    a[:4, 4:] = np.outer(bf, cd[0])
    a[4:, :4] = np.outer(bd[:, 0], cy)
    a[4:, 4:] = ad
    bt = np.concatenate([bf * dd[0, 0] * dy, bd[:, 0] * dy])
    c = np.zeros((1, 4 + nd))
    c[0, 2] = 1.0
    return control.ss(a, bt[:, None], c, 0)


def _seapass(v: dict[str, float], mass: float, tau: float, **kw: object) -> DelayedSimulationResult:
    ca = "kd + bd*s" if "kd" in v else "0"
    cl = "kl + bl*s" if "kl" in v else "0"
    sea = SEA(D1="k1 + b1*s", CA=ca, CL=cl, values=v)
    r = simulate_delayed(sea, load_mass=mass, delay_time=tau, **kw)  # type: ignore[arg-type]
    assert isinstance(r, DelayedSimulationResult)
    return r


@pytest.mark.parametrize(
    ("v", "mass", "tau"),
    [(OURS, 10.0, 0.005), (OURS, 10.0, 0.02), (OURS, 1.0, 0.02),
     ({**PLANT, "kd": 200.0, "bd": 20.0, "kl": 300.0, "bl": 10.0}, 25.0, 0.0125)],
)  # fmt: skip
def test_step_response_agrees_with_a_pade_loop_in_python_control(v, mass, tau) -> None:
    r = _seapass(v, mass, tau, scenario=Step(0.5), horizon=3.0, dt=1e-3)
    ref = control.forced_response(_pade_loop(v, mass, tau), T=r.time, U=0.5 * np.ones(r.time.size))
    assert np.max(np.abs(np.asarray(ref.outputs) - r.x_L)) < 2e-5
    # the delay matters at this tolerance: the delay-free loop is far off
    free = simulate(SEA(D1="k1 + b1*s", CA=_ca(v), CL=_cl(v), values=v),
                    load_mass=mass, scenario=Step(0.5), horizon=3.0, dt=1e-3)  # fmt: skip
    assert np.max(np.abs(free.x_L - np.interp(free.time, r.time, r.x_L))) > 100 * 2e-5


def _ca(v: dict[str, float]) -> str:
    return "kd + bd*s" if "kd" in v else "0"


def _cl(v: dict[str, float]) -> str:
    return "kl + bl*s" if "kl" in v else "0"


def test_the_method_converges_at_fourth_order_on_refinement() -> None:
    coarse = _seapass(OURS, 10.0, 0.02, horizon=2.0, dt=2e-3)
    fine = _seapass(OURS, 10.0, 0.02, horizon=2.0, dt=2.5e-4)
    mid = _seapass(OURS, 10.0, 0.02, horizon=2.0, dt=1e-3)
    e_coarse = np.max(np.abs(np.interp(coarse.time, fine.time, fine.x_L) - coarse.x_L))
    e_mid = np.max(np.abs(np.interp(mid.time, fine.time, fine.x_L) - mid.x_L))
    assert e_mid < 1e-8 and e_coarse > 8 * e_mid  # halving the step: about 16x (fourth order)


def test_rightmost_roots_agree_with_the_pade_loop_and_decide_stability() -> None:
    for v, tau, status in ((OURS, 0.02, "stable"), ({**PLANT, "kd": 3000.0, "bd": 150.0},
                                                     0.02, "unstable")):  # fmt: skip
        r = _seapass(v, 10.0, tau, horizon=1.0)
        ev = np.linalg.eigvals(_pade_loop(v, 10.0, tau).A)  # type: ignore[attr-defined]
        right = ev[np.argmax(ev.real)]
        assert str(r.status) == status
        assert r.poles[0].real == pytest.approx(right.real, rel=1e-4, abs=1e-4)
        assert abs(r.poles[0].imag) == pytest.approx(abs(right.imag), rel=1e-4)
    # the delay-free loop of the unstable case is stable: the delay destabilizes it
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**PLANT, "kd": 3000.0, "bd": 150.0})
    assert str(simulate(sea, load_mass=10.0, horizon=1.0).status) == "stable"


def test_tau_to_zero_is_the_delay_free_simulation() -> None:
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=OURS)
    free = simulate(sea, load_mass=10.0, horizon=1.0, dt=1e-3)
    same = simulate_delayed(sea, load_mass=10.0, delay_time=0.0, horizon=1.0, dt=1e-3)
    assert np.array_equal(same.x_L, free.x_L) and not isinstance(same, DelayedSimulationResult)
    errors = []
    for tau in (4e-4, 2e-4, 1e-4):
        r = simulate_delayed(sea, load_mass=10.0, delay_time=tau, horizon=1.0, dt=1e-3)
        errors.append(np.max(np.abs(np.interp(free.time, r.time, r.x_L) - free.x_L)))
    # first order in tau: halving the delay halves the difference
    assert (
        errors[2] < 2e-4 and 1.8 < errors[0] / errors[1] < 2.2 and 1.8 < errors[1] / errors[2] < 2.2
    )


def test_metrics_state_and_force_between_samples_are_consistent() -> None:
    r = _seapass(OURS, 10.0, 0.02, horizon=3.0, dt=1e-3)
    met = tracking_metrics(r)
    assert met.settled and met.settling_time is not None
    k = 123
    assert np.allclose(r.state_at(float(r.time[k])), r.states[k])
    assert r.output_at("f_A", float(r.time[k])) == pytest.approx(r.f_A[k])
    # the force is applied tau late: zero before the delay, the controller's kd*step after
    assert np.all(r.f_A[r.time < 0.02 - 1e-12] == 0.0)
    assert r.f_A[20] == pytest.approx(OURS["kd"] * 0.5)
    # between samples: the exact propagation of the step, against a grid through that time
    finer = _seapass(OURS, 10.0, 0.02, horizon=3.0, dt=5e-4)
    mid = 0.5 * float(r.time[k] + r.time[k + 1])
    assert finer.time[2 * k + 1] == pytest.approx(mid)
    assert r.state_at(mid)[2] == pytest.approx(finer.x_L[2 * k + 1], abs=1e-8)
    assert r.output_at("f_A", mid) == pytest.approx(finer.f_A[2 * k + 1], rel=1e-6)


def test_a_displaced_load_returns_to_rest() -> None:
    r = _seapass(OURS, 10.0, 0.01, scenario=LoadDisplaced(0.02), horizon=10.0)
    assert abs(r.x_L[-1]) < 1e-6 and r.x_L[0] == pytest.approx(0.02) and str(r.status) == "stable"


def test_a_model_delay_on_the_controllers_is_the_latency() -> None:
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)", values={**OURS, "tau": 0.02})
    free, tau = controller_latency(sea)
    assert tau == 0.02 and "tau" not in free.values
    a = simulate_delayed(sea, load_mass=10.0, horizon=1.0)
    b = _seapass(OURS, 10.0, 0.02, horizon=1.0)
    assert np.array_equal(a.x_L, b.x_L)


@pytest.mark.parametrize(
    ("sea", "kw", "error", "words"),
    [(SEA(D1="k1*exp(-tau*s)", CA="kd", values={"m": 1, "b": 1, "k1": 10, "kd": 1, "tau": 0.01}),
      {}, SimulationError, "D1 has a delay"),
     (SEA(D1="k1", CA="kd*exp(-tau*s)", CL="kl", values={"m": 1, "b": 1, "k1": 10, "kd": 1,
                                                         "kl": 1, "tau": 0.01}),
      {}, SimulationError, "C_A and C_L must each be exp"),
     (SEA(D1="k1", CA="kd*exp(-tau*s)", values={"m": 1, "b": 1, "k1": 10, "kd": 1, "tau": 0.01}),
      {"delay_time": 0.01}, ParameterError, "give the latency once"),
     (SEA(D1="k1", CA="kd", values={"m": 1, "b": 1, "k1": 10, "kd": 1}),
      {"delay_time": -0.01}, ParameterError, "delay_time must be >= 0"),
     (SEA(D1="k1", CA="kd", values={"m": 1, "b": 1, "k1": 10, "kd": 1}),
      {"delay_time": 1e-7, "horizon": 1.0}, ParameterError, f"limit of {MAX_SIM_STEPS}")],
)  # fmt: skip
def test_bad_input(sea: SEA, kw: dict[str, object], error: type, words: str) -> None:
    with pytest.raises(error, match=words):
        simulate_delayed(sea, load_mass=1.0, **kw)  # type: ignore[arg-type]
