"""Deployable discrete-time controllers: one difference equation per controller.

The continuous controllers ``C_A``, ``C_L`` of an [`SEA`][seapass.model.sea.SEA] are
discretized by [`seapass.sampled.emulation`][seapass.sampled.emulation] into four exact
paths (error and measurement path of each side: derivative on measurement, the backward
difference velocity through the optional low-pass, the strictly proper part by Tustin,
ZOH or backward difference), or given directly in ``z`` (`DiscreteController.from_z`).
The four paths are realized together, over their exact least common denominator
([`seapass.sampled.joint`][seapass.sampled.joint]), and run as ONE
direct-form-II-transposed difference equation: a pole ``C_A`` and ``C_L`` share is one
state.  With constant references the closed loop equals ``u = K(z)(θ − x)`` with ``K``
the sum of the two paths of each side, which is what
[`seapass.sampled.passivity`][seapass.sampled.passivity] analyses.

References
----------
.. [1] G. F. Franklin, J. D. Powell, M. Workman, *Digital Control of Dynamic
   Systems*, 3rd ed., Addison-Wesley, 1998, ch. 6.
.. [2] K. J. Åström, T. Hägglund, *Advanced PID Control*, ISA, 2006, §3.4
   (derivative on measurement, derivative filtering).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from flint import fmpq, fmpq_poly

from ..errors import ParameterError
from ..model.loop import METHODS, Method, SampledLoop
from ..model.minimal import numeric_controllers, split_proper
from ..model.sea import SEA
from ..model.zcontroller import continuous_only
from .emulation import (
    Rational,
    as_discrete_tf,
    check_period,
    discrete_paths,
    discretize,
    emulate,
    filter_pole,
    zoh_discretize,
    zoh_row,
    zoh_row_exact,
)
from .joint import (
    DiscreteTF,
    JointDifferenceEquation,
    JointRealization,
    poly_add,
    poly_mul,
    q_lcm,
    q_reduce,
)

__all__ = [
    "SIGNALS",
    "APDController",
    "DifferenceEquation",
    "DiscreteController",
    "DiscreteTF",
    "LPController",
    "OursController",
    "controller_parts",
    "controller_state_space",
    "controller_tfs",
    "discrete_paths",
    "discretize",
    "filter_pole",
    "state_space",
    "zoh_discretize",
    "zoh_row",
]


class DifferenceEquation:
    """Run a `DiscreteTF` sample by sample (direct form II transposed, float64)."""

    def __init__(self, tf: DiscreteTF) -> None:
        n = max(len(tf.num), len(tf.den))
        self.b = np.array([float(c) for c in tf.num] + [0.0] * (n - len(tf.num)))
        self.a = np.array([float(c) for c in tf.den] + [0.0] * (n - len(tf.den)))
        self.z = np.zeros(max(n - 1, 0))

    def reset(self) -> None:
        self.z[:] = 0.0

    def step(self, x: float) -> float:
        y = self.b[0] * x + (self.z[0] if self.z.size else 0.0)
        for i in range(self.z.size):
            nxt = self.z[i + 1] if i + 1 < self.z.size else 0.0
            self.z[i] = nxt + self.b[i + 1] * x - self.a[i + 1] * y
        return float(y)


SIGNALS = ("error_A", "measurement_A", "error_L", "measurement_L")
"""The controller's four inputs: ``θ_A − x_A``, ``−x_A``, ``θ_L − x_L``, ``−x_L``."""


