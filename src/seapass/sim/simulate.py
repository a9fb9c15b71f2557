"""Time-domain simulation of an SEA driving a load mass, with exact discretization.

Plant (the free-body model of [`seapass.model.stiffness`][seapass.model.stiffness] with a load mass ``m_L``
at the port):

* actuator: ``m ẍ_A + b ẋ_A = f_A + F_1``, with ``F_1 = D1 (x_L − x_A)``
* load: ``m_L ẍ_L = −F_1 − D2 x_L + f_ext``
* control: ``f_A = C_A (θ_A − x_A) + C_L (θ_L − x_L)``

Every element is a rational function of ``s``.  It is split by polynomial
division into ``p0 + p1 s + N(s)/D(s)`` with ``N/D`` strictly proper.  The
strictly proper part is realized in controllable canonical form; the
polynomial part acts on measured positions and velocities, which are plant
states.  A controller's ``p1 s`` term acts on the *measurement only*
("derivative on measurement": ``p1 (θ̇ − ẋ)`` is replaced by ``−p1 ẋ``), so a
step reference never produces an impulse.  An element whose polynomial part
has degree 2 or more would need accelerations and raises
[`UnrealizableError`][seapass.errors.UnrealizableError].

The closed loop is linear time-invariant, ``ẋ = A x + B u`` with inputs
``u = (θ_A, θ_L, f_ext)``.  Inputs are held (ZOH) or linearly interpolated
(first-order hold) between grid points and the state is propagated with the
matrix exponential of an augmented matrix, so samples are exact up to
rounding for any time step; `SimulationResult.state_at` evaluates the
exact solution between samples.

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Eqs. (1)-(3) and Sec. V.
.. [2] C. F. Van Loan, "Computing integrals involving the matrix exponential",
   IEEE Trans. Automatic Control 23(3), 1978.
.. [3] G. F. Franklin, J. D. Powell, M. Workman, *Digital Control of Dynamic
   Systems*, 3rd ed., sec. 6.3 (ZOH and triangle-hold equivalents).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg

from ..analysis.coupled import Stability
from ..errors import ParameterError, SimulationError
from ..files.limits import MAX_SIM_STEPS
from ..model.display import html_card, short_repr
from ..model.experiment import PAPER_EXPERIMENT
from ..model.expr import finite_number
from ..model.realization import ClosedLoop, closed_loop
from ..model.sea import SEA
from .scenarios import (
    ForceImpulse,
    ForceStep,
    LoadDisplaced,
    Scenario,
    Step,
    Trajectory,
    reference_values,
)

__all__ = [
    "SimulationResult",
    "Stability",
    "checked_expm",
    "scenario_setup",
    "simulate",
    "simulate_closed_loop",
]


_DIVERGENCE = 1e8  # |state| above this multiple of the problem scale counts as diverged


# --------------------------------------------------------------------------- simulation


@dataclass(frozen=True, repr=False, kw_only=True)
class SimulationResult:
    """Sampled response of a closed-loop simulation.

    Arrays have one entry per grid time ``time`` (axis 0); for a diverging run
    they end at the last sample before divergence (``diverged=True``).

    Attributes
    ----------
    time, x_A, v_A, x_L, v_L, f_A : ndarray, shape (N,)
        Time (s), positions (m), velocities (m/s) and actuator force (N).
    energy : float
        Work done by the actuator ``∫ f_A ẋ_A dt`` (J), exact for the LTI solution.
    positive_work : float
        ``∫ max(f_A ẋ_A, 0) dt`` (J), the energy the actuator injects
        (trapezoidal rule on the samples).
    stable : bool
        All closed-loop poles in the open left half-plane.
    marginal : bool
        Not stable, but no pole in the open right half-plane.
    diverged : bool
        The state exceeded ``1e8`` times the problem scale and the run was cut.
    poles : ndarray of complex
    target : float
        Final load reference (m), the settling target.
    scale : float
        Size of the motion the 2 % settling band refers to (m).
    """

    time: np.ndarray
    x_A: np.ndarray
    v_A: np.ndarray
    x_L: np.ndarray
    v_L: np.ndarray
    f_A: np.ndarray
    energy: float
    positive_work: float
    stable: bool
    marginal: bool
    diverged: bool
    poles: np.ndarray
    target: float
    scale: float
    has_step: bool
    system: ClosedLoop
    scenario: Any
    states: np.ndarray = field(repr=False)
    inputs: np.ndarray = field(repr=False)
    slopes: np.ndarray = field(repr=False)

    def __post_init__(self) -> None:
        names = ("time", "x_A", "v_A", "x_L", "v_L", "f_A", "poles", "states", "inputs", "slopes")
        for name in names:
            arr = np.array(getattr(self, name))
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)

    @property
    def status(self) -> Stability:
        """Stability of the simulated closed loop."""
        if self.diverged or not (self.stable or self.marginal):
            return Stability.UNSTABLE
        return Stability.STABLE if self.stable else Stability.MARGINAL

    def state_at(self, t: float) -> np.ndarray:
        """Exact state at time ``t`` (propagated from the sample before ``t``)."""
        time = self.time
        if not (time[0] <= t <= time[-1]):
            raise ParameterError(f"t = {t} is outside the simulated span [0, {time[-1]}]")
        if time.size < 2:
            return np.array(self.states[0])
        k = min(max(int(np.searchsorted(time, t, side="right")) - 1, 0), time.size - 2)
        tau = t - time[k]
        if tau == 0.0:
            return np.array(self.states[k])
        aug = _foh_matrix(self.system)
        w = np.concatenate([self.states[k], self.inputs[k], self.slopes[k]])
        return (scipy.linalg.expm(aug * tau) @ w)[: len(self.system.states)]

    def output_at(self, name: str, t: float) -> float:
        """Exact value of output ``name`` (see `OUTPUTS`) at time ``t``."""
        c, d = self.system.output(name)
        k = min(max(int(np.searchsorted(self.time, t, side="right")) - 1, 0), self.time.size - 1)
        u = self.inputs[k] + self.slopes[min(k, len(self.slopes) - 1)] * (t - self.time[k])
        return float(c @ self.state_at(t) + d @ u)

    def to_dict(self) -> dict[str, Any]:
        return {
            "status": self.status,
            "stable": self.stable,
            "diverged": self.diverged,
            "energy": self.energy,
            "positive_work": self.positive_work,
            "poles": [[float(p.real), float(p.imag)] for p in self.poles],
        }

    def plot(self, metrics: Any = None, *, axes: Any = None, **kwargs: Any) -> Any:
        """Positions and actuator force (with the settling band of ``metrics``); two Axes."""
        from ..plot.sim import plot_simulation

        return plot_simulation(self, metrics, axes=axes, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "SimulationResult",
            {
                "status": str(self.status),
                "samples": self.time.size,
                "horizon": float(self.time[-1]) if self.time.size else None,
                "final_x_L": float(self.x_L[-1]) if self.x_L.size else None,
                "target": self.target,
            },
        )

    def _repr_html_(self) -> str:
        end = float(self.time[-1]) if self.time.size else 0.0
        return html_card(
            f"Simulation: {self.status}",
            [
                ("samples", f"{self.time.size} over {end:.6g} s"),
                ("load x_L at the end", f"{self.x_L[-1]:.6g} m (target {self.target:g} m)"),
                ("peak actuator force", f"{np.abs(self.f_A).max():.6g} N"),
                ("actuator work", f"{self.energy:.6g} J"),
            ],
        )


def _foh_matrix(sys: ClosedLoop) -> np.ndarray:
    n = sys.A.shape[0]
    aug = np.zeros((n + 6, n + 6))
    aug[:n, :n] = sys.A
    aug[:n, n : n + 3] = sys.B
    aug[n : n + 3, n + 3 :] = np.eye(3)
    return aug


def scenario_setup(
    scenario: Scenario, sys: ClosedLoop, t: np.ndarray
) -> tuple[np.ndarray, np.ndarray, bool, float, float, bool]:
    """Initial state, inputs on the grid, linear-interpolation flag, target, scale, has_step."""
    n = len(sys.states)
    x0 = np.zeros(n)
    u = np.zeros((t.size, 3))
    if isinstance(scenario, Step):
        u[:, :2] = reference_values(scenario.apply_to, scenario.size)
        return x0, u, False, scenario.size, abs(scenario.size), True
    if isinstance(scenario, LoadDisplaced):
        x0[2] = scenario.displacement
        return sys.relaxed @ x0, u, False, 0.0, abs(scenario.displacement), True
    if isinstance(scenario, ForceImpulse):
        x0[3] = scenario.impulse / sys.load_mass
        return x0, u, False, 0.0, 0.0, False
    if isinstance(scenario, ForceStep):
        u[:, 2] = scenario.force
        return x0, u, False, 0.0, 0.0, False
    if isinstance(scenario, Trajectory):
        ref = scenario.sample(t)
        ra, rl = reference_values(scenario.apply_to, 1.0)
        u[:, 0], u[:, 1] = ra * ref, rl * ref
        target = scenario.values[-1]
        scale = abs(target - 0.0)
        return x0, u, scenario.interpolation == "linear", float(target), scale, scale > 0
    raise ParameterError(f"unknown scenario {scenario!r}")


def checked_expm(m: np.ndarray, dt: float) -> np.ndarray:
    """``expm(m dt)``, or `SimulationError` when it is not finite in double precision.

    A load mass that is tiny next to the other masses makes a mode so fast that
    the matrix exponential over one step overflows; without this check the run
    would "diverge" and a passive design would be called unstable.
    """
    with np.errstate(all="ignore"):
        e = scipy.linalg.expm(m * dt)
    if not np.all(np.isfinite(e)):
        rate = float(np.max(np.abs(m))) if np.all(np.isfinite(m)) else math.inf
        raise SimulationError(
            f"the closed loop is too stiff to simulate in double precision: a rate of "
            f"{rate:.3g} 1/s over a time step of {dt:.3g} s; use a smaller dt, or a load mass "
            "that is not tiny next to the other masses"
        )
    return e


def _propagate_constant(
    sys: ClosedLoop, x0: np.ndarray, u0: np.ndarray, dt: float, N: int, limit: float
) -> np.ndarray:
    """States at ``k dt``, ``k = 0..N`` for constant input, in vectorized blocks."""
    n = x0.size
    aug = np.zeros((n + 3, n + 3))
    aug[:n, :n], aug[:n, n:] = sys.A, sys.B
    phi = checked_expm(aug, dt)
    block = min(64, N)
    powers = np.empty((block, n + 3, n + 3))
    powers[0] = np.eye(n + 3)
    for i in range(1, block):
        powers[i] = phi @ powers[i - 1]
    jump = phi @ powers[-1]
    out = np.empty((N + 1, n))
    w = np.concatenate([x0, u0])
    k = 0
    with np.errstate(over="ignore", invalid="ignore"):
        while k <= N:
            m = min(block, N + 1 - k)
            chunk = powers[:m] @ w
            bad = ~np.all(np.isfinite(chunk[:, :n]) & (np.abs(chunk[:, :n]) <= limit), axis=1)
            if bad.any():
                first = int(np.argmax(bad))
                out[k : k + first] = chunk[:first, :n]
                return out[: k + first]
            out[k : k + m] = chunk[:, :n]
            k += m
            w = jump @ w
    return out


def _propagate_general(
    sys: ClosedLoop, x0: np.ndarray, u: np.ndarray, slopes: np.ndarray, dt: float, limit: float
) -> np.ndarray:
    n = x0.size
    e = checked_expm(_foh_matrix(sys), dt)
    phi, g0, g1 = e[:n, :n], e[:n, n : n + 3], e[:n, n + 3 :]
    out = np.empty((u.shape[0], n))
    out[0] = x = x0
    for k in range(u.shape[0] - 1):
        x = phi @ x + g0 @ u[k] + g1 @ slopes[k]
        if not (np.all(np.isfinite(x)) and np.max(np.abs(x), initial=0.0) <= limit):
            return out[: k + 1]
        out[k + 1] = x
    return out


def simulate_closed_loop(
    sys: ClosedLoop,
    *,
    scenario: Scenario | None = None,
    horizon: float | None = None,
    dt: float = 1e-3,
) -> SimulationResult:
    """Simulate an already built `ClosedLoop`; see `simulate`."""
    scenario = Step() if scenario is None else scenario
    horizon = finite_number(PAPER_EXPERIMENT.pick("horizon", horizon), "horizon", positive=True)
    dt = finite_number(dt, "time step dt", positive=True)
    if horizon < dt:
        raise ParameterError(
            f"horizon ({horizon:g} s) is shorter than the time step dt ({dt:g} s); "
            f"give a longer horizon or a smaller dt"
        )
    N = math.ceil(horizon / dt - 1e-9)
    if N > MAX_SIM_STEPS:
        raise ParameterError(
            f"horizon/dt = {N} steps exceeds the limit of {MAX_SIM_STEPS}; increase dt"
        )
    t = np.linspace(0.0, horizon, N + 1)
    h = horizon / N
    x0, u, linear, target, scale, has_step = scenario_setup(scenario, sys, t)
    slopes = np.diff(u, axis=0) / h if linear else np.zeros((N, 3))
    mag = max(1.0, float(np.max(np.abs(u), initial=0.0)), float(np.max(np.abs(x0), initial=0.0)))
    limit = _DIVERGENCE * mag * max(1.0, float(np.max(np.abs(sys.B), initial=0.0)))
    with np.errstate(all="ignore"):  # overflow is caught as divergence, never printed
        if not linear and np.all(u == u[0]):
            x = _propagate_constant(sys, x0, u[0], h, N, limit)
        else:
            x = _propagate_general(sys, x0, u, slopes, h, limit)
    diverged = x.shape[0] < N + 1
    K = x.shape[0]
    t, u, slopes = t[:K], u[:K], slopes[: max(K - 1, 0)]
    y = x @ sys.C.T + u @ sys.D.T
    power = y[:, 4] * y[:, 1]
    energy = _exact_work(sys, x, u, slopes, h)
    positive = float(np.trapezoid(np.maximum(power, 0.0), t)) if K > 1 else 0.0
    poles = sys.poles
    tol = 1e-9 * max(1.0, float(np.max(np.abs(poles), initial=0.0)))
    stable = bool(np.all(poles.real < -tol)) and not diverged
    marginal = not stable and not diverged and bool(np.all(poles.real <= tol))
    if not has_step:
        # settle to the equilibrium for the final input; band relative to the motion size
        steady = _steady_state(sys, u[-1])
        target = steady if steady is not None else 0.0
        scale = abs(target - float(y[0, 2]))
        if scale == 0.0:
            scale = float(np.max(np.abs(y[:, 2] - target), initial=0.0))
    return SimulationResult(
        time=t,
        x_A=y[:, 0],
        v_A=y[:, 1],
        x_L=y[:, 2],
        v_L=y[:, 3],
        f_A=y[:, 4],
        energy=energy,
        positive_work=positive,
        stable=stable,
        marginal=marginal,
        diverged=diverged,
        poles=poles,
        target=float(target),
        scale=float(scale),
        has_step=has_step,
        system=sys,
        scenario=scenario,
        states=x,
        inputs=u,
        slopes=slopes,
    )


def _exact_work(
    sys: ClosedLoop, x: np.ndarray, u: np.ndarray, slopes: np.ndarray, h: float
) -> float:
    """``∫ f_A v_A dt`` exactly: per interval a quadratic form in the augmented state.

    With ``w = (x, u, u̇)`` and ``ẇ = M w`` the integral over one step is
    ``w_kᵀ W w_k``, ``W = ∫_0^h e^{Mᵀτ} Q e^{Mτ} dτ``, from one matrix
    exponential (Van Loan, 1978).
    """
    if x.shape[0] < 2:
        return 0.0
    M = _foh_matrix(sys)
    cf = np.concatenate([sys.C[4], sys.D[4], np.zeros(3)])
    cv = np.concatenate([sys.C[1], sys.D[1], np.zeros(3)])
    Q = 0.5 * (np.outer(cf, cv) + np.outer(cv, cf))
    N = M.shape[0]
    big = np.zeros((2 * N, 2 * N))
    big[:N, :N], big[:N, N:], big[N:, N:] = -M.T, Q, M
    E = checked_expm(big, h)
    W = E[N:, N:].T @ E[:N, N:]
    W = 0.5 * (W + W.T)
    w = np.hstack([x[:-1], u[: x.shape[0] - 1], slopes[: x.shape[0] - 1]])
    return float(np.sum((w @ W) * w))


def _steady_state(sys: ClosedLoop, u: np.ndarray) -> float | None:
    """Load position in equilibrium for constant input ``u``, or None if undefined."""
    try:
        xs = np.linalg.solve(sys.A, -sys.B @ u)
    except np.linalg.LinAlgError:
        return None
    return float(xs[2]) if np.all(np.isfinite(xs)) else None


def simulate(
    sea: SEA,
    *,
    load_mass: float,
    scenario: Scenario | None = None,
    horizon: float | None = None,
    dt: float = 1e-3,
    values: Mapping[str, float] | None = None,
) -> SimulationResult:
    """Simulate ``sea`` driving a load mass, exactly at the grid times.

    Parameters
    ----------
    sea : SEA
        The design; every parameter needs a value.
    load_mass : float
        Load mass ``m_L`` (kg), positive.
    scenario : Step, LoadDisplaced, ForceStep, ForceImpulse or Trajectory
        What happens; default ``Step()``, the paper's 0.5 m reference step from rest.
    horizon : float, optional
        Simulated time (s); default the paper's 10 s
        ([`PAPER_EXPERIMENT`][seapass.model.experiment.PAPER_EXPERIMENT]).
    dt : float
        Largest time step (s); the grid is ``linspace(0, horizon, N + 1)`` with
        ``N = ceil(horizon/dt)``.
    values : mapping, optional
        Parameter values overriding ``sea.values``.

    Returns
    -------
    SimulationResult
        An unstable closed loop is a result (``status == "unstable"``), never an error.

    Raises
    ------
    ParameterError
        Non-positive load mass, horizon shorter than ``dt``, missing values.
    UnrealizableError
        An element needs more derivatives than positions and velocities provide.

    Examples
    --------
    >>> from seapass.model.sea import SEA
    >>> sea = SEA(D1="k1 + b1*s", CA="kd + bd*s",
    ...           values=dict(m=1, b=10, k1=1000, b1=100, kd=2000, bd=60))
    >>> r = simulate(sea, load_mass=10, horizon=5)
    >>> print(r.status)
    stable
    """
    sys = closed_loop(sea, load_mass=load_mass, values=values)
    return simulate_closed_loop(sys, scenario=scenario, horizon=horizon, dt=dt)
