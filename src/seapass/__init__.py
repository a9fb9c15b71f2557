"""seapass: design series elastic actuators that are both passive (safe) and accurate.

The top level holds the few names most users need; everything else lives in
one subpackage per concept (see ``docs/architecture.md``):

==================  =====================================================
subpackage          what lives there
==================  =====================================================
``seapass.errors``  every exception and warning (a module)
``seapass.outcome``  the verdict vocabulary ``Outcome`` (a module)
``seapass.progress``  the progress protocol of long jobs (a module)
``seapass.files``   guarded reading, atomic writing, TOML, input limits
``seapass.exact``   the exact polynomial kernel
``seapass.model``   ``SEA``, the safe parser, stiffness, catalog, design files
``seapass.analysis``  exact passivity, conditions, passive sets, witnesses
``seapass.ports``   two-ports and n-ports: absolute stability, passivity
``seapass.delay``   continuous time delay: certified passivity, delay margin
``seapass.sim``     simulation, tracking metrics
``seapass.batch``   vectorized verdicts and step metrics
``seapass.sampled``  discrete controllers, sampled-data passivity, runtime
``seapass.robust``  robust passivity for every plant in a box of parameters
``seapass.tuning``  passivity-constrained tuning of any design
``seapass.rig``     rig files, the digital twin, the paper's experiment
``seapass.export``  C code of the deployed controller, envelope built in
``seapass.sweep``   resumable design-space sweeps (local or Dask)
``seapass.paper``   Tables I and II, the simulation study
``seapass.plot``    every figure
``seapass.report``  ``reproduce`` and ``analyze`` reports
``seapass.explore``  the interactive explorer in the browser
``seapass.cli``     the ``seapass`` command
==================  =====================================================

Names are loaded on first use, so ``import seapass`` is fast.

Examples
--------
>>> import seapass as sp
>>> sea = sp.SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))
>>> sp.is_passive(sea).passive
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .errors import SeapassError
from .lazy import lazy_exports
from .version import __version__

# name -> module that defines it
_LAZY: dict[str, str] = {
    "SEA": "model.sea",
    "Impedance": "model.impedance",
    "Design": "model.design_file",
    "Controller": "model.controller",
    "derive_controller": "model.controller",
    "SampledLoop": "model.loop",
    "load_design": "model.design_file",
    "derive_stiffness": "model.stiffness",
    "is_passive": "robust.api",
    "delay_margin": "delay.margin",
    "PassivityResult": "analysis.passivity",
    "passivity_indices": "analysis.indices",
    "passive_intervals": "robust.api",
    "passive_map": "analysis.region",
    "exact_passivity_condition": "analysis.conditions",
    "stiffness_response": "analysis.freqresp",
    "find_destabilizing_environment": "analysis.witness",
    "two_port": "ports.twoport",
    "TwoPort": "ports.twoport",
    "absolute_stability": "ports.stability",
    "two_port_passivity": "ports.check",
    "mimo_is_passive": "ports.mimo",
    "simulate": "sim.simulate",
    "Step": "sim.scenarios",
    "tracking_metrics": "sim.metrics",
    "tune": "tuning.optimize",
    "TuningOptions": "tuning.problem",
    "sampled_passivity": "sampled.passivity",
    "sampled_passive_bound": "sampled.bound",
    "load_rig": "rig.rigfile",
    "paper_rig": "rig.rigfile",
    "export_c": "export.c_code",
    "analyze": "report.analyze",
    "reproduce": "report.reproduce",
    "write_report": "report.output",
}

_SUBPACKAGES = frozenset(
    {"analysis", "batch", "cli", "delay", "errors", "exact", "explore", "export", "files",
     "model", "outcome", "paper", "plot", "ports", "progress", "report", "rig", "robust",
     "sampled", "sim", "sweep", "tuning"}
)  # fmt: skip
"""Every subpackage and top-level module, loaded on first attribute access."""

__all__ = [
    "SEA",
    "Controller",
    "Design",
    "Impedance",
    "PassivityResult",
    "SampledLoop",
    "SeapassError",
    "Step",
    "TuningOptions",
    "TwoPort",
    "__version__",
    "absolute_stability",
    "analyze",
    "delay_margin",
    "derive_controller",
    "derive_stiffness",
    "exact_passivity_condition",
    "export_c",
    "find_destabilizing_environment",
    "is_passive",
    "load_design",
    "load_rig",
    "mimo_is_passive",
    "paper_rig",
    "passive_intervals",
    "passive_map",
    "passivity_indices",
    "reproduce",
    "sampled_passive_bound",
    "sampled_passivity",
    "simulate",
    "stiffness_response",
    "tracking_metrics",
    "tune",
    "two_port",
    "two_port_passivity",
    "write_report",
]


__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals(), submodules=_SUBPACKAGES)


if TYPE_CHECKING:  # what type checkers and IDEs see
    from .analysis.conditions import exact_passivity_condition
    from .analysis.freqresp import stiffness_response
    from .analysis.indices import passivity_indices
    from .analysis.passivity import PassivityResult
    from .analysis.region import passive_map
    from .analysis.witness import find_destabilizing_environment
    from .delay.margin import delay_margin
    from .export.c_code import export_c
    from .model.controller import Controller, derive_controller
    from .model.design_file import Design, load_design
    from .model.impedance import Impedance
    from .model.loop import SampledLoop
    from .model.sea import SEA
    from .model.stiffness import derive_stiffness
    from .ports.check import two_port_passivity
    from .ports.mimo import mimo_is_passive
    from .ports.stability import absolute_stability
    from .ports.twoport import TwoPort, two_port
    from .report.analyze import analyze
    from .report.output import write_report
    from .report.reproduce import reproduce
    from .rig.rigfile import load_rig, paper_rig
    from .robust.api import is_passive, passive_intervals
    from .sampled.bound import sampled_passive_bound
    from .sampled.passivity import sampled_passivity
    from .sim.metrics import tracking_metrics
    from .sim.scenarios import Step
    from .sim.simulate import simulate
    from .tuning.optimize import tune
    from .tuning.problem import TuningOptions
