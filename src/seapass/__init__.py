"""seapass: design series elastic actuators that are both passive (safe) and accurate.

The public surface is re-exported here explicitly; everything else is internal.
"""

from .conditions import ExactCondition, exact_passivity_condition
from .errors import (
    DegenerateModelError,
    ExpressionError,
    FileFormatError,
    ModelError,
    NotPassiveError,
    ParameterError,
    SeapassError,
    SimulationError,
    SymbolicLimitError,
    UnrealizableError,
)
from .freqresp import FrequencyResponse, stiffness_response
from .model import SEA, Impedance
from .passivity import PassivityResult, is_passive
from .region import PassiveIntervals, PassiveMap, passive_intervals, passive_map
from .stiffness import derive_stiffness, load_impedance, paper_eq4_stiffness, passivity_polynomial
from .tables import build_tables

__version__ = "0.1.0"

__all__ = [
    "SEA",
    "DegenerateModelError",
    "ExactCondition",
    "ExpressionError",
    "FileFormatError",
    "FrequencyResponse",
    "Impedance",
    "ModelError",
    "NotPassiveError",
    "ParameterError",
    "PassiveIntervals",
    "PassiveMap",
    "PassivityResult",
    "SeapassError",
    "SimulationError",
    "SymbolicLimitError",
    "UnrealizableError",
    "__version__",
    "build_tables",
    "derive_stiffness",
    "exact_passivity_condition",
    "is_passive",
    "load_impedance",
    "paper_eq4_stiffness",
    "passive_intervals",
    "passive_map",
    "passivity_polynomial",
    "stiffness_response",
]
