"""Fixed-rate runtime loop: timing, safety, passivity gate, and the digital twin end to end."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm

from seapass.errors import NotPassiveError, ParameterError
from seapass.model.sea import SEA
from seapass.sampled.controllers import LPController, OursController
from seapass.sampled.runtime import (
    ControlLoop,
    FakeClock,
    HardwareInterface,
    RealTimeClock,
    SimulatedClock,
    SimulatedHardware,
)

T = 0.002
VALS = {"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 30.0}


class LinearPlant:
    """Tiny exact linear stand-in with the TwinPlant interface (1 µm encoders)."""

    res = 1e-6

    def __init__(self, mL: float = 0.5) -> None:
        m, b, k1, b1 = VALS["m"], VALS["b"], VALS["k1"], VALS["b1"]
        self.A = np.array(
            [
                [0, 1, 0, 0],
                [-k1 / m, -(b + b1) / m, k1 / m, b1 / m],
                [0, 0, 0, 1],
                [k1 / mL, b1 / mL, -k1 / mL, -b1 / mL],
            ]
        )
        self.B = np.array([0, 1 / m, 0, 0.0])
        self.E = np.array([0, 0, 0, 1 / mL])
        self.x = np.zeros(4)
        self.time = 0.0

    def reset(
        self, *, x_A: float = 0.0, x_L: float = 0.0, v_A: float = 0.0, v_L: float = 0.0
    ) -> None:
        self.x = np.array([x_A, v_A, x_L, v_L])
        self.time = 0.0

    def apply(self, force_command: float, duration: float, *, external_force: float = 0.0) -> None:
        big = np.zeros((5, 5))
        big[:4, :4] = self.A * duration
        big[:4, 4] = (self.B * force_command + self.E * external_force) * duration
        self.x = (expm(big) @ np.r_[self.x, 1.0])[:4]
        self.time += duration

    def read_encoders(self) -> tuple[int, int]:
        return round(self.x[0] / self.res), round((self.x[2] - self.x[0]) / self.res)

    def counts_to_positions(self, motor_counts: float, linear_counts: float) -> tuple[float, float]:
        return motor_counts * self.res, (motor_counts + linear_counts) * self.res

    @property
    def state(self) -> tuple[float, float, float, float]:
        return tuple(self.x)  # type: ignore[return-value]


def ours_design(kd: float, bd: float = 25.0) -> SEA:
    return SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**VALS, "kd": kd, "bd": bd})


def make_loop(plant: LinearPlant | None = None, **kw):  # type: ignore[no-untyped-def]
    plant = plant or LinearPlant()
    plant.reset(x_L=0.02)
    hw = SimulatedHardware(plant)
    return hw, ControlLoop(hw, OursController(1000.0, 25.0, T), period=T, **kw)


def test_simulated_loop_regulates_linear_plant() -> None:
    hw, loop = make_loop(design=ours_design(1000.0))
    assert isinstance(hw, HardwareInterface)
    assert isinstance(loop.clock, SimulatedClock)
    assert loop.passivity["sampled"]["passive"] and loop.passivity["continuous"]["passive"]
    rec = loop.run(2.0)
    assert rec.stop_reason == "" and len(rec.t) == 1000
    assert abs(rec.x_L[-1]) < 2e-4 and rec.overruns == 0 and np.all(rec.jitter == 0)
    assert not hw.enabled and hw.active_command == 0.0  # always ends in a safe stop


def test_non_passive_design_is_refused_unless_overridden() -> None:
    plant = LinearPlant()
    hw = SimulatedHardware(plant)
    design = SEA(D1="k1 + b1*s", CL="kd", values={**VALS, "kd": 2000.0})
    with pytest.raises(NotPassiveError, match="allow_nonpassive"):
        ControlLoop(hw, LPController(2000.0, T), period=T, design=design)
    loop = ControlLoop(hw, LPController(2000.0, T), period=T, design=design, allow_nonpassive=True)
    assert loop.passivity["continuous"]["passive"] is False


def test_sampled_gate_uses_loop_delay() -> None:
    # passive at 500 Hz without delay, not with the rig's one-sample delay and 50 Hz filter
    design = ours_design(30000.0)
    hw = SimulatedHardware(LinearPlant())
    ControlLoop(hw, OursController(30000.0, 25.0, T), period=T, design=design)
    with pytest.raises(NotPassiveError, match="sampled"):
        ControlLoop(
            hw,
            OursController(30000.0, 25.0, T, velocity_filter=50.0),
            period=T,
            design=design,
            delay=1,
        )


class SlowController:
    """Wraps a controller and burns fake time on chosen ticks."""

    def __init__(self, inner, clock: FakeClock, costs: dict[int, float]) -> None:  # type: ignore[no-untyped-def]
        self.inner, self.clock, self.costs, self.k = inner, clock, costs, 0

    def reset(self) -> None:
        self.inner.reset()
        self.k = 0

    def step(self, meas, ref=(0.0, 0.0)):  # type: ignore[no-untyped-def]
        self.clock.advance(self.costs.get(self.k, 0.0))
        self.k += 1
        return self.inner.step(meas, ref)


def test_overrun_detection_with_fake_clock() -> None:
    clock = FakeClock()
    hw = SimulatedHardware(LinearPlant())
    ctrl = SlowController(OursController(1000.0, 25.0, T), clock, {3: 2.5 * T})
    rec = ControlLoop(hw, ctrl, period=T, clock=clock).run(20 * T)
    assert rec.overruns == 1 and bool(rec.overrun[3])
    assert rec.skipped == 2  # ticks 4 and 5 were already late
    assert rec.stop_reason == ""
    assert len(rec.t) == 20 - 2


class StallingClock(FakeClock):
    """sleep_until overshoots once (an OS stall)."""

    def __init__(self, stall_at: float, stall: float) -> None:
        super().__init__()
        self.stall_at, self.stall, self.done = stall_at, stall, False

    def sleep_until(self, t: float) -> None:
        super().sleep_until(t)
        if not self.done and t >= self.stall_at:
            self.t += self.stall
            self.done = True


def test_watchdog_trips_on_a_stall() -> None:
    hw = SimulatedHardware(LinearPlant())
    loop = ControlLoop(
        hw, OursController(1000.0, 25.0, T), period=T, clock=StallingClock(10 * T, 20 * T)
    )
    rec = loop.run(50 * T)
    assert rec.stop_reason.startswith("watchdog") and len(rec.t) == 10
    assert not hw.enabled


def test_stale_measurement_stops_safely() -> None:
    hw, loop = make_loop()
    hw.fail_reads = 1
    rec = loop.run(10 * T)
    assert rec.stop_reason.startswith("stale") and len(rec.t) == 0
    assert hw.active_command == 0.0 and not hw.enabled


class BrokenEncoders(LinearPlant):
    def __init__(self, after: int) -> None:
        super().__init__()
        self.after, self.n = after, 0

    def counts_to_positions(self, motor_counts: float, linear_counts: float) -> tuple[float, float]:
        self.n += 1
        return (
            (math.nan, 0.0)
            if self.n > self.after
            else super().counts_to_positions(motor_counts, linear_counts)
        )


def test_non_finite_and_out_of_range_measurements_stop() -> None:
    hw = SimulatedHardware(BrokenEncoders(after=5))
    rec = ControlLoop(hw, OursController(1000.0, 25.0, T), period=T).run(20 * T)
    assert rec.stop_reason.startswith("non-finite") and len(rec.t) == 5
    hw2, loop2 = make_loop(position_limits=(-0.01, 0.01))
    rec2 = loop2.run(10 * T)
    assert rec2.stop_reason.startswith("measurement out of range") and not hw2.enabled


def test_saturation() -> None:
    _hw, loop = make_loop(force_limit=5.0)
    rec = loop.run(0.2, reference=(0.05, 0.0))
    assert rec.saturated > 0 and np.max(np.abs(rec.command)) <= 5.0


class LateClock(FakeClock):
    """Wakes every tick ``late`` seconds after the requested time (deterministic jitter)."""

    def __init__(self, late: float) -> None:
        super().__init__()
        self.late = late

    def sleep_until(self, t: float) -> None:
        super().sleep_until(t + self.late)


def test_overrun_at_the_end_skips_only_ticks_of_the_run() -> None:
    """An overrun on the last tick drops no tick beyond the run's end."""
    plant = LinearPlant()
    hw = SimulatedHardware(plant)
    rec = ControlLoop(
        hw, OursController(1000.0, 25.0, T), period=T, clock=LateClock(7.5 * T), watchdog=60.0
    ).run(3 * T)
    assert len(rec.jitter) + rec.skipped == 3


