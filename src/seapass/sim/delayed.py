"""Time-domain simulation of the continuous loop with a latency on the controller output.

A design with a loop latency ``τ`` (``[control] delay_time``, or a model whose controllers
are both multiplied by ``exp(-tau*s)``) applies the controller's output ``τ`` seconds late:

* plant and load as in [`seapass.sim.simulate`][seapass.sim.simulate], with the actuator
  force ``f_A(t) = y(t − τ)``,
* ``y = C_A (θ_A − x_A) + C_L (θ_L − x_L)`` the output the (delay-free) controller computes.

With ``x`` the state of the delay-free closed loop ``ẋ = A x + B u`` (`ClosedLoop`), whose
actuator force enters the actuator's row as ``e f_A`` (``e = 1/m`` in the row of ``v_A``),
this is the retarded delay-differential equation

``ẋ(t) = (A − e c) x(t) + (B − e d) u(t) + e y(t − τ)``,  ``y = c x + d u``

(``c``, ``d``: the ``f_A`` row of the loop's outputs).  Before ``t = 0`` the state is its
initial value and the references are zero (the constant initial function), so ``y`` is
``c x(0)`` there: zero for a step from rest.

**Discretization** (method of steps on a fixed grid).  The step is ``h = τ/d`` with
``d = ⌈τ/dt⌉`` (so ``h ≤ dt`` and the delay is a whole number of steps; the last step is
shortened to end at the horizon).  On step ``k`` the delayed force ``y(t − τ)`` is the
controller output on step ``k − d``, already computed: it is replaced by its cubic Hermite
interpolant from the values and one-sided derivatives of ``y`` at the ends of that step
(``ẏ = c ẋ + d u̇``, exact from the state equation), and the state is propagated
*exactly* for that cubic input (one matrix exponential of the loop augmented by a chain of
four integrators, Van Loan).  The only error is the interpolation error of the delayed
force, at most ``h⁴/384 · max|y⁽⁴⁾|`` per step (fourth order; the references' jumps and
the kinks they cause fall on grid points, at multiples of ``τ``).  Tests compare the
result with python-control and a high-order Padé approximation of the delay, and check
that ``τ → 0`` gives the delay-free simulation.

**Stability** of the delayed loop is that of the discretized solution operator: the
eigenvalues ``λ`` of the one-step map of the recurrence (the state and ``d`` steps of
history), reported as ``s = log(λ)/h`` (approximate rightmost characteristic roots of the
delay-differential equation).  The map has ``n(d + 1) + 4d`` states; above
`MAX_OPERATOR_STATES` the operator is built on a coarser grid (fewer steps per delay).

The work is bounded: ``horizon/h`` is at most
[`MAX_SIM_STEPS`][seapass.files.limits.MAX_SIM_STEPS].

References
----------
.. [1] A. Bellen and M. Zennaro, *Numerical Methods for Delay Differential Equations*,
   Oxford, 2003, ch. 3 (method of steps, continuous extensions) and ch. 5 (stability).
.. [2] D. Breda, S. Maset and R. Vermiglio, *Stability of Linear Delay Differential
   Equations: A Numerical Approach with MATLAB*, Springer, 2015 (discretized solution
   operators).
.. [3] C. F. Van Loan, "Computing integrals involving the matrix exponential",
   IEEE Trans. Automatic Control 23(3), 1978.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..errors import ParameterError, SimulationError
from ..files.limits import MAX_SIM_STEPS
from ..model.delayatom import model_delays
from ..model.expr import finite_number
from ..model.realization import ClosedLoop, closed_loop
from ..model.sea import SEA
from ..model.symbolic import Delay
from .scenarios import Scenario, Step
from .simulate import SimulationResult, checked_expm, scenario_setup, simulate_closed_loop

__all__ = [
    "MAX_OPERATOR_STATES",
    "DelayedSimulationResult",
    "actuator_mass",
    "controller_latency",
    "simulate_delayed",
    "simulate_delayed_loop",
]

MAX_OPERATOR_STATES = 120
"""Largest one-step operator whose eigenvalues decide the delayed loop's stability."""

