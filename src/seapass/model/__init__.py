"""The model: safe expressions, the immutable SEA, its stiffness, its realization, the catalog.

What lives here: [`expr`][seapass.model.expr] (the safe parser and value
checks), [`budget`][seapass.model.budget] (size bounds and a time limit for the
symbolic work), [`sea`][seapass.model.sea] (`SEA`, `Impedance`),
[`stiffness`][seapass.model.stiffness] (the rendered stiffness ``F_L/X_L`` derived
from first principles), [`realization`][seapass.model.realization] (the closed loop as
a state-space system), [`controller`][seapass.model.controller] (SEA controller blocks
solved from their block diagram into ``C_A``, ``C_L``), [`minimal`][seapass.model.minimal]
(the controller ``K(s) = [C_A  C_L]`` realized once and minimally), [`catalog`][seapass.model.catalog] (the one catalog of named
designs: LP, APD, Ours and every Table I/II row), [`experiment`][seapass.model.experiment]
(the paper's step-response experiment: step, horizon, load masses), [`loop`][seapass.model.loop]
(`SampledLoop`, the digital controller's period, delay, velocity filter and discretization)
and [`design_file`][seapass.model.design_file] (a user's design as a strict TOML file).

May import: [`seapass.errors`][seapass.errors], [`seapass.files`][seapass.files].
"""

from .catalog import CATALOG, PAPER_VALUES, REFERENCE_VALUES, CatalogDesign, design
from .controller import Controller, ControllerKind, derive_controller
from .design_file import Design, load_design
from .experiment import PAPER_EXPERIMENT, Experiment
from .loop import SampledLoop
from .realization import ClosedLoop, closed_loop
from .sea import PLANT_SYMBOLS, SEA, Impedance
from .stiffness import derive_stiffness, load_impedance, paper_eq4_stiffness, passivity_polynomial

__all__ = [
    "CATALOG",
    "PAPER_EXPERIMENT",
    "PAPER_VALUES",
    "PLANT_SYMBOLS",
    "REFERENCE_VALUES",
    "SEA",
    "CatalogDesign",
    "ClosedLoop",
    "Controller",
    "ControllerKind",
    "Design",
    "Experiment",
    "Impedance",
    "SampledLoop",
    "closed_loop",
    "derive_controller",
    "derive_stiffness",
    "design",
    "load_design",
    "load_impedance",
    "paper_eq4_stiffness",
    "passivity_polynomial",
]
