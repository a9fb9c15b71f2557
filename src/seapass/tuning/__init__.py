"""Passivity-constrained tuning of any SEA design.

What lives here: [`problem`][seapass.tuning.problem] (the design, the gains and
their box, the objective and the limits: `TuningOptions`, validated into a
`TuningProblem` before any work), [`cost`][seapass.tuning.cost] (what the
optimizer minimizes: the simulated objective, penalties for the force and
overshoot limits, exact continuous and sampled passivity where it matters),
[`constraints`][seapass.tuning.constraints] (the one passivity constraint of a run:
exact, certified at a fixed continuous delay, or certified for every plant in a box),
[`limits`][seapass.tuning.limits] (what a tuned design misses, one sentence each),
[`masses`][seapass.tuning.masses] (the load masses a candidate is judged on: the worst
case over a design's masses or the tuning mass, and the step response at each),
[`search`][seapass.tuning.search] (differential evolution with a seed, its progress
and a clean Ctrl-C), [`optimize`][seapass.tuning.optimize] (`tune`, the
step-response entry point), [`sampled_design`][seapass.tuning.sampled_design] (its path
for a controller given in z: certified sampled passivity, the sampled step response) and
[`result`][seapass.tuning.result] (its `TuningResult`); the interaction-control objectives
(what to optimize: [`objective_spec`][seapass.tuning.objective_spec]) in
[`objectives`][seapass.tuning.objectives] (rendering fidelity, force bandwidth,
Z-width) and, for a controller given in z, in
[`sampled_objectives`][seapass.tuning.sampled_objectives] (the sampled loop's own
responses, certified sampled passivity), their entry point [`interaction`][seapass.tuning.interaction]
(`tune_objective`, constrained and unconstrained) and its result in
[`objective_result`][seapass.tuning.objective_result].

May import: [`seapass.errors`][seapass.errors], [`seapass.progress`][seapass.progress],
[`seapass.files`][seapass.files], [`seapass.model`][seapass.model],
[`seapass.analysis`][seapass.analysis], [`seapass.sim`][seapass.sim],
[`seapass.sampled`][seapass.sampled] (the sampled-data passivity constraint),
[`seapass.delay`][seapass.delay] (the certified constraint at a delay),
[`seapass.robust`][seapass.robust] (the certified constraint over a box),
[`seapass.outcome`][seapass.outcome].
"""

from .constraints import ConstraintKind, PassivityConstraint, constrained_problem
from .interaction import tune_objective
from .masses import MassPolicy, MassRun
from .objective_result import ObjectiveOptimum, ObjectiveTuningResult
from .objectives import Interaction, InteractionObjective
from .optimize import tune
from .problem import QUICK_OPTIONS, Objective, TuningOptions, TuningProblem, resolve_problem
from .result import TuningResult

__all__ = [
    "QUICK_OPTIONS",
    "ConstraintKind",
    "Interaction",
    "InteractionObjective",
    "MassPolicy",
    "MassRun",
    "Objective",
    "ObjectiveOptimum",
    "ObjectiveTuningResult",
    "PassivityConstraint",
    "TuningOptions",
    "TuningProblem",
    "TuningResult",
    "constrained_problem",
    "resolve_problem",
    "tune",
    "tune_objective",
]