_DIVERGENCE = 1e8
_CHAIN = 4  # the cubic input: g, g', g'', g'''


@dataclass(frozen=True, repr=False, kw_only=True)
class DelayedSimulationResult(SimulationResult):
    """A `SimulationResult` of the loop with the controller output delayed by ``delay_time``.

    ``f_A`` is the force applied (the controller output ``delay_time`` earlier);
    ``system`` is the delay-free closed loop; ``poles`` are the approximate rightmost
    characteristic roots of the delayed loop (see the module docstring);
    ``energy`` is the trapezoidal rule on the samples.

    Attributes
    ----------
    delay_time : float
        The latency [s].
    steps_per_delay : int
        ``d``: the grid step is ``delay_time/d``.
    """

    delay_time: float
    steps_per_delay: int
    chain: np.ndarray = field(repr=False)
    augmented: np.ndarray = field(repr=False)

    def state_at(self, t: float) -> np.ndarray:
        """The state at ``t`` (exact for the interpolated delayed force on its step)."""
        time = self.time
        if not (time[0] <= t <= time[-1]):
            raise ParameterError(f"t = {t} is outside the simulated span [0, {time[-1]}]")
        if time.size < 2:
            return np.array(self.states[0])
        k = min(max(int(np.searchsorted(time, t, side="right")) - 1, 0), time.size - 2)
        if t == time[k]:
            return np.array(self.states[k])
        w = np.concatenate([self.states[k], self.inputs[k], self.slopes[k], self.chain[k]])
        return (checked_expm(self.augmented, t - time[k]) @ w)[: self.states.shape[1]]

    def output_at(self, name: str, t: float) -> float:
        """The output ``name`` at ``t``; ``f_A`` is the delayed force applied."""
        k = min(max(int(np.searchsorted(self.time, t, side="right")) - 1, 0), self.time.size - 1)
        if name == "f_A":
            z = self.chain[min(k, len(self.chain) - 1)]
            s = t - self.time[k]
            return float(z[0] + z[1] * s + z[2] * s**2 / 2 + z[3] * s**3 / 6)
        c, d = self.system.output(name)
        u = self.inputs[k] + self.slopes[min(k, len(self.slopes) - 1)] * (t - self.time[k])
        return float(c @ self.state_at(t) + d @ u)


def controller_latency(sea: SEA) -> tuple[SEA, float]:
    """``sea`` without its controller delay, and the delay [s] (0 without one).

    The simulator handles a delay on the controller output: ``C_A`` and ``C_L`` each
    ``exp(-NAME*s)`` times a rational function (or zero), ``NAME`` given a value.

    Raises
    ------
    SimulationError
        A delay elsewhere (in ``D1``/``D2``, on only one of two controllers, or squared).
    ParameterError
        A delay without a value.

    Examples
    --------
    >>> sea = SEA(D1="k1", CA="(kd + bd*s)*exp(-tau*s)",
    ...           values=dict(m=1, b=1, k1=100, kd=5, bd=1, tau=0.01))
    >>> free, tau = controller_latency(sea)
    >>> free.CA, tau
    (bd*s + kd, 0.01)
    """
    names = model_delays(sea)
    if not names:
        return sea, 0.0
    (name,) = names
    value = sea.values.get(name)
    if value is None:
        raise ParameterError(f"the delay {name} of exp(-{name}*s) needs a value [s]")
    tau = finite_number(value, name)
    if tau < 0:
        raise ParameterError(f"{name}: a delay must be >= 0, got {tau:g}")
    parts = dict(sea.elements())
    for key in ("D1", "D2"):
        if sp.sympify(parts[key]).atoms(Delay):
            raise SimulationError(
                f"{key} has a delay exp(-{name}*s): the simulator delays the controller output "
                "only (C_A and C_L both times exp(-NAME*s))"
            )
    for key in ("CA", "CL"):
        expr = sp.sympify(parts[key])
        if expr == 0:
            continue
        delays = list(expr.atoms(Delay))
        rest = sp.cancel(sp.together(expr / delays[0])) if len(delays) == 1 else expr
        if len(delays) != 1 or rest.atoms(Delay):
            raise SimulationError(
                f"{key} = {expr}: the simulator delays the controller output only, so C_A and "
                f"C_L must each be exp(-{name}*s) times a rational function (or zero)"
            )
        parts[key] = rest
    values = {k: v for k, v in sea.values.items() if k != name}
    return SEA(**parts, values=values, name=sea.name, plant=sea.plant), float(tau)


