"""Time response of the sampled loop: the deployed difference equation driving the plant.

[`seapass.sim.simulate`][seapass.sim.simulate] simulates a continuous controller; a
controller given in ``z`` (``SEA.discrete``, see
[`ZController`][seapass.model.zcontroller.ZController]) exists only at its rate, so its
response is that of the sampled loop: at each sampling instant ``x_A`` and ``x_L`` are
read, the one difference equation of the controller
([`DiscreteController`][seapass.sampled.controllers.DiscreteController], run as is) gives
the force, which is applied ``loop.delay`` samples later and held (ZOH) over the period.
The plant with its load mass is discretized exactly (matrix exponential), so the samples
are exact up to rounding; stability is the spectral radius of the one-period transition
matrix of the whole loop ([`coupled_closed_loop`][seapass.sampled.coupling.coupled_closed_loop]).
Any rational ``D1``, ``D2`` with at most one derivative is supported (the plant of
[`discrete_plant`][seapass.sampled.plantloop.discrete_plant]: their internal states are
plant states).

The tracking metrics ([`SampledResponse.metrics`][seapass.sampled.response.SampledResponse.metrics]:
settling time, overshoot, final error, force, energy) are those of
[`tracking_metrics`][seapass.sim.metrics.tracking_metrics], computed by the same function on
[`SampledResponse.simulation`][seapass.sampled.response.SampledResponse.simulation]: the plant
driven by the held force, whose exact solution between the instants is known, so the
settling time is that of the continuous load motion, not only of its samples.

References
----------
.. [1] G. F. Franklin, J. D. Powell, M. Workman, *Digital Control of Dynamic
   Systems*, 3rd ed., Addison-Wesley, 1998, §4.3 (ZOH equivalent), ch. 6.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..files.limits import MAX_SIM_STEPS
from ..model.display import html_card, short_repr
from ..model.experiment import PAPER_EXPERIMENT
from ..model.expr import finite_number
from ..model.loop import SampledLoop
from ..model.sea import SEA
from ..sim.metrics import TrackingMetrics, tracking_metrics
from ..sim.scenarios import (
    ForceImpulse,
    ForceStep,
    LoadDisplaced,
    Scenario,
    Step,
    Trajectory,
    reference_values,
)
from ..sim.simulate import SimulationResult
from .controllers import DiscreteController
from .plant import numeric_element
from .plantloop import discrete_plant, loop_matrix

__all__ = ["SampledResponse", "sampled_response"]


@dataclass(frozen=True, kw_only=True, repr=False)
class SampledResponse:
    """The sampled loop's response at the sampling instants ``k T``.

    Attributes
    ----------
    time, x_A, v_A, x_L, v_L, f_A : ndarray, shape (N + 1,)
        Time (s), plant states at the instants and the force applied from each instant on.
    loop : SampledLoop
    spectral_radius : float
        Of the loop's one-period transition matrix; ``< 1`` is stable.
    target : float
        Final load reference (m).
    scenario : Scenario
    plant_A, plant_B : ndarray, shapes (n, n) and (n, 2)
        The continuous plant with its load mass, ``ẋ = A x + B (f_A, f_ext)`` (states
        ``x_A, v_A, x_L, v_L`` first, then those of ``D1`` and ``D2``).
    f_ext : ndarray, shape (N + 1,)
        External force held from each instant on (N).
    statics : ndarray, shape (6,) or None
        ``(n_A(1), d_A(1), n_L(1), d_L(1), D1(0), D2(0))``: the controller's numerators
        and denominators at ``z = 1`` and the static stiffnesses, from which the rest position under a
        constant external force is found (None: not computed).
    periods : int
        Periods asked for; fewer samples than ``periods + 1`` mean the run diverged.
    plant : ClosedLoop or None
        The plant's realization (`plant_realization`; None: the ``k + b s`` plant of
        ``plant_A``); ``plant_states`` its whole state at the instants, shape (N + 1, n).
    """

    time: np.ndarray
    x_A: np.ndarray
    v_A: np.ndarray
    x_L: np.ndarray
    v_L: np.ndarray
    f_A: np.ndarray
    loop: SampledLoop
    spectral_radius: float
    target: float
    scenario: Any = field(default=None)
    plant_A: np.ndarray = field(default_factory=lambda: np.zeros((4, 4)), repr=False)
    plant_B: np.ndarray = field(default_factory=lambda: np.zeros((4, 2)), repr=False)
    f_ext: np.ndarray | None = field(default=None, repr=False)
    statics: np.ndarray | None = field(default=None, repr=False)
    periods: int = 0
    plant: Any = field(default=None, repr=False)
    plant_states: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if self.f_ext is None:
            object.__setattr__(self, "f_ext", np.zeros(np.shape(self.time)))
        for name in ("time", "x_A", "v_A", "x_L", "v_L", "f_A", "plant_A", "plant_B", "f_ext"):
            arr = np.array(getattr(self, name), dtype=float)
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)

    @property
    def stable(self) -> bool:
        """Spectral radius below 1."""
        return self.spectral_radius < 1.0

    @property
    def final_error(self) -> float:
        """``x_L`` at the end minus the target (m)."""
        return float(self.x_L[-1] - self.target)

    def simulation(self) -> SimulationResult:
        """This response as a [`SimulationResult`][seapass.sim.simulate.SimulationResult].

        Its ``system`` is the plant alone, driven by the held inputs ``(f_A, 0, f_ext)``
        (the input slots of ``θ_A``, ``θ_L``, ``f_ext``), so
        [`state_at`][seapass.sim.simulate.SimulationResult.state_at] is the exact load
        motion between the instants.  ``stable`` is ``spectral_radius < 1`` and the run
        counts as diverged when it was cut; ``poles`` is empty (the loop's are in z).
        ``energy`` is exact (the force is constant over each period); ``positive_work``
        is the trapezoidal rule on the instants.
        """
        from ..model.realization import ClosedLoop

        A, B = self.plant_A, self.plant_B
        if self.plant is not None:
            sys = self.plant
        else:  # the former k + b s plant, from its matrices
            m_l = 1.0 / B[3, 1]
            C, D = np.zeros((7, 4)), np.zeros((7, 3))
            C[:4, :4] = np.eye(4)
            D[4, 0] = 1.0
            k1, b1 = A[3, 0] * m_l, A[3, 1] * m_l
            C[5] = [-k1, -b1, k1, b1]  # f_D1 = D1 (x_L − x_A)
            C[6], D[6, 2] = A[3], B[3, 1]
            B3 = np.column_stack([B[:, 0], np.zeros(4), B[:, 1]])
            sys = ClosedLoop(A=A, B=B3, C=C, D=D, states=("x_A", "v_A", "x_L", "v_L"),
                             load_mass=m_l, relaxed=np.eye(4))  # fmt: skip
        f_ext = np.zeros(self.time.size) if self.f_ext is None else self.f_ext
        u = np.column_stack([self.f_A, np.zeros(self.time.size), f_ext])
        x = (
            np.asarray(self.plant_states)
            if self.plant_states is not None
            else np.column_stack([self.x_A, self.v_A, self.x_L, self.v_L])
        )
        diverged = self.time.size < self.periods + 1
        target, scale, has_step = self._target()
        power = self.f_A * self.v_A
        t = self.time
        return SimulationResult(
            time=t, x_A=self.x_A, v_A=self.v_A, x_L=self.x_L, v_L=self.v_L, f_A=self.f_A,
            energy=float(np.sum(self.f_A[:-1] * np.diff(self.x_A))),
            positive_work=float(np.trapezoid(np.maximum(power, 0.0), t)) if t.size > 1 else 0.0,
            stable=self.stable and not diverged, marginal=False, diverged=diverged,
            poles=np.zeros(0, dtype=complex), target=target, scale=scale, has_step=has_step,
            system=sys, scenario=self.scenario, states=x, inputs=u,
            slopes=np.zeros((max(t.size - 1, 0), 3)),
        )  # fmt: skip

    def _target(self) -> tuple[float, float, bool]:
        """Settling target, the motion size the band refers to, and whether it is a step."""
        sc = self.scenario
        if isinstance(sc, LoadDisplaced):
            return 0.0, abs(float(sc.displacement)), True
        if isinstance(sc, Step | Trajectory):
            return self.target, abs(self.target), abs(self.target) > 0
        target = 0.0
        if isinstance(sc, ForceStep) and self.statics is not None:
            n_a, d_a, n_l, d_l, k1, k2 = (float(v) for v in self.statics)
            # rest, unknowns (x_A, x_L, u_A, u_L): K(1) = n/d with d = 0 for an integrator
            M = np.array([[-k1, k1, 1.0, 1.0], [k1, -k1 - k2, 0.0, 0.0],
                          [n_a, 0.0, d_a, 0.0], [0.0, n_l, 0.0, d_l]])  # fmt: skip
            try:
                target = float(np.linalg.solve(M, [0.0, -float(sc.force), 0.0, 0.0])[1])
            except np.linalg.LinAlgError:
                target = 0.0
        scale = abs(target - float(self.x_L[0]))
        if scale == 0.0:
            scale = float(np.max(np.abs(self.x_L - target), initial=0.0))
        return target, scale, False

    def metrics(self, *, tolerance: float = 0.02) -> TrackingMetrics:
        """Settling time, overshoot, final error, peak force and energy of this response.

        [`tracking_metrics`][seapass.sim.metrics.tracking_metrics] of
        [`simulation`][seapass.sampled.response.SampledResponse.simulation]: the settling
        time is located on the exact load motion between the instants.

        Examples
        --------
        >>> from seapass.model.zcontroller import ZController
        >>> sea = SEA(D1="k1 + b1*s", values=dict(m=1, b=10, k1=1000, b1=20, kd=500),
        ...           discrete=ZController(CL="kd", rate=1000.0))
        >>> met = sampled_response(sea, loop=SampledLoop(rate=1000.0), load_mass=1.0,
        ...                        horizon=2.0).metrics()
        >>> str(met.status), round(met.settling_time, 4), round(met.overshoot, 3)
        ('settled', 1.9312, 0.801)
        """
        return tracking_metrics(self.simulation(), tolerance=tolerance)

    def to_dict(self) -> dict[str, Any]:
        return {
            "kind": "sampled",
            "period": self.loop.period,
            "delay": self.loop.delay,
            "samples": int(self.time.size),
            "horizon": float(self.time[-1]),
            "stable": self.stable,
            "spectral_radius": self.spectral_radius,
            "target": self.target,
            "final_x_L": float(self.x_L[-1]),
            "final_error": self.final_error,
            "peak_force": float(np.abs(self.f_A).max()),
            "scenario": type(self.scenario).__name__ if self.scenario is not None else None,
            "metrics": self.metrics().to_dict(),
        }

    def plot(self, *, ax: Any = None) -> Any:
        """``x_A`` and ``x_L`` against time (held between the instants); returns the Axes."""
        from ..plot.sampled import plot_sampled_response

        return plot_sampled_response(self, ax=ax)

    def __repr__(self) -> str:
        return short_repr(
            "SampledResponse",
            {"stable": self.stable, "samples": int(self.time.size),
             "final_x_L": float(self.x_L[-1]), "target": self.target},
        )  # fmt: skip

    def _repr_html_(self) -> str:
        return html_card(
            "Sampled-loop response: " + ("stable" if self.stable else "unstable"),
            [(k, v) for k, v in self.to_dict().items()],
        )


def _setup(
    scenario: Scenario, load_mass: float, relaxed: np.ndarray
) -> tuple[np.ndarray, Any, float]:
    """Initial plant state, ``t -> (θ_A, θ_L, f_ext)`` and the target (``relaxed``: the
    plant's map from a configuration to its state with the elements at rest)."""
    x0 = np.zeros(relaxed.shape[0])
    if isinstance(scenario, Step):
        ra, rl = reference_values(scenario.apply_to, scenario.size)
        return x0, lambda t: (ra, rl, 0.0), float(scenario.size)
    if isinstance(scenario, LoadDisplaced):  # the spring relaxed: both at the displacement
        x0[0] = x0[2] = scenario.displacement
        return relaxed @ x0, lambda t: (0.0, 0.0, 0.0), 0.0
    if isinstance(scenario, ForceImpulse):
        x0[3] = scenario.impulse / load_mass
        return x0, lambda t: (0.0, 0.0, 0.0), 0.0
    if isinstance(scenario, ForceStep):
        f = float(scenario.force)
        return x0, lambda t: (0.0, 0.0, f), 0.0
    if isinstance(scenario, Trajectory):
        ra, rl = reference_values(scenario.apply_to, 1.0)

        def at(t: float) -> tuple[float, float, float]:
            r = float(scenario.sample(np.array([t]))[0])
            return ra * r, rl * r, 0.0

        return x0, at, float(scenario.values[-1])
    raise ParameterError(f"unknown scenario {scenario!r}")


def sampled_response(
    sea: SEA,
    *,
    loop: SampledLoop,
    load_mass: float,
    scenario: Scenario | None = None,
    horizon: float | None = None,
    controller: DiscreteController | None = None,
) -> SampledResponse:
    """Simulate the sampled loop of ``sea`` with a load mass, sample by sample.

    Parameters
    ----------
    sea : SEA
        The design (a controller in ``z`` is run as is; ``CA``/``CL`` are discretized as
        [`DiscreteController.for_loop`][seapass.sampled.controllers.DiscreteController.for_loop]
        does).  ``D1``, ``D2``: any rational function with at most one derivative.
    loop : SampledLoop
        Period and computational delay.
    load_mass : float
        ``m_L`` (kg) at the port, positive.
    scenario : Scenario, optional
        As for [`simulate`][seapass.sim.simulate.simulate]; default a 0.5 m step.
    horizon : float, optional
        Simulated time (s); default the paper's experiment.  At most
        [`MAX_SIM_STEPS`][seapass.files.limits.MAX_SIM_STEPS] periods.
    controller : DiscreteController, optional
        Run this controller instead of the design's.

    Returns
    -------
    SampledResponse

    Examples
    --------
    >>> from seapass.model.zcontroller import ZController
    >>> sea = SEA(D1="k1 + b1*s", values=dict(m=1, b=10, k1=1000, b1=20, kd=500),
    ...           discrete=ZController(CL="kd", rate=1000.0))
    >>> r = sampled_response(sea, loop=SampledLoop(rate=1000.0), load_mass=1.0, horizon=2.0)
    >>> r.stable, r.time.size
    (True, 2001)
    """

    m_l = finite_number(load_mass, "load mass m_L", positive=True)
    horizon = PAPER_EXPERIMENT.horizon if horizon is None else horizon
    horizon = finite_number(horizon, "horizon", positive=True)
    T = loop.period
    n = math.ceil(horizon / T - 1e-9)
    if n > MAX_SIM_STEPS:
        raise ParameterError(
            f"horizon {horizon:g} s is {n} periods of {T:g} s; the limit is {MAX_SIM_STEPS}"
        )
    ctrl = controller or DiscreteController.for_loop(sea, loop)
    plant = discrete_plant(sea, T, load_mass=m_l)
    Ad, Bd = plant.Phi, plant.Gamma
    acl = loop_matrix(plant, ctrl, loop.delay)
    rho = float(np.max(np.abs(np.linalg.eigvals(acl))))
    x, inputs, target = _setup(
        scenario if scenario is not None else Step(), m_l, np.asarray(plant.continuous.relaxed)
    )
    ctrl.reset()
    pending: deque[float] = deque([0.0] * loop.delay)
    states, forces, external = [x.copy()], [], []
    bound = 1e12 * max(1.0, float(np.abs(x).max()), abs(target))  # diverged: stop there
    for k in range(n):
        ta, tl, f_ext = inputs(k * T)
        u = ctrl.step((float(x[0]), float(x[2])), (ta, tl))
        pending.append(u)
        applied = pending.popleft()
        forces.append(applied)
        external.append(f_ext)
        x = Ad @ x + Bd @ np.array([applied, f_ext])
        states.append(x.copy())
        if not float(np.abs(x).max()) < bound:
            break
    forces.append(forces[-1] if forces else 0.0)
    external.append(external[-1] if external else 0.0)
    s = np.array(states)
    ka, kl = ctrl.transfer_functions()
    statics = np.array([float(sum(ka.num)), float(sum(ka.den)), float(sum(kl.num)),
                        float(sum(kl.den)), _static(sea, "D1"), _static(sea, "D2")])  # fmt: skip
    return SampledResponse(
        time=np.arange(len(states)) * T,
        x_A=s[:, 0],
        v_A=s[:, 1],
        x_L=s[:, 2],
        v_L=s[:, 3],
        f_A=np.array(forces),
        loop=loop,
        spectral_radius=rho,
        target=target,
        scenario=scenario if scenario is not None else Step(),
        plant_A=plant.continuous.A,
        plant_B=np.column_stack([plant.continuous.B[:, 0], plant.continuous.B[:, 2]]),
        f_ext=np.array(external),
        statics=statics,
        periods=n,
        plant=plant.continuous,
        plant_states=s,
    )


def _static(sea: SEA, key: str) -> float:
    """``D(0)`` of a plant element (inf for a pole at 0)."""
    num, den = numeric_element(sea, key)
    d0 = den(0)
    return float(num(0) / d0) if d0 != 0 else math.inf
