"""Fixed-rate control loop with safety, for real hardware or the digital twin.

The same `ControlLoop` code drives a physical bench (anything that
implements `HardwareInterface`, timed by `RealTimeClock`) and the
digital twin (`SimulatedHardware` wrapping a
[`TwinPlant`][seapass.rig.plant.TwinPlant], timed by `SimulatedClock`).  Tests
inject a `FakeClock` to create overruns deterministically.

Safety layers, in order:

1. before the loop starts, the design is checked for continuous passivity
   ([`seapass.analysis.passivity.is_passive`][seapass.analysis.passivity.is_passive]) and for sampled-data passivity at the
   loop's own period and delay ([`seapass.sampled.passivity.sampled_passivity`][seapass.sampled.passivity.sampled_passivity], with
   the deployed controller's exact transfer functions); a non-passive design
   raises [`NotPassiveError`][seapass.errors.NotPassiveError] unless
   ``allow_nonpassive=True``;
2. every command is saturated to ``±force_limit``;
3. a non-finite or out-of-range measurement, a failed encoder read (stale
   measurement) or a loop that was not serviced within ``watchdog`` seconds
   triggers a safe stop: command 0, then ``disable()``.

References
----------
.. [1] J. E. Colgate, G. G. Schenkel, "Passivity of a class of sampled-data
   systems: application to haptic interfaces", J. Robotic Systems, 1997.
"""

from __future__ import annotations

import math
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import NotPassiveError, ParameterError
from ..model.loop import SampledLoop, renamed_keywords
from ..model.sea import SEA
from .controllers import DiscreteController

__all__ = [
    "ControlLoop",
    "FakeClock",
    "HardwareInterface",
    "LoopRecord",
    "RealTimeClock",
    "SimulatedClock",
    "SimulatedHardware",
]


@runtime_checkable
class HardwareInterface(Protocol):
    """What the loop needs from a bench (or its twin)."""

    def read_encoders(self) -> tuple[int, int]:
        """Raw ``(motor_counts, linear_counts)``; raise ``TimeoutError`` when stale."""
        ...

    def counts_to_positions(self, motor_counts: int, linear_counts: int) -> tuple[float, float]:
        """``(x_A, x_L)`` in metres."""
        ...

    def write_command(self, force: float) -> None:
        """Actuator force command (N), held until the next write."""
        ...

    def enable(self) -> None: ...

    def disable(self) -> None: ...


class SimulatedHardware:
    """`HardwareInterface` backed by a [`TwinPlant`][seapass.rig.plant.TwinPlant].

    Parameters
    ----------
    plant : TwinPlant
        The twin (already ``reset`` to its initial state).
    delay : int, default 0
        A written command takes effect this many writes later (PC-in-the-loop delay).
        Its old keyword still works for one release, with a warning
        ([`renamed_keywords`][seapass.model.loop.renamed_keywords]).
    external_force : callable, optional
        ``f(t) -> N`` acting on the load (e.g. a push by a person).
    """

    def __init__(
        self,
        plant: Any,
        *,
        delay: int = 0,
        external_force: Callable[[float], float] | None = None,
        **old: Any,
    ) -> None:
        delay = renamed_keywords(old, where="SimulatedHardware").get("delay", delay)
        if delay < 0:
            raise ParameterError(f"delay: must be >= 0, got {delay}", argument="delay")
        self.plant = plant
        self.delay = int(delay)
        self.external_force = external_force
        self.enabled = False
        self._queue: deque[float] = deque([0.0] * (self.delay + 1))
        self.fail_reads = 0  # test hook: the next n reads time out

    @property
    def active_command(self) -> float:
        return self._queue[0] if self.enabled else 0.0

    def read_encoders(self) -> tuple[int, int]:
        if self.fail_reads > 0:
            self.fail_reads -= 1
            raise TimeoutError("encoder read timed out")
        return self.plant.read_encoders()

    def counts_to_positions(self, motor_counts: int, linear_counts: int) -> tuple[float, float]:
        return self.plant.counts_to_positions(motor_counts, linear_counts)

    def write_command(self, force: float) -> None:
        self._queue.append(float(force))
        self._queue.popleft()

    def enable(self) -> None:
        self.enabled = True

    def disable(self) -> None:
        self.enabled = False
        for i in range(len(self._queue)):
            self._queue[i] = 0.0

    def advance(self, dt: float) -> None:
        """Integrate the twin for ``dt`` seconds under the active (held) command."""
        if dt <= 0:
            return
        f_ext = self.external_force(self.plant.time) if self.external_force else 0.0
        self.plant.apply(self.active_command, dt, external_force=f_ext)