def actuator_mass(sea: SEA, values: Mapping[str, float] | None = None) -> float:
    """The actuator mass ``m`` [kg] of ``sea`` as a number."""
    m = sp.sympify(sea.m).xreplace(sea.substitutions(values))
    if m.free_symbols:
        raise ParameterError(f"m needs values for {', '.join(sorted(map(str, m.free_symbols)))}")
    return float(m)


def simulate_delayed(
    sea: SEA,
    *,
    load_mass: float,
    delay_time: float | None = None,
    scenario: Scenario | None = None,
    horizon: float | None = None,
    dt: float = 1e-3,
    values: Mapping[str, float] | None = None,
) -> SimulationResult:
    """Simulate ``sea`` driving a load mass with its controller output delayed.

    Parameters
    ----------
    sea : SEA
        The design; a delay factor on its controllers (see `controller_latency`) is the
        latency, else ``delay_time``.
    load_mass, scenario, horizon, dt, values
        As for [`simulate`][seapass.sim.simulate.simulate]; ``dt`` is the largest step.
    delay_time : float, optional
        The latency [s] of a delay-free model (a design file's ``delay_time``).

    Returns
    -------
    SimulationResult
        A `DelayedSimulationResult` when the latency is positive; with no latency the
        delay-free simulation itself.

    Raises
    ------
    ParameterError
        As `simulate`; a latency given twice; ``horizon/step`` over ``MAX_SIM_STEPS``.
    SimulationError
        A delay the simulator does not handle (see `controller_latency`).

    Examples
    --------
    >>> sea = SEA(D1="k1 + b1*s", CA="kd + bd*s",
    ...           values=dict(m=1, b=10, k1=1000, b1=30, kd=300, bd=40))
    >>> r = simulate_delayed(sea, load_mass=10, delay_time=0.02, horizon=5)
    >>> print(r.status), r.steps_per_delay
    stable
    (None, 20)
    """
    free, tau = controller_latency(sea)
    if delay_time is not None:
        given = finite_number(delay_time, "delay_time")
        if given < 0:
            raise ParameterError(f"delay_time must be >= 0, got {given:g}", argument="delay_time")
        if tau and given:
            raise ParameterError(
                "delay_time: the model already has a delay; give the latency once",
                argument="delay_time",
            )
        tau = tau or given
    sys = closed_loop(free, load_mass=load_mass, values=values)
    if tau == 0:
        return simulate_closed_loop(sys, scenario=scenario, horizon=horizon, dt=dt)
    return simulate_delayed_loop(
        sys, delay_time=tau, actuator_mass=actuator_mass(free, values), scenario=scenario,
        horizon=horizon, dt=dt,
    )  # fmt: skip


