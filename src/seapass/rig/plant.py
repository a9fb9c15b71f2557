"""Digital twin of an SEA test bench: nonlinear plant, encoders, sampled control loop.

The plant has two bodies on a rail: the actuator carriage (mass ``m`` = carriage
+ rotor inertia reflected through gearbox and pulley, viscous ``b`` and dry
friction to ground) and the output carriage with the load (mass ``m_L``, light
viscous and dry rail friction).  They are joined by the spring ``k1`` in
parallel with a friction damper (viscous ``b1`` plus Coulomb level ``F_c1``).
The motor force is saturated at the peak force of the rig.

Integration is deterministic and fixed-step: each control period is split into
``rig.control.substeps`` substeps; the linear part (masses, springs, viscous
dampers) is advanced by the trapezoidal rule (A-stable, no numerical damping)
and the three dry-friction contacts are solved at velocity level as bounded
impulses (projected Gauss-Seidel, warm-started), so sticking is exact rather
than a stiff regularised ``tanh``.  With all dry friction set to zero this is
the exact trapezoidal discretisation of the linear model.

Sensors follow the bench: a rotary incremental encoder on the motor (counts of
the carriage position through gearbox and pulley) and a linear encoder on the
spring deflection ``x_L − x_A``.  Counts are floors of position/resolution plus
a phase offset (0.5 count, i.e. rounding, unless a ``seed`` draws random phases
like an encoder powered up at an arbitrary point of a line).

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Section VI.
.. [2] D. E. Stewart, "Rigid-body dynamics with friction and impact",
   SIAM Review 42(1), 2000 (velocity-level friction impulses).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ParameterError, SimulationError
from .rigfile import Rig

__all__ = ["Encoders", "PlantKernel", "TwinPlant", "as_batch"]


_PGS_ITERATIONS = 4


FloatArray = NDArray[np.float64]


def as_batch(name: str, value: ArrayLike, n: int) -> FloatArray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,):
        raise ParameterError(f"{name} must be a scalar or have shape ({n},), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} must be finite")
    return arr


def _clip_scalar(x: float, lo: float, hi: float) -> float:
    return lo if x < lo else hi if x > hi else x


def _clip_array(x: Any, lo: Any, hi: Any) -> Any:
    # np.clip's Python-level checks cost ~3x the two ufuncs on the short arrays of a sweep
    return np.minimum(np.maximum(x, lo), hi)


class PlantKernel:
    """Plant integrator over a batch of ``n`` independent runs.

    Every parameter may be a scalar or an array of shape ``(n,)``.  With
    ``scalar=True`` (``n`` = 1) state and coefficients are Python floats: the
    same arithmetic, ~10x faster for the single-run `TwinPlant`.
    """

    # float in scalar mode, (n,) arrays otherwise
    xa: Any
    va: Any
    xl: Any
    vl: Any
    lam_a: Any
    lam_1: Any
    lam_l: Any

    def __init__(
        self,
        rig: Rig,
        n: int,
        *,
        load_mass: ArrayLike,
        b1: ArrayLike | None = None,
        friction: bool = True,
        saturate: bool = True,
        scalar: bool = False,
    ) -> None:
        if scalar and n != 1:
            raise ValueError("scalar mode needs n == 1")
        self.n, self.scalar = n, scalar
        self.h = rig.period / rig.control.substeps
        ml = as_batch("load_mass", load_mass, n)
        if np.any(ml < 0):
            raise ParameterError("load_mass must be non-negative")
        ml = ml + rig.load.carriage_mass
        if np.any(ml <= 0):
            raise ParameterError("the load side needs a positive mass (carriage + load)")
        b1a = as_batch("b1", rig.damper.b1 if b1 is None else b1, n)
        if np.any(b1a < 0):
            raise ParameterError("b1 must be non-negative")
        self._m, self._ml, self._b1 = rig.actuator_mass, ml, b1a
        self._b, self._bl, self.k1 = rig.actuator_damping, rig.load.viscous, rig.damper.k1
        fc = (rig.transmission.coulomb, rig.damper.coulomb, rig.load.coulomb)
        self._fc = fc if friction else (0.0, 0.0, 0.0)
        self.friction = friction and any(f > 0 for f in fc)
        self.fmax = rig.force_limit if saturate else math.inf
        self._cache: dict[float, tuple[Any, ...]] = {}
        self._clip: Any = _clip_scalar if scalar else _clip_array
        self._coeffs(self.h)
        self.set_state(0.0, 0.0, 0.0, 0.0)

    def _coeffs(self, h: float) -> tuple[Any, ...]:
        """Trapezoidal-rule coefficients for step ``h`` (cached)."""
        if h in self._cache:
            return self._cache[h]
        m, ml, b1, b, bl, k1 = self._m, self._ml, self._b1, self._b, self._bl, self.k1
        # A = M + h/2 B + h^2/4 K and its inverse (symmetric 2x2, per run).
        a11 = m + 0.5 * h * (b + b1) + 0.25 * h * h * k1
        a22 = ml + 0.5 * h * (bl + b1) + 0.25 * h * h * k1
        a12 = -0.5 * h * b1 - 0.25 * h * h * k1
        det = a11 * a22 - a12 * a12
        i11, i22, i12 = a22 / det, a11 / det, -a12 / det
        # R = M - h/2 B - h^2/4 K for the explicit half of the trapezoidal rule.
        r11 = m - 0.5 * h * (b + b1) - 0.25 * h * h * k1
        r22 = ml - 0.5 * h * (bl + b1) - 0.25 * h * h * k1
        r12 = 0.5 * h * b1 + 0.25 * h * h * k1
        # Inverse effective masses of the contacts: ground-A, A-L (damper), ground-L.
        w1 = i11 + i22 - 2.0 * i12
        vals: tuple[Any, ...] = (i11, i22, i12, r11, r22, r12, i11, w1, i22)
        if self.scalar:
            vals = tuple(float(np.ravel(v)[0]) for v in vals)
        caps = tuple(h * f for f in self._fc)
        out = (*vals, *caps)
        self._cache[h] = out
        return out

    def set_state(self, xa: ArrayLike, va: ArrayLike, xl: ArrayLike, vl: ArrayLike) -> None:
        vals = [
            as_batch(k, v, self.n).copy()
            for k, v in zip(("x_A", "v_A", "x_L", "v_L"), (xa, va, xl, vl), strict=True)
        ]
        if self.scalar:
            self.xa, self.va, self.xl, self.vl = (float(v[0]) for v in vals)
            self.lam_a = self.lam_1 = self.lam_l = 0.0
        else:
            self.xa, self.va, self.xl, self.vl = vals
            z = np.zeros(self.n)
            self.lam_a, self.lam_1, self.lam_l = z, z.copy(), z.copy()
        self._lam_h = self.h

    def saturate(self, force: Any) -> Any:
        return self._clip(force, -self.fmax, self.fmax)

    def substep(self, force: Any, f_ext: Any, h: float | None = None) -> None:
        """Advance one substep of ``h`` (default the nominal substep) with the
        (already saturated) motor force and the force on the load."""
        h = self.h if h is None else h
        i11, i22, i12, r11, r22, r12, w_a, w_1, w_l, cap_a, cap_1, cap_l = self._coeffs(h)
        k1 = self.k1
        xa, va, xl, vl = self.xa, self.va, self.xl, self.vl
        spring = k1 * (xa - xl)
        rhs_a = r11 * va + r12 * vl + h * (force - spring)
        rhs_l = r12 * va + r22 * vl + h * (f_ext + spring)
        nva = i11 * rhs_a + i12 * rhs_l
        nvl = i12 * rhs_a + i22 * rhs_l
        if self.friction:
            if h != self._lam_h:
                # Impulses scale with the step; keep the warm start consistent.
                r = h / self._lam_h
                self.lam_a, self.lam_1, self.lam_l = self.lam_a * r, self.lam_1 * r, self.lam_l * r
                self._lam_h = h
            clip = self._clip
            la, l1, ll = self.lam_a, self.lam_1, self.lam_l
            # Warm start with last substep's impulses (sticking persists across substeps).
            ga, gl = la + l1, ll - l1
            nva = nva + i11 * ga + i12 * gl
            nvl = nvl + i12 * ga + i22 * gl
            for _ in range(_PGS_ITERATIONS):
                new = clip(la - nva / w_a, -cap_a, cap_a)
                d = new - la
                nva, nvl, la = nva + i11 * d, nvl + i12 * d, new
                new = clip(l1 - (nva - nvl) / w_1, -cap_1, cap_1)
                d = new - l1
                nva, nvl, l1 = nva + (i11 - i12) * d, nvl + (i12 - i22) * d, new
                new = clip(ll - nvl / w_l, -cap_l, cap_l)
                d = new - ll
                nva, nvl, ll = nva + i12 * d, nvl + i22 * d, new
            self.lam_a, self.lam_1, self.lam_l = la, l1, ll
        self.xa = xa + 0.5 * h * (va + nva)
        self.xl = xl + 0.5 * h * (vl + nvl)
        self.va, self.vl = nva, nvl


class Encoders:
    def __init__(self, rig: Rig, n: int, seed: int | None, quantize: bool) -> None:
        self.res_a = rig.motor_resolution
        self.res_l = rig.linear_resolution
        self.quantize = quantize
        if seed is None:
            self.off_a = np.full(n, 0.5)
            self.off_l = np.full(n, 0.5)
        else:
            # One (motor, linear) pair per run, so run i's phases do not depend on n.
            phases = np.random.default_rng(seed).random((n, 2))
            self.off_a = phases[:, 0].copy()
            self.off_l = phases[:, 1].copy()

    def counts(self, xa: FloatArray, xl: FloatArray) -> tuple[FloatArray, FloatArray]:
        return (
            np.floor(xa / self.res_a + self.off_a),
            np.floor((xl - xa) / self.res_l + self.off_l),
        )

    def measure(self, xa: FloatArray, xl: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Positions ``x̂_A, x̂_L`` as the controller sees them."""
        if not self.quantize:
            return xa.copy(), xl.copy()
        ca, cl = self.counts(xa, xl)
        xa_hat = ca * self.res_a
        return xa_hat, xa_hat + cl * self.res_l


