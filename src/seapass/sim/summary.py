"""One simulation with its tracking metrics and the design's passivity: ``seapass simulate``.

`simulation_summary` is the one call behind the command: it simulates the
design with a load mass ([`simulate`][seapass.sim.simulate.simulate]; a design whose
controller output is delayed, by ``exp(-tau*s)`` on its controllers or a loop latency,
by [`simulate_delayed`][seapass.sim.delayed.simulate_delayed]), measures
the response ([`tracking_metrics`][seapass.sim.metrics.tracking_metrics]) and
decides passivity exactly ([`is_passive`][seapass.analysis.passivity.is_passive];
certified at the delay by [`delayed_passivity`][seapass.delay.passivity.delayed_passivity]),
which is informative here: a model the passivity test cannot take still has
its simulation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ..analysis.passivity import is_passive
from ..delay.passivity import delayed_passivity
from ..errors import SeapassError
from ..model.display import html_card, short_repr
from ..model.sea import SEA
from ..outcome import Outcome
from .delayed import controller_latency, simulate_delayed
from .metrics import TrackingMetrics, tracking_metrics
from .scenarios import Scenario
from .simulate import SimulationResult

__all__ = ["SimulationSummary", "simulation_summary"]


@dataclass(frozen=True, kw_only=True, repr=False)
class SimulationSummary:
    """A simulated response, its metrics and the design's passivity (`simulation_summary`).

    Attributes
    ----------
    result : SimulationResult
    metrics : TrackingMetrics
    passive : bool or None
        The exact verdict; None when the passivity test could not be run.
    passive_error : str or None
        Why it could not (one line).
    load_mass, horizon, dt : float
        Load mass (kg), simulated time (s) and the time step of the grid (s).
    delay_time : float
        The loop latency [s] the controller output was delayed by (0: none).
    """

    result: SimulationResult
    metrics: TrackingMetrics
    passive: bool | None
    passive_error: str | None = None
    load_mass: float
    horizon: float
    dt: float
    delay_time: float = 0.0

    def to_dict(self) -> dict[str, Any]:
        """The metrics, the verdict, the closed loop and the run (``simulate --json``)."""
        met, res = self.metrics, self.result
        out: dict[str, Any] = {
            "settling_time": met.settling_time,
            "final_error": met.final_error,
            "overshoot": met.overshoot,
            "status": met.status,
            "passive": self.passive,
        }
        if self.passive_error is not None:
            out["passive_error"] = self.passive_error
        return {
            **out,
            "stable": res.stable,
            "marginal": res.marginal,
            "diverged": res.diverged,
            "peak_force": met.peak_force,
            "energy": met.energy,
            "positive_work": met.positive_work,
            "band": met.band,
            "target": met.target,
            "load_mass": self.load_mass,
            "horizon": self.horizon,
            "dt": self.dt,
            **({"delay_time": self.delay_time} if self.delay_time else {}),
            "scenario": type(res.scenario).__name__,
            "poles": [[float(p.real), float(p.imag)] for p in res.poles],
        }

    def plot(self, *, axes: Any = None, **kwargs: Any) -> Any:
        """Positions and actuator force with the settling band; two Axes."""
        from ..plot.sim import plot_simulation

        return plot_simulation(self.result, self.metrics, axes=axes, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "SimulationSummary",
            {
                "status": str(self.metrics.status),
                "settling_time": self.metrics.settling_time,
                "passive": self.passive,
                "load_mass": self.load_mass,
            },
        )

    def _repr_html_(self) -> str:
        ts = self.metrics.settling_time
        verdict = {True: "passive", False: "not passive", None: "not decided"}[self.passive]
        return html_card(
            f"Simulation: {self.metrics.status}",
            [
                ("settling time", "-" if ts is None else f"{ts:.6g} s"),
                ("final error", f"{self.metrics.final_error:.3e} m"),
                ("peak actuator force", f"{self.metrics.peak_force:.6g} N"),
                ("closed loop", str(self.result.status)),
                ("passivity", verdict if self.passive_error is None else self.passive_error),
            ],
        )


def simulation_summary(
    sea: SEA,
    *,
    load_mass: float,
    scenario: Scenario | None = None,
    horizon: float | None = None,
    dt: float = 1e-3,
    tolerance: float = 0.02,
) -> SimulationSummary:
    """Simulate ``sea`` with a load mass, measure the response and decide passivity.

    Parameters
    ----------
    sea, load_mass, scenario, horizon, dt
        As for [`simulate`][seapass.sim.simulate.simulate] (default scenario: a
        0.5 m reference step).  A delay ``exp(-NAME*s)`` on the controllers is simulated
        ([`simulate_delayed`][seapass.sim.delayed.simulate_delayed]; ``dt`` is then the
        largest step) and passivity is certified at it.
    tolerance : float
        Settling band, a fraction of the motion.

    Returns
    -------
    SimulationSummary
        An unstable closed loop is a result, never an error; so is a design
        whose passivity cannot be decided (``passive`` None, the reason in
        ``passive_error``).

    Examples
    --------
    >>> sea = SEA(D1="k1 + b1*s", CA="kd + bd*s",
    ...           values=dict(m=1, b=10, k1=1000, b1=20, kd=1000, bd=25))
    >>> s = simulation_summary(sea, load_mass=10, horizon=5)
    >>> s.passive, str(s.result.status), s.to_dict()["scenario"]
    (True, 'stable', 'Step')
    """
    result = simulate_delayed(sea, load_mass=load_mass, scenario=scenario, horizon=horizon, dt=dt)
    metrics = tracking_metrics(result, tolerance=tolerance)
    tau = controller_latency(sea)[1]
    passive: bool | None
    error: str | None = None
    try:
        if tau:
            outcome = delayed_passivity(sea).outcome
            passive = None if outcome is Outcome.UNDECIDED else outcome is Outcome.PASSIVE
            if passive is None:
                error = f"undecided at the delay {tau:g} s (the certified test)"
        else:
            passive = is_passive(sea).passive
    except SeapassError as exc:  # informative here: the simulation stands
        passive, error = None, " ".join(str(exc).split()) or type(exc).__name__
    step = float(result.time[1] - result.time[0]) if result.time.size > 1 else float(dt)
    return SimulationSummary(
        result=result,
        metrics=metrics,
        passive=passive,
        passive_error=error,
        load_mass=float(load_mass),
        horizon=float(result.time[-1]) if result.time.size else math.nan,
        dt=step,
        delay_time=tau,
    )
