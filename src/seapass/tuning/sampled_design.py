"""Tuning a design whose controller is given in z: certified sampled passivity, sampled steps.

A controller in ``z`` (``SEA.discrete``, see
[`ZController`][seapass.model.zcontroller.ZController]) exists only at its rate, so
[`tune`][seapass.tuning.optimize.tune] judges its candidates on the sampled loop:

* the **constraint** is the certified sampled-data verdict
  [`sampled_passivity`][seapass.sampled.passivity.sampled_passivity] with the z-controller
  as given, at its rate (and the loop's computational delay); ``undecided`` counts as not
  passive, and the search checks it only for candidates that could become the best;
* the **objective** (settling time or ITAE) is that of the sampled step response
  [`sampled_response`][seapass.sampled.response.sampled_response] (plant propagated
  exactly between the instants, the force held), through the same
  [`tracking_metrics`][seapass.sim.metrics.tracking_metrics] and
  [`objective_value`][seapass.tuning.cost.objective_value] as a continuous tune.

The tuned gains must be named in the z-expressions and each needs an explicit box (the
file's ``[ranges]`` or ``tune={name: (lo, hi)}``): a controller in z has no default scale.

References
----------
.. [1] G. F. Franklin, J. D. Powell, M. Workman, *Digital Control of Dynamic Systems*,
   3rd ed., Addison-Wesley, 1998, ch. 6.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import replace
from types import MappingProxyType, SimpleNamespace
from typing import Any

import numpy as np

from ..errors import ParameterError, SeapassError
from ..model.loop import SampledLoop
from ..outcome import Outcome
from ..progress import ProgressLike, as_progress
from ..sampled.passivity import SampledPassivityResult, sampled_passivity
from ..sampled.response import SampledResponse, sampled_response
from ..sim.metrics import Settling, TrackingMetrics, tracking_metrics
from ..sim.scenarios import Step
from .constraints import PassivityConstraint, rounded_gains
from .cost import CONSTRAINT_UNITS, UNSTABLE_UNITS, cost_unit, limit_penalty, objective_value
from .limits import edge_note, limit_violations
from .masses import MassRun
from .problem import Objective, TuningProblem
from .result import TuningResult
from .search import differential_search, snap_to_edges

__all__ = [
    "SampledCandidateCost",
    "latency_loop",
    "sampled_loop_of",
    "sampled_step",
    "tune_sampled",
]


def sampled_loop_of(problem: TuningProblem) -> SampledLoop:
    """The loop a z-design is tuned in: ``options.loop``, else one at the controller's rate."""
    zc = problem.sea.discrete
    if zc is None:
        raise ParameterError(f"{problem.name}: its controller is not given in z")
    return problem.options.loop or SampledLoop(rate=float(zc.rate))


def latency_loop(loop: SampledLoop, delay_time: float) -> SampledLoop:
    """``loop`` with a loop latency of ``delay_time`` seconds added, in whole samples.

    The certified sampled verdict of a controller given in z takes a delay only as whole
    periods (``loop.delay``), so a latency ``n T`` adds ``n`` samples; any other latency
    is refused.

    Raises
    ------
    ParameterError
        Naming ``delay_time``: negative, not finite, or not a whole number of periods.

    Examples
    --------
    >>> latency_loop(SampledLoop(rate=500.0, delay=1), 0.004).delay
    3
    """
    from ..model.latency import check_delay_time

    tau = check_delay_time(delay_time)
    T = loop.period
    n = round(tau / T)
    if abs(tau - n * T) > 1e-9 * max(T, tau):
        raise ParameterError(
            f"delay_time: a controller given in z at {loop.rate:g} Hz takes a loop latency "
            f"only in whole periods (delay_time = n*{T:g} s adds n samples to the loop's "
            f"delay); {tau:g} s is {tau / T:.6g} periods: give a whole number of periods "
            "or 0",
            argument="delay_time",
        )
    return loop.replace(delay=loop.delay + n)


