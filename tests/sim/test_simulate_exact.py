"""Simulator: exactness against analytic and independent solutions, scenarios, failures."""

from __future__ import annotations

import math
import warnings

import control
import numpy as np
import pytest
import scipy.signal
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers import (
    one_error,
)
from seapass.errors import ParameterError, UnrealizableError
from seapass.model.catalog import PAPER_VALUES
from seapass.model.expr import S, parse_expression, symbol
from seapass.model.realization import closed_loop, closed_loop_factory
from seapass.model.sea import SEA
from seapass.sim import (
    ForceImpulse,
    ForceStep,
    LoadDisplaced,
    Stability,
    Step,
    Trajectory,
    simulate,
)

PLANT = PAPER_VALUES
s = S


def ours(kd: float = 2000.0, bd: float = 60.0, b1: float = 100.0) -> SEA:
    return SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**PLANT, "kd": kd, "bd": bd, "b1": b1})


def _step_response_by_residues(D1, D2, CA, CA_ref, CL, CL_ref, m, b, mL, r, t):
    """Independent solution: X_L/Θ by sympy from the Laplace equations, then partial fractions.

    ``C*_ref`` is the part of each controller that acts on the reference
    (derivative on measurement: the ``s`` term acts on the measurement only).
    """
    xa, xl, th = sp.symbols("xa xl th")
    fa = CA_ref * th - CA * xa + CL_ref * th - CL * xl
    eqs = [
        sp.Eq((m * s**2 + b * s) * xa, fa + D1 * (xl - xa)),
        sp.Eq(mL * s**2 * xl, -D1 * (xl - xa) - D2 * xl),
    ]
    sol = sp.solve(eqs, [xa, xl], dict=True)[0]
    G = sp.cancel(sp.together(sol[xl] / th))
    num, den = sp.fraction(G)
    num = [float(c) for c in sp.Poly(num, s).all_coeffs()]
    den = [float(c) for c in sp.Poly(den * s, s).all_coeffs()]
    res, poles, direct = scipy.signal.residue(num, den)
    assert len(direct) == 0 or np.allclose(direct, 0)
    y = np.zeros_like(t, dtype=complex)
    for ri, pi in zip(res, poles, strict=True):
        y += ri * np.exp(pi * t)
    return r * y.real


CASES = [
    # (D1, D2, CA, CA_ref, CL, CL_ref, values)
    ("k1 + b1*s", "0", "kd + bd*s", "kd", "0", "0", {"kd": 2000.0, "bd": 60.0, "b1": 100.0}),
    ("k1", "0", "0", "0", "kd", "kd", {"kd": 400.0}),
    ("k1", "0", "kd + bd*s", "kd", "0", "0", {"kd": 385.0, "bd": 111.0}),
    ("k1", "k2", "kd + ki/s", "kd + ki/s", "0", "0", {"kd": 300.0, "ki": 200.0, "k2": 50.0}),
    (
        "k1*b1*s/(k1 + b1*s) + k2",
        "b2*s",
        "kd*(s + 20)/(s + 60)",
        "kd*(s + 20)/(s + 60)",
        "0",
        "0",
        {"kd": 500.0, "b1": 40.0, "k2": 100.0, "b2": 5.0},
    ),
]


@pytest.mark.parametrize("case", CASES, ids=[c[0] + "|" + c[2] + "|" + c[4] for c in CASES])
@pytest.mark.parametrize("mL", [1.0, 10.0])
def test_step_matches_partial_fraction_solution(case, mL):
    D1, D2, CA, CA_ref, CL, CL_ref, vals = case
    values = {**PLANT, **vals}
    sea = SEA(D1=D1, D2=D2, CA=CA, CL=CL, values=values)
    res = simulate(sea, load_mass=mL, scenario=Step(0.5), horizon=3.0, dt=1e-3)
    subs = {symbol(k): sp.Rational(v) for k, v in values.items()}
    exprs = [parse_expression(e, values).xreplace(subs) for e in (D1, D2, CA, CA_ref, CL, CL_ref)]
    ref = _step_response_by_residues(*exprs, values["m"], values["b"], mL, 0.5, res.time)
    assert res.status == "stable"
    np.testing.assert_allclose(res.x_L, ref, atol=1e-9, rtol=0)


def test_free_two_mass_oscillator_by_hand():
    # no damping, no control: relative motion d0 cos(ωt), centre of mass at rest
    m, mL, k1, d0 = 1.0, 4.0, 1000.0, 0.02
    sea = SEA(D1="k1", values={"m": m, "b": 0.0, "k1": k1})
    res = simulate(sea, load_mass=mL, scenario=LoadDisplaced(d0), horizon=2.0, dt=1e-3)
    w = math.sqrt(k1 * (1 / m + 1 / mL))
    xcm = mL * d0 / (m + mL)
    x_l = xcm + m / (m + mL) * d0 * np.cos(w * res.time)
    x_a = xcm - mL / (m + mL) * d0 * np.cos(w * res.time)
    np.testing.assert_allclose(res.x_L, x_l, atol=1e-12)
    np.testing.assert_allclose(res.x_A, x_a, atol=1e-12)
    assert res.status == Stability.MARGINAL
    # lossless and no actuator: no work
    assert abs(res.energy) < 1e-12


