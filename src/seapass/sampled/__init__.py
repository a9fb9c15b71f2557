"""Sampled-data control: discrete controllers, certified sampled passivity, the runtime.

What lives here: [`controllers`][seapass.sampled.controllers] (exact discretization and
the deployable difference equations, with [`emulation`][seapass.sampled.emulation] for
numeric controllers); the certified sampled-data passivity analysis:
[`plant`][seapass.sampled.plant] (exact plant rationals), [`alias`][seapass.sampled.alias]
(alias sums as arb balls), [`power`][seapass.sampled.power] (the weighted power polynomial),
[`certified`][seapass.sampled.certified] (sign and stability decisions on ball polynomials),
[`verdict`][seapass.sampled.verdict] (one certified decision),
[`lowfreq`][seapass.sampled.lowfreq] (the closed-form low-frequency condition),
[`passivity`][seapass.sampled.passivity] (the public verdict),
[`family`][seapass.sampled.family] and [`boxes`][seapass.sampled.boxes] (controllers as
functions of one parameter, branch and bound), [`bound`][seapass.sampled.bound] (certified
passive sets of one parameter), [`region`][seapass.sampled.region] (Z-width maps);
[`coupling`][seapass.sampled.coupling] (the digital loop coupled to passive environments,
a simulation check), [`plantloop`][seapass.sampled.plantloop] (the sampled loop in state
space, any rational plant), [`response`][seapass.sampled.response] (the sampled loop's time
response, for controllers given in z) and [`runtime`][seapass.sampled.runtime] (a fixed-rate control loop
with safety, for hardware or the twin).

May import: ``seapass.lazy``, [`seapass.errors`][seapass.errors], [`seapass.progress`][seapass.progress], ``seapass.outcome``, [`seapass.files`][seapass.files],
[`seapass.exact`][seapass.exact], [`seapass.model`][seapass.model], [`seapass.analysis`][seapass.analysis],
[`seapass.sim`][seapass.sim] (its scenarios, results and tracking metrics).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

_LAZY: dict[str, str] = {
    "SampledBoundResult": "bound",
    "sampled_passive_bound": "bound",
    "APDController": "controllers",
    "DiscreteController": "controllers",
    "DiscreteTF": "controllers",
    "LPController": "controllers",
    "OursController": "controllers",
    "discretize": "controllers",
    "SampledPassivityResult": "passivity",
    "SampledReason": "passivity",
    "SampledStatus": "passivity",
    "sampled_passivity": "passivity",
    "SampledResponse": "response",
    "sampled_response": "response",
    "ZWidthMap": "region",
    "sampled_region": "region",
    "ControlLoop": "runtime",
    "HardwareInterface": "runtime",
    "SimulatedHardware": "runtime",
}
"""Public name -> the module that defines it (loaded on first use, so importing a
module of this package does not import every other one)."""

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
    "SampledReason",
    "SampledResponse",
    "SampledStatus",
    "SimulatedHardware",
    "ZWidthMap",
    "discretize",
    "sampled_passive_bound",
    "sampled_passivity",
    "sampled_region",
    "sampled_response",
]


__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())


if TYPE_CHECKING:  # what type checkers and IDEs see
    from .bound import SampledBoundResult, sampled_passive_bound
    from .controllers import (
        APDController,
        DiscreteController,
        DiscreteTF,
        LPController,
        OursController,
        discretize,
    )
    from .passivity import (
        SampledPassivityResult,
        SampledReason,
        SampledStatus,
        sampled_passivity,
    )
    from .region import ZWidthMap, sampled_region
    from .response import SampledResponse, sampled_response
    from .runtime import ControlLoop, HardwareInterface, SimulatedHardware