@dataclass(frozen=True, kw_only=True)
class _Scheme:
    """The one-step maps of the delayed recurrence (see the module docstring)."""

    A: np.ndarray  # A - e c
    B: np.ndarray  # B - e d
    e: np.ndarray
    c: np.ndarray
    d: np.ndarray
    aug: np.ndarray

    @classmethod
    def of(cls, sys: ClosedLoop, m: float) -> _Scheme:
        n = sys.A.shape[0]
        e = np.zeros(n)
        e[1] = 1.0 / m
        c, d = sys.output("f_A")
        A, B = sys.A - np.outer(e, c), sys.B - np.outer(e, d)
        aug = np.zeros((n + 6 + _CHAIN, n + 6 + _CHAIN))
        aug[:n, :n], aug[:n, n : n + 3], aug[:n, n + 6] = A, B, e
        aug[n : n + 3, n + 3 : n + 6] = np.eye(3)
        for i in range(_CHAIN - 1):
            aug[n + 6 + i, n + 7 + i] = 1.0
        return cls(A=A, B=B, e=e, c=c, d=d, aug=aug)

    def chain_map(self, n: int, h: float) -> np.ndarray:
        """`chain` as a matrix on ``(x0, x1, u, s, z)`` (it is linear in them)."""
        size = 2 * n + 6 + _CHAIN
        cols = []
        for i in range(size):
            w = np.zeros(size)
            w[i] = 1.0
            x0, x1, u, s, z = np.split(w, [n, 2 * n, 2 * n + 3, 2 * n + 6])
            cols.append(self.chain(x0, x1, u, s, z, h))
        return np.column_stack(cols)

    def chain(self, x0: np.ndarray, x1: np.ndarray, u: np.ndarray, s: np.ndarray,
              z: np.ndarray, h: float) -> np.ndarray:  # fmt: skip
        """The cubic Hermite chain ``(g, g', g'', g''')`` at 0 of ``y`` on a past step."""
        g0, g1 = z[0], z[0] + z[1] * h + z[2] * h * h / 2 + z[3] * h**3 / 6
        u1 = u + s * h
        y0, y1 = self.c @ x0 + self.d @ u, self.c @ x1 + self.d @ u1
        m0 = self.c @ (self.A @ x0 + self.B @ u + self.e * g0) + self.d @ s
        m1 = self.c @ (self.A @ x1 + self.B @ u1 + self.e * g1) + self.d @ s
        q = (y1 - y0) / h
        c2 = (3 * q - 2 * m0 - m1) / h
        c3 = (m0 + m1 - 2 * q) / (h * h)
        return np.array([y0, m0, 2 * c2, 6 * c3])


def _grid(horizon: float, tau: float, dt: float) -> tuple[np.ndarray, float, int]:
    d = max(1, math.ceil(tau / dt - 1e-9))
    h = tau / d
    N = max(1, math.ceil(horizon / h - 1e-9))
    if N > MAX_SIM_STEPS:
        raise ParameterError(
            f"horizon/step = {N} steps (the step is delay_time/{d} = {h:.3g} s) exceeds the "
            f"limit of {MAX_SIM_STEPS}; increase dt or shorten the horizon"
        )
    t = np.minimum(np.arange(N + 1) * h, horizon)
    t[-1] = horizon
    return t, h, d