def test_trajectory_matches_lsim_and_control_forced_response():
    sea = ours()
    times = np.linspace(0.0, 2.0, 21)
    vals = 0.3 * np.sin(2 * times)
    res = simulate(
        sea, load_mass=5.0, scenario=Trajectory(times, vals, "linear"), horizon=2.0, dt=1e-2
    )
    sys = res.system
    u = np.zeros((res.time.size, 3))
    u[:, 0] = u[:, 1] = np.interp(res.time, times, vals)
    _, y, _ = scipy.signal.lsim((sys.A, sys.B, sys.C, sys.D), u, res.time, interp=True)
    np.testing.assert_allclose(res.x_L, y[:, 2], atol=1e-10)
    fr = control.forced_response(control.ss(sys.A, sys.B, sys.C, sys.D), res.time, u.T)
    np.testing.assert_allclose(res.f_A, fr.outputs[4], atol=1e-7)


def test_zoh_trajectory_equals_step():
    sea = ours()
    step = simulate(sea, load_mass=3.0, scenario=Step(0.2), horizon=1.0, dt=1e-3)
    traj = simulate(
        sea, load_mass=3.0, scenario=Trajectory([0.0], [0.2], "zoh"), horizon=1.0, dt=1e-3
    )
    np.testing.assert_allclose(traj.x_L, step.x_L, atol=1e-12)


def test_derivative_on_measurement_gives_no_force_impulse():
    res = simulate(ours(kd=2000, bd=60), load_mass=10.0, scenario=Step(0.5), horizon=0.5)
    assert res.f_A[0] == pytest.approx(2000 * 0.5)
    assert np.max(np.abs(res.f_A)) == pytest.approx(1000.0)


def test_state_between_samples_is_exact():
    sea = ours()
    coarse = simulate(sea, load_mass=10.0, horizon=1.0, dt=0.1)
    fine = simulate(sea, load_mass=10.0, horizon=1.0, dt=0.001)
    for t in (0.0371, 0.5, 0.999):
        k = round(t / 0.001)
        np.testing.assert_allclose(coarse.state_at(k * 0.001), fine.states[k], atol=1e-10)
        assert coarse.output_at("x_L", k * 0.001) == pytest.approx(fine.x_L[k], abs=1e-10)
    np.testing.assert_allclose(coarse.x_L, fine.x_L[::100], atol=1e-11)


def test_energy_is_exact_and_step_independent():
    sea = ours()
    e = [simulate(sea, load_mass=10.0, horizon=2.0, dt=dt).energy for dt in (0.05, 1e-3)]
    assert e[0] == pytest.approx(e[1], rel=1e-9)
    fine = simulate(sea, load_mass=10.0, horizon=2.0, dt=2e-5)
    trap = np.trapezoid(fine.f_A * fine.v_A, fine.time)
    assert e[1] == pytest.approx(trap, rel=1e-4)


def test_integral_action_rejects_force_step():
    sea = SEA(D1="k1", CL="kd + ki/s", values={**PLANT, "kd": 200.0, "ki": 100.0})
    res = simulate(sea, load_mass=2.0, scenario=ForceStep(5.0), horizon=30.0, dt=5e-3)
    assert res.status == "stable"
    assert abs(res.x_L[-1]) < 1e-6  # integral action: no steady deflection
    assert res.target == pytest.approx(0.0, abs=1e-12)


def test_force_step_settles_to_compliance():
    sea = SEA(D1="k1", CA="kd + bd*s", values={**PLANT, "kd": 1000.0, "bd": 50.0})
    res = simulate(sea, load_mass=2.0, scenario=ForceStep(10.0), horizon=20.0, dt=5e-3)
    # springs in series: k1 and kd -> 500 N/m
    assert res.target == pytest.approx(10.0 / 500.0)
    assert res.x_L[-1] == pytest.approx(0.02, rel=1e-6)


def test_impulse_sets_load_velocity():
    res = simulate(ours(), load_mass=4.0, scenario=ForceImpulse(2.0), horizon=0.1)
    assert res.v_L[0] == pytest.approx(0.5)
    assert res.x_L[0] == 0.0


def test_load_displaced_maxwell_element_starts_relaxed():
    sea = SEA(
        D1="k1 + k2*b1*s/(k2 + b1*s)",
        CA="kd + bd*s",
        values={**PLANT, "k2": 500.0, "b1": 20.0, "kd": 300.0, "bd": 30.0},
    )
    res = simulate(sea, load_mass=1.0, scenario=LoadDisplaced(0.02), horizon=3.0)
    assert res.x_L[0] == 0.02 and res.v_L[0] == 0.0
    # a relaxed Maxwell element carries no force at rest: the initial force is k1*d only
    f1 = res.system.C[5] @ res.states[0]
    assert f1 == pytest.approx(1000.0 * 0.02)
    assert abs(res.x_L[-1]) < 1e-3


