"""Continuous-time analysis: exact passivity, conditions, passive sets, responses, witnesses.

What lives here: [`passivity`][seapass.analysis.passivity] (the exact positive-real
test), [`conditions`][seapass.analysis.conditions] (symbolic necessary-and-sufficient
conditions), [`region`][seapass.analysis.region] (exact passive intervals and 2-D
maps), [`boundary`][seapass.analysis.boundary] (the exact 2-D passive region and its
boundary curves), [`freqresp`][seapass.analysis.freqresp] (the stiffness frequency response),
[`coupled`][seapass.analysis.coupled] (coupled stability with an environment) and
[`witness`][seapass.analysis.witness] (a passive environment that destabilizes a
design that is not passive).

May import: [`seapass.errors`][seapass.errors], [`seapass.exact`][seapass.exact], [`seapass.model`][seapass.model].
"""

from .boundary import PassiveRegion, passive_region
from .conditions import ExactCondition, exact_passivity_condition
from .coupled import CoupledResult, Environment, Stability, coupled_stability
from .coupled_response import CoupledSimulation, simulate_coupled
from .freqresp import FrequencyResponse, stiffness_response
from .passivity import PassivityResult, is_passive
from .region import PassiveIntervals, PassiveMap, passive_intervals, passive_map
from .witness import WitnessResult, find_destabilizing_environment

__all__ = [
    "CoupledResult",
    "CoupledSimulation",
    "Environment",
    "ExactCondition",
    "FrequencyResponse",
    "PassiveIntervals",
    "PassiveMap",
    "PassiveRegion",
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
    "simulate_coupled",
    "stiffness_response",
]
