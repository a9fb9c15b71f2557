"""The model: safe expressions, the immutable SEA, its stiffness, its realization, the catalog.

What lives here: [`expr`][seapass.model.expr] (the safe parser: a checked tree
folded by one dispatch table), [`values`][seapass.model.values] (value and name
checks), [`rational`][seapass.model.rational] (exact rational functions of ``s`` and
the parameters, on flint, within a size budget), [`symbolic`][seapass.model.symbolic]
(the sympy side of the parser), [`budget`][seapass.model.budget] (size bounds and a
time limit for the symbolic work), [`elements`][seapass.model.elements] (elements as
given, their exact and sympy forms), [`sea`][seapass.model.sea] (`SEA`), [`impedance`][seapass.model.impedance] (`Impedance`),
[`freebody`][seapass.model.freebody] (``Z_L`` solved exactly from the free-body
equations, without sympy), [`stiffness`][seapass.model.stiffness] (the rendered
stiffness ``F_L/X_L`` derived in sympy, for people and the symbolic analyses), [`realization`][seapass.model.realization] (the closed loop as
a state-space system), [`controller`][seapass.model.controller] (SEA controller blocks
solved from their block diagram into ``C_A``, ``C_L``), [`minimal`][seapass.model.minimal]
(the controller ``K(s) = [C_A  C_L]`` realized once and minimally), [`catalog`][seapass.model.catalog] (the one catalog of named
designs: LP, APD, Ours and every Table I/II row), [`experiment`][seapass.model.experiment]
(the paper's step-response experiment: step, horizon, load masses), [`loop`][seapass.model.loop]
(`SampledLoop`, the digital controller's period, delay, velocity filter and discretization)
[`design_file`][seapass.model.design_file] (a user's design as a strict TOML file),
[`resolve`][seapass.model.resolve] (a design file merged with the caller's values: what
every command runs) and [`units`][seapass.model.units] (the unit grammar and defaults).

May import: ``seapass.lazy``, [`seapass.errors`][seapass.errors], [`seapass.files`][seapass.files].
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

_LAZY: dict[str, str] = {
    "CATALOG": "catalog",
    "PAPER_VALUES": "catalog",
    "REFERENCE_VALUES": "catalog",
    "CatalogDesign": "catalog",
    "design": "catalog",
    "Design": "design_file",
    "load_design": "design_file",
    "PAPER_EXPERIMENT": "experiment",
    "Experiment": "experiment",
    "SampledLoop": "loop",
    "ClosedLoop": "realization",
    "closed_loop": "realization",
    "Controller": "controller",
    "ControllerKind": "controller",
    "derive_controller": "controller",
    "PLANT_SYMBOLS": "sea",
    "SEA": "sea",
    "Impedance": "impedance",
    "derive_stiffness": "stiffness",
    "load_impedance": "stiffness",
    "paper_eq4_stiffness": "stiffness",
    "passivity_polynomial": "stiffness",
}
"""Public name -> the module that defines it (loaded on first use, so importing a
module of this package does not import every other one)."""

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


__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())


if TYPE_CHECKING:  # what type checkers and IDEs see
    from .catalog import CATALOG, PAPER_VALUES, REFERENCE_VALUES, CatalogDesign, design
    from .controller import Controller, ControllerKind, derive_controller
    from .design_file import Design, load_design
    from .experiment import PAPER_EXPERIMENT, Experiment
    from .impedance import Impedance
    from .loop import SampledLoop
    from .realization import ClosedLoop, closed_loop
    from .sea import PLANT_SYMBOLS, SEA
    from .stiffness import (
        derive_stiffness,
        load_impedance,
        paper_eq4_stiffness,
        passivity_polynomial,
    )
