"""The cost the optimizer sees: objective plus penalties, with exact constraint checks.

One candidate (a vector of gains) is simulated at the search time step at each load
mass of the run (``options.masses``); its cost at one mass is the objective
(`objective_value`) plus, for each violated soft limit (peak force, overshoot), a
penalty of at least one `cost_unit`, and its cost is the worst over the masses; an
unstable closed loop (at any mass) costs ten units.  Under a delay constraint the step
response is that of the loop with its controller output delayed
([`simulate_delayed_loop`][seapass.sim.delayed.simulate_delayed_loop]).  The unit exceeds every feasible objective, so any
candidate within the limits beats any candidate outside them.

The hard constraints are decided exactly, but only where they can matter: for
a candidate that would become the best so far.  Exact continuous passivity
([`is_passive`][seapass.analysis.passivity.is_passive]) comes first, then, when a
period is given, passivity under sampled-data control
([`sampled_passivity`][seapass.sampled.passivity.sampled_passivity]); a candidate
that fails either costs five more units and cannot become the best.  Both
verdicts are cached per candidate.  A check that cannot decide (an error for
these values) counts as a failure: the tuner never calls an undecided design
passive.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..analysis.passivity import is_passive
from ..errors import SeapassError
from ..model.realization import closed_loop_factory
from ..sampled.passivity import sampled_passivity
from ..sim.delayed import actuator_mass, simulate_delayed_loop
from ..sim.metrics import Settling, TrackingMetrics, tracking_metrics
from ..sim.scenarios import Step
from ..sim.simulate import SimulationResult, simulate_closed_loop
from .constraints import ConstraintKind, PassivityConstraint
from .problem import Objective, ResolvedTuning, TuningOptions, TuningProblem

__all__ = [
    "CandidateCost",
    "ConstraintChecks",
    "cost_unit",
    "itae",
    "limit_penalty",
    "objective_value",
]

UNSTABLE_UNITS = 10.0
CONSTRAINT_UNITS = 5.0


def cost_unit(options: ResolvedTuning) -> float:
    """A cost above every feasible objective value (see the module docstring).

    ``10·horizon`` for the settling time (a run that has not settled costs at
    most about twice the horizon), ``|step|·horizon²`` for ITAE (twice that of a
    load that never moves).
    """
    if options.objective is Objective.ITAE:
        return abs(options.step) * options.horizon**2
    return 10.0 * options.horizon


def itae(result: SimulationResult) -> float:
    """``∫ t |x_L − θ| dt`` over the samples (trapezoidal rule), m·s²."""
    t = result.time
    y = t * np.abs(result.x_L - result.target)
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t))) if t.size > 1 else 0.0


def objective_value(
    options: TuningOptions, result: SimulationResult, metrics: TrackingMetrics
) -> float:
    """The objective of one run, without penalties.

    Settling: the settling time, or, for a run that has not settled in the
    horizon, ``horizon·(1 + tail error/|step|)``.  ITAE: `itae`.
    """
    if options.objective is Objective.ITAE:
        return itae(result)
    if metrics.settling_time is not None:
        return metrics.settling_time
    tail = np.abs(result.x_L[int(0.8 * result.x_L.size) :] - result.target)
    return float(options.horizon or 0.0) * (1.0 + float(np.max(tail)) / abs(options.step or 1.0))


def limit_penalty(options: TuningOptions, metrics: TrackingMetrics) -> float:
    """Penalty of the soft limits (peak force, overshoot) in units of `cost_unit`."""
    units = 0.0
    if options.force_limit is not None and metrics.peak_force > options.force_limit:
        units += 1.0 + metrics.peak_force / options.force_limit
    overshoot = metrics.overshoot or 0.0
    if options.max_overshoot is not None and overshoot > options.max_overshoot:
        units += 1.0 + overshoot / max(options.max_overshoot, options.tolerance)
    return units


@dataclass
class ConstraintChecks:
    """Exact passivity verdicts of candidates, cached; counts what it ran."""

    problem: TuningProblem
    constraint: PassivityConstraint | None = None
    continuous: dict[tuple[float, ...], bool] = field(default_factory=dict)
    sampled: dict[tuple[float, ...], bool] = field(default_factory=dict)

    def passive(self, x: tuple[float, ...]) -> bool:
        """The continuous constraint (exact; or certified at a delay or over a box, see
        [`PassivityConstraint`][seapass.tuning.constraints.PassivityConstraint]), then
        sampled passivity when a loop is set."""
        if x not in self.continuous:
            c = self.constraint
            self.continuous[x] = (
                c.passive(x)
                if c is not None
                else _decide(lambda: is_passive(self.problem.candidate(x)).passive)
            )
        if not self.continuous[x]:
            return False
        loop = self.problem.options.loop
        if loop is None:
            return True
        if x not in self.sampled:
            self.sampled[x] = _decide(
                lambda: sampled_passivity(self.problem.candidate(x), loop=loop).passive
            )
        return self.sampled[x]


def _decide(check: Any) -> bool:
    try:
        return bool(check())
    except (SeapassError, ArithmeticError, ValueError):
        return False  # undecided for these values: never called passive


class CandidateCost:
    """The search cost of a gain vector (callable), see the module docstring.

    Parameters
    ----------
    problem : TuningProblem
    checks : ConstraintChecks
        Where the exact verdicts are cached (shared with the final verification).
    """

    def __init__(self, problem: TuningProblem, checks: ConstraintChecks) -> None:
        opts = problem.options
        self.problem = problem
        self.checks = checks
        self.unit = cost_unit(opts)
        self.best = math.inf
        self.evaluations = 0
        self._builds = [
            closed_loop_factory(problem.sea, problem.gains, load_mass=mass) for mass in opts.masses
        ]
        self._scenario = Step(opts.step)
        c = checks.constraint
        self._delay = c.tau if c is not None and c.kind is ConstraintKind.DELAY else None
        self._mass = actuator_mass(problem.sea) if self._delay else 1.0

    def __call__(self, x: np.ndarray) -> float:
        self.evaluations += 1
        cost = -math.inf
        for build in self._builds:  # the worst case over the load masses
            one, unstable = self._at_mass(build, x)
            if unstable:
                return one
            cost = max(cost, one)
        # the exact constraints only where they can matter: a candidate that would be the best
        if cost < self.best:
            if not self.checks.passive(tuple(float(v) for v in x)):
                return cost + CONSTRAINT_UNITS * self.unit
            self.best = cost
        return cost

    def _at_mass(self, build: Any, x: np.ndarray) -> tuple[float, bool]:
        """Objective plus limit penalties at one load mass, and whether the loop is unstable
        there (then the cost is ten units or more)."""
        opts = self.problem.options
        try:
            loop = build(list(x))
        except SeapassError:  # e.g. a zero denominator at these gains
            return UNSTABLE_UNITS * self.unit + 1e3, True
        res: SimulationResult
        if self._delay:  # the loop with its controller output delayed
            res = simulate_delayed_loop(
                loop, delay_time=self._delay, actuator_mass=self._mass,
                scenario=self._scenario, horizon=opts.horizon, dt=opts.dt_search,
            )  # fmt: skip
            worst = float(np.max(res.poles.real)) if res.poles.size else -1.0
            if worst >= 0:
                return UNSTABLE_UNITS * self.unit + min(worst, 1e3), True
        else:
            worst = float(np.max(loop.poles.real)) if loop.poles.size else -1.0
            if worst >= 0:
                return UNSTABLE_UNITS * self.unit + min(worst, 1e3), True
            res = simulate_closed_loop(
                loop, scenario=self._scenario, horizon=opts.horizon, dt=opts.dt_search
            )
        met = tracking_metrics(res, tolerance=opts.tolerance)
        if met.status == Settling.UNSTABLE:
            return UNSTABLE_UNITS * self.unit + min(float(np.max(res.poles.real)), 1e3), True
        cost = objective_value(opts, res, met)
        if opts.objective is Objective.SETTLING and met.settling_time is not None:
            cost += 1e-3 * met.final_error / max(met.band, 1e-300)  # tie-break
        return cost + self.unit * limit_penalty(opts, met), False