def sampled_step(
    problem: TuningProblem, x: list[float] | tuple[float, ...], load_mass: float
) -> tuple[SampledResponse, TrackingMetrics]:
    """The sampled step response of the candidate ``x`` at ``load_mass`` and its metrics."""
    opts = problem.options
    res = sampled_response(
        problem.candidate(list(x)),
        loop=sampled_loop_of(problem),
        load_mass=load_mass,
        scenario=Step(opts.step),
        horizon=opts.horizon,
    )
    return res, tracking_metrics(res.simulation(), tolerance=opts.tolerance)


def _verdict(problem: TuningProblem, x: list[float] | tuple[float, ...]) -> SampledPassivityResult:
    return sampled_passivity(problem.candidate(list(x)), loop=sampled_loop_of(problem))


class SampledCandidateCost:
    """The search cost of a gain vector of a z-design (callable); as
    [`CandidateCost`][seapass.tuning.cost.CandidateCost] with the sampled loop."""

    def __init__(
        self, problem: TuningProblem, constraint: PassivityConstraint | None = None
    ) -> None:
        self.problem = problem
        self.constraint = constraint
        self.unit = cost_unit(problem.options)
        self.best = math.inf
        self.evaluations = 0
        self.verdicts: dict[tuple[float, ...], bool] = {}

    def passive(self, x: tuple[float, ...]) -> bool:
        """Certified sampled-passive (cached); undecided or an error is not passive."""
        if x not in self.verdicts:
            if self.constraint is not None:  # over a box: the robust sampled verdict
                self.verdicts[x] = self.constraint.passive(x)
                return self.verdicts[x]
            try:
                self.verdicts[x] = _verdict(self.problem, x).passive
            except (SeapassError, ArithmeticError, ValueError):
                self.verdicts[x] = False
        return self.verdicts[x]

    def __call__(self, x: np.ndarray) -> float:
        self.evaluations += 1
        opts = self.problem.options
        cost = -math.inf
        for mass in opts.masses:
            try:
                res, met = sampled_step(self.problem, [float(v) for v in x], mass)
            except SeapassError:  # e.g. a zero denominator at these gains
                return UNSTABLE_UNITS * self.unit + 1e3
            if met.status == Settling.UNSTABLE:
                return UNSTABLE_UNITS * self.unit + min(res.spectral_radius, 1e3)
            one = objective_value(opts, res.simulation(), met)
            if opts.objective is Objective.SETTLING and met.settling_time is not None:
                one += 1e-3 * met.final_error / max(met.band, 1e-300)  # tie-break
            cost = max(cost, one + self.unit * limit_penalty(opts, met))
        if cost < self.best:
            if not self.passive(tuple(float(v) for v in x)):
                return cost + CONSTRAINT_UNITS * self.unit
            self.best = cost
        return cost


def check_sampled_boxes(
    problem: TuningProblem, given: Mapping[str, Any], ranges: Mapping[str, Any]
) -> None:
    """Every tuned gain of a z-design is named in ``K_A``/``K_L`` and has an explicit box.

    Raises
    ------
    ParameterError
        Naming ``tune`` and what to give.
    """
    zc = problem.sea.discrete
    names = set(zc.names) if zc is not None else set()
    for g in problem.gains:
        if g not in names:
            raise ParameterError(
                f"tune[{g!r}]: {g} is not a gain of the controller in z (its parameters: "
                f"{', '.join(sorted(names)) or 'none'}); tune one of those",
                argument="tune",
            )
        if given.get(g) is None and g not in ranges:
            raise ParameterError(
                f"tune[{g!r}]: a controller in z has no default box; give {g}'s box in the "
                f"design file's [ranges] or as tune={{{g!r}: (lo, hi)}}",
                argument="tune",
            )