@dataclass
class DiscreteController:
    """``u = K_A(θ_A − x_A) + K_L(θ_L − x_L)`` at a fixed period, ready to deploy.

    Derivative terms act on the measurement only (see module docstring).  The four paths
    (error and measurement of each side) run as ONE difference equation over their exact
    least common denominator ([`JointRealization`][seapass.sampled.joint.JointRealization]):
    a pole ``C_A`` and ``C_L`` share is one state.  Build from an SEA with `from_sea`,
    from z-transfer functions with `from_z`, or use `LPController`, `APDController`,
    `OursController`.

    Parameters
    ----------
    CA, CL : tuple of DiscreteTF
        ``(error_path, measurement_path)`` for each side.
    period : float
    """

    CA: tuple[DiscreteTF, DiscreteTF]
    CL: tuple[DiscreteTF, DiscreteTF]
    period: float
    name: str = ""
    realization: JointRealization = field(init=False, repr=False)
    _runner: JointDifferenceEquation = field(init=False, repr=False)

    def __post_init__(self) -> None:
        paths = (*self.CA, *self.CL)
        self.realization = JointRealization.of(
            [(tf.num, tf.den) for tf in paths], SIGNALS, paths[0].period
        )
        self._runner = JointDifferenceEquation(self.realization)

    @classmethod
    def from_sea(
        cls,
        sea: SEA,
        period: float,
        *,
        method: Method = "tustin",
        velocity_filter: float | None = None,
        values: Mapping[str, float] | None = None,
    ) -> DiscreteController:
        """Discretize ``sea.CA`` and ``sea.CL`` with the model's parameter values.

        With ``method="zoh"`` the strictly proper parts are discretized together, from their
        one minimal realization (`zoh_row`).
        """
        if method not in METHODS:
            raise ParameterError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
        continuous_only(sea, "discretizing CA and CL")
        T = check_period(period)
        rows = numeric_controllers(sea, values)
        propers: list[Rational | None] = [None, None]
        if method == "zoh":
            parts_s = [split_proper(r)[1] for r in rows]
            if any(not n.is_zero() for n, _d in parts_s):
                propers = list(zoh_row_exact(parts_s, T))
        a = filter_pole(velocity_filter, float(T))
        parts = []
        for (num, den), pq in zip(rows, propers, strict=True):
            err, meas = emulate(num, den, T, method=method, filter_pole=a, proper_q=pq)
            parts.append((as_discrete_tf(err, T), as_discrete_tf(meas, T)))
        return cls(parts[0], parts[1], float(period), sea.name)

    @classmethod
    def for_loop(
        cls, sea: SEA, loop: SampledLoop, *, values: Mapping[str, float] | None = None
    ) -> DiscreteController:
        """`from_sea` at the period, discretization and velocity filter of ``loop``.

        A controller given in ``z`` (``sea.discrete``) is used as is, at the loop's period,
        which must be its own (`from_z`; the method and velocity filter do not apply).
        """
        if sea.discrete is not None:
            return cls.of_z(sea, loop.period, values=values)
        return cls.from_sea(
            sea,
            loop.period,
            method=loop.method,
            velocity_filter=loop.velocity_filter,
            values=values,
        )

    @classmethod
    def of_z(
        cls, sea: SEA, period: float, *, values: Mapping[str, float] | None = None
    ) -> DiscreteController:
        """The controller in ``z`` of ``sea`` (``sea.discrete``), run as is at ``period``.

        Raises
        ------
        ParameterError
            Without a controller in z, or when ``period`` is not its rate's (naming both).
        """
        zc = sea.discrete
        if zc is None:
            raise ParameterError("the model has no controller in z (discrete)")
        zc.check_loop(period)
        T = check_period(period)
        merged = {**{k: v for k, v in sea.values.items() if v is not None}, **dict(values or {})}
        (na, da), (nl, dl) = zc.coefficients(merged)
        return cls.from_z(DiscreteTF(na, da, T), DiscreteTF(nl, dl, T), name=sea.name)

    @classmethod
    def from_z(cls, KA: DiscreteTF, KL: DiscreteTF, *, name: str = "") -> DiscreteController:
        """A controller given in ``z`` (``u = K_A(θ_A − x_A) + K_L(θ_L − x_L)``), run as is.

        Both transfer functions must be at the same period; nothing is re-discretized.
        """
        if KA.period != KL.period:
            raise ParameterError(
                f"K_A and K_L are at different periods ({float(KA.period):g} s and "
                f"{float(KL.period):g} s); give both at the loop's period"
            )
        zero = DiscreteTF((Fraction(0),), (Fraction(1),), KA.period)
        return cls((KA, zero), (KL, zero), float(KA.period), name)

    @property
    def order(self) -> int:
        """Number of states of the one difference equation (the McMillan degree)."""
        return self.realization.order

    def transfer_functions(self) -> tuple[DiscreteTF, DiscreteTF]:
        """Total ``(K_A(z), K_L(z))`` acting on ``−x`` when references are zero, reduced."""
        out = []
        for err, meas in (("error_A", "measurement_A"), ("error_L", "measurement_L")):
            (n1, d), (n2, d2) = self.realization.entry(err), self.realization.entry(meas)
            num = poly_add(poly_mul(n1, d2), poly_mul(n2, d))
            out.append(DiscreteTF(*q_reduce(num, poly_mul(d, d2)), self.realization.period))
        return out[0], out[1]

    def hidden_modes(self) -> tuple[Fraction, ...]:
        """Denominator factor of the running realization that ``(K_A, K_L)`` do not show.

        With constant references the loop sees only ``K_A + K_L`` paths summed; a pole of the
        realization that cancels in those sums (exceptional) is still a mode of the loop.
        Ascending in ``z⁻¹``, constant term 1; ``(1,)`` when there is none.
        """
        ka, kl = self.transfer_functions()
        seen = q_lcm(ka.den, kl.den)
        full = self.realization.denominator
        rest, rem = divmod(_as_q(full), _as_q(seen))
        if not rem.is_zero():  # cannot happen: every entry's poles are the realization's
            raise AssertionError("the transfer functions have poles the realization lacks")
        return q_reduce(_tuple_q(rest), (Fraction(1),))[0]

    def reset(self) -> None:
        self._runner.reset()

    def step(
        self,
        measurement: tuple[float, float],
        reference: tuple[float, float] = (0.0, 0.0),
    ) -> float:
        """One control period: ``(x_A, x_L)`` and ``(θ_A, θ_L)`` in, force command out."""
        xa, xl = measurement
        ta, tl = reference
        signals = {
            "error_A": ta - xa,
            "measurement_A": -xa,
            "error_L": tl - xl,
            "measurement_L": -xl,
        }
        return self._runner.step([signals[k] for k in self.realization.inputs])


