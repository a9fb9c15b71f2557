"""Optional MuJoCo model of the rig, for cross-checking the digital twin.

The rig becomes an MJCF model with two slide joints (actuator carriage ``x_A``
with viscous damping ``b``; output carriage ``x_L`` with ``b_L``), the spring
and damper of the transmission as a *fixed tendon* ``L = x_L − x_A`` with
``stiffness = k1`` and ``damping = b1``, and a ``motor`` actuator on ``x_A``
whose control range is the rig's force limit.  Dry friction and encoder
quantization are left out: the model is the linear, friction-free plant to
which [`seapass.rig.plant.TwinPlant`][seapass.rig.plant.TwinPlant] reduces with ``friction=False,
quantize=False``, and `compare_with_twin` checks the two agree.

MuJoCo is imported lazily; without it these functions raise
[`SimulationError`][seapass.errors.SimulationError] suggesting ``pip install seapass[mujoco]``.

References
----------
.. [1] E. Todorov, T. Erez, Y. Tassa, "MuJoCo: A physics engine for
   model-based control", IROS 2012; MJCF reference: tendon/fixed, actuator/motor.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import MissingExtraError, ParameterError
from .plant import TwinPlant
from .rigfile import Rig
from .twin import simulate_loop

__all__ = ["MujocoComparison", "MujocoRun", "build_mjcf", "compare_with_twin", "simulate_mujoco"]

FloatArray = NDArray[np.float64]


def _mujoco() -> Any:
    try:
        import mujoco
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingExtraError(
            "the MuJoCo cross-check needs the mujoco extra: pip install 'seapass[mujoco]'"
        ) from None
    return mujoco


def build_mjcf(rig: Rig, *, load_mass: float, timestep: float = 1e-4) -> str:
    """MJCF text of the linear rig with ``load_mass`` on the output."""
    if not (math.isfinite(load_mass) and load_mass >= 0):
        raise ParameterError(f"load_mass must be >= 0, got {load_mass!r}")
    if not (0 < timestep <= rig.period):
        raise ParameterError(f"timestep must be in (0, {rig.period:g}] s, got {timestep!r}")
    m, ml = rig.actuator_mass, rig.load_side_mass(load_mass)
    f = rig.force_limit
    return f"""
<mujoco model="seapass_rig">
  <option timestep="{timestep!r}" integrator="RK4" gravity="0 0 0"/>
  <worldbody>
    <body name="actuator">
      <joint name="x_A" type="slide" axis="1 0 0" damping="{rig.actuator_damping!r}"/>
      <inertial pos="0 0 0" mass="{m!r}" diaginertia="1e-6 1e-6 1e-6"/>
    </body>
    <body name="load">
      <joint name="x_L" type="slide" axis="1 0 0" damping="{rig.load.viscous!r}"/>
      <inertial pos="0 0 0" mass="{ml!r}" diaginertia="1e-6 1e-6 1e-6"/>
    </body>
  </worldbody>
  <tendon>
    <fixed name="transmission" stiffness="{rig.damper.k1!r}" damping="{rig.damper.b1!r}"
           springlength="0">
      <joint joint="x_L" coef="1"/>
      <joint joint="x_A" coef="-1"/>
    </fixed>
  </tendon>
  <actuator>
    <motor name="motor" joint="x_A" gear="1" ctrllimited="true" ctrlrange="{-f!r} {f!r}"/>
  </actuator>
