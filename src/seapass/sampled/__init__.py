"""Sampled-data control: discrete controllers, sampled passivity, the fixed-rate runtime.

What lives here: [`controllers`][seapass.sampled.controllers] (exact discretization and
the deployable difference equations), [`passivity`][seapass.sampled.passivity]
(passivity of the continuous port under the digital controller, and passive
bounds), [`coupling`][seapass.sampled.coupling] (the digital loop coupled to passive
environments, a simulation check) and [`runtime`][seapass.sampled.runtime] (a
fixed-rate control loop with safety, for hardware or the twin).

May import: [`seapass.errors`][seapass.errors], [`seapass.exact`][seapass.exact], [`seapass.model`][seapass.model],
[`seapass.analysis`][seapass.analysis], [`seapass.sim`][seapass.sim], [`seapass.batch`][seapass.batch].
"""

from .bound import SampledBoundResult, sampled_passive_bound
from .controllers import (
    APDController,
    DiscreteController,
    DiscreteTF,
    LPController,
    OursController,
    discretize,
)
from .passivity import SampledPassivityResult, sampled_passivity
from .runtime import ControlLoop, HardwareInterface, SimulatedHardware

__all__ = [
    "APDController",
    "ControlLoop",
    "DiscreteController",
    "DiscreteTF",
    "HardwareInterface",
    "LPController",
    "OursController",
    "SampledBoundResult",
    "SampledPassivityResult",
    "SimulatedHardware",
    "discretize",
    "sampled_passive_bound",
    "sampled_passivity",
]
