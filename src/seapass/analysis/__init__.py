"""Continuous-time analysis: exact passivity, conditions, passive sets, responses, witnesses.

What lives here: [`passivity`][seapass.analysis.passivity] (the exact positive-real
test), [`conditions`][seapass.analysis.conditions] (symbolic necessary-and-sufficient
conditions), [`region`][seapass.analysis.region] (exact passive intervals and 2-D
maps), [`boundary`][seapass.analysis.boundary] (the exact 2-D passive region and its
boundary curves), [`freqresp`][seapass.analysis.freqresp] (the stiffness frequency response),
[`coupled`][seapass.analysis.coupled] (coupled stability with an environment),
[`indices`][seapass.analysis.indices] (the passivity indices ν and ρ, exact),
[`environment_box`][seapass.analysis.environment_box] (environments within physical
bounds, and the exact proof that none of them destabilizes a design) and
[`witness`][seapass.analysis.witness] with [`witness_search`][seapass.analysis.witness_search]
(a passive environment, within bounds, that destabilizes a design that is not passive).

May import: [`seapass.errors`][seapass.errors], ``seapass.outcome``, [`seapass.files`][seapass.files], [`seapass.exact`][seapass.exact], [`seapass.model`][seapass.model].
"""

from .boundary import PassiveRegion, passive_region
from .conditions import ExactCondition, exact_passivity_condition
from .coupled import CoupledResult, Environment, Stability, coupled_stability
from .coupled_response import CoupledSimulation, simulate_coupled
from .environment_box import HUMAN_LIMB, EnvironmentBounds
from .freqresp import FrequencyResponse, stiffness_response
from .indices import PassivityIndices, passivity_indices
from .passivity import PassivityResult, is_passive
from .region import PassiveIntervals, PassiveMap, passive_intervals, passive_map
from .witness import WitnessResult, find_destabilizing_environment

__all__ = [
    "HUMAN_LIMB",
    "CoupledResult",
    "CoupledSimulation",
    "Environment",
    "EnvironmentBounds",
    "ExactCondition",
    "FrequencyResponse",
    "PassiveIntervals",
    "PassiveMap",
    "PassiveRegion",
    "PassivityIndices",
    "PassivityResult",
    "Stability",
    "WitnessResult",
    "coupled_stability",
    "exact_passivity_condition",
    "find_destabilizing_environment",
    "is_passive",
    "passive_intervals",
    "passive_map",
    "passive_region",
    "passivity_indices",
    "simulate_coupled",
    "stiffness_response",
]
