"""Time-domain simulation and tracking metrics.

What lives here: [`scenarios`][seapass.sim.scenarios] (what drives the loop: steps,
displaced loads, forces, trajectories), [`simulate`][seapass.sim.simulate] (exact
matrix-exponential simulation with a load mass), [`delayed`][seapass.sim.delayed] (the
loop with its controller output delayed: a loop latency, method of steps), [`metrics`][seapass.sim.metrics]
(the one settling definition and the `Settling` status enum), [`summary`][seapass.sim.summary]
(one simulation with its metrics and the design's passivity: ``seapass simulate``).  Tuning lives in
[`seapass.tuning`][seapass.tuning] (it also needs the sampled-data analysis).

May import: [`seapass.errors`][seapass.errors], [`seapass.files`][seapass.files], [`seapass.model`][seapass.model],
[`seapass.analysis`][seapass.analysis], [`seapass.delay`][seapass.delay] (the certified
verdict at a delay, in `summary`), [`seapass.outcome`][seapass.outcome].
"""

from .delayed import DelayedSimulationResult, simulate_delayed
from .metrics import Settling, TrackingMetrics, settling_time, tracking_metrics
from .scenarios import ForceImpulse, ForceStep, LoadDisplaced, Step, Trajectory, read_trajectory
from .simulate import SimulationResult, Stability, simulate
from .summary import SimulationSummary, simulation_summary

__all__ = [
    "DelayedSimulationResult",
    "ForceImpulse",
    "ForceStep",
    "LoadDisplaced",
    "Settling",
    "SimulationResult",
    "SimulationSummary",
    "Stability",
    "Step",
    "TrackingMetrics",
    "Trajectory",
    "read_trajectory",
    "settling_time",
    "simulate",
    "simulate_delayed",
    "simulation_summary",
    "tracking_metrics",
]
