"""Digital twin plant: integrator accuracy, dry friction, encoders, sampled loop."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.linalg import expm

from seapass.errors import ParameterError, SimulationError
from seapass.rig.plant import TwinPlant
from seapass.rig.rigfile import paper_rig
from seapass.rig.twin import linear_matrices, simulate_loop

RIG = paper_rig()


def test_linear_twin_matches_exact_zoh_solution():
    plant = TwinPlant(RIG, load_mass=0.6, friction=False, quantize=False)
    plant.reset(x_A=0.01, x_L=0.02, v_A=-0.1)
    a, b = linear_matrices(RIG, load_mass=0.6)
    blk = np.zeros((5, 5))
    blk[:4, :4], blk[:4, 4:] = a, b
    e = expm(blk * RIG.period)
    x = np.array([0.01, -0.1, 0.02, 0.0])
    rng = np.random.default_rng(0)
    for _ in range(300):
        f = float(rng.uniform(-20, 20))
        plant.apply(f, RIG.period)
        x = e[:4, :4] @ x + e[:4, 4] * f
    assert np.allclose(plant.state, x, rtol=0, atol=2e-6 * np.abs(x).max() + 1e-9)
    assert plant.time == pytest.approx(300 * RIG.period)


def test_rest_stays_at_rest_and_sticks_below_breakaway():
    plant = TwinPlant(RIG, load_mass=0.1)
    plant.reset(x_A=0.01, x_L=0.01)
    for _ in range(100):
        plant.apply(0.0, RIG.period)
    assert plant.state == pytest.approx((0.01, 0.0, 0.01, 0.0), abs=1e-12)
    # 0.7 N is below the actuator's 0.8 N dry friction: nothing moves.
    for _ in range(200):
        plant.apply(0.7, RIG.period)
    xa, va, _xl, _vl = plant.state
    assert abs(xa - 0.01) < 1e-9 and abs(va) < 1e-9
    # 5 N breaks away.
    for _ in range(50):
        plant.apply(5.0, RIG.period)
    assert plant.state[0] > 0.011


def test_coulomb_stopping_distance():
    rig = RIG.replace(
        transmission={"viscous": 0.0, "coulomb": 2.0},
        damper={"b1": 0.0, "coulomb": 0.0},
        load={"viscous": 0.0, "coulomb": 0.0},
    )
    plant = TwinPlant(rig, load_mass=0.6, quantize=False)
    v0 = 0.2
    plant.reset(v_A=v0, v_L=v0)
    for _ in range(1000):
        plant.apply(0.0, rig.period)
    mass = rig.actuator_mass + rig.load_side_mass(0.6)
    expected = mass * v0**2 / (2 * 2.0)
    xa, va, _xl, _vl = plant.state
    assert abs(va) < 1e-6
    assert xa == pytest.approx(expected, rel=0.05)


def test_energy_never_increases_without_input():
    plant = TwinPlant(RIG, load_mass=0.1, quantize=False)
    plant.reset(x_A=0.0, x_L=0.01)
    m, ml, k1 = RIG.actuator_mass, RIG.load_side_mass(0.1), RIG.damper.k1

    def energy():
        xa, va, xl, vl = plant.state
        return 0.5 * m * va**2 + 0.5 * ml * vl**2 + 0.5 * k1 * (xl - xa) ** 2

    last = energy()
    for _ in range(300):
        plant.apply(0.0, RIG.period)
        now = energy()
        assert now <= last * (1 + 1e-9) + 1e-15
        last = now


def test_encoders_quantize_and_convert():
    plant = TwinPlant(RIG, load_mass=0.1)
    plant.reset(x_A=0.0123456, x_L=0.0133456)
    ca, cl = plant.read_encoders()
    assert isinstance(ca, int) and isinstance(cl, int)
    xa, xl = plant.counts_to_positions(ca, cl)
    assert abs(xa - 0.0123456) <= 0.5 * RIG.motor_resolution + 1e-12
    assert abs((xl - xa) - 0.001) <= 0.5 * RIG.linear_resolution + 1e-12
    assert cl == round(0.001 / 12.7e-6)


@settings(max_examples=30, deadline=None)
@given(
    st.floats(min_value=-0.1, max_value=0.1),
    st.floats(min_value=-0.005, max_value=0.005),
    st.integers(0, 1000),
)
def test_encoder_error_bounded(xa, defl, seed):
    plant = TwinPlant(RIG, load_mass=0.1, seed=seed)
    plant.reset(x_A=xa, x_L=xa + defl)
    mxa, mxl = plant.counts_to_positions(*plant.read_encoders())
    assert abs(mxa - xa) <= RIG.motor_resolution * (1 + 1e-9)
    assert abs((mxl - mxa) - defl) <= RIG.linear_resolution * (1 + 1e-9)


def test_saturation_and_bad_input():
    plant = TwinPlant(RIG, load_mass=0.1)
    plant.reset()
    plant.apply(1e6, RIG.period)
    assert plant.last_force == pytest.approx(RIG.force_limit)
    with pytest.raises(SimulationError):
        plant.apply(math.nan, RIG.period)
    with pytest.raises(ParameterError):
        plant.apply(1.0, -1.0)
    with pytest.raises(ParameterError):
        TwinPlant(RIG, load_mass=-1.0)


def test_external_force_pushes_load():
    plant = TwinPlant(RIG, load_mass=0.1)
    plant.reset()
    for _ in range(20):
        plant.apply(0.0, RIG.period, external_force=5.0)
    assert plant.state[2] > plant.state[0] >= 0.0


def _manual_loop(kd, bd, load_mass, seed):
    """The sampled PD loop written against the public TwinPlant interface."""
    plant = TwinPlant(RIG, load_mass=load_mass, seed=seed)
    plant.reset(x_A=0.02, x_L=0.02)
    T = RIG.period
    alpha = math.exp(-2 * math.pi * RIG.loop.velocity_filter * T)
    xa, xl = plant.counts_to_positions(*plant.read_encoders())
    prev, v, pending, out = xa, 0.0, 0.0, []
    for _ in range(400):
        out.append(xl)
        v = alpha * v + (1 - alpha) * (xa - prev) / T
        u = -kd * xa - bd * v
        plant.apply(pending, T)
        pending = u
        prev = xa
        xa, xl = plant.counts_to_positions(*plant.read_encoders())
    return np.array(out)


def test_simulate_loop_matches_twin_plant_interface():
    res = simulate_loop(
        RIG,
        load_mass=0.6,
        kp_actuator=[300.0, 1500.0],
        kv_actuator=25.0,
        duration=0.8,
        x0=0.02,
        seed=7,
    )
    # Run 0 of a seeded batch has the same encoder phases as a single seeded run.
    manual = _manual_loop(300.0, 25.0, 0.6, seed=7)
    assert np.allclose(res.x_L_measured[0, :400], manual, rtol=0, atol=1e-12)
    assert res.x_L.shape == (2, 401) and res.force.shape == (2, 400)
    assert np.all(np.abs(res.x_L[:, -1]) < 0.005)


def test_batch_equals_single_runs():
    kd = np.array([0.0, 400.0, 1200.0])
    batch = simulate_loop(RIG, load_mass=0.1, kp_load=kd, duration=0.5, x0=0.02)
    for i, k in enumerate(kd):
        one = simulate_loop(RIG, load_mass=0.1, kp_load=k, duration=0.5, x0=0.02)
        assert np.array_equal(batch.x_L[i], one.x_L[0])


def test_batch_shape_errors_name_the_argument():
    with pytest.raises(ParameterError, match="kv_actuator"):
        simulate_loop(RIG, load_mass=0.1, kp_actuator=[1, 2, 3], kv_actuator=[1, 2], duration=0.1)
    with pytest.raises(ParameterError, match="duration"):
        simulate_loop(RIG, load_mass=0.1, duration=0.0)
    with pytest.raises(ParameterError, match="delay"):
        simulate_loop(RIG, load_mass=0.1, duration=0.1, loop=RIG.loop.replace(delay=3))


def test_unstable_run_is_frozen_and_flagged():
    res = simulate_loop(RIG, load_mass=0.6, kp_load=5000.0, duration=2.0, x0=0.02, saturate=False)
    assert res.diverged[0]
    assert np.all(np.isfinite(res.x_L))
    # frozen at the end stop from the moment it left the travel
    reach = np.maximum(np.abs(res.x_L[0]), np.abs(res.x_A[0]))
    k = int(np.argmax(reach >= RIG.load.travel * (1 - 1e-12)))
    assert k > 0 and reach[k] == pytest.approx(RIG.load.travel)
    assert np.all(res.x_L[0, k:] == res.x_L[0, k]) and np.all(res.x_A[0, k:] == res.x_A[0, k])


def test_hand_contact_force_is_unilateral():
    res = simulate_loop(
        RIG,
        load_mass=0.1,
        kp_actuator=1000.0,
        kv_actuator=25.0,
        duration=0.3,
        hand={"mass": 0.5, "stiffness": 3000.0, "damping": 5.0, "speed": 0.2},
    )
    f = res.external_force[0]
    assert np.all(f >= 0) and f.max() > 1.0
    assert res.x_L[0].max() > 0.0


def test_runs_are_deterministic_and_seed_sets_encoder_phase():
    kw = {"load_mass": 0.1, "kp_actuator": 800.0, "kv_actuator": 25.0, "duration": 0.4, "x0": 0.02}
    a = simulate_loop(RIG, seed=3, **kw)
    b = simulate_loop(RIG, seed=3, **kw)
    c = simulate_loop(RIG, seed=4, **kw)
    assert np.array_equal(a.x_L_measured, b.x_L_measured)
    assert not np.array_equal(a.x_L_measured, c.x_L_measured)


def test_apply_accepts_partial_periods():
    whole = TwinPlant(RIG, load_mass=0.1, friction=False, quantize=False)
    split = TwinPlant(RIG, load_mass=0.1, friction=False, quantize=False)
    for p in (whole, split):
        p.reset(x_A=0.0, x_L=0.01)
    for _ in range(50):
        whole.apply(3.0, RIG.period)
        split.apply(3.0, 0.00137)
        split.apply(3.0, RIG.period - 0.00137)
    assert split.time == pytest.approx(whole.time)
    assert np.allclose(split.state, whole.state, rtol=0, atol=1e-8)
    # with dry friction the partial step keeps sticking exact
    stuck = TwinPlant(RIG, load_mass=0.1)
    stuck.reset(x_A=0.005, x_L=0.005)
    for _ in range(30):
        stuck.apply(0.5, 0.0003)
    assert stuck.state[0] == pytest.approx(0.005, abs=1e-12)


# ------------------------------------- bounded batches (moved from test_hardening, issue 12 item 3)


def test_twin_batch_is_capped_before_allocation() -> None:
    from seapass.rig.twin import simulate_loop

    rig = paper_rig()
    with pytest.raises(ParameterError, match="recorded samples"):
        simulate_loop(rig, load_mass=[0.1] * 5000, duration=10.0, kp_actuator=100.0)
