"""The sections of a rig file: one frozen spec per TOML table, each key typed and range-checked.

What lives here: the section specs (`MotorSpec` ... `ImpactSpec`), the
schema of every key (`SCHEMA`, `TOP_FIELDS`, `rig_fields`), declared with
[`seapass.files.schema.Field`][seapass.files.schema.Field] and checked by
[`check_table`][seapass.files.schema.check_table], the one checker of design and
rig files.  The `Rig` itself is in [`seapass.rig.rigfile`][seapass.rig.rigfile].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ..files import limits
from ..files.schema import Field

__all__ = [
    "SCHEMA",
    "TOP_FIELDS",
    "ControlSpec",
    "DamperSpec",
    "EncoderSpec",
    "ExperimentSpec",
    "ImpactSpec",
    "LoadSpec",
    "MotorSpec",
    "TransmissionSpec",
    "rig_fields",
]

_INF = math.inf


def _f(lo: float = -_INF, hi: float = _INF, *, open_lo: bool = False, default: Any = None) -> Field:
    return Field(float, lo, hi, open_lo, default is None, default)


def _i(lo: float, hi: float, *, default: int | None = None) -> Field:
    return Field(int, lo, hi, False, default is None, default)


@dataclass(frozen=True)
class MotorSpec:
    """Motor datasheet values (rotor side of the gearbox)."""

    name: str
    rotor_inertia: float  # kg m^2
    continuous_torque: float  # N m
    peak_torque: float  # N m


@dataclass(frozen=True)
class TransmissionSpec:
    """Gearbox plus rotary-to-linear stage driving the actuator carriage."""

    gear_ratio: float
    pulley_radius: float  # m
    carriage_mass: float  # kg, actuator carriage + pulley/belt reflected
    viscous: float  # N s/m, actuator-to-ground (b of the model)
    coulomb: float  # N, actuator-to-ground dry friction


@dataclass(frozen=True)
class DamperSpec:
    """Spring and friction damper in the transmission (``D1 = k1 + b1 s`` plus dry friction)."""

    k1: float  # N/m
    b1: float  # N s/m
    coulomb: float  # N


@dataclass(frozen=True)
class LoadSpec:
    """Output carriage sliding on the guide rail."""

    carriage_mass: float  # kg, output carriage without the added load mass
    viscous: float  # N s/m, load-to-ground
    coulomb: float  # N, load-to-ground dry friction
    travel: float  # m, |x| beyond which the rail end is hit (run aborted as unstable)


@dataclass(frozen=True)
class EncoderSpec:
    """Incremental encoders: motor shaft (rotary) and spring deflection (linear)."""

    motor_cpt: int  # cycles (lines) per motor turn
    motor_quadrature: int  # edges counted per cycle (4 for x4 decoding)
    linear_lpi: float  # lines per inch of the linear strip
    linear_quadrature: int


@dataclass(frozen=True)
class ControlSpec:
    """Digital control loop of the bench (`Rig.loop` is it as a `SampledLoop`)."""

    rate: float  # Hz
    delay: int  # samples, 0 or 1: command computed from sample k applied at k+1
    substeps: int  # integrator substeps per control period
    velocity_filter: float | None = None  # Hz, first-order low-pass on finite differences


@dataclass(frozen=True)
class ExperimentSpec:
    """Protocol of the settling experiment (paper Sec. VI, bottom row of Fig. 3)."""

    initial_position: float  # m, load (and actuator) start position; reference is 0
    initial_deflection: float  # m, x_L - x_A at start (0 = spring relaxed)
    kd_max: float
    kd_step: float
    bd_ours: float
    load_masses: tuple[float, ...]
    settle_cap: float  # s
    settle_band: float  # fraction of the initial offset
    horizon: float  # s, simulated time (> settle_cap to judge the final value)


@dataclass(frozen=True)
class ImpactSpec:
    """Protocol of the impact experiment (paper Sec. VI, top right of Fig. 3)."""

    count: int
    kd: float
    bd: float
    load_mass: float
    force_min: float  # N, step magnitude range across impacts
    force_max: float
    window: float  # s after onset at which k_out = F_L / X_L is read
    duration: float  # s simulated per impact
    seed: int


SCHEMA: dict[str, tuple[type, dict[str, Field]]] = {
    "motor": (
        MotorSpec,
        {
            "name": Field(str, hi=limits.MAX_TITLE_CHARS, default="motor", required=False),
            "rotor_inertia": _f(0.0, 1.0, open_lo=True),
            "continuous_torque": _f(0.0, 100.0, open_lo=True),
            "peak_torque": _f(0.0, 1000.0, open_lo=True),
        },
    ),
    "transmission": (
        TransmissionSpec,
        {
            "gear_ratio": _f(0.0, 1e4, open_lo=True),
            "pulley_radius": _f(0.0, 1.0, open_lo=True),
            "carriage_mass": _f(0.0, 1e3),
            "viscous": _f(0.0, 1e5),
            "coulomb": _f(0.0, 1e4),
        },
    ),
    "damper": (
        DamperSpec,
        {
            "k1": _f(0.0, 1e8, open_lo=True),
            "b1": _f(0.0, 1e6),
            "coulomb": _f(0.0, 1e4),
        },
    ),
    "load": (
        LoadSpec,
        {
            "carriage_mass": _f(0.0, 1e3),
            "viscous": _f(0.0, 1e5),
            "coulomb": _f(0.0, 1e4),
            "travel": _f(0.0, 100.0, open_lo=True),
        },
    ),
    "encoders": (
        EncoderSpec,
        {
            "motor_cpt": _i(1, 1e9),
            "motor_quadrature": _i(1, 4),
            "linear_lpi": _f(0.0, 1e6, open_lo=True),
            "linear_quadrature": _i(1, 4),
        },
    ),
    "control": (
        ControlSpec,
        {
            "rate": _f(1.0, 1e6),
            "delay": _i(0, 1, default=0),
            "velocity_filter": Field(float, 0.0, 1e6, lo_open=True, required=False),
            "substeps": _i(1, 10_000, default=10),
        },
    ),
    "experiment": (
        ExperimentSpec,
        {
            "initial_position": _f(-10.0, 10.0),
            "initial_deflection": _f(-1.0, 1.0, default=0.0),
            "kd_max": _f(0.0, 1e8, open_lo=True),
            "kd_step": _f(0.0, 1e8, open_lo=True),
            "bd_ours": _f(0.0, 1e6),
            "load_masses": Field(list, 0.0, 1e4, True),
            "settle_cap": _f(0.0, 1e4, open_lo=True),
            "settle_band": _f(0.0, 1.0, open_lo=True),
            "horizon": _f(0.0, 1e4, open_lo=True),
        },
    ),
    "impacts": (
        ImpactSpec,
        {
            "count": _i(1, 10_000),
            "kd": _f(0.0, 1e8),
            "bd": _f(0.0, 1e6),
            "load_mass": _f(0.0, 1e4),
            "force_min": _f(0.0, 1e5, open_lo=True),
            "force_max": _f(0.0, 1e5, open_lo=True),
            "window": _f(0.0, 100.0, open_lo=True),
            "duration": _f(0.0, 100.0, open_lo=True),
            "seed": _i(0, 2**31 - 1, default=0),
        },
    ),
}

TOP_FIELDS = {
    "name": Field(str, hi=limits.MAX_NAME_CHARS, required=False, default="rig"),
    "description": Field(str, hi=limits.MAX_DESCRIPTION_CHARS, required=False, default=""),
}


def rig_fields() -> dict[str, Field]:
    """Every key of a rig file: `TOP_FIELDS` and one table per section of `SCHEMA`."""
    return {**TOP_FIELDS, **{name: Field(dict, fields=f) for name, (_cls, f) in SCHEMA.items()}}
