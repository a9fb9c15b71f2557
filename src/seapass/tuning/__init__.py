"""Passivity-constrained tuning of any SEA design.

What lives here: [`problem`][seapass.tuning.problem] (the design, the gains and
their box, the objective and the limits: `TuningOptions`, validated into a
`TuningProblem` before any work), [`cost`][seapass.tuning.cost] (what the
optimizer minimizes: the simulated objective, penalties for the force and
overshoot limits, exact continuous and sampled passivity where it matters),
[`search`][seapass.tuning.search] (differential evolution with a seed, its progress
and a clean Ctrl-C) and [`optimize`][seapass.tuning.optimize] (`tune`, the
step-response entry point, and its `TuningResult`); the interaction-control objectives
in [`objectives`][seapass.tuning.objectives] (rendering fidelity, force bandwidth,
Z-width), their entry point [`interaction`][seapass.tuning.interaction]
(`tune_objective`, constrained and unconstrained) and its result in
[`objective_result`][seapass.tuning.objective_result].

May import: [`seapass.errors`][seapass.errors], [`seapass.progress`][seapass.progress],
[`seapass.files`][seapass.files], [`seapass.model`][seapass.model],
[`seapass.analysis`][seapass.analysis], [`seapass.sim`][seapass.sim],
[`seapass.sampled`][seapass.sampled] (the sampled-data passivity constraint),
[`seapass.outcome`][seapass.outcome].
"""

from .interaction import tune_objective
from .objective_result import ObjectiveOptimum, ObjectiveTuningResult
from .objectives import Interaction, InteractionObjective
from .optimize import TuningResult, tune
from .problem import QUICK_OPTIONS, Objective, TuningOptions, TuningProblem, resolve_problem

__all__ = [
    "QUICK_OPTIONS",
    "Interaction",
    "InteractionObjective",
    "Objective",
    "ObjectiveOptimum",
    "ObjectiveTuningResult",
    "TuningOptions",
    "TuningProblem",
    "TuningResult",
    "resolve_problem",
    "tune",
    "tune_objective",
]