class RealTimeClock:
    """Wall clock (``time.perf_counter``); sleeps, then spins for the last ~0.5 ms."""

    def now(self) -> float:
        return time.perf_counter()

    def sleep_until(self, t: float) -> None:
        while True:
            left = t - time.perf_counter()
            if left <= 0:
                return
            if left > 5e-4:
                time.sleep(left - 5e-4)


class FakeClock:
    """Manual clock for tests: time moves only by `advance` or `sleep_until`."""

    def __init__(self, start: float = 0.0) -> None:
        self.t = float(start)

    def now(self) -> float:
        return self.t

    def advance(self, dt: float) -> None:
        self.t += float(dt)

    def sleep_until(self, t: float) -> None:
        self.t = max(self.t, float(t))


class SimulatedClock(FakeClock):
    """Simulated time that advances a `SimulatedHardware` with it."""

    def __init__(self, hardware: SimulatedHardware, start: float = 0.0) -> None:
        super().__init__(start)
        self.hardware = hardware

    def advance(self, dt: float) -> None:
        self.hardware.advance(dt)
        super().advance(dt)

    def sleep_until(self, t: float) -> None:
        if t > self.t:
            self.advance(t - self.t)


@dataclass(frozen=True, kw_only=True)
class LoopRecord:
    """What one run of `ControlLoop.run` did; arrays have one entry per serviced tick.

    Attributes
    ----------
    t : ndarray
        Scheduled tick times (s, clock time minus the start).
    x_A, x_L : ndarray
        Measured positions (m).
    command : ndarray
        Saturated force commands written (N).
    jitter : ndarray
        Start of the tick's work minus its scheduled time (s).
    overrun : ndarray of bool
        The tick's work ended after the next tick was due.
    skipped : int
        Ticks dropped to recover from overruns.
    saturated : int
        Commands clipped at the force limit.
    stop_reason : str
        ``""`` after a full run, else why the loop stopped safely.
    """

    t: np.ndarray
    x_A: np.ndarray
    x_L: np.ndarray
    command: np.ndarray
    jitter: np.ndarray
    overrun: np.ndarray
    skipped: int
    saturated: int
    stop_reason: str

    @property
    def stopped(self) -> bool:
        return bool(self.stop_reason)

    @property
    def overruns(self) -> int:
        return int(np.count_nonzero(self.overrun))

    def summary(self) -> dict[str, Any]:
        j = self.jitter
        return {
            "ticks": len(self.t),
            "overruns": self.overruns,
            "skipped": self.skipped,
            "saturated": self.saturated,
            "jitter_max": float(np.max(np.abs(j))) if j.size else 0.0,
            "jitter_rms": float(np.sqrt(np.mean(j**2))) if j.size else 0.0,
            "stop_reason": self.stop_reason,
        }