class TwinPlant:
    """Nonlinear digital twin of one rig with one load mass (single run).

    Stable interface used by the runtime layer (``SimulatedHardware``):

    * ``reset(*, x_A=0.0, x_L=0.0, v_A=0.0, v_L=0.0)`` — set the state, time 0.
    * ``apply(force_command, duration, *, external_force=0.0)`` — saturate the
      command at ``rig.force_limit``, hold it (ZOH) and integrate the nonlinear
      dynamics for ``duration`` seconds (normally one control period) in
      substeps of ``rig.period / rig.control.substeps``; ``external_force`` acts
      on the load (positive in +x, i.e. stretching the transmission).
    * ``read_encoders() -> (motor_counts, linear_counts)`` — integer counts of
      the motor encoder (carriage position) and the linear encoder (deflection
      ``x_L − x_A``).
    * ``counts_to_positions(motor_counts, linear_counts) -> (x_A, x_L)`` in m.
    * ``state -> (x_A, v_A, x_L, v_L)`` and ``time`` (s), the true values.

    Parameters
    ----------
    rig : Rig
    load_mass : float
        Mass attached to the output carriage (kg), e.g. 0.1 or 0.6.
    seed : int or None
        Draws the encoders' sub-count phase offsets; ``None`` means rounding to
        the nearest count (fully deterministic, no randomness).
    friction, quantize, saturate : bool
        Turn off dry friction, encoder quantization or force saturation (for
        comparisons with the linear model).
    """

    def __init__(
        self,
        rig: Rig,
        *,
        load_mass: float,
        seed: int | None = None,
        friction: bool = True,
        quantize: bool = True,
        saturate: bool = True,
    ) -> None:
        if not isinstance(rig, Rig):
            raise ParameterError(f"rig must be a Rig, got {type(rig).__name__}")
        self.rig = rig
        self.load_mass = float(load_mass)
        self._k = PlantKernel(
            rig, 1, load_mass=self.load_mass, friction=friction, saturate=saturate, scalar=True
        )
        self._enc = Encoders(rig, 1, seed, quantize)
        self._res_a, self._res_l = self._enc.res_a, self._enc.res_l
        self._off_a, self._off_l = float(self._enc.off_a[0]), float(self._enc.off_l[0])
        self._t = 0.0
        self.last_force = 0.0

    def reset(
        self, *, x_A: float = 0.0, x_L: float = 0.0, v_A: float = 0.0, v_L: float = 0.0
    ) -> None:
        self._k.set_state(x_A, v_A, x_L, v_L)
        self._t = 0.0
        self.last_force = 0.0

    def apply(self, force_command: float, duration: float, *, external_force: float = 0.0) -> None:
        f = float(force_command)
        if not math.isfinite(f):
            raise SimulationError(f"force command must be finite, got {force_command!r}")
        if not (duration >= 0 and math.isfinite(duration)):
            raise ParameterError(f"duration must be a non-negative finite time, got {duration!r}")
        k = self._k
        force = k.saturate(f)
        self.last_force = force
        ext = float(external_force)
        # Whole substeps, then one shorter substep for any remainder: time stays exact.
        n_full = int(duration / k.h * (1 + 1e-12))
        rest = duration - n_full * k.h
        for _ in range(n_full):
            k.substep(force, ext)
        if rest > 1e-9 * k.h:
            k.substep(force, ext, rest)
        self._t += duration

    def read_encoders(self) -> tuple[int, int]:
        k = self._k
        return (
            math.floor(k.xa / self._res_a + self._off_a),
            math.floor((k.xl - k.xa) / self._res_l + self._off_l),
        )

    def counts_to_positions(self, motor_counts: float, linear_counts: float) -> tuple[float, float]:
        xa = float(motor_counts) * self._res_a
        return xa, xa + float(linear_counts) * self._res_l

    def measured_positions(self) -> tuple[float, float]:
        """``(x̂_A, x̂_L)``: encoder readings in metres (exact positions if ``quantize=False``)."""
        if not self._enc.quantize:
            return self._k.xa, self._k.xl
        return self.counts_to_positions(*self.read_encoders())

    @property
    def state(self) -> tuple[float, float, float, float]:
        k = self._k
        return k.xa, k.va, k.xl, k.vl

    @property
    def time(self) -> float:
        return self._t
