"""The model: safe expressions, the immutable SEA, its stiffness, its realization, the catalog.

What lives here: :mod:`~seapass.model.expr` (the safe parser and value
checks), :mod:`~seapass.model.sea` (:class:`SEA`, :class:`Impedance`),
:mod:`~seapass.model.stiffness` (the rendered stiffness ``F_L/X_L`` derived
from first principles), :mod:`~seapass.model.realization` (the closed loop as
a state-space system), :mod:`~seapass.model.catalog` (the one catalog of named
designs: LP, APD, Ours and every Table I/II row) and
:mod:`~seapass.model.design_file` (a user's design as a strict TOML file).

May import: :mod:`seapass.errors`, :mod:`seapass.files`, :mod:`seapass.exact`.
"""

from .catalog import CATALOG, PAPER_VALUES, REFERENCE_VALUES, CatalogDesign, design
from .design_file import Design, load_design
from .realization import ClosedLoop, closed_loop
from .sea import SEA, Impedance
from .stiffness import derive_stiffness, load_impedance, paper_eq4_stiffness, passivity_polynomial

__all__ = [
    "CATALOG",
    "PAPER_VALUES",
    "REFERENCE_VALUES",
    "SEA",
    "CatalogDesign",
    "ClosedLoop",
    "Design",
    "Impedance",
    "closed_loop",
    "derive_stiffness",
    "design",
    "load_design",
    "load_impedance",
    "paper_eq4_stiffness",
    "passivity_polynomial",
]
