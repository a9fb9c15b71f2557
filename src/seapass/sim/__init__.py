"""Time-domain simulation, tracking metrics and passivity-constrained tuning.

What lives here: :mod:`~seapass.sim.scenarios` (what drives the loop: steps,
displaced loads, forces, trajectories), :mod:`~seapass.sim.simulate` (exact
matrix-exponential simulation with a load mass), :mod:`~seapass.sim.metrics`
(the one settling definition and the :class:`Settling` status enum) and
:mod:`~seapass.sim.tuning` (the fastest passive gains).

May import: :mod:`seapass.errors`, :mod:`seapass.exact`, :mod:`seapass.model`,
:mod:`seapass.analysis`.
"""

from .metrics import Settling, TrackingMetrics, settling_time, tracking_metrics
from .scenarios import ForceImpulse, ForceStep, LoadDisplaced, Step, Trajectory
from .simulate import SimulationResult, Stability, simulate
from .tuning import TuningOptions, TuningResult, tune

__all__ = [
    "ForceImpulse",
    "ForceStep",
    "LoadDisplaced",
    "Settling",
    "SimulationResult",
    "Stability",
    "Step",
    "TrackingMetrics",
    "Trajectory",
    "TuningOptions",
    "TuningResult",
    "settling_time",
    "simulate",
    "tracking_metrics",
    "tune",
]