def _as_q(c: Sequence[Fraction]) -> Any:
    return fmpq_poly([fmpq(Fraction(x).numerator, Fraction(x).denominator) for x in c])


def _tuple_q(p: Any) -> tuple[Fraction, ...]:
    return tuple(Fraction(int(x.p), int(x.q)) for x in p.coeffs()) or (Fraction(0),)


def _pd(kd: float, bd: float) -> str:
    return f"({Fraction(kd)}) + ({Fraction(bd)})*s"


class LPController(DiscreteController):
    """Load-side proportional control ``C_L = kd`` (the paper's LP)."""

    def __init__(self, kd: float, period: float, **kw: object) -> None:
        sea = SEA(D1="k1", CL=_pd(kd, 0.0), values={"k1": 1.0}, name="LP")
        base = DiscreteController.from_sea(sea, period, **kw)  # type: ignore[arg-type]
        super().__init__(base.CA, base.CL, float(period), "LP")


class APDController(DiscreteController):
    """Actuator-side PD ``C_A = kd + bd s`` (the paper's APD, pure-spring hardware)."""

    def __init__(self, kd: float, bd: float, period: float, **kw: object) -> None:
        sea = SEA(D1="k1", CA=_pd(kd, bd), values={"k1": 1.0}, name="APD")
        base = DiscreteController.from_sea(sea, period, **kw)  # type: ignore[arg-type]
        super().__init__(base.CA, base.CL, float(period), "APD")


class OursController(DiscreteController):
    """Actuator-side PD ``C_A = kd + bd s`` for the damped transmission (the paper's Ours)."""

    def __init__(self, kd: float, bd: float, period: float, **kw: object) -> None:
        sea = SEA(D1="k1 + b1*s", CA=_pd(kd, bd), values={"k1": 1.0, "b1": 1.0}, name="Ours")
        base = DiscreteController.from_sea(sea, period, **kw)  # type: ignore[arg-type]
        super().__init__(base.CA, base.CL, float(period), "Ours")


def state_space(tf: DiscreteTF) -> tuple[np.ndarray, ...]:
    """Direct-form-II-transposed state space ``(A, B, C, D)`` of ``tf``, as it runs."""
    n = max(len(tf.num), len(tf.den))
    b = np.array([float(c) for c in tf.num] + [0.0] * (n - len(tf.num)))
    a = np.array([float(c) for c in tf.den] + [0.0] * (n - len(tf.den)))
    k = n - 1
    A = np.zeros((k, k))
    if k:
        A[:, 0] = -a[1:]
        A[:-1, 1:] = np.eye(k - 1)
    B = (b[1:] - a[1:] * b[0]).reshape(k, 1)
    C = np.zeros((1, k))
    if k:
        C[0, 0] = 1.0
    return A, B, C, np.array([[b[0]]])


def controller_tfs(sea: SEA, loop: SampledLoop) -> tuple[DiscreteTF, DiscreteTF]:
    """``(z^-d K_A(z), z^-d K_L(z))`` in ``loop`` exactly as `DiscreteController` runs them."""
    ka, kl, _hidden = controller_parts(DiscreteController.for_loop(sea, loop), loop.delay)
    return ka, kl


def controller_parts(
    ctrl: DiscreteController, delay: int
) -> tuple[DiscreteTF, DiscreteTF, tuple[Fraction, ...]]:
    """``(z^-d K_A, z^-d K_L, hidden modes)`` of a controller: what the sampled analysis needs.

    The hidden modes (`DiscreteController.hidden_modes`) are poles of the running realization
    that the two transfer functions do not show; the loop with the port held must keep them
    stable too.
    """
    ka, kl = ctrl.transfer_functions()
    return ka.delayed(delay), kl.delayed(delay), ctrl.hidden_modes()


def controller_state_space(
    ctrl: DiscreteController, delay: int = 0
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(A, B, C, D)`` with ``u = −(C ξ + D x)``, ``ξ⁺ = A ξ + B x``, ``x = (x_A, x_L)``.

    The one minimal realization of the controller with zero references (error and
    measurement paths both see ``−x``), followed by ``delay`` samples of delay on its
    output (a shift register): the controller block of a sampled closed loop.
    """
    A, B, C, D = ctrl.realization.state_space()
    n = A.shape[0]
    Bx, Dx = np.zeros((n, 2)), np.zeros(2)
    for j, name in enumerate(ctrl.realization.inputs):
        side = 0 if name.endswith("_A") else 1
        Bx[:, side] += B[:, j]
        Dx[side] += D[j]
    if not delay:
        return A, Bx, C, Dx
    # shift register w: w1⁺ = C ξ + D x, w_{i+1}⁺ = w_i, output w_d
    m = n + delay
    Ad, Bd, Cd = np.zeros((m, m)), np.zeros((m, 2)), np.zeros(m)
    Ad[:n, :n], Bd[:n] = A, Bx
    Ad[n, :n], Bd[n] = C, Dx
    for i in range(1, delay):
        Ad[n + i, n + i - 1] = 1.0
    Cd[m - 1] = 1.0
    return Ad, Bd, Cd, np.zeros(2)