def test_unstable_run_is_a_result_not_nan():
    sea = SEA(D1="k1", CL="kd", values={**PLANT, "kd": 5000.0})
    res = simulate(sea, load_mass=10.0, horizon=10.0)
    assert res.status == "unstable" and not res.stable
    assert np.all(np.isfinite(res.x_L)) and np.isfinite(res.energy)
    assert np.max(res.poles.real) > 0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"load_mass": 0.0}, "load mass"),
        ({"load_mass": -1.0}, "load mass"),
        ({"load_mass": math.nan}, "load mass"),
        ({"load_mass": 1.0, "horizon": 1e-4, "dt": 1e-3}, "shorter than the time step"),
        ({"load_mass": 1.0, "dt": 0.0}, "dt"),
    ],
)
def test_bad_input(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        simulate(ours(), **kwargs)


def test_missing_parameter_value():
    sea = SEA(D1="k1", CL="kd", values={**PLANT, "kd": None})
    with pytest.raises(ParameterError, match="kd"):
        simulate(sea, load_mass=1.0)


@pytest.mark.parametrize(
    ("elements", "name"),
    [({"D1": "k1", "CA": "kd*s**2"}, "CA"), ({"D1": "k1 + b1*s + m*s**2"}, "D1")],
)
def test_unrealizable(elements, name):
    used = {"m", "b", "k1", "kd" if "CA" in elements else "b1"}
    values = {**PLANT, "kd": 1.0, "b1": 1.0}
    sea = SEA(**elements, values={k: v for k, v in values.items() if k in used})
    with pytest.raises(UnrealizableError, match=name):
        simulate(sea, load_mass=1.0)


def test_bad_scenarios():
    with pytest.raises(ParameterError):
        Step(0.0)
    with pytest.raises(ParameterError):
        Trajectory([0, 1, 1], [0, 1, 2])
    with pytest.raises(ParameterError):
        Trajectory([0, 1], [0, 1], "cubic")  # type: ignore[arg-type]
    with pytest.raises(ParameterError):
        Step(0.5, apply_to="motor")


def test_step_on_one_reference_only():
    sea = SEA(D1="k1", CA="kd + bd*s", CL="kd", values={**PLANT, "kd": 200.0, "bd": 30.0})
    act = simulate(sea, load_mass=1.0, scenario=Step(0.1, apply_to="actuator"), horizon=0.01)
    load = simulate(sea, load_mass=1.0, scenario=Step(0.1, apply_to="load"), horizon=0.01)
    both = simulate(sea, load_mass=1.0, scenario=Step(0.1), horizon=0.01)
    assert act.f_A[0] == pytest.approx(20.0) and load.f_A[0] == pytest.approx(20.0)
    np.testing.assert_allclose(act.x_L + load.x_L, both.x_L, atol=1e-15)


def test_factory_matches_exact_builder():
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**PLANT, "kd": None, "bd": None, "b1": None})
    build = closed_loop_factory(sea, ("kd", "bd", "b1"), load_mass=7.0)
    a = build([1500.0, 80.0, 0.0])  # b1 = 0 drops the damper degree
    b = closed_loop(sea.with_values(kd=1500.0, bd=80.0, b1=0.0), load_mass=7.0)
    np.testing.assert_allclose(a.A, b.A)
    np.testing.assert_allclose(a.B, b.B)


@settings(max_examples=15, deadline=None)
@given(
    kd=st.floats(1.0, 3000.0),
    bd=st.floats(0.0, 200.0),
    b1=st.floats(0.0, 300.0),
    mL=st.floats(0.1, 30.0),
)
def test_agrees_with_control_forced_response(kd, bd, b1, mL):
    res = simulate(ours(kd, bd, b1), load_mass=mL, horizon=0.5, dt=1e-3)
    sys = res.system
    u = np.zeros((3, res.time.size))
    u[0] = u[1] = 0.5
    fr = control.forced_response(control.ss(sys.A, sys.B, sys.C, sys.D), res.time, u)
    scale = max(1.0, float(np.max(np.abs(res.x_L))))
    np.testing.assert_allclose(res.x_L, fr.outputs[2], atol=1e-8 * scale)


# ------------------ a load mass too light to simulate (moved from test_hardening, issue 12 item 10)


def test_tiny_load_mass_is_an_error_not_an_unstable_verdict() -> None:
    ours = ["--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--set", "b1=20", "--set", "bd=25", "--set", "kd=1000"]  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # scipy overflow warnings must not escape either
        for mass in ("1e-300", "1e-6"):
            err = one_error(["simulate", *ours, "--load-mass", mass], "too stiff")
            assert "unstable" not in err
