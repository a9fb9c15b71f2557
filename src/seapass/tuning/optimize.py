"""Tune the gains of any SEA design under exact passivity: `tune` and its `TuningResult`.

The job, in four readable steps:

1. **resolve** the problem (`resolve_problem`): the design, the gains to tune
   and their box, every other parameter fixed, the objective and the limits;
   every input error is raised here, before any work;
2. **narrow** the box of a single tuned gain to the exact passive set
   ([`passive_intervals`][seapass.analysis.region.passive_intervals], its largest
   piece), so the search never leaves it;
3. **search** with differential evolution (`differential_search`) on the
   cost of `CandidateCost`: the objective on the simulated step response,
   penalties for the force and overshoot limits, and exact passivity (and
   sampled passivity when a period is given) for every candidate that could
   become the best; then move gains that ended next to an edge of the box onto
   it when that is better (`seapass.tuning.search.snap_to_edges`); round the gains for
   printing (over several load masses keeping the search's cost too: the worst case
   has ridges where the settling time jumps);
4. **verify** the optimum at the finer time step: exact verdicts, metrics, the
   limits, and which gains sit at an edge of their box (``on_bound``, with a
   [`TuningWarning`][seapass.errors.TuningWarning]: the optimum may lie beyond).

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Sec. V.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping
from dataclasses import replace
from types import MappingProxyType
from typing import Any

import numpy as np

from ..analysis.passivity import is_passive
from ..analysis.region import passive_intervals
from ..errors import NotPassiveError, ParameterError, SeapassDeprecationWarning, TuningWarning
from ..model.sea import SEA
from ..model.zcontroller import discrete_loop
from ..progress import ProgressLike, as_progress
from ..sampled.passivity import SampledPassivityResult, sampled_passivity
from .constraints import (
    ConstraintKind,
    PassivityConstraint,
    constrained_problem,
    rounded_gains,
)
from .cost import CandidateCost, ConstraintChecks, objective_value
from .limits import edge_note, limit_violations
from .masses import MassRun, step_run
from .problem import BoxLike, DesignLike, TuningOptions, TuningProblem
from .result import TuningResult
from .search import differential_search, snap_to_edges

__all__ = [
    "TuningResult",  # from seapass.tuning.result, where it lives
    "narrowed_box",
    "step_run",
    "tune",
    "verify",
]


def tune(
    design: DesignLike,
    *,
    tune: BoxLike | None = None,
    values: Mapping[str, float] | None = None,
    options: TuningOptions | None = None,
    progress: ProgressLike = None,
    callback: Callable[[int, float], None] | None = None,
    throw: bool = False,
    allow_plant: bool = False,
    uncertain: Mapping[str, Any] | None = None,
    budget: int | None = None,
    delay_time: float | None = None,
    **changes: Any,
) -> TuningResult:
    """Tune the gains of ``design`` for the best passive step response.

    Parameters
    ----------
    design : SEA, Design, CatalogDesign or str
        Any SEA; a design file's [`Design`][seapass.model.design_file.Design] (its
        ``[ranges]`` give the boxes, its ``[simulation]`` the load mass, step and
        horizon); or a catalog name ``"LP"``, ``"APD"``, ``"ours"`` (the paper's
        plant, the catalog's gains and boxes).
    tune : mapping of str to (lo, hi) or None, or iterable of str, optional
        The gains to tune, each with its box ``(lo, hi)`` or None for the
        design's default box.  Every other parameter keeps its value.  Default:
        the catalog's gains, else the controller gains (the parameters of
        ``C_A`` and ``C_L`` that are not plant parameters) of a design file or an SEA; see
        [`resolve_problem`][seapass.tuning.problem.resolve_problem].
    values : mapping of str to float, optional
        Values of fixed parameters overriding the design's, e.g. the plant of a
        catalog design: ``tune("ours", values={"k1": 1005, "b1": 30}, tune=["kd", "bd"])``.
    options : TuningOptions, optional
        Objective, limits, load mass, step, sampled-data period, budget, seed.
    progress : Progress, optional
        Where the search reports (a [`seapass.progress.Progress`][seapass.progress.Progress]):
        one task of ``options.maxiter`` steps, advanced after every generation with the
        best cost as its note; a ``KeyboardInterrupt`` from it stops the run.  Default:
        none.  ``True``/``False`` still work for one release (deprecated).
    callback : callable, optional
        Deprecated (one release): ``callback(generation, best_cost)`` after each
        generation; use ``progress``.
    uncertain : mapping, optional
        A box of uncertain plants: robust tuning, not available yet (refused).
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] when the result is
        not feasible (not passive, or a limit is violated).
    allow_plant : bool, default False
        Allow ``tune`` to name plant parameters (``k1``, a ``[plant]`` value) that the
        design does not offer for tuning; see `resolve_problem`.
    uncertain : mapping of str to (lo, hi), optional
        Uncertain plant parameters: the gains must be passive for every plant in the box
        ([`robust_check`][seapass.robust.verdict.robust_check]); the nominal tune runs
        too (``nominal``, ``robustness_cost``).  A design with a delay ``exp(-NAME*s)``
        is tuned passive at its delay (certified); see
        [`constrained_problem`][seapass.tuning.constraints.constrained_problem].
    budget : int, optional
        Budget of the certified delay or box test (undecided counts as not passive).
    delay_time : float, optional
        A loop latency [s] replacing the design file's ``[control] delay_time`` (a
        [`Design`][seapass.model.design_file.Design] only).  For a controller given in z
        it must be a whole number of periods: each adds one sample to the sampled loop's
        delay, where every candidate is certified
        ([`latency_loop`][seapass.tuning.sampled_design.latency_loop]).
    **changes
        Any field of `TuningOptions`, replacing the one in ``options``, e.g.
        ``objective="itae"``, ``loop=SampledLoop(period=0.002)``, ``seed=3``.

    Returns
    -------
    TuningResult
        A result that is not feasible (nothing in the box is passive, say) is
        returned with ``feasible=False`` and its ``violations``.

    Raises
    ------
    ParameterError
        For invalid input (before any work), naming the argument.
    KeyboardInterrupt
        Propagated after the progress task is closed; nothing is written.

    Examples
    --------
    >>> import seapass
    >>> sea = seapass.SEA(D1="k1 + b1*s", CA="kd + bd*s",
    ...                   values=dict(m=1, b=10, k1=1000, b1=30, kd=500, bd=25))
    >>> r = seapass.tune(sea, tune={"kd": (0, 3000), "bd": (0, 400)},
    ...                  maxiter=4, popsize=4, dt_search=1e-2)
    >>> r.passive, sorted(r.gains)
    (True, ['bd', 'kd'])
    """
    opts = (options or TuningOptions()).replace(**changes)
    if delay_time is not None:
        design, opts = _with_latency(design, opts, delay_time)
    problem, constraint = constrained_problem(
        design, tune, opts, values, allow_plant=allow_plant, uncertain=uncertain, budget=budget
    )
    if problem.sea.discrete is not None:  # a controller in z: the sampled loop, certified
        result = _tune_z(design, tune, problem, constraint, progress, callback)
        if constraint.kind is ConstraintKind.BOX:  # the nominal z-tune, same plant and budget
            result = _with_nominal(result, design, problem, constraint, opts, values, allow_plant)
        for message in result.warnings:
            warnings.warn(message, TuningWarning, stacklevel=2)
        if throw and not result.feasible:
            raise NotPassiveError(f"tuning {problem.name}: {'; '.join(result.warnings)}")
        return result
    bounds = narrowed_box(problem) if constraint.kind is ConstraintKind.EXACT else dict(problem.box)
    if problem.options.loop is not None:  # fail now on what the sampled analysis refuses
        _sampled_verdict(problem, problem.candidate(sum(bounds[g]) / 2 for g in problem.gains))
    checks = ConstraintChecks(problem, constraint)
    cost = CandidateCost(problem, checks)
    shown = as_progress(progress, where="tune")
    if callback is not None:
        warnings.warn(
            "tune(callback=...) is deprecated; pass progress=, a seapass.progress.Progress "
            "whose advance() runs after every generation",
            SeapassDeprecationWarning,
            stacklevel=2,
        )
    found = differential_search(
        cost,
        [bounds[g] for g in problem.gains],
        problem.options,
        label=problem.name,
        progress=shown,
        callback=callback,
    )
    x, best = snap_to_edges(problem, bounds, [float(v) for v in found.x], float(found.fun), cost)
    several = len(problem.options.masses) > 1

    def keep(r: tuple[float, ...]) -> bool:  # over several masses the rounding must not step
        if several and float(cost(np.array(r))) > best + 1e-9 * abs(best):  # off a ridge
            return False
        return checks.passive(r)

    x = rounded_gains(x, [bounds[g] for g in problem.gains], keep)  # printed = verified
    result = verify(
        problem, x, bounds=bounds, checks=checks, cost=best, evaluations=cost.evaluations,
        generations=int(found.nit), constraint=constraint,
    )  # fmt: skip
    if constraint.kind is ConstraintKind.BOX:  # the nominal tune, same plant and budget
        result = _with_nominal(result, design, problem, constraint, opts, values, allow_plant)
    for message in result.warnings:
        warnings.warn(message, TuningWarning, stacklevel=2)
    if throw and not result.feasible:
        raise NotPassiveError(f"tuning {problem.name}: {'; '.join(result.warnings)}")
    return result


_nominal_tune = tune  # the function itself (inside it, ``tune`` is the argument)


def _with_latency(
    design: DesignLike, opts: TuningOptions, delay_time: float
) -> tuple[DesignLike, TuningOptions]:
    """The design (continuous: its ``[control] delay_time``) or the loop (a controller in z:
    whole samples) with the loop latency ``delay_time``."""
    from ..model.design_file import Design
    from .problem import design_parts
    from .sampled_design import latency_loop

    zc = design_parts(design)[1].discrete
    if zc is not None:
        loop = discrete_loop(zc, opts.loop)
        return design, opts.replace(loop=latency_loop(loop, delay_time))
    if not isinstance(design, Design):
        raise ParameterError(
            "delay_time: a loop latency replaces a design file's [control] delay_time; for "
            "another design put the delay in the model, e.g. CA='(kd + bd*s)*exp(-tau*s)' "
            "with values={'tau': 0.001}",
            argument="delay_time",
        )
    return replace(design, delay_time=delay_time), opts


def _with_nominal(
    result: TuningResult,
    design: DesignLike,
    problem: TuningProblem,
    constraint: PassivityConstraint,
    opts: TuningOptions,
    values: Mapping[str, float] | None,
    allow_plant: bool,
) -> TuningResult:
    """``result`` (robust, over a box) with the nominal tune of the same budget beside it:
    the plant at its nominal values, the same boxes (``robustness_cost``)."""
    assert constraint.box is not None
    fixed = {n: float(problem.sea.values[n] or 0) for n in constraint.box.names}
    with warnings.catch_warnings():  # the nominal run's own notes are not this result's
        warnings.simplefilter("ignore", TuningWarning)
        nominal = _nominal_tune(design, tune=dict(problem.box), options=opts,
                                values={**(values or {}), **fixed}, allow_plant=allow_plant)  # fmt: skip
    if result.feasible and (not nominal.feasible or result.objective < nominal.objective):
        x = [result.gains[g] for g in problem.gains]  # the robust gains are nominal ones too
        if problem.sea.discrete is not None:
            from .sampled_design import verify_sampled

            alt = verify_sampled(problem, x, bounds=result.bounds, cost=result.cost,
                                 generations=nominal.generations)  # fmt: skip
        else:
            alt = verify(problem, x, bounds=result.bounds, cost=result.cost,
                         generations=nominal.generations)  # fmt: skip
        nominal = alt if alt.feasible else nominal
    return replace(result, nominal=nominal)


def _tune_z(
    design: DesignLike,
    tune: BoxLike | None,
    problem: TuningProblem,
    constraint: PassivityConstraint,
    progress: ProgressLike,
    callback: Callable[[int, float], None] | None,
) -> TuningResult:
    """`tune` of a design whose controller is given in z (`seapass.tuning.sampled_design`);
    over a box, every candidate is certified by the robust sampled verdict."""
    from .sampled_design import check_sampled_boxes, tune_sampled

    ranges = dict(getattr(design, "ranges", None) or {})  # a file's explicit [ranges] only
    given = dict(tune) if isinstance(tune, Mapping) else {}
    check_sampled_boxes(problem, given, ranges)
    box = constraint if constraint.kind is ConstraintKind.BOX else None
    return tune_sampled(problem, progress=progress, callback=callback, constraint=box)


def narrowed_box(problem: TuningProblem) -> dict[str, tuple[float, float]]:
    """The box to search: a single gain's box narrowed to the largest piece of its exact
    passive set (several gains: the box as given; passivity is checked per candidate).

    Raises
    ------
    ParameterError
        When a single gain is passive nowhere in its box.
    """
    box = dict(problem.box)
    if len(problem.gains) != 1:
        return box
    (gain,) = problem.gains
    lo, hi = box[gain]
    passive = passive_intervals(problem.sea, gain, lo, hi).intervals
    pieces = [(a, b) for a, b in passive if b > a]
    if not pieces:
        raise ParameterError(
            f"{problem.name} is not passive for any {gain} in [{lo:g}, {hi:g}] "
            "(the other parameters at their values): nothing to tune"
        )
    a, b = max(pieces, key=lambda ab: ab[1] - ab[0])
    return {gain: (float(a), float(b))}


def verify(
    problem: TuningProblem,
    x: list[float],
    *,
    bounds: Mapping[str, tuple[float, float]],
    checks: ConstraintChecks | None = None,
    cost: float = float("nan"),
    evaluations: int = 0,
    generations: int = 0,
    constraint: PassivityConstraint | None = None,
) -> TuningResult:
    """Everything about the gains ``x``: exact verdicts, metrics at ``dt_verify``, limits.

    ``cost``, ``evaluations`` and ``generations`` are the search's best cost, simulation
    count and generations, when ``x`` comes from a search.  ``constraint``: the passivity
    test (default: exact, at ``problem.sea``); the step response is the constraint's design
    (a delay delays the controller output).
    """
    opts = problem.options
    gains = dict(zip(problem.gains, x, strict=True))
    sea = problem.candidate(x)
    pr = is_passive(sea) if constraint is None else constraint.verdict(x)
    sampled = None if opts.loop is None else _sampled_verdict(problem, sea)
    simulated = sea if constraint is None else constraint.design(x)  # with its delay
    runs = []
    for mass in opts.masses:
        res, met = step_run(simulated, opts, mass)
        runs.append(MassRun(load_mass=mass, objective=objective_value(opts, res, met), metrics=met))
    worst = max(runs, key=lambda r: r.objective)
    violations, notes = limit_violations(
        problem, pr, sampled, {r.load_mass: r.metrics for r in runs}
    )
    on_bound = problem.on_bound(gains)
    notes += [edge_note(problem, name, gains[name], edge) for name, edge in on_bound.items()]
    return TuningResult(
        design=problem.name,
        gains=MappingProxyType(gains),
        objective=worst.objective,
        outcome=pr.outcome,
        sampled_outcome=None if sampled is None else sampled.outcome,
        feasible=not violations,
        violations=tuple(violations),
        on_bound=MappingProxyType(on_bound),
        metrics=worst.metrics,
        box=problem.box,
        bounds=MappingProxyType(dict(bounds)),
        cost=cost,
        evaluations=evaluations,
        passivity_checks=len(checks.continuous) if checks else 0,
        sampled_checks=len(checks.sampled) if checks else 0,
        generations=generations,
        sea=sea if constraint is None else constraint.design(x),
        options=opts,
        passivity=pr,
        sampled=sampled,
        warnings=tuple(notes),
        constraint=constraint,
        per_mass=tuple(runs),
    )


def _sampled_verdict(problem: TuningProblem, sea: SEA) -> SampledPassivityResult:
    opts = problem.options
    if opts.loop is None:
        raise ParameterError("no sampled-data verdict without a sampled loop (options.loop)")
    return sampled_passivity(sea, loop=opts.loop)