class ControlLoop:
    """Fixed-rate loop: read encoders → controller → saturate → write, every ``period``.

    Parameters
    ----------
    hardware : HardwareInterface
    controller : DiscreteController
        Anything with ``step((x_A, x_L), (θ_A, θ_L)) -> float`` and ``reset()``.
    period : float
        Loop period (s).
    clock : RealTimeClock, SimulatedClock or FakeClock, optional
        Default: `SimulatedClock` for `SimulatedHardware`, else real time.
    force_limit : float
        Saturation of the command (N).
    position_limits : (float, float)
        Allowed range of both measured positions (m); outside → safe stop.
    watchdog : float, optional
        Longest allowed time between serviced ticks (s); default ``5·period``.
    design : SEA, optional
        The continuous design (plant values + controllers) to check for passivity
        before starting; ``delay`` and ``velocity_filter`` describe the deployed loop.
    allow_nonpassive : bool, default False
        Run a design that fails either passivity check (explicit override).
    """

    def __init__(
        self,
        hardware: HardwareInterface,
        controller: DiscreteController,
        *,
        period: float,
        clock: Any = None,
        force_limit: float = math.inf,
        position_limits: tuple[float, float] = (-math.inf, math.inf),
        watchdog: float | None = None,
        design: SEA | None = None,
        delay: int = 0,
        allow_nonpassive: bool = False,
    ) -> None:
        if not (period > 0 and math.isfinite(period)):
            raise ParameterError(f"period must be a positive number of seconds, got {period!r}")
        if not force_limit > 0:
            raise ParameterError(f"force_limit must be positive, got {force_limit!r}")
        self.hardware = hardware
        self.controller = controller
        self.period = float(period)
        if clock is None:
            if isinstance(hardware, SimulatedHardware):
                clock = SimulatedClock(hardware)
            else:
                clock = RealTimeClock()
        self.clock = clock
        self.force_limit = float(force_limit)
        self.position_limits = (float(position_limits[0]), float(position_limits[1]))
        self.watchdog = 5 * self.period if watchdog is None else float(watchdog)
        self.passivity: dict[str, Any] = {}
        if design is not None:
            self.passivity = self._check(design, int(delay), allow_nonpassive)

    def _check(self, design: SEA, delay: int, allow: bool) -> dict[str, Any]:
        from ..analysis.passivity import is_passive
        from .passivity import sampled_passivity

        cont = is_passive(design)
        samp = sampled_passivity(
            design, loop=SampledLoop(period=self.period, delay=delay), controller=self.controller
        )
        info = {"continuous": cont.to_dict(), "sampled": samp.to_dict()}
        if not (cont.passive and samp.passive) and not allow:
            which = "continuous-time" if not cont.passive else f"sampled ({1 / self.period:g} Hz)"
            why = cont.detail if not cont.passive else samp.detail
            raise NotPassiveError(
                f"refusing to run: the design is not passive ({which}): {why}; lower the gains "
                "or pass allow_nonpassive=True to override"
            )
        return info

    def _safe_stop(self) -> None:
        try:
            self.hardware.write_command(0.0)
        finally:
            self.hardware.disable()

    def run(
        self,
        duration: float,
        *,
        reference: Callable[[float], tuple[float, float]] | tuple[float, float] = (0.0, 0.0),
    ) -> LoopRecord:
        """Run for ``duration`` seconds of clock time; always ends with a safe stop.

        ``reference`` is ``(θ_A, θ_L)`` or a function of the tick time returning it.
        """
        n_ticks = round(duration / self.period)
        ref = reference if callable(reference) else (lambda _t, r=reference: r)
        rec: dict[str, list[float]] = {k: [] for k in ("t", "xa", "xl", "u", "jit", "ovr")}
        skipped = saturated = 0
        reason = ""
        lo, hi = self.position_limits
        self.controller.reset()
        self.hardware.enable()
        t0 = self.clock.now()
        last_service = t0
        k = 0
        try:
            while k < n_ticks:
                due = t0 + k * self.period
                self.clock.sleep_until(due)
                start = self.clock.now()
                if start - last_service > self.watchdog and k > 0:
                    reason = f"watchdog: loop not serviced for {start - last_service:.4g} s"
                    break
                try:
                    counts = self.hardware.read_encoders()
                except TimeoutError:
                    reason = "stale measurement: encoder read timed out"
                    break
                xa, xl = self.hardware.counts_to_positions(*counts)
                if not (math.isfinite(xa) and math.isfinite(xl)):
                    reason = f"non-finite measurement (x_A={xa}, x_L={xl})"
                    break
                if not (lo <= xa <= hi and lo <= xl <= hi):
                    reason = f"measurement out of range (x_A={xa:.4g}, x_L={xl:.4g} m)"
                    break
                u = float(self.controller.step((xa, xl), ref(due - t0)))
                if not math.isfinite(u):
                    reason = "non-finite command"
                    break
                if abs(u) > self.force_limit:
                    u = math.copysign(self.force_limit, u)
                    saturated += 1
                self.hardware.write_command(u)
                end = self.clock.now()
                last_service = end
                over = end > due + self.period
                for key, v in zip(
                    ("t", "xa", "xl", "u", "jit", "ovr"),
                    (due - t0, xa, xl, u, start - due, float(over)),
                    strict=True,
                ):
                    rec[key].append(v)
                k += 1
                if over:  # drop the ticks that are already late (only those within the run)
                    late = min(math.floor((end - t0) / self.period) + 1, n_ticks)
                    skipped += max(0, late - k)
                    k = max(k, late)
        except KeyboardInterrupt:
            reason = "interrupted"
        finally:
            self._safe_stop()
        return LoopRecord(
            t=np.array(rec["t"]),
            x_A=np.array(rec["xa"]),
            x_L=np.array(rec["xl"]),
            command=np.array(rec["u"]),
            jitter=np.array(rec["jit"]),
            overrun=np.array(rec["ovr"], dtype=bool),
            skipped=skipped,
            saturated=saturated,
            stop_reason=reason,
        )
