"""Continuous-time analysis: exact passivity, conditions, passive sets, responses, witnesses.

What lives here: [`passivity`][seapass.analysis.passivity] (the exact positive-real
test), [`impedance`][seapass.analysis.impedance] (the exact ``N/D`` at given values),
[`conditions`][seapass.analysis.conditions] (symbolic necessary-and-sufficient
conditions), [`critical`][seapass.analysis.critical] (the critical values of one
parameter, isolated exactly), [`region`][seapass.analysis.region] (exact passive
intervals, reported inward, and 2-D maps), [`boundary`][seapass.analysis.boundary] (the exact 2-D passive region and its
boundary curves), [`freqresp`][seapass.analysis.freqresp] (the stiffness frequency response),
[`coupled`][seapass.analysis.coupled] (coupled stability with an environment),
[`indices`][seapass.analysis.indices] (the passivity indices ν and ρ, exact),
[`environment_box`][seapass.analysis.environment_box] (environments within physical
bounds, and the exact proof that none of them destabilizes a design) and
[`witness`][seapass.analysis.witness] with [`witness_search`][seapass.analysis.witness_search]
(a passive environment, within bounds, that destabilizes a design that is not passive).

May import: ``seapass.lazy``, [`seapass.errors`][seapass.errors], [`seapass.files`][seapass.files], [`seapass.exact`][seapass.exact], [`seapass.model`][seapass.model], [`seapass.outcome`][seapass.outcome].
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

_LAZY: dict[str, str] = {
    "PassiveRegion": "boundary",
    "passive_region": "boundary",
    "ExactCondition": "conditions",
    "exact_passivity_condition": "conditions",
    "CoupledResult": "coupled",
    "Environment": "coupled",
    "Stability": "coupled",
    "coupled_stability": "coupled",
    "CoupledSimulation": "coupled_response",
    "simulate_coupled": "coupled_response",
    "HUMAN_LIMB": "environment_box",
    "EnvironmentBounds": "environment_box",
    "FrequencyResponse": "freqresp",
    "stiffness_response": "freqresp",
    "PassivityIndices": "indices",
    "passivity_indices": "indices",
    "PassivityResult": "passivity",
    "is_passive": "passivity",
    "PassiveIntervals": "region",
    "PassiveMap": "region",
    "passive_intervals": "region",
    "passive_map": "region",
    "WitnessResult": "witness",
    "find_destabilizing_environment": "witness",
}
"""Public name -> the module that defines it (loaded on first use, so importing a
module of this package does not import every other one)."""

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


__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())


if TYPE_CHECKING:  # what type checkers and IDEs see
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
