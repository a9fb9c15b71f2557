"""Time-domain simulation, tracking metrics and passivity-constrained tuning.

What lives here: [`scenarios`][seapass.sim.scenarios] (what drives the loop: steps,
displaced loads, forces, trajectories), [`simulate`][seapass.sim.simulate] (exact
matrix-exponential simulation with a load mass), [`metrics`][seapass.sim.metrics]
(the one settling definition and the `Settling` status enum) and
[`tuning`][seapass.sim.tuning] (the fastest passive gains).

May import: [`seapass.errors`][seapass.errors], [`seapass.exact`][seapass.exact], [`seapass.model`][seapass.model],
[`seapass.analysis`][seapass.analysis].
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