def simulate_delayed_loop(
    sys: ClosedLoop,
    *,
    delay_time: float,
    actuator_mass: float,
    scenario: Scenario | None = None,
    horizon: float | None = None,
    dt: float = 1e-3,
) -> DelayedSimulationResult:
    """Simulate an already built delay-free `ClosedLoop` with its force delayed (see the module).

    ``actuator_mass`` [kg] is the ``m`` of the loop (the actuator force enters as ``f_A/m``).
    """
    from ..model.experiment import PAPER_EXPERIMENT

    scenario = Step() if scenario is None else scenario
    tau = finite_number(delay_time, "delay_time", positive=True)
    horizon = finite_number(PAPER_EXPERIMENT.pick("horizon", horizon), "horizon", positive=True)
    dt = finite_number(dt, "time step dt", positive=True)
    if horizon < dt:
        raise ParameterError(f"horizon ({horizon:g} s) is shorter than the time step dt ({dt:g} s)")
    t, h, d = _grid(horizon, tau, dt)
    N = t.size - 1
    scheme = _Scheme.of(sys, finite_number(actuator_mass, "actuator_mass", positive=True))
    x0, u, linear, target, scale, has_step = scenario_setup(scenario, sys, t)
    slopes = np.diff(u, axis=0) / np.diff(t)[:, None] if linear else np.zeros((N, 3))
    n = x0.size
    full = checked_expm(scheme.aug, h)
    last = full if math.isclose(t[-1] - t[-2], h, rel_tol=1e-12) else checked_expm(
        scheme.aug, float(t[-1] - t[-2])
    )  # fmt: skip
    mag = max(1.0, float(np.max(np.abs(u), initial=0.0)), float(np.max(np.abs(x0), initial=0.0)))
    limit = _DIVERGENCE * mag * max(1.0, float(np.max(np.abs(sys.B), initial=0.0)))
    xs = np.empty((N + 1, n))
    zs = np.zeros((N, _CHAIN))
    history = np.array([scheme.c @ x0, 0.0, 0.0, 0.0])
    xs[0] = x0
    lmap = scheme.chain_map(n, h)  # z_{j+d} from (x_j, x_{j+1}, u_j, s_j, z_j)
    pm, pl = full[:n], last[:n]
    K = N + 1
    with np.errstate(all="ignore"):
        for start in range(0, N, d):  # a block of d steps needs only the block before it
            stop = min(start + d, N)
            if start == 0:
                zs[:stop] = history
            else:
                j = np.arange(start - d, stop - d)
                zs[start:stop] = np.hstack([xs[j], xs[j + 1], u[j], slopes[j], zs[j]]) @ lmap.T
            for k in range(start, stop):
                xs[k + 1] = (pm if k < N - 1 else pl) @ np.concatenate(
                    [xs[k], u[k], slopes[k], zs[k]]
                )
            block = xs[start + 1 : stop + 1]
            bad = ~np.all(np.isfinite(block) & (np.abs(block) <= limit), axis=1)
            if bad.any():
                K = start + 1 + int(np.argmax(bad))
                break
    diverged = K < N + 1
    t, u, xs, zs = t[:K], u[:K], xs[:K], zs[: max(K - 1, 1)]
    slopes = slopes[: max(K - 1, 0)]
    y = xs @ sys.C.T + u @ sys.D.T
    applied = np.empty(K)
    applied[: K - 1] = zs[: K - 1, 0]  # the force applied from each sample on
    applied[K - 1] = _chain_end(zs[K - 2], float(t[K - 1] - t[K - 2])) if K > 1 else history[0]
    y[:, 4] = applied
    power = y[:, 4] * y[:, 1]
    energy = float(np.trapezoid(power, t)) if K > 1 else 0.0
    positive = float(np.trapezoid(np.maximum(power, 0.0), t)) if K > 1 else 0.0
    poles, radius = _operator_roots(sys, scheme, tau, n, d, h)
    stable = radius < 1.0 - 1e-12 and not diverged
    marginal = not stable and not diverged and radius <= 1.0 + 1e-9
    if not has_step:
        steady = _steady_state(scheme, sys, u[-1])
        target = steady if steady is not None else 0.0
        scale = abs(target - float(y[0, 2]))
        if scale == 0.0:
            scale = float(np.max(np.abs(y[:, 2] - target), initial=0.0))
    return DelayedSimulationResult(
        time=t, x_A=y[:, 0], v_A=y[:, 1], x_L=y[:, 2], v_L=y[:, 3], f_A=y[:, 4],
        energy=energy, positive_work=positive, stable=stable, marginal=marginal,
        diverged=diverged, poles=poles, target=float(target), scale=float(scale),
        has_step=has_step, system=sys, scenario=scenario, states=xs, inputs=u, slopes=slopes,
        delay_time=tau, steps_per_delay=d, chain=zs, augmented=scheme.aug,
    )  # fmt: skip


