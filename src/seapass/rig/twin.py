"""Batch closed-loop runs of the digital twin: the sampled controller on the plant.

`simulate_loop` runs many closed loops at once (axis ``run``) of the
plant of [`seapass.rig.plant`][seapass.rig.plant] under a discrete PD controller with encoder
positions, filtered finite-difference velocities, ZOH and an optional
one-sample delay; `linear_matrices` is the friction-free linear model the
twin reduces to.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ParameterError
from ..files.limits import MAX_RIG_INTEGRATOR_STEPS, MAX_TWIN_VALUES
from ..model.loop import SampledLoop, loop_argument
from .plant import Encoders, PlantKernel, as_batch
from .rigfile import Rig

FloatArray = NDArray[np.float64]

__all__ = ["LoopResult", "linear_matrices", "simulate_loop"]


@dataclass(frozen=True, kw_only=True)
class LoopResult:
    """Batch closed-loop run of `simulate_loop`.

    Arrays have axis order ``(run, sample)``; ``sample`` indexes the control
    instants ``t[k] = k * period``.

    Attributes
    ----------
    t : ndarray, shape (N+1,)
    x_A, x_L : ndarray, shape (B, N+1)
        True positions.
    x_A_measured, x_L_measured : ndarray, shape (B, N+1)
        Actuator and load positions from the encoders.
    command : ndarray, shape (B, N)
        The controller's output at sample ``k``, before the delay and the
        saturation (what a bench logs as the commanded force).
    force : ndarray, shape (B, N)
        Saturated force applied during period ``k``.
    external_force : ndarray, shape (B, N+1)
        Force on the load at the samples (contact force in impact runs).
    diverged : ndarray of bool, shape (B,)
        Run left ``±rig.load.travel`` (it is frozen from then on).
    """

    t: FloatArray
    x_A: FloatArray
    x_L: FloatArray
    x_A_measured: FloatArray
    x_L_measured: FloatArray
    command: FloatArray
    force: FloatArray
    external_force: FloatArray
    diverged: NDArray[np.bool_]
    meta: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))


def simulate_loop(
    rig: Rig,
    *,
    load_mass: ArrayLike,
    kp_actuator: ArrayLike = 0.0,
    kv_actuator: ArrayLike = 0.0,
    kp_load: ArrayLike = 0.0,
    kv_load: ArrayLike = 0.0,
    duration: float,
    x0: ArrayLike = 0.0,
    deflection0: ArrayLike = 0.0,
    reference: float = 0.0,
    load_force: ArrayLike = 0.0,
    b1: ArrayLike | None = None,
    hand: dict[str, ArrayLike] | None = None,
    friction: bool = True,
    quantize: bool = True,
    saturate: bool = True,
    loop: SampledLoop | None = None,
    seed: int | None = None,
    **old: Any,
) -> LoopResult:
    """Simulate a batch of sampled closed loops on the twin.

    The internal discrete controller is
    ``u_k = kp_A (r − x̂_A) − kv_A v̂_A + kp_L (r − x̂_L) − kv_L v̂_L`` with
    encoder positions ``x̂`` and velocities ``v̂`` from finite differences
    through the loop's first-order low-pass (none: raw).  ``u`` is held for one
    period (ZOH), optionally one sample late (the loop's delay).
    LP of the paper is ``kp_load = kd``; "Ours" is ``kp_actuator = kd,
    kv_actuator = bd``.

    Parameters
    ----------
    rig : Rig
    load_mass, kp_actuator, kv_actuator, kp_load, kv_load, x0, deflection0, b1 : scalar or (B,)
        Per-run values, broadcast from length-1 (scalars).  The batch size B is
        the common length.  The runs start at rest with ``x_L = x0`` and
        ``x_A = x0 − deflection0``.
    duration : float
        Simulated time (s).
    load_force : scalar or (B,)
        Constant force on the load from ``t = 0`` (a step in load force).
    hand : dict, optional
        Impact contact: ``mass, stiffness, damping, speed`` (each scalar or
        (B,)).  A hand body starts touching the load at rest position and moving
        at ``speed`` in +x; the unilateral contact force
        ``max(0, k p + c ṗ)`` (``p`` penetration) acts on the load.
    friction, quantize, saturate : bool
        Model switches (all True for the twin).
    loop : SampledLoop, optional
        The sampled loop (the rig's period, delay 0 or 1, velocity filter); default the rig's
        ([`Rig.loop`][seapass.rig.rigfile.Rig.loop]).  Its discretization method does not
        matter here: the twin's controller is proportional-derivative.
    seed : int or None
        Encoder phase offsets (see `TwinPlant`).
    **old
        The loop's old keywords (delay and velocity filter in Hz, 0 for none), accepted
        for one release with a warning.
    """
    arr = _broadcast_runs(
        load_mass=load_mass, kp_actuator=kp_actuator, kv_actuator=kv_actuator,
        kp_load=kp_load, kv_load=kv_load, x0=x0, deflection0=deflection0,
        load_force=load_force, b1=b1, hand=hand,
    )  # fmt: skip
    n = arr["load_mass"].size
    if not (math.isfinite(duration) and duration > 0):
        raise ParameterError(f"duration must be a positive time, got {duration!r}")
    loop = loop_argument(loop, old, where="simulate_loop", base=rig.loop)
    if loop.delay not in (0, 1):
        raise ParameterError(f"loop: the twin runs 0 or 1 samples of delay, got {loop.delay}")
    if loop.period != rig.period:
        raise ParameterError(
            f"loop: the twin runs at the rig's control.rate ({rig.control.rate:g} Hz); change "
            "it with rig.replace(control={'rate': ...})"
        )
    delay, fc, T = loop.delay, loop.velocity_filter or 0.0, loop.period
    steps = round(duration / T)
    if n * (steps + 1) > MAX_TWIN_VALUES or steps * rig.control.substeps > MAX_RIG_INTEGRATOR_STEPS:
        raise ParameterError(
            f"{n} run(s) of {steps + 1:,} control periods ({rig.control.substeps} substeps "
            f"each) exceed the limits of {MAX_TWIN_VALUES:,} recorded samples and "
            f"{MAX_RIG_INTEGRATOR_STEPS:,} integrator steps per run: run fewer gains or "
            "shorten the duration"
        )

    kern = PlantKernel(
        rig, n, load_mass=arr["load_mass"], b1=arr.get("b1"), friction=friction, saturate=saturate
    )
    enc = Encoders(rig, n, seed, quantize)
    kern.set_state(arr["x0"] - arr["deflection0"], 0.0, arr["x0"], 0.0)
    contact = _Contact(arr, kern) if hand is not None else None
    ctrl = _Controller(arr, period=T, filter_hz=fc, delay=delay, reference=reference)
    stop = _EndStop(n, rig.load.travel)
    rec = _Record(n, steps)

    xa_hat, xl_hat = enc.measure(kern.xa, kern.xl)
    ctrl.start(xa_hat, xl_hat)
    ext = arr["load_force"] + (contact.force() if contact is not None else 0.0)
    for step in range(steps):
        rec.sample(step, kern, xa_hat, xl_hat, ext)
        force = np.where(stop.diverged, 0.0, kern.saturate(ctrl.command(xa_hat, xl_hat)))
        rec.force[:, step], rec.command[:, step] = force, ctrl.pending
        for _ in range(rig.control.substeps):
            if contact is not None:
                ext = arr["load_force"] + contact.advance(kern.h)
            kern.substep(force, ext)
        if contact is not None:
            ext = arr["load_force"] + contact.force()
        stop.hold(kern)
        xa_hat, xl_hat = enc.measure(kern.xa, kern.xl)
    rec.sample(steps, kern, xa_hat, xl_hat, ext)
    return LoopResult(
        t=np.arange(steps + 1, dtype=float) * T,
        x_A=rec.x_A,
        x_L=rec.x_L,
        x_A_measured=rec.x_A_measured,
        x_L_measured=rec.x_L_measured,
        command=rec.command,
        force=rec.force,
        external_force=rec.external,
        diverged=stop.diverged,
        meta=MappingProxyType(
            {
                "loop": loop,
                "friction": friction,
                "quantize": quantize,
                "saturate": saturate,
            }
        ),
    )


def _broadcast_runs(
    *, b1: ArrayLike | None, hand: dict[str, ArrayLike] | None, **given: ArrayLike
) -> dict[str, FloatArray]:
    """Every per-run argument as a ``(B,)`` array; length-1 arguments broadcast."""
    raw: dict[str, ArrayLike] = dict(given)
    if b1 is not None:
        raw["b1"] = b1
    if hand is not None:
        for key in ("mass", "stiffness", "damping", "speed"):
            if key not in hand:
                raise ParameterError(f"hand needs key {key!r}")
            raw[f"hand.{key}"] = hand[key]
    sizes = {k: np.size(v) for k, v in raw.items()}
    n = max(sizes.values())
    for k, size in sizes.items():
        if size not in (1, n):
            raise ParameterError(
                f"{k} has length {size}; every batch argument must have length 1 or {n}"
            )
    out = {}
    for k, v in raw.items():
        flat = np.ravel(np.asarray(v, dtype=float))
        out[k] = as_batch(k, flat if sizes[k] == n else float(flat[0]), n)
    return out


class _Controller:
    """``u = kp_A (r − x̂_A) − kv_A v̂_A + kp_L (r − x̂_L) − kv_L v̂_L``, optionally one sample late.

    Velocities are finite differences of the encoder positions through a
    first-order low-pass of cut-off ``filter_hz`` (0: raw differences).
    """

    def __init__(
        self,
        arr: dict[str, FloatArray],
        *,
        period: float,
        filter_hz: float,
        delay: int,
        reference: float,
    ) -> None:
        self.kpa, self.kva = arr["kp_actuator"], arr["kv_actuator"]
        self.kpl, self.kvl = arr["kp_load"], arr["kv_load"]
        self.T, self.delay, self.r = period, delay, reference
        self.alpha = math.exp(-2.0 * math.pi * filter_hz * period) if filter_hz > 0 else 0.0
        n = self.kpa.size
        self.va, self.vl, self.pending = np.zeros(n), np.zeros(n), np.zeros(n)

    def start(self, xa_hat: FloatArray, xl_hat: FloatArray) -> None:
        self.prev_a, self.prev_l = xa_hat, xl_hat

    def command(self, xa_hat: FloatArray, xl_hat: FloatArray) -> FloatArray:
        a, T = self.alpha, self.T
        self.va = a * self.va + (1.0 - a) * (xa_hat - self.prev_a) / T
        self.vl = a * self.vl + (1.0 - a) * (xl_hat - self.prev_l) / T
        self.prev_a, self.prev_l = xa_hat, xl_hat
        r = self.r
        u = (
            self.kpa * (r - xa_hat)
            - self.kva * self.va
            + self.kpl * (r - xl_hat)
            - self.kvl * self.vl
        )
        applied = self.pending if self.delay else u
        self.pending = u
        return applied


class _Contact:
    """A hand body pressing on the load through the unilateral contact ``max(0, k p + c ṗ)``."""

    def __init__(self, arr: dict[str, FloatArray], kern: PlantKernel) -> None:
        self.m, self.k, self.c = arr["hand.mass"], arr["hand.stiffness"], arr["hand.damping"]
        if np.any(self.m <= 0) or np.any(self.k <= 0) or np.any(self.c < 0):
            raise ParameterError("hand mass and stiffness must be positive, damping non-negative")
        self.kern = kern
        self.x, self.v = kern.xl.copy(), arr["hand.speed"].copy()

    def force(self) -> FloatArray:
        pen = self.x - self.kern.xl
        f = self.k * pen + self.c * (self.v - self.kern.vl)
        return np.where(pen > 0, np.maximum(f, 0.0), 0.0)

    def advance(self, h: float) -> FloatArray:
        """Move the hand by one substep ``h`` (symplectic Euler); return the contact force."""
        f = self.force()
        self.v = self.v - h * f / self.m
        self.x = self.x + h * self.v
        return f


class _EndStop:
    """Runs that leave ``±travel`` are frozen at the end stop.

    The bench would hit the stop and be switched off, so a diverged run can
    neither overflow nor drift back.
    """

    def __init__(self, n: int, travel: float) -> None:
        self.travel = travel
        self.diverged = np.zeros(n, dtype=bool)
        self.xa, self.xl = np.zeros(n), np.zeros(n)

    def hold(self, kern: PlantKernel) -> None:
        tr = self.travel
        bad = (np.abs(kern.xl) > tr) | (np.abs(kern.xa) > tr) | ~np.isfinite(kern.xl)
        new = bad & ~self.diverged
        if np.any(new):
            self.xa = np.where(new, np.clip(np.nan_to_num(kern.xa), -tr, tr), self.xa)
            self.xl = np.where(new, np.clip(np.nan_to_num(kern.xl), -tr, tr), self.xl)
            self.diverged |= bad
        if np.any(self.diverged):
            kern.xa = np.where(self.diverged, self.xa, kern.xa)
            kern.xl = np.where(self.diverged, self.xl, kern.xl)
            kern.va = np.where(self.diverged, 0.0, kern.va)
            kern.vl = np.where(self.diverged, 0.0, kern.vl)


class _Record:
    """Output arrays, axis order ``(run, sample)``."""

    def __init__(self, n: int, steps: int) -> None:
        self.x_A = np.empty((n, steps + 1))
        self.x_L = np.empty((n, steps + 1))
        self.x_A_measured = np.empty((n, steps + 1))
        self.x_L_measured = np.empty((n, steps + 1))
        self.external = np.zeros((n, steps + 1))
        self.force = np.zeros((n, steps))
        self.command = np.zeros((n, steps))

    def sample(
        self, k: int, kern: PlantKernel, xa_hat: FloatArray, xl_hat: FloatArray, ext: Any
    ) -> None:
        self.x_A[:, k], self.x_L[:, k] = kern.xa, kern.xl
        self.x_A_measured[:, k], self.x_L_measured[:, k] = xa_hat, xl_hat
        self.external[:, k] = ext


def linear_matrices(
    rig: Rig, *, load_mass: float, b1: float | None = None
) -> tuple[FloatArray, FloatArray]:
    """Continuous linear plant ``ẋ = A x + B u`` with ``x = (x_A, v_A, x_L, v_L)``.

    Friction-free, unsaturated, unquantized: the model the twin reduces to.
    """
    m = rig.actuator_mass
    ml = rig.load_side_mass(load_mass)
    b, bl, k1 = rig.actuator_damping, rig.load.viscous, rig.damper.k1
    c = rig.damper.b1 if b1 is None else float(b1)
    a = np.array(
        [
            [0.0, 1.0, 0.0, 0.0],
            [-k1 / m, -(b + c) / m, k1 / m, c / m],
            [0.0, 0.0, 0.0, 1.0],
            [k1 / ml, c / ml, -k1 / ml, -(bl + c) / ml],
        ]
    )
    bmat = np.array([[0.0], [1.0 / m], [0.0], [0.0]])
    return a, bmat
