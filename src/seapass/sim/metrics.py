"""Tracking metrics of a simulated response: settling time, final error, overshoot, force, energy.

The settling time is the first time after which ``|x_L − θ|`` stays within
``tolerance`` (2 %) of the motion size until the end of the horizon.  It is
computed on the exact LTI solution, not only on the samples:

1. the last grid interval on which ``|e| = |x_L − θ|`` leaves the band is
   found, where an excursion *between* samples is detected from the exact
   velocity (``d|e|/dt`` changes sign inside the interval) and located by
   root finding on ``v_L``;
2. the crossing back into the band is refined by Brent's method on the exact
   solution ``x(t) = e^{A (t − t_k)} x_k + …`` between the samples.

Refining the time step therefore changes the settling time only by rounding.

References
----------
.. [1] K. Ogata, *Modern Control Engineering*, 5th ed., sec. 5-3 (transient
   response specifications, 2 % criterion).
.. [2] R. P. Brent, *Algorithms for Minimization without Derivatives*, 1973, ch. 4.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from enum import StrEnum
from typing import Any

import numpy as np
from scipy.optimize import brentq

from ..errors import ParameterError, SimulationError
from .simulate import SimulationResult, Stability

__all__ = ["SETTLING_CODES", "Settling", "TrackingMetrics", "settling_time", "tracking_metrics"]


class Settling(StrEnum):
    """How a response ended: one vocabulary for simulations, batches and the rig twin.

    The values are the words written to reports and data files.  Batch
    results store `code` (an index into `SETTLING_CODES`) in
    ``int8`` arrays.
    """

    SETTLED = "settled"
    """Within the band around the target for good, inside the horizon (or cap)."""
    NOT_SETTLED = "did not settle"
    """Stable, but still outside the band at the end of the horizon."""
    UNSTABLE = "unstable"
    """Diverging (or a sustained oscillation on the rig)."""
    INVALID = "invalid"
    """No response: the design could not be simulated (batches only)."""
    SLOW = "slow"
    """Rig: converged, but later than the settling cap."""
    STUCK = "stuck"
    """Rig: never left the band around its start (dry friction held it)."""
    OSCILLATING = "oscillating"
    """Rig: bounded, not converged."""

    @property
    def code(self) -> int:
        """Index of this status in `SETTLING_CODES`."""
        return SETTLING_CODES.index(self)


SETTLING_CODES: tuple[Settling, ...] = tuple(Settling)
"""Every `Settling` status, by code (batch ``status`` arrays hold these indices)."""


@dataclass(frozen=True, kw_only=True)
class TrackingMetrics:
    """Tracking metrics of one run.

    Attributes
    ----------
    status : Settling
        ``SETTLED``, ``NOT_SETTLED`` (within the horizon) or ``UNSTABLE``.
    settling_time : float or None
        Seconds; None unless ``status == "settled"``.
    final_error : float
        ``|x_L − θ|`` at the end of the horizon (m); ``inf`` when unstable.
    overshoot : float or None
        Largest excursion beyond the target in the direction of motion, as a
        fraction of the motion size; None for scenarios without a step.
    peak_force : float
        ``max |f_A|`` over the samples (N).
    energy, positive_work : float
        ``∫ f_A ẋ_A dt`` and ``∫ max(f_A ẋ_A, 0) dt`` (J).
    band : float
        Half-width of the settling band (m).
    target : float
        Settling target (m).
    """

    status: Settling
    settling_time: float | None
    final_error: float
    overshoot: float | None
    peak_force: float
    energy: float
    positive_work: float
    band: float
    target: float

    def __post_init__(self) -> None:
        allowed = (Settling.SETTLED, Settling.NOT_SETTLED, Settling.UNSTABLE)
        if self.status not in allowed:
            raise ParameterError(f"unknown status {self.status!r}")
        object.__setattr__(self, "status", Settling(self.status))
        if (self.settling_time is None) == (self.status == Settling.SETTLED):
            raise ParameterError("settling_time must be given exactly when status is 'settled'")

    @property
    def settled(self) -> bool:
        return self.status == Settling.SETTLED

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def _error(result: SimulationResult, t: float) -> float:
    return result.output_at("x_L", t) - result.target


def settling_time(result: SimulationResult, *, tolerance: float = 0.02) -> float | None:
    """Settling time of ``result`` in seconds, or None if it does not settle in the horizon.

    Parameters
    ----------
    result : SimulationResult
    tolerance : float
        Band half-width as a fraction of ``result.scale`` (default 2 %).

    Returns
    -------
    float or None
        None when the last sample is outside the band, the run is unstable, or
        the motion size is zero.
    """
    if not (0 < tolerance < 1):
        raise ParameterError(f"tolerance must be in (0, 1), got {tolerance}")
    if result.status == Stability.UNSTABLE or result.scale <= 0:
        return None
    band = tolerance * result.scale
    t = result.time
    e = result.x_L - result.target
    v = result.v_L
    ae = np.abs(e)
    if ae[-1] > band:
        return None
    if t.size < 2:
        return 0.0
    outside = ae > band
    last_out = int(np.flatnonzero(outside)[-1]) if outside.any() else -1
    # Interior maxima of |e|: d|e|/dt = sign(e) v goes from >0 to <0 inside an interval.
    # |e| there is at most max|e_end| + h max|v_end| (plus curvature), so test only near-band ones.
    s = np.sign(e) * v
    h = np.diff(t)
    rising = (s[:-1] > 0) & (s[1:] < 0) & (np.sign(e[:-1]) == np.sign(e[1:]))
    reach = np.maximum(ae[:-1], ae[1:]) + 2 * h * np.maximum(np.abs(v[:-1]), np.abs(v[1:]))
    suspects = np.flatnonzero(rising & (reach > band))
    suspects = suspects[suspects > last_out - 1]
    start: tuple[int, float] | None = None  # (interval index, a time outside the band)
    for j in suspects[::-1]:
        tj, tk = float(t[j]), float(t[j + 1])
        try:
            tp = brentq(lambda x: result.output_at("v_L", x), tj, tk, xtol=1e-13, rtol=1e-13)
        except ValueError:
            continue
        if abs(_error(result, tp)) > band:
            start = (int(j), tp)
            break
    if start is None:
        if last_out < 0:
            return 0.0
        start = (last_out, float(t[last_out]))
    j, tp = start
    tk = float(t[j + 1])

    def g(x: float) -> float:
        return abs(_error(result, x)) - band

    if g(tk) > 0:  # t_k is inside on the samples; only rounding can put it outside
        return tk
    return float(brentq(g, tp, tk, xtol=1e-13, rtol=1e-13))


def tracking_metrics(
    result: SimulationResult, *, tolerance: float = 0.02, throw: bool = False
) -> TrackingMetrics:
    """All tracking metrics of ``result``.

    Parameters
    ----------
    result : SimulationResult
    tolerance : float
        Settling band as a fraction of the motion size (2 % by default).
    throw : bool
        Raise [`SimulationError`][seapass.errors.SimulationError] for an unstable run
        instead of returning ``status="unstable"``.

    Returns
    -------
    TrackingMetrics
    """
    band = tolerance * result.scale
    peak = float(np.max(np.abs(result.f_A), initial=0.0))
    if result.status == Stability.UNSTABLE:
        if throw:
            raise SimulationError("the closed loop is unstable")
        return TrackingMetrics(
            status=Settling.UNSTABLE,
            settling_time=None,
            final_error=math.inf,
            overshoot=None,
            peak_force=peak,
            energy=result.energy,
            positive_work=result.positive_work,
            band=band,
            target=result.target,
        )
    ts = settling_time(result, tolerance=tolerance)
    e = result.x_L - result.target
    overshoot: float | None = None
    if result.has_step and result.scale > 0:
        direction = math.copysign(1.0, result.target - float(result.x_L[0]))
        overshoot = max(0.0, float(np.max(e * direction))) / result.scale
    return TrackingMetrics(
        status=Settling.SETTLED if ts is not None else Settling.NOT_SETTLED,
        settling_time=ts,
        final_error=float(abs(e[-1])),
        overshoot=overshoot,
        peak_force=peak,
        energy=result.energy,
        positive_work=result.positive_work,
        band=band,
        target=result.target,
    )