def test_jitter_is_recorded_from_the_injected_clock() -> None:
    plant = LinearPlant()
    plant.reset(x_L=0.01)
    hw = SimulatedHardware(plant)
    rec = ControlLoop(hw, OursController(1000.0, 25.0, T), period=T, clock=LateClock(3e-4)).run(
        10 * T
    )
    assert rec.skipped == 0 and rec.overruns == 0 and rec.stop_reason == ""
    np.testing.assert_allclose(rec.jitter[1:], 3e-4, rtol=1e-9)
    summary = rec.summary()
    assert summary["jitter_max"] == pytest.approx(3e-4, rel=1e-9)


def test_real_time_clock_runs_the_loop() -> None:
    """The wall clock drives the loop; the watchdog is generous, so a busy machine cannot trip it."""
    plant = LinearPlant()
    plant.reset(x_L=0.01)
    hw = SimulatedHardware(plant)
    loop = ControlLoop(
        hw, OursController(1000.0, 25.0, T), period=T, clock=RealTimeClock(), watchdog=60.0
    )
    rec = loop.run(10 * T)
    # a busy machine may drop late ticks, counted in skipped: every tick is either run or skipped
    assert rec.stop_reason == "" and len(rec.jitter) + rec.skipped == 10
    assert np.all(rec.jitter >= 0)
    assert set(rec.summary()) >= {"jitter_max", "jitter_rms", "overruns"}


