"""The sampled loop's time response (``simulate`` of a controller given in z).

Independent cross-check: python-control builds the same loop from its own pieces (the
plant discretized by ``sample_system(..., "zoh")``, the controller as discrete transfer
functions, joined by ``interconnect``) and ``forced_response`` gives the same samples.
"""

from __future__ import annotations

import control
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from seapass.errors import ModelError, ParameterError
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.model.zcontroller import ZController
from seapass.sampled.response import sampled_response
from seapass.sim.scenarios import ForceStep, LoadDisplaced, Step

VALS = {"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 30.0, "kd": 800.0, "bd": 20.0, "kl": 300.0}
ZC = ZController(CA="kd + bd*500*(1 - z^-1)", CL="kl*(1 + z^-1)/2/(1 - z^-1/5)", rate=500.0)
SEA_Z = SEA(D1="k1 + b1*s", values=VALS, discrete=ZC)
LOOP = SampledLoop(rate=500.0)


def _tf(coeffs: tuple[tuple, tuple], dt: float, name: str, out: str) -> control.TransferFunction:
    num, den = ([float(c) for c in p] for p in coeffs)
    n = max(len(num), len(den))  # ascending in z^-1 == descending in z, padded alike
    num, den = num + [0.0] * (n - len(num)), den + [0.0] * (n - len(den))
    return control.tf(num, den, dt, inputs=name, outputs=out)


def _python_control_loop(load_mass: float, T: float, delay: int) -> control.InputOutputSystem:
    m, b, k1, b1, ml = VALS["m"], VALS["b"], VALS["k1"], VALS["b1"], load_mass
    A = [[0, 1, 0, 0], [-k1 / m, -(b + b1) / m, k1 / m, b1 / m], [0, 0, 0, 1],
         [k1 / ml, b1 / ml, -k1 / ml, -b1 / ml]]  # fmt: skip
    B = [[0, 0], [1 / m, 0], [0, 0], [0, 1 / ml]]
    C = [[1, 0, 0, 0], [0, 0, 1, 0]]
    plant = control.sample_system(
        control.ss(A, B, C, np.zeros((2, 2)), inputs=["fa", "fe"], outputs=["xa", "xl"]),
        T, method="zoh",
    )  # fmt: skip
    ka, kl = ZC.coefficients(VALS)
    blocks = [
        plant,
        _tf(ka, T, "ea", "ua"),
        _tf(kl, T, "el", "ul"),
        control.summing_junction(["ra", "-xa"], "ea", dt=T),
        control.summing_junction(["rl", "-xl"], "el", dt=T),
        control.summing_junction(["ua", "ul"], "u", dt=T),
        control.tf([1.0], [1.0] + [0.0] * delay, T, inputs="u", outputs="fa"),  # z^-delay
    ]
    return control.interconnect(blocks, inplist=["ra", "rl", "fe"], outlist=["xa", "xl"])


@pytest.mark.parametrize(("delay", "load_mass"), [(0, 0.5), (1, 2.0)])
def test_agrees_with_python_control_forced_response(delay: int, load_mass: float) -> None:
    loop = LOOP.replace(delay=delay)
    res = sampled_response(SEA_Z, loop=loop, load_mass=load_mass, scenario=Step(0.02),
                           horizon=0.6)  # fmt: skip
    n = res.time.size
    assert n == 301  # counted steps, not time
    sys = _python_control_loop(load_mass, loop.period, delay)
    u = np.zeros((3, n))
    u[0], u[1] = 0.02, 0.02
    fr = control.forced_response(sys, T=res.time, U=u)
    assert np.allclose(fr.outputs[0], res.x_A, rtol=1e-9, atol=1e-12)
    assert np.allclose(fr.outputs[1], res.x_L, rtol=1e-9, atol=1e-12)
    assert res.stable and not np.allclose(res.x_L, 0.0)


def test_force_step_settles_where_statics_say() -> None:
    # K_A(1) = kd, K_L(1) = kl (1 + 1)/2/(1 - 1/5) = 1.25 kl (the DC gains), so at rest
    # actuator: 0 = −kd xA − kl xL − k1 (xA − xL);  load: 0 = 10 − k1 (xL − xA)
    r = sampled_response(SEA_Z, loop=LOOP, load_mass=1.0, scenario=ForceStep(10.0), horizon=8.0)
    k1, kd, kl = VALS["k1"], VALS["kd"], 1.25 * VALS["kl"]
    a = np.array([[-(k1 + kd), k1 - kl], [k1, -k1]])
    want = np.linalg.solve(a, [0.0, -10.0])
    assert r.stable
    assert np.allclose([r.x_A[-1], r.x_L[-1]], want, rtol=1e-6)


def test_results_and_bad_input() -> None:
    r = sampled_response(SEA_Z, loop=LOOP, load_mass=1.0, scenario=LoadDisplaced(0.01),
                         horizon=0.1)  # fmt: skip
    d = r.to_dict()
    assert d["samples"] == 51 and d["kind"] == "sampled" and d["target"] == 0.0
    assert "SampledResponse" in repr(r) and "stable" in r._repr_html_()
    ax = r.plot()
    assert len(ax.lines) == 3
    with pytest.raises(ParameterError, match="load mass"):
        sampled_response(SEA_Z, loop=LOOP, load_mass=0.0)
    with pytest.raises(ParameterError, match="runs at 500 Hz but the sampled loop at 1000 Hz"):
        sampled_response(SEA_Z, loop=SampledLoop(rate=1000.0), load_mass=1.0)
    with pytest.raises(ParameterError, match="limit"):
        sampled_response(SEA_Z, loop=LOOP, load_mass=1.0, horizon=1e9)
    inerter = SEA(D1="k1 + b1*s + mi*s**2", values={**VALS, "mi": 0.1}, discrete=ZC)
    with pytest.raises(ModelError, match="improper with 2 more zeros"):
        sampled_response(inerter, loop=LOOP, load_mass=1.0, horizon=0.1)


def test_an_unstable_loop_is_a_result_cut_at_divergence() -> None:
    hot = SEA(D1="k1 + b1*s", values={**VALS, "kd": 4e5}, discrete=ZC)
    r = sampled_response(hot, loop=LOOP, load_mass=1.0, scenario=Step(0.01), horizon=100.0)
    assert not r.stable and r.spectral_radius > 1
    assert r.time.size < 50_001 and np.all(np.isfinite(r.x_L))


def _fine_load_motion(res: object, sub: int) -> tuple[np.ndarray, np.ndarray]:
    """``x_L`` on a grid ``sub`` times finer than the samples, the force held (scipy ZOH)."""
    from scipy.signal import cont2discrete

    m, b, k1, b1, ml = VALS["m"], VALS["b"], VALS["k1"], VALS["b1"], 1.0
    A = np.array([[0, 1, 0, 0], [-k1 / m, -(b + b1) / m, k1 / m, b1 / m], [0, 0, 0, 1],
                  [k1 / ml, b1 / ml, -k1 / ml, -b1 / ml]])  # fmt: skip
    B = np.array([[0.0], [1 / m], [0.0], [0.0]])
    h = LOOP.period / sub
    Ad, Bd, *_ = cont2discrete((A, B, np.eye(4), np.zeros((4, 1))), h, method="zoh")
    x, t, xl = np.zeros(4), [0.0], [0.0]
    for k, f in enumerate(res.f_A[:-1]):  # type: ignore[attr-defined]
        for j in range(sub):
            x = Ad @ x + Bd[:, 0] * f
            t.append((k * sub + j + 1) * h)
            xl.append(x[2])
    return np.array(t), np.array(xl)


def test_metrics_agree_with_an_independent_fine_scipy_run() -> None:
    # the python-control loop gives the same held force; scipy's ZOH plant at T/40 gives
    # x_L between the instants; settling = the last fine instant outside the 2 % band
    res = sampled_response(SEA_Z, loop=LOOP, load_mass=1.0, scenario=Step(0.02), horizon=1.5)
    met = res.metrics()
    sys = _python_control_loop(1.0, LOOP.period, 0)
    u = np.zeros((3, res.time.size))
    u[0], u[1] = 0.02, 0.02
    fr = control.forced_response(sys, T=res.time, U=u)
    assert np.allclose(fr.outputs[1], res.x_L, rtol=1e-9, atol=1e-12)
    sub = 40
    t, xl = _fine_load_motion(res, sub)
    assert np.allclose(xl[::sub], res.x_L, rtol=1e-8, atol=1e-12)
    outside = np.flatnonzero(np.abs(xl - 0.02) > 0.02 * 0.02)
    t_fine = t[outside[-1] + 1]
    assert met.settled and met.settling_time is not None
    assert abs(met.settling_time - t_fine) <= LOOP.period / sub
    # the true settling falls between the instants: not a multiple of T
    assert abs(met.settling_time / LOOP.period - round(met.settling_time / LOOP.period)) > 1e-6
    assert met.overshoot == pytest.approx((xl.max() - 0.02) / 0.02, abs=1e-4)
    assert met.peak_force == pytest.approx(np.abs(res.f_A).max())
    assert met.final_error == pytest.approx(abs(res.x_L[-1] - 0.02))
    # energy: exact ∫ f_A dx_A with the force held
    assert met.energy == pytest.approx(float(np.sum(res.f_A[:-1] * np.diff(res.x_A))))


def test_metrics_of_other_scenarios_and_divergence() -> None:
    fs = sampled_response(SEA_Z, loop=LOOP, load_mass=1.0, scenario=ForceStep(10.0), horizon=4.0)
    met = fs.metrics()
    assert met.settled and met.target == pytest.approx(fs.x_L[-1], rel=1e-9)
    assert met.overshoot is None
    hot = SEA(D1="k1 + b1*s", values={**VALS, "kd": 4e5}, discrete=ZC)
    r = sampled_response(hot, loop=LOOP, load_mass=1.0, scenario=Step(0.01), horizon=100.0)
    assert str(r.metrics().status) == "unstable"
    assert r.simulation().diverged


# a rational transmission (a spring with a lead network) and a filtered damper to ground
RATIONAL = {"m": 1.02, "b": 10.0, "k1": 1005.0, "b2": 4.0, "kd": 800.0, "bd": 20.0, "kl": 300.0}
SEA_R = SEA(D1="k1*(1 + s/40)/(1 + s/400)", D2="b2*s/(1 + s/200)", values=RATIONAL,
            discrete=ZC)  # fmt: skip


def _python_control_rational_plant(load_mass: float) -> control.InputOutputSystem:
    """The rational plant joined by python-control from its own blocks (written here)."""
    m, b, k1, b2 = (RATIONAL[k] for k in ("m", "b", "k1", "b2"))
    act = control.tf([1.0], [m, b, 0.0], inputs="fa_net", outputs="xa")
    load = control.tf([1.0], [load_mass, 0.0, 0.0], inputs="fl_net", outputs="xl")
    d1 = control.tf([k1 / 40, k1], [1 / 400, 1.0], inputs="dx", outputs="f1")
    d2 = control.tf([b2, 0.0], [1 / 200, 1.0], inputs="xl", outputs="f2")
    blocks = [
        act, load, d1, d2,
        control.summing_junction(["xl", "-xa"], "dx"),
        control.summing_junction(["fa", "f1"], "fa_net"),
        control.summing_junction(["fe", "-f1", "-f2"], "fl_net"),
    ]  # fmt: skip
    return control.interconnect(blocks, inplist=["fa", "fe"], outlist=["xa", "xl"])


@pytest.mark.parametrize("delay", [0, 1])
def test_rational_plant_agrees_with_python_control_c2d_and_a_fine_run(delay: int) -> None:
    loop = LOOP.replace(delay=delay)
    res = sampled_response(SEA_R, loop=loop, load_mass=1.5, scenario=Step(0.02), horizon=0.4)
    assert res.time.size == 201 and res.plant_A.shape == (6, 6)  # 4 + one state each
    T = loop.period
    plant = control.sample_system(control.ss(_python_control_rational_plant(1.5)), T, "zoh")
    # the held force res.f_A through python-control's ZOH plant gives the same samples
    fr = control.forced_response(plant, T=res.time, U=np.vstack([res.f_A, 0 * res.f_A]))
    assert np.allclose(fr.outputs[0], res.x_A, rtol=1e-7, atol=1e-11)
    assert np.allclose(fr.outputs[1], res.x_L, rtol=1e-7, atol=1e-11)
    # and an ODE solver on the continuous plant, the force held over each period
    cont = control.ss(_python_control_rational_plant(1.5))
    A, B, C = (np.asarray(x) for x in (cont.A, cont.B, cont.C))
    x, xl = np.zeros(A.shape[0]), [0.0]
    for k in range(60):  # the first 60 periods, counted
        f = B[:, 0] * res.f_A[k]
        x = solve_ivp(lambda _t, y, f=f: A @ y + f, (0.0, T), x, rtol=1e-11, atol=1e-14).y[:, -1]
        xl.append(float(C[1] @ x))
    assert np.allclose(xl, res.x_L[:61], rtol=1e-6, atol=1e-10)
    assert res.stable and abs(res.x_L[-1]) > 0.01
    met = res.metrics()  # the metrics run on the exact inter-sample motion of the plant
    assert met.peak_force == pytest.approx(float(np.abs(res.f_A).max()))


def test_rational_plant_stability_is_the_spectral_radius_of_the_whole_loop() -> None:
    from seapass.sampled.controllers import DiscreteController, controller_state_space
    from seapass.sampled.coupling import coupled_closed_loop

    acl = coupled_closed_loop(SEA_R, loop=LOOP, env_mass=1.5)
    order = controller_state_space(DiscreteController.for_loop(SEA_R, LOOP), 0)[0].shape[0]
    assert acl.shape[0] == 6 + order  # plant with two element states, then the controller
    r = sampled_response(SEA_R, loop=LOOP, load_mass=1.5, horizon=0.2)
    assert r.spectral_radius == pytest.approx(float(np.max(np.abs(np.linalg.eigvals(acl)))))
    d = LoadDisplaced(0.01)
    rest = sampled_response(SEA_R, loop=LOOP, load_mass=1.5, scenario=d, horizon=0.01)
    assert rest.plant_states is not None  # the elements at rest: D1 not deflected, D2 is
    assert rest.plant_states[0, 4] == 0.0 and rest.plant_states[0, 5] == pytest.approx(5e-5)