def _chain_end(z: np.ndarray, s: float) -> float:
    return float(z[0] + z[1] * s + z[2] * s * s / 2 + z[3] * s**3 / 6)


def _steady_state(scheme: _Scheme, sys: ClosedLoop, u: np.ndarray) -> float | None:
    """Load position in equilibrium (the delay does not move it), or None."""
    try:
        xs = np.linalg.solve(sys.A, -sys.B @ u)
    except np.linalg.LinAlgError:
        return None
    return float(xs[2]) if np.all(np.isfinite(xs)) else None


def _operator_roots(
    sys: ClosedLoop, scheme: _Scheme, tau: float, n: int, d: int, h: float
) -> tuple[np.ndarray, float]:
    """Approximate rightmost roots ``log(λ)/h`` and the spectral radius of the one-step map.

    The state of the map is ``(x_k, …, x_{k−d}, z_{k−1}, …, z_{k−d})``; above
    `MAX_OPERATOR_STATES` states it is built with fewer steps per delay.
    """
    if n * (d + 1) + _CHAIN * d > MAX_OPERATOR_STATES:
        d = max(1, (MAX_OPERATOR_STATES - n) // (n + _CHAIN))
        h = tau / d
    full = checked_expm(scheme.aug, h)[:n]
    phi, gz = full[:, :n], full[:, n + 6 :]
    # z_k = L0 x_{k-d} + L1 x_{k-d+1} + Lz z_{k-d}, from the Hermite chain with u = 0
    eye_n, eye_z = np.eye(n), np.eye(_CHAIN)
    zero_u = np.zeros(3)
    L0 = np.column_stack(
        [scheme.chain(eye_n[i], np.zeros(n), zero_u, zero_u, np.zeros(4), h) for i in range(n)]
    )
    L1 = np.column_stack(
        [scheme.chain(np.zeros(n), eye_n[i], zero_u, zero_u, np.zeros(4), h) for i in range(n)]
    )
    Lz = np.column_stack(
        [scheme.chain(np.zeros(n), np.zeros(n), zero_u, zero_u, eye_z[i], h) for i in range(4)]
    )
    size = n * (d + 1) + _CHAIN * d
    T = np.zeros((size, size))
    xoff = lambda i: i * n  # noqa: E731  (x_{k-i})
    zoff = lambda i: n * (d + 1) + (i - 1) * _CHAIN  # noqa: E731  (z_{k-i}, i >= 1)
    # z_k from x_{k-d}, x_{k-d+1}, z_{k-d}; x_{k+1} = phi x_k + gz z_k
    zk = np.zeros((_CHAIN, size))
    zk[:, xoff(d) : xoff(d) + n] += L0
    zk[:, xoff(d - 1) : xoff(d - 1) + n] += L1
    zk[:, zoff(d) : zoff(d) + _CHAIN] += Lz
    T[0:n, 0:n] = phi
    T[0:n] += gz @ zk
    for i in range(1, d + 1):  # shift x_{k-i+1} -> x_{k-i}
        T[xoff(i) : xoff(i) + n, xoff(i - 1) : xoff(i - 1) + n] = np.eye(n)
    T[zoff(1) : zoff(1) + _CHAIN] = zk
    for i in range(2, d + 1):
        T[zoff(i) : zoff(i) + _CHAIN, zoff(i - 1) : zoff(i - 1) + _CHAIN] = np.eye(_CHAIN)
    lam = np.linalg.eigvals(T)
    radius = float(np.max(np.abs(lam))) if lam.size else 0.0
    keep = lam[np.abs(lam) > 1e-300]
    roots = np.log(keep.astype(complex)) / h
    order = np.argsort(-roots.real)
    return roots[order][: max(sys.A.shape[0], 1)], radius
