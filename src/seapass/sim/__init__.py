"""Time-domain simulation and tracking metrics.

What lives here: [`scenarios`][seapass.sim.scenarios] (what drives the loop: steps,
displaced loads, forces, trajectories), [`simulate`][seapass.sim.simulate] (exact
matrix-exponential simulation with a load mass), [`metrics`][seapass.sim.metrics]
(the one settling definition and the `Settling` status enum).  Tuning lives in
[`seapass.tuning`][seapass.tuning] (it also needs the sampled-data analysis).

May import: [`seapass.errors`][seapass.errors], [`seapass.exact`][seapass.exact], [`seapass.model`][seapass.model],
[`seapass.analysis`][seapass.analysis].
"""

from .metrics import Settling, TrackingMetrics, settling_time, tracking_metrics
from .scenarios import ForceImpulse, ForceStep, LoadDisplaced, Step, Trajectory
from .simulate import SimulationResult, Stability, simulate

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
    "settling_time",
    "simulate",
    "tracking_metrics",
]