def tune_sampled(
    problem: TuningProblem,
    *,
    progress: ProgressLike = None,
    callback: Callable[[int, float], None] | None = None,
    constraint: PassivityConstraint | None = None,
) -> TuningResult:
    """Tune a z-design: see the module docstring.  ``outcome`` and ``sampled_outcome`` of
    the result are both the certified sampled verdict (there is no continuous one).

    ``constraint``: a box of uncertain plants (``kind == "box"`` with the loop): every
    candidate that could become the best must be passive for every plant of the box by the
    robust sampled verdict within the constraint's budget (undecided: not passive); the
    step response is that of the nominal plant."""
    bounds = dict(problem.box)
    _verdict(problem, [sum(bounds[g]) / 2 for g in problem.gains])  # refused input fails now
    cost = SampledCandidateCost(problem, constraint)
    found = differential_search(
        cost,
        [bounds[g] for g in problem.gains],
        problem.options,
        label=problem.name,
        progress=as_progress(progress, where="tune"),
        callback=callback,
    )
    x, best = snap_to_edges(problem, bounds, [float(v) for v in found.x], float(found.fun), cost)
    x = rounded_gains(x, [bounds[g] for g in problem.gains], cost.passive)
    return verify_sampled(
        problem, x, bounds=bounds, cost=best, evaluations=cost.evaluations,
        generations=int(found.nit), checks=len(cost.verdicts), constraint=constraint,
    )  # fmt: skip


def verify_sampled(
    problem: TuningProblem,
    x: list[float],
    *,
    bounds: Mapping[str, tuple[float, float]],
    cost: float = float("nan"),
    evaluations: int = 0,
    generations: int = 0,
    checks: int = 0,
    constraint: PassivityConstraint | None = None,
) -> TuningResult:
    """Everything about the gains ``x`` of a z-design: the certified sampled verdict (over
    the constraint's box: the robust one), the sampled step responses and metrics at every
    load mass, the limits."""
    opts = problem.options
    gains = dict(zip(problem.gains, x, strict=True))
    robust: Any = None
    try:
        sampled: Any = _verdict(problem, x)
        if constraint is not None:
            robust = constraint.verdict(x)
            detail = f"{constraint.label}: {robust.detail}"
            sampled = SimpleNamespace(outcome=robust.outcome, passive=robust.passive,
                                      period=sampled.period, detail=detail, reason="")  # fmt: skip
    except (SeapassError, ArithmeticError, ValueError) as exc:
        raise ParameterError(f"{problem.name}: no sampled verdict at {gains}: {exc}") from None
    runs = []
    for mass in opts.masses:
        res, met = sampled_step(problem, x, mass)
        runs.append(MassRun(load_mass=mass, objective=objective_value(opts, res.simulation(), met),
                            metrics=met))  # fmt: skip
    worst = max(runs, key=lambda r: r.objective)
    violations, notes = limit_violations(
        problem, SimpleNamespace(passive=True), sampled, {r.load_mass: r.metrics for r in runs}
    )
    if sampled.outcome is Outcome.UNDECIDED:
        notes.append("the sampled verdict is undecided: counted as not passive")
    on_bound = problem.on_bound(gains)
    notes += [edge_note(problem, name, gains[name], edge) for name, edge in on_bound.items()]
    return TuningResult(
        design=problem.name,
        gains=MappingProxyType(gains),
        objective=worst.objective,
        outcome=sampled.outcome,
        sampled_outcome=sampled.outcome,
        feasible=not violations,
        violations=tuple(violations),
        on_bound=MappingProxyType(on_bound),
        metrics=worst.metrics,
        box=problem.box,
        bounds=MappingProxyType(dict(bounds)),
        cost=cost,
        evaluations=evaluations,
        passivity_checks=0,
        sampled_checks=checks,
        generations=generations,
        sea=problem.candidate(x),
        options=replace(opts, loop=sampled_loop_of(problem)),
        passivity=robust,
        sampled=None if robust is not None else sampled,
        constraint=constraint,
        warnings=tuple(notes),
        per_mass=tuple(runs),
    )