</mujoco>
"""


@dataclass(frozen=True, kw_only=True)
class MujocoRun:
    """Positions at the control instants: ``t`` (N+1,), ``x_A``/``x_L`` (N+1,)."""

    t: FloatArray
    x_A: FloatArray
    x_L: FloatArray


def simulate_mujoco(
    rig: Rig,
    *,
    load_mass: float,
    duration: float,
    kp_actuator: float = 0.0,
    kv_actuator: float = 0.0,
    kp_load: float = 0.0,
    force: float = 0.0,
    x0: float = 0.0,
    deflection0: float = 0.0,
    timestep: float = 1e-4,
) -> MujocoRun:
    """Run the MJCF rig under the same sampled controller as [`seapass.rig.twin.simulate_loop`][seapass.rig.twin.simulate_loop].

    ``u_k = − kp_A x_A − kv_A v̂_A − kp_L x_L`` is computed from exact
    positions at the control rate (finite-difference velocity with the rig's
    filter), applied with the rig's delay and held between samples; ``force``
    is an open-loop motor force added without delay from ``t = 0``.
    """
    mj = _mujoco()
    model = mj.MjModel.from_xml_string(build_mjcf(rig, load_mass=load_mass, timestep=timestep))
    data = mj.MjData(model)
    ja, jl = model.joint("x_A").qposadr[0], model.joint("x_L").qposadr[0]
    data.qpos[ja], data.qpos[jl] = x0 - deflection0, x0
    mj.mj_forward(model, data)
    T = rig.period
    sub = round(T / timestep)
    if abs(sub * timestep - T) > 1e-9 * T:
        raise ParameterError("timestep must divide the control period")
    fc = rig.control.velocity_filter
    alpha = math.exp(-2.0 * math.pi * fc * T) if fc else 0.0
    steps = round(duration / T)
    xa = np.empty(steps + 1)
    xl = np.empty(steps + 1)
    prev, vhat, pending = float(data.qpos[ja]), 0.0, 0.0
    for k in range(steps):
        a, ll = float(data.qpos[ja]), float(data.qpos[jl])
        xa[k], xl[k] = a, ll
        vhat = alpha * vhat + (1.0 - alpha) * (a - prev) / T
        prev = a
        u = -kp_actuator * a - kv_actuator * vhat - kp_load * ll
        applied = pending if rig.control.delay else u
        pending = u
        data.ctrl[0] = force + applied
        for _ in range(sub):
            mj.mj_step(model, data)
    xa[steps], xl[steps] = data.qpos[ja], data.qpos[jl]
    return MujocoRun(t=np.arange(steps + 1, dtype=float) * T, x_A=xa, x_L=xl)


@dataclass(frozen=True, kw_only=True)
class MujocoComparison:
    """MuJoCo vs linear twin: ``max_error`` (m) over both positions and all samples."""

    max_error: float
    tolerance: float
    agree: bool
    mujoco: MujocoRun
    twin_x_A: FloatArray
    twin_x_L: FloatArray


def compare_with_twin(
    rig: Rig,
    *,
    load_mass: float,
    kp_actuator: float = 0.0,
    kv_actuator: float = 0.0,
    kp_load: float = 0.0,
    force: float = 0.0,
    x0: float = 0.02,
    duration: float = 1.0,
    tolerance: float | None = None,
    timestep: float = 1e-4,
) -> MujocoComparison:
    """Step response of the MuJoCo rig against the linear, friction-free, unquantized twin.

    A closed-loop step (from ``x0`` to 0) or an open-loop force step
    (``force``) is run in both; they agree when the largest position
    difference is within ``tolerance`` (default 1 % of the largest load
    excursion).  The residual is the integrators' (MuJoCo RK4 at ``timestep``
    vs trapezoidal substeps of the twin); it is ~1e-8 m for the paper rig.
    """
    mj_run = simulate_mujoco(
        rig,
        load_mass=load_mass,
        duration=duration,
        kp_actuator=kp_actuator,
        kv_actuator=kv_actuator,
        kp_load=kp_load,
        force=force,
        x0=x0,
        timestep=timestep,
    )
    if force != 0.0 and (kp_actuator or kv_actuator or kp_load):
        raise ParameterError("give either controller gains (closed-loop step) or force, not both")
    if force == 0.0:
        tw = simulate_loop(
            rig,
            load_mass=load_mass,
            kp_actuator=kp_actuator,
            kv_actuator=kv_actuator,
            kp_load=kp_load,
            duration=duration,
            x0=x0,
            friction=False,
            quantize=False,
        )
        tw_a, tw_l = tw.x_A[0], tw.x_L[0]
    else:
        tw_a, tw_l = _twin_force_step(rig, load_mass, force, duration, x0)
    scale = max(abs(x0), float(np.max(np.abs(tw_l))))
    tol = 0.01 * scale if tolerance is None else float(tolerance)
    err = float(max(np.max(np.abs(mj_run.x_A - tw_a)), np.max(np.abs(mj_run.x_L - tw_l))))
    return MujocoComparison(
        max_error=err, tolerance=tol, agree=err <= tol, mujoco=mj_run, twin_x_A=tw_a, twin_x_L=tw_l
    )


def _twin_force_step(
    rig: Rig, load_mass: float, force: float, duration: float, x0: float
) -> tuple[FloatArray, FloatArray]:
    plant = TwinPlant(rig, load_mass=load_mass, friction=False, quantize=False)
    plant.reset(x_A=x0, x_L=x0)
    steps = round(duration / rig.period)
    xa, xl = np.empty(steps + 1), np.empty(steps + 1)
    for k in range(steps + 1):
        xa[k], _, xl[k], _ = plant.state
        if k < steps:
            plant.apply(force, rig.period)
    return xa, xl
