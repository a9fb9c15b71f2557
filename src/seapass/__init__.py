"""seapass: design series elastic actuators that are both passive (safe) and accurate.

The public surface is re-exported here explicitly; everything else is internal.
"""

from .analyze import analyze
from .batch import BatchPassivity, batch_is_passive, compile_passivity
from .batchsim import BatchMetrics, batch_step_metrics
from .conditions import ExactCondition, exact_passivity_condition
from .controllers import APDController, DiscreteController, LPController, OursController, discretize
from .coupled import (
    CoupledResult,
    CoupledSimulation,
    Environment,
    coupled_stability,
    simulate_coupled,
)
from .design import Design, load_design
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
from .experiment import (
    ExperimentResult,
    ImpactResult,
    SweepResult,
    run_experiment,
    run_impacts,
)
from .experiment import run_sweep as run_rig_sweep
from .freqresp import FrequencyResponse, stiffness_response
from .metrics import TrackingMetrics, settling_time, tracking_metrics
from .model import SEA, Impedance
from .passivity import PassivityResult, is_passive
from .region import PassiveIntervals, PassiveMap, passive_intervals, passive_map
from .report import Report, write_report
from .reproduce import reproduce
from .rig import Rig, load_rig, paper_rig
from .runtime import ControlLoop, HardwareInterface, SimulatedHardware
from .sampled import (
    SampledBoundResult,
    SampledPassivityResult,
    sampled_passive_bound,
    sampled_passivity,
)
from .simstudy import SimulationStudy, run_simulation_study
from .simulate import (
    ClosedLoop,
    ForceImpulse,
    ForceStep,
    LoadDisplaced,
    SimulationResult,
    Step,
    Trajectory,
    closed_loop,
    simulate,
)
from .stiffness import derive_stiffness, load_impedance, paper_eq4_stiffness, passivity_polynomial
from .sweep import SweepSpec
from .sweep import run_sweep as run_design_sweep
from .tables import build_tables
from .tuning import TuningOptions, TuningResult, tune
from .twin import TwinPlant, simulate_loop
from .witness import WitnessResult, find_destabilizing_environment

__version__ = "0.1.0"

__all__ = [
    "SEA",
    "APDController",
    "BatchMetrics",
    "BatchPassivity",
    "ClosedLoop",
    "ControlLoop",
    "CoupledResult",
    "CoupledSimulation",
    "DegenerateModelError",
    "Design",
    "DiscreteController",
    "Environment",
    "ExactCondition",
    "ExperimentResult",
    "ExpressionError",
    "FileFormatError",
    "ForceImpulse",
    "ForceStep",
    "FrequencyResponse",
    "HardwareInterface",
    "ImpactResult",
    "Impedance",
    "LPController",
    "LoadDisplaced",
    "ModelError",
    "NotPassiveError",
    "OursController",
    "ParameterError",
    "PassiveIntervals",
    "PassiveMap",
    "PassivityResult",
    "Report",
    "Rig",
    "SampledBoundResult",
    "SampledPassivityResult",
    "SeapassError",
    "SimulatedHardware",
    "SimulationError",
    "SimulationResult",
    "SimulationStudy",
    "Step",
    "SweepResult",
    "SweepSpec",
    "SymbolicLimitError",
    "TrackingMetrics",
    "Trajectory",
    "TuningOptions",
    "TuningResult",
    "TwinPlant",
    "UnrealizableError",
    "WitnessResult",
    "__version__",
    "analyze",
    "batch_is_passive",
    "batch_step_metrics",
    "build_tables",
    "closed_loop",
    "compile_passivity",
    "coupled_stability",
    "derive_stiffness",
    "discretize",
    "exact_passivity_condition",
    "find_destabilizing_environment",
    "is_passive",
    "load_design",
    "load_impedance",
    "load_rig",
    "paper_eq4_stiffness",
    "paper_rig",
    "passive_intervals",
    "passive_map",
    "passivity_polynomial",
    "reproduce",
    "run_design_sweep",
    "run_experiment",
    "run_impacts",
    "run_rig_sweep",
    "run_simulation_study",
    "sampled_passive_bound",
    "sampled_passivity",
    "settling_time",
    "simulate",
    "simulate_coupled",
    "simulate_loop",
    "stiffness_response",
    "tracking_metrics",
    "tune",
    "write_report",
]
