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
Supported plants are those of the coupled check: ``D1 = k1 + b1 s``, ``D2 = k2 + b2 s``.

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
from ..sim.scenarios import (
    ForceImpulse,
    ForceStep,
    LoadDisplaced,
    Scenario,
    Step,
    Trajectory,
    reference_values,
)
from .controllers import DiscreteController
from .coupling import coupled_closed_loop, coupled_plant

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

    def __post_init__(self) -> None:
        for name in ("time", "x_A", "v_A", "x_L", "v_L", "f_A"):
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


def _setup(scenario: Scenario, load_mass: float) -> tuple[np.ndarray, Any, float]:
    """Initial plant state, ``t -> (θ_A, θ_L, f_ext)`` and the target."""
    x0 = np.zeros(4)
    if isinstance(scenario, Step):
        ra, rl = reference_values(scenario.apply_to, scenario.size)
        return x0, lambda t: (ra, rl, 0.0), float(scenario.size)
    if isinstance(scenario, LoadDisplaced):  # the spring relaxed: both at the displacement
        x0[0] = x0[2] = scenario.displacement
        return x0, lambda t: (0.0, 0.0, 0.0), 0.0
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
        does).  ``D1 = k1 + b1 s`` and ``D2 = k2 + b2 s``.
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
    from scipy.linalg import expm

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
    m, b, k1, b1, k2, b2 = coupled_plant(sea)
    A = np.array(
        [
            [0.0, 1.0, 0.0, 0.0],
            [-k1 / m, -(b + b1) / m, k1 / m, b1 / m],
            [0.0, 0.0, 0.0, 1.0],
            [k1 / m_l, b1 / m_l, -(k1 + k2) / m_l, -(b1 + b2) / m_l],
        ]
    )
    B = np.array([[0.0, 0.0], [1.0 / m, 0.0], [0.0, 0.0], [0.0, 1.0 / m_l]])
    big = np.zeros((6, 6))
    big[:4, :4], big[:4, 4:] = A * T, B * T
    E = expm(big)
    Ad, Bd = E[:4, :4], E[:4, 4:]
    acl = coupled_closed_loop(sea, loop=loop, env_mass=m_l, controller=ctrl)
    rho = float(np.max(np.abs(np.linalg.eigvals(acl))))
    x, inputs, target = _setup(scenario if scenario is not None else Step(), m_l)
    ctrl.reset()
    pending: deque[float] = deque([0.0] * loop.delay)
    states, forces = [x.copy()], []
    bound = 1e12 * max(1.0, float(np.abs(x).max()), abs(target))  # diverged: stop there
    for k in range(n):
        ta, tl, f_ext = inputs(k * T)
        u = ctrl.step((float(x[0]), float(x[2])), (ta, tl))
        pending.append(u)
        applied = pending.popleft()
        forces.append(applied)
        x = Ad @ x + Bd @ np.array([applied, f_ext])
        states.append(x.copy())
        if not float(np.abs(x).max()) < bound:
            break
    forces.append(forces[-1] if forces else 0.0)
    s = np.array(states)
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
    )
