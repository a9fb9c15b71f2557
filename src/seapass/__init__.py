"""seapass: design series elastic actuators that are both passive (safe) and accurate.

The public surface is re-exported here explicitly; everything else is internal.
"""

from .report.analyze import analyze
from .batch.verdicts import BatchPassivity, batch_is_passive, compile_passivity
from .batch.step_metrics import BatchMetrics, batch_step_metrics
from .analysis.conditions import ExactCondition, exact_passivity_condition
from .sampled.controllers import APDController, DiscreteController, LPController, OursController, discretize
from .analysis.coupled import (
    CoupledResult,
    CoupledSimulation,
    Environment,
    coupled_stability,
    simulate_coupled,
)
from .model.design_file import Design, load_design
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
from .rig.experiment import (
    ExperimentResult,
    ImpactResult,
    SweepResult,
    run_experiment,
    run_impacts,
)
from .rig.experiment import run_sweep as run_rig_sweep
from .analysis.freqresp import FrequencyResponse, stiffness_response
from .sim.metrics import TrackingMetrics, settling_time, tracking_metrics
from .model.sea import SEA, Impedance
from .analysis.passivity import PassivityResult, is_passive
from .analysis.region import PassiveIntervals, PassiveMap, passive_intervals, passive_map
from .report.document import Report, write_report
from .report.reproduce import reproduce
from .rig.rigfile import Rig, load_rig, paper_rig
from .sampled.runtime import ControlLoop, HardwareInterface, SimulatedHardware
from .sampled.passivity import (
    SampledBoundResult,
    SampledPassivityResult,
    sampled_passive_bound,
    sampled_passivity,
)
from .paper.simstudy import SimulationStudy, run_simulation_study
from .sim.simulate import (
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
from .model.stiffness import derive_stiffness, load_impedance, paper_eq4_stiffness, passivity_polynomial
from .sweep.runner import SweepSpec
from .sweep.runner import run_sweep as run_design_sweep
from .paper.tables import build_tables
from .sim.tuning import TuningOptions, TuningResult, tune
from .rig.twin import TwinPlant, simulate_loop
from .analysis.witness import WitnessResult, find_destabilizing_environment

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
