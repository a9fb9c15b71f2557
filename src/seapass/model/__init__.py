"""The model: safe expressions, the immutable SEA, its stiffness, its realization, the catalog.

What lives here: [`expr`][seapass.model.expr] (the safe parser: a checked tree
folded by one dispatch table), [`values`][seapass.model.values] (value and name
checks), [`rational`][seapass.model.rational] (exact rational functions of ``s`` and
the parameters, on flint, within a size budget), [`symbolic`][seapass.model.symbolic]
(the sympy side of the parser), [`budget`][seapass.model.budget] (size bounds and a
time limit for the symbolic work), [`elements`][seapass.model.elements] (elements as
given, their exact and sympy forms), [`sea`][seapass.model.sea] (`SEA`, `Impedance`),
[`freebody`][seapass.model.freebody] (``Z_L`` solved exactly from the free-body
equations, without sympy), [`stiffness`][seapass.model.stiffness] (the rendered
stiffness ``F_L/X_L`` derived in sympy, for people and the symbolic analyses), [`realization`][seapass.model.realization] (the closed loop as
a state-space system), [`catalog`][seapass.model.catalog] (the one catalog of named
designs: LP, APD, Ours and every Table I/II row), [`experiment`][seapass.model.experiment]
(the paper's step-response experiment: step, horizon, load masses), [`loop`][seapass.model.loop]
(`SampledLoop`, the digital controller's period, delay, velocity filter and discretization)
and [`design_file`][seapass.model.design_file] (a user's design as a strict TOML file).

May import: [`seapass.errors`][seapass.errors], [`seapass.files`][seapass.files].
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

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
    "SEA": "sea",
    "Impedance": "sea",
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
    "REFERENCE_VALUES",
    "SEA",
    "CatalogDesign",
    "ClosedLoop",
    "Design",
    "Experiment",
    "Impedance",
    "SampledLoop",
    "closed_loop",
    "derive_stiffness",
    "design",
    "load_design",
    "load_impedance",
    "paper_eq4_stiffness",
    "passivity_polynomial",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})


if TYPE_CHECKING:  # what type checkers and IDEs see
    from .catalog import CATALOG, PAPER_VALUES, REFERENCE_VALUES, CatalogDesign, design
    from .design_file import Design, load_design
    from .experiment import PAPER_EXPERIMENT, Experiment
    from .loop import SampledLoop
    from .realization import ClosedLoop, closed_loop
    from .sea import SEA, Impedance
    from .stiffness import (
        derive_stiffness,
        load_impedance,
        paper_eq4_stiffness,
        passivity_polynomial,
    )