def test_bad_arguments() -> None:
    hw = SimulatedHardware(LinearPlant())
    with pytest.raises(ParameterError):
        ControlLoop(hw, OursController(1.0, 1.0, T), period=0.0)
    with pytest.raises(ParameterError):
        ControlLoop(hw, OursController(1.0, 1.0, T), period=T, force_limit=-1.0)
    with pytest.raises(ParameterError):
        SimulatedHardware(LinearPlant(), delay=-1)


def test_delayed_hardware_applies_commands_late() -> None:
    hw = SimulatedHardware(LinearPlant(), delay=1)
    hw.enable()
    hw.write_command(3.0)
    assert hw.active_command == 0.0
    hw.write_command(4.0)
    assert hw.active_command == 3.0


def test_twin_end_to_end() -> None:
    twin = pytest.importorskip("seapass.rig.plant")
    rig = pytest.importorskip("seapass.rig.rigfile").paper_rig()
    plant = twin.TwinPlant(rig, load_mass=0.1, seed=None)
    plant.reset(x_L=0.02)
    hw = SimulatedHardware(plant, delay=rig.control.delay)
    design = ours_design(1000.0).with_values(**rig.model_values())
    ctrl = OursController(1000.0, 25.0, rig.period, velocity_filter=rig.control.velocity_filter)
    loop = ControlLoop(
        hw,
        ctrl,
        period=rig.period,
        force_limit=rig.force_limit,
        position_limits=(-rig.load.travel, rig.load.travel),
        design=design,
        delay=rig.control.delay,
    )
    rec = loop.run(1.5)
    assert rec.stop_reason == ""
    assert abs(rec.x_L[-1]) < 2e-3  # dry friction leaves a sub-mm offset
    assert abs(plant.state[2] - rec.x_L[-1]) < 1e-4


def test_twin_nonpassive_lp_is_refused_then_stopped_safely() -> None:
    twin = pytest.importorskip("seapass.rig.plant")
    rig = pytest.importorskip("seapass.rig.rigfile").paper_rig()
    design = SEA(D1="k1 + b1*s", CL="kd", values={**rig.model_values(), "kd": 3000.0})
    plant = twin.TwinPlant(rig, load_mass=0.6, seed=None)
    plant.reset(x_L=0.02)
    hw = SimulatedHardware(plant, delay=1)
    ctrl = LPController(3000.0, rig.period, velocity_filter=50.0)
    kw = {
        "period": rig.period,
        "force_limit": rig.force_limit,
        "design": design,
        "delay": 1,
        "position_limits": (-rig.load.travel, rig.load.travel),
    }
    with pytest.raises(NotPassiveError):
        ControlLoop(hw, ctrl, **kw)
    rec = ControlLoop(hw, ctrl, allow_nonpassive=True, **kw).run(3.0)
    assert rec.stop_reason.startswith("measurement out of range")  # it diverged; safe stop
    assert not hw.enabled and hw.active_command == 0.0 and rec.saturated > 0
