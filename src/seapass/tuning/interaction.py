"""Tune for an interaction-control objective under exact passivity: `tune_objective`.

The objectives (rendering fidelity, force bandwidth, Z-width) are defined in
[`seapass.tuning.objectives`][seapass.tuning.objectives].  The job:

1. **resolve** the problem as [`tune`][seapass.tuning.optimize.tune] does
   (`resolve_problem`; for the Z-width the stiffness gain is the objective, not a
   searched gain);
2. **search** with differential evolution twice with the same budget and seed:
   *constrained* (every candidate that could become the best is checked with the
   exact passivity test, and the sampled-data test when a loop is given, as
   `tune` does) and *unconstrained* (no passivity check; for the Z-width, whose
   objective is itself certified sampled passivity, no continuous check).  Both
   require a closed loop that is stable with every listed load mass;
3. **verify** both optima: the objective on a grid four times denser, the exact
   verdicts;
4. **compare**: each optimum is a candidate of the other problem when it qualifies
   (the constrained optimum always is one of the unconstrained problem; an unconstrained
   optimum that is passive, sampled-passive when a loop is given, and stable is one of
   the constrained problem), and each takes the other when it is better.  So
   ``passivity_cost`` — what the constraint costs in the objective,
   ``unconstrained − constrained`` for a maximized objective, ``constrained −
   unconstrained`` for the rendering error — is never negative, and positive only when
   the unconstrained optimum is not passive.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import replace
from types import MappingProxyType
from typing import Any

import numpy as np

from ..analysis.freqresp import log_frequencies
from ..analysis.passivity import is_passive
from ..errors import DelayError, NotPassiveError, ParameterError, SeapassError, TuningWarning
from ..files.limits import MAX_FREQUENCY_POINTS
from ..model.delayatom import model_delays
from ..model.design_file import Design
from ..outcome import Outcome
from ..progress import ProgressLike, as_progress
from ..sampled.passivity import sampled_passivity
from .cost import ConstraintChecks
from .objective_result import ObjectiveOptimum, ObjectiveTuningResult
from .objectives import (
    Interaction,
    InteractionObjective,
    ObjectiveFunction,
    squash,
    stiffness_gain,
)
from .optimize import narrowed_box
from .problem import (
    BoxLike,
    DesignLike,
    TuningOptions,
    TuningProblem,
    default_box,
    design_parts,
    resolve_problem,
)
from .sampled_design import check_sampled_boxes, sampled_loop_of
from .sampled_objectives import SampledChecks, SampledObjectiveFunction
from .search import differential_search, snap_to_edges

__all__ = ["ObjectiveCost", "tune_objective"]

UNSTABLE_COST = 2.0
NO_VALUE_COST = 3.0
CONSTRAINT_COST = 1.0


class ObjectiveCost:
    """The search cost of a candidate: `squash` of the objective in ``[0, 1)``, plus 1 for
    a failed passivity check (constrained runs, only for a candidate that would be the
    best), 2 when a load mass destabilizes it, 3 when the objective has no value."""

    def __init__(
        self, fn: ObjectiveFunction, checks: ConstraintChecks | SampledChecks, *, constrained: bool
    ) -> None:
        self.fn = fn
        self.checks = checks
        self.constrained = constrained
        self.best = math.inf
        self.evaluations = 0

    def __call__(self, x: Any) -> float:
        self.evaluations += 1
        xs = tuple(float(v) for v in x)
        fn = self.fn
        if fn.stiffness is None and not fn.stable(xs):
            return UNSTABLE_COST
        try:
            value = fn.value(xs)
        except (SeapassError, ArithmeticError, ValueError):
            return NO_VALUE_COST
        if math.isnan(value):
            return NO_VALUE_COST
        full = fn.full(xs, value)
        if fn.stiffness is not None and not fn.stable(full):
            return UNSTABLE_COST
        cost = squash(value, fn.kind)
        if cost <= self.best:  # ties too: a capped objective (the band's top) ties often
            if self.constrained and not self.checks.passive(full):
                return cost + CONSTRAINT_COST
            self.best = cost
        return cost


def tune_objective(
    design: DesignLike,
    objective: InteractionObjective | Interaction | str,
    *,
    tune: BoxLike | None = None,
    values: Mapping[str, float] | None = None,
    options: TuningOptions | None = None,
    progress: ProgressLike = None,
    throw: bool = False,
    allow_plant: bool = False,
    **changes: Any,
) -> ObjectiveTuningResult:
    """Tune the gains of ``design`` for an interaction-control objective under exact passivity.

    Parameters
    ----------
    design : SEA, Design, CatalogDesign or str
        As for [`tune`][seapass.tuning.optimize.tune].
    objective : InteractionObjective, Interaction or str
        What to optimize (see [`seapass.tuning.objectives`][seapass.tuning.objectives]);
        a bare kind is ``InteractionObjective(kind=...)``.
    tune, values, allow_plant
        As for `tune`.  For the Z-width the stiffness gain is the objective and is not
        searched (default: the design's other gains).
    options : TuningOptions, optional
        The loop (the sampled constraint; required for the Z-width), the budget
        (``maxiter``, ``popsize``, ``seed``, for each of the two searches) and the tuning
        load mass (when neither the objective nor the design file lists load masses).
    progress : Progress, optional
        One task per search.
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] when the constrained
        optimum is not feasible.
    **changes
        Fields of `TuningOptions` replacing those of ``options``.

    Returns
    -------
    ObjectiveTuningResult

    Raises
    ------
    ParameterError
        Bad input, before any work: a Z-width without a loop, an unparseable target,
        the stiffness gain among the tuned ones, and what `resolve_problem` refuses.

    Examples
    --------
    >>> import seapass
    >>> from seapass.tuning import tune_objective
    >>> r = tune_objective("APD", "force-bandwidth", maxiter=3, popsize=4)
    >>> r.passive, r.passivity_cost >= 0
    (True, True)
    """
    spec = (
        objective
        if isinstance(objective, InteractionObjective)
        else InteractionObjective(kind=objective)
    )
    kind = Interaction(spec.kind)
    opts = (options or TuningOptions()).replace(**changes)
    stiffness: str | None = None
    stiff_box: tuple[float, float] | None = None
    z_design = design_parts(design)[1].discrete is not None
    if kind is Interaction.ZWIDTH:
        if opts.loop is None and not z_design:
            raise ParameterError(
                "the zwidth objective needs the loop rate: give options.loop "
                "(e.g. SampledLoop(period=0.002)) or a design file with a [control] rate",
                argument="loop",
            )
        full, problem, stiffness, stiff_box = _zwidth_problems(
            design, spec, tune, opts, values, allow_plant
        )
    else:
        full = problem = resolve_problem(design, tune, opts, values, allow_plant=allow_plant)
    delays = model_delays(full.sea)
    if delays:  # the objectives evaluate exact rational responses: a delay would be dropped
        raise DelayError(
            f"a delay exp(-{delays[0]}*s) in the model: the interaction objectives (rendering, "
            "force-bandwidth, zwidth) need a delay-free design; tune a delayed design with "
            "the settling or itae objective"
        )
    masses = spec.load_masses or (
        design.load_masses if isinstance(design, Design) else (problem.options.load_mass,)
    )
    masses = tuple(float(m) for m in masses)
    checks: ConstraintChecks | SampledChecks
    if z_design:  # a controller in z: its sampled loop, certified (sampled_objectives)
        full, problem = _z_problems(design, tune, full, problem, stiffness)
        fn: ObjectiveFunction = SampledObjectiveFunction(
            spec, problem.sea, problem.gains, load_masses=masses, loop=problem.options.loop,
            stiffness=stiffness, stiffness_box=stiff_box,
        )  # fmt: skip
        checks = SampledChecks(candidate=full.candidate, loop=sampled_loop_of(full))
    else:
        fn = ObjectiveFunction(
            spec, problem.sea, problem.gains, load_masses=masses, loop=problem.options.loop,
            stiffness=stiffness, stiffness_box=stiff_box,
        )  # fmt: skip
        checks = ConstraintChecks(full)
    shown = as_progress(progress, where="tune_objective")
    box = dict(problem.box)
    narrow = kind is not Interaction.ZWIDTH and problem.gains and not z_design
    bounds = narrowed_box(problem) if narrow else box
    con_x, con_cost = _search(problem, fn, checks, bounds, True, shown)
    unc_x, unc_cost = _search(problem, fn, checks, box, False, shown)
    con = _optimum(fn, full, con_x, con_cost, checks)
    unc = _optimum(fn, full, unc_x, unc_cost, checks)
    # each optimum is a candidate of the other problem when it qualifies for it
    if unc.passive and unc.stable and _better(kind, unc.value, con.value):
        con = replace(unc, evaluations=con.evaluations, generations=con.generations)
    if not unc.stable or (_better(kind, con.value, unc.value) and con.stable):
        unc = replace(con, evaluations=unc.evaluations, generations=unc.generations)
    gap = (unc.value - con.value) if kind.maximize else (con.value - unc.value)
    gap = max(gap, 0.0) if math.isfinite(gap) else math.nan
    relative = gap / abs(unc.value) if unc.value and math.isfinite(unc.value) else None
    violations, notes = _violations(con, fn, full, box, stiffness)
    result = ObjectiveTuningResult(
        design=problem.name, objective=spec, unit=_unit(kind, design, stiffness),
        constrained=con, unconstrained=unc, passivity_cost=gap, relative_cost=relative,
        feasible=not violations, violations=tuple(violations), load_masses=masses,
        stiffness=stiffness, box=MappingProxyType(box), bounds=MappingProxyType(dict(bounds)),
        passivity_checks=len(checks.continuous), sampled_checks=len(checks.sampled),
        budget_exhausted=fn.boxes_exhausted,
        sea=full.candidate(con.gains[g] for g in full.gains), options=problem.options,
        warnings=tuple(notes), function=fn,
    )  # fmt: skip
    for message in result.warnings:
        warnings.warn(message, TuningWarning, stacklevel=2)
    if throw and not result.feasible:
        raise NotPassiveError(f"tuning {problem.name}: {'; '.join(result.warnings)}")
    return result


def _better(kind: Interaction, a: float, b: float) -> bool:
    """``a`` is a strictly better objective value than ``b`` (nan is never better)."""
    if math.isnan(a):
        return False
    if math.isnan(b):
        return True
    return a > b if kind.maximize else a < b


def _zwidth_problems(
    design: DesignLike,
    spec: InteractionObjective,
    tune: BoxLike | None,
    opts: TuningOptions,
    values: Mapping[str, float] | None,
    allow_plant: bool,
) -> tuple[TuningProblem, TuningProblem, str, tuple[float, float]]:
    """The full problem (the searched gains and the stiffness gain) and the searched one."""
    _name, sea, defaults, boxes = design_parts(design)
    controller = [g for g in defaults if g in sea.gains] or list(defaults)
    stiffness = stiffness_gain(sea, controller, spec.stiffness)
    if tune is None:
        wanted: dict[str, Any] = {g: None for g in defaults if g != stiffness}
    elif isinstance(tune, Mapping):
        wanted = dict(tune)
    elif isinstance(tune, str):
        raise ParameterError(f"tune: expected a mapping {{name: (lo, hi)}} or names, got {tune!r}")
    else:
        wanted = dict.fromkeys(tune)
    if stiffness in wanted:
        raise ParameterError(
            f"tune[{stiffness!r}]: the zwidth objective computes the largest passive "
            f"{stiffness}; tune the other gains (or choose another stiffness gain)",
            argument="tune",
        )
    box = boxes.get(stiffness) or default_box(stiffness, sea.values.get(stiffness))
    if box is None:
        raise ParameterError(
            f"{stiffness} has no value and no range: give it a [ranges] entry", argument="tune"
        )
    full = resolve_problem(
        design, {**wanted, stiffness: box}, opts, values, allow_plant=allow_plant
    )
    others = tuple(g for g in full.gains if g != stiffness)
    searched = replace(full, gains=others, box=MappingProxyType({g: full.box[g] for g in others}))
    return full, searched, stiffness, full.box[stiffness]


def _z_problems(
    design: DesignLike,
    tune: BoxLike | None,
    full: TuningProblem,
    problem: TuningProblem,
    stiffness: str | None,
) -> tuple[TuningProblem, TuningProblem]:
    """The problems of a controller in z with its loop (the controller's rate unless the
    options give one): every tuned gain named in the z-expressions with an explicit box."""
    ranges = dict(getattr(design, "ranges", None) or {})  # a file's explicit [ranges] only
    given = dict(tune) if isinstance(tune, Mapping) else {}
    if stiffness is not None and stiffness not in ranges:
        raise ParameterError(
            f"{stiffness}: a controller in z has no default box; give the stiffness gain "
            f"{stiffness}'s box in the design file's [ranges]",
            argument="tune",
        )
    check_sampled_boxes(full, {**given, **({stiffness: full.box[stiffness]} if stiffness else {})},
                        ranges)  # fmt: skip
    loop = sampled_loop_of(full)
    full = replace(full, options=replace(full.options, loop=loop))
    return full, replace(problem, options=replace(problem.options, loop=loop))


def _search(
    problem: TuningProblem,
    fn: ObjectiveFunction,
    checks: ConstraintChecks | SampledChecks,
    bounds: Mapping[str, tuple[float, float]],
    constrained: bool,
    progress: Any,
) -> tuple[tuple[float, ...], ObjectiveCost]:
    cost = ObjectiveCost(fn, checks, constrained=constrained)
    if not problem.gains:  # nothing to search (the Z-width of a one-gain design)
        cost(np.zeros(0))
        return (), cost
    label = f"{problem.name} ({'passive' if constrained else 'unconstrained'})"
    found = differential_search(
        cost, [bounds[g] for g in problem.gains], problem.options, label=label, progress=progress
    )
    x, _best = snap_to_edges(problem, bounds, [float(v) for v in found.x], float(found.fun), cost)
    cost.generations = int(found.nit)  # type: ignore[attr-defined]
    return tuple(x), cost


def _optimum(
    fn: ObjectiveFunction,
    full: TuningProblem,
    x: tuple[float, ...],
    cost: ObjectiveCost,
    checks: ConstraintChecks | SampledChecks,
) -> ObjectiveOptimum:
    """The verified optimum at ``x``: the objective on a denser grid, exact verdicts (a
    controller in z: the certified sampled verdict is both)."""
    at = None
    dense = log_frequencies(*fn.band, min(4 * fn.spec.points, MAX_FREQUENCY_POINTS))
    try:
        if fn.kind is Interaction.RENDERING:
            value, at = fn.rendering_error(x, dense)
        elif fn.kind is Interaction.FORCE_BANDWIDTH:
            value = fn.force_bandwidth(x, dense)
        else:
            value = fn.zwidth(x)
    except (SeapassError, ArithmeticError, ValueError):
        value = math.nan
    point = fn.full(x, value)
    sea = full.candidate(point)
    sampled = None
    if isinstance(checks, SampledChecks):
        outcome = sampled = checks.outcome(point)
    else:
        outcome = is_passive(sea).outcome
    if full.options.loop is not None and sampled is None:
        try:
            sampled = sampled_passivity(sea, loop=full.options.loop).outcome
        except (SeapassError, ArithmeticError, ValueError):
            sampled = Outcome.UNDECIDED
    return ObjectiveOptimum(
        gains=MappingProxyType(dict(zip(full.gains, point, strict=True))),
        value=value, outcome=outcome, sampled_outcome=sampled, stable=fn.stable(point), at=at,
        evaluations=cost.evaluations, generations=getattr(cost, "generations", 0),
    )  # fmt: skip


def _violations(
    opt: ObjectiveOptimum,
    fn: ObjectiveFunction,
    full: TuningProblem,
    box: Mapping[str, tuple[float, float]],
    stiffness: str | None,
) -> tuple[list[str], list[str]]:
    violations, notes = [], []
    if not opt.outcome.passive:
        violations.append("passivity")
        notes.append(f"no passive gains found in the box: the best is {opt.outcome}")
    in_z = fn.nyquist is not None  # the one verdict is the sampled one
    if opt.sampled_outcome is not None and not opt.sampled_outcome.passive and not in_z:
        violations.append("sampled passivity")
        notes.append(f"the best gains are {opt.sampled_outcome} under sampled-data control")
    if not opt.stable:
        violations.append("stability")
        notes.append("the best gains are not stable with every load mass")
    if not math.isfinite(opt.value):
        violations.append("objective")
        notes.append("the objective has no finite value at the best gains")
    for name, (lo, hi) in box.items():
        v = opt.gains[name]
        if hi - v <= 0.01 * (hi - lo) or (v - lo <= 0.01 * (hi - lo) and lo != 0):
            notes.append(f"{name} = {v:.6g} is at an edge of its box [{lo:g}, {hi:g}]")
    top = fn.band[1]
    if fn.kind is Interaction.FORCE_BANDWIDTH and opt.value >= top * (1 - 1e-9) and in_z:
        notes.append(
            f"the sampled force response stays above -3 dB up to {top:g} rad/s, just below "
            f"the Nyquist frequency {fn.nyquist:g} rad/s of the controller's rate: the "
            "bandwidth shown is that top"
        )
    elif fn.kind is Interaction.FORCE_BANDWIDTH and opt.value >= top * (1 - 1e-9):
        notes.append(
            f"the force response stays above -3 dB up to the band's top {top:g} rad/s "
            "(a biproper force transfer never falls off): the bandwidth shown is that top; "
            "widen the band (band=(lo, hi)) to see more"
        )
    if stiffness is not None:
        lo, hi = full.box[stiffness]
        if opt.gains[stiffness] >= hi * (1 - 1e-6):
            notes.append(
                f"the Z-width reaches the top of {stiffness}'s range {hi:g}: widen it "
                "([ranges]) to see how far it goes"
            )
        if fn.boxes_exhausted:
            notes.append(
                f"{fn.boxes_exhausted} Z-width bounds stopped at max_boxes = {fn.spec.max_boxes} "
                "(their values are proven, perhaps smaller than the true Z-width)"
            )
    return violations, notes


def _unit(kind: Interaction, design: DesignLike, stiffness: str | None) -> str:
    """``"1"``, ``"rad/s"`` or the stiffness gain's unit (a design file's ``[units]``)."""
    if kind is Interaction.RENDERING:
        return "1"
    if kind is Interaction.FORCE_BANDWIDTH:
        return "rad/s"
    from ..model.units import unit_map

    declared = design.units if isinstance(design, Design) else None
    return unit_map(declared, [stiffness or ""]).get(stiffness or "", "")
