"""Hardware rig description: a frozen `Rig` and a strict TOML loader.

A rig file describes one physical SEA test bench (motor, transmission, spring,
friction damper, load carriage, encoders, control loop) plus the protocol of
the paper's experiment run on it.  The package ships the reconstruction of the
bench of Mehta & Losey [1]_ as ``seapass/data/paper_rig.toml``; load it with
`paper_rig`.  Users write their own files in the same format.

Validation is strict: an unknown section or key, a wrong type, a missing
required key or a value out of its physical range raises
[`FileFormatError`][seapass.errors.FileFormatError] naming the key (``spring.k1``), so a
typo never silently falls back to a default.

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Section VI (Experiments).
"""

from __future__ import annotations

import dataclasses
import math
import os
import tomllib
from dataclasses import dataclass
from importlib import resources
from typing import Any

from ..errors import FileFormatError
from ..files import limits
from ..files.toml import dump_toml, load_toml_file

__all__ = [
    "ControlSpec",
    "DamperSpec",
    "EncoderSpec",
    "ExperimentSpec",
    "ImpactSpec",
    "LoadSpec",
    "MotorSpec",
    "Rig",
    "TransmissionSpec",
    "load_rig",
    "paper_rig",
    "parse_rig",
]

_INF = math.inf


@dataclass(frozen=True)
class _Field:
    kind: type  # float, int, str, bool or list (list of floats)
    lo: float = -_INF
    hi: float = _INF  # for str: the longest text; for list: the largest value
    lo_open: bool = False
    required: bool = True
    default: Any = None


def _f(
    lo: float = -_INF, hi: float = _INF, *, open_lo: bool = False, default: Any = None
) -> _Field:
    return _Field(float, lo, hi, open_lo, default is None, default)


def _i(lo: float, hi: float, *, default: int | None = None) -> _Field:
    return _Field(int, lo, hi, False, default is None, default)


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
    """Digital control loop of the bench."""

    rate: float  # Hz
    delay_samples: int  # 0 or 1: command computed from sample k applied at k+1
    velocity_filter_hz: float  # first-order low-pass on finite differences; 0 = none
    substeps: int  # integrator substeps per control period


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


_SCHEMA: dict[str, tuple[type, dict[str, _Field]]] = {
    "motor": (
        MotorSpec,
        {
            "name": _Field(str, hi=limits.MAX_TITLE_CHARS, default="motor", required=False),
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
            "delay_samples": _i(0, 1, default=0),
            "velocity_filter_hz": _f(0.0, 1e6, default=0.0),
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
            "load_masses": _Field(list, 0.0, 1e4, True),
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

_TOP = {
    "name": _Field(str, hi=limits.MAX_NAME_CHARS, required=False, default="rig"),
    "description": _Field(str, hi=limits.MAX_DESCRIPTION_CHARS, required=False, default=""),
}


@dataclass(frozen=True)
class Rig:
    """A complete, validated description of one SEA test bench.

    Build one with `load_rig` / `parse_rig` / `paper_rig`, or
    directly from the section dataclasses; use `replace` for variants
    (``rig.replace(damper={"b1": 0.0})``).

    Attributes
    ----------
    actuator_mass : float
        ``m`` of the model: carriage mass plus rotor inertia reflected through
        gearbox and pulley, ``J N^2 / r^2`` (kg).
    actuator_damping : float
        ``b`` of the model (N s/m).
    force_limit, continuous_force : float
        Peak and continuous actuator force, ``torque * N / r`` (N); the twin
        saturates commands at ``force_limit``.
    motor_resolution, linear_resolution : float
        Metres per count of the two encoders.
    period : float
        Control period ``1/rate`` (s).
    """

    motor: MotorSpec
    transmission: TransmissionSpec
    damper: DamperSpec
    load: LoadSpec
    encoders: EncoderSpec
    control: ControlSpec
    experiment: ExperimentSpec
    impacts: ImpactSpec
    name: str = "rig"
    description: str = ""

    def __post_init__(self) -> None:
        if self.motor.peak_torque < self.motor.continuous_torque:
            raise FileFormatError(
                "motor.peak_torque must be at least motor.continuous_torque "
                f"({self.motor.peak_torque:g} < {self.motor.continuous_torque:g})"
            )
        if self.impacts.force_max < self.impacts.force_min:
            raise FileFormatError("impacts.force_max must be at least impacts.force_min")
        if self.impacts.duration < self.impacts.window:
            raise FileFormatError("impacts.duration must be at least impacts.window")
        if self.experiment.horizon < self.experiment.settle_cap:
            raise FileFormatError("experiment.horizon must be at least experiment.settle_cap")
        if not self.experiment.load_masses:
            raise FileFormatError("experiment.load_masses must list at least one mass")
        if abs(self.experiment.initial_position) >= self.load.travel:
            raise FileFormatError("experiment.initial_position must lie inside ±load.travel")
        c, n_max, steps_max = self.control, limits.MAX_RIG_SAMPLES, limits.MAX_RIG_INTEGRATOR_STEPS
        for key, n in (("experiment.horizon", self.experiment.horizon * c.rate),
                       ("impacts.duration", self.impacts.duration * c.rate)):  # fmt: skip
            if n > n_max or n * c.substeps > steps_max:  # bounded before any run
                raise FileFormatError(
                    f"{key} × control.rate = {n:.3g} control periods per run, {c.substeps} "
                    f"substeps each; the limits are {n_max:,} periods and {steps_max:,} "
                    f"substeps: shorten {key} or lower control.rate or control.substeps"
                )

    @property
    def actuator_mass(self) -> float:
        t = self.transmission
        return t.carriage_mass + self.motor.rotor_inertia * (t.gear_ratio / t.pulley_radius) ** 2

    @property
    def actuator_damping(self) -> float:
        return self.transmission.viscous

    @property
    def force_limit(self) -> float:
        t = self.transmission
        return self.motor.peak_torque * t.gear_ratio / t.pulley_radius

    @property
    def continuous_force(self) -> float:
        t = self.transmission
        return self.motor.continuous_torque * t.gear_ratio / t.pulley_radius

    @property
    def motor_resolution(self) -> float:
        e, t = self.encoders, self.transmission
        counts_per_carriage_turn = e.motor_cpt * e.motor_quadrature * t.gear_ratio
        return 2.0 * math.pi * t.pulley_radius / counts_per_carriage_turn

    @property
    def linear_resolution(self) -> float:
        e = self.encoders
        return 0.0254 / (e.linear_lpi * e.linear_quadrature)

    @property
    def period(self) -> float:
        return 1.0 / self.control.rate

    def load_side_mass(self, load_mass: float) -> float:
        """Output carriage plus the attached load (kg)."""
        return self.load.carriage_mass + float(load_mass)

    def model_values(self, *, load_mass: float | None = None) -> dict[str, float]:
        """Linear-model parameters ``m, b, k1, b1`` (and ``mL`` when ``load_mass`` is given)."""
        out = {
            "m": self.actuator_mass,
            "b": self.actuator_damping,
            "k1": self.damper.k1,
            "b1": self.damper.b1,
        }
        if load_mass is not None:
            out["mL"] = self.load_side_mass(load_mass)
        return out

    def replace(self, **sections: Any) -> Rig:
        """A validated copy with some fields changed: ``replace(damper={"b1": 10.0}, name="x")``.

        Raises
        ------
        FileFormatError
            Naming the key, exactly as for a rig file.
        """
        data = self.to_dict()
        for key, val in sections.items():
            if key in _SCHEMA:
                if not isinstance(val, dict):
                    raise FileFormatError(
                        f"[{key}] changes must be a dict, got {type(val).__name__}"
                    )
                data[key].update(
                    {k: (list(v) if isinstance(v, tuple) else v) for k, v in val.items()}
                )
            else:
                data[key] = val
        return parse_rig(data)

    def to_dict(self) -> dict[str, Any]:
        """Plain nested dict in the layout of a rig file."""
        out: dict[str, Any] = {"name": self.name, "description": self.description}
        for sec in _SCHEMA:
            d = dataclasses.asdict(getattr(self, sec))
            out[sec] = {k: (list(v) if isinstance(v, tuple) else v) for k, v in d.items()}
        return out

    def to_toml(self) -> str:
        """The rig as rig-file TOML that `parse_rig` reads back to an equal `Rig`.

        The derived values (`derived`) follow as comments.
        """
        derived = "\n".join(f"#   {k} = {v:.6g}" for k, v in self.derived().items())
        return dump_toml(self.to_dict()) + "\n# derived (not read back):\n" + derived + "\n"

    def derived(self) -> dict[str, float]:
        """Derived quantities (for reports)."""
        return {
            "actuator_mass": self.actuator_mass,
            "actuator_damping": self.actuator_damping,
            "force_limit": self.force_limit,
            "continuous_force": self.continuous_force,
            "motor_resolution": self.motor_resolution,
            "linear_resolution": self.linear_resolution,
            "period": self.period,
        }


def _check_value(key: str, spec: _Field, value: Any) -> Any:
    if spec.kind is str:
        if not isinstance(value, str):
            raise FileFormatError(f"{key}: expected a string, got {type(value).__name__}")
        if len(value) > spec.hi:
            raise FileFormatError(f"{key}: {len(value):,} characters; the limit is {spec.hi:g}")
        return value
    if spec.kind is list:
        if not isinstance(value, list):
            raise FileFormatError(f"{key}: expected a list of numbers, got {type(value).__name__}")
        if len(value) > (most := limits.MAX_LIST_LENGTH):
            raise FileFormatError(f"{key}: {len(value):,} entries; the limit is {most}")
        return tuple(_check_number(f"{key}[{i}]", spec, v, float) for i, v in enumerate(value))
    return _check_number(key, spec, value, spec.kind)


def _check_number(key: str, spec: _Field, value: Any, kind: type) -> Any:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise FileFormatError(f"{key}: expected a number, got {type(value).__name__} {value!r}")
    if kind is int and not isinstance(value, int):
        raise FileFormatError(f"{key}: expected an integer, got {value!r}")
    if not math.isfinite(value):
        raise FileFormatError(f"{key}: must be finite, got {value!r}")
    too_low = value <= spec.lo if spec.lo_open else value < spec.lo
    if too_low or value > spec.hi:
        lo = "(" if spec.lo_open else "["
        raise FileFormatError(f"{key} = {value!r} is out of range {lo}{spec.lo:g}, {spec.hi:g}]")
    return kind(value)


def _build(section: str, table: Any) -> Any:
    cls, fields = _SCHEMA[section]
    if not isinstance(table, dict):
        raise FileFormatError(f"[{section}] must be a table, got {type(table).__name__}")
    unknown = sorted(set(table) - set(fields))
    if unknown:
        raise FileFormatError(
            f"unknown key {section}.{unknown[0]}; allowed keys: {', '.join(fields)}"
        )
    kwargs: dict[str, Any] = {}
    for key, spec in fields.items():
        if key in table:
            kwargs[key] = _check_value(f"{section}.{key}", spec, table[key])
        elif spec.required:
            raise FileFormatError(f"missing required key {section}.{key}")
        else:
            kwargs[key] = spec.default
    return cls(**kwargs)


def parse_rig(data: dict[str, Any]) -> Rig:
    """Validate a parsed TOML document (nested dict) and build a `Rig`.

    Raises
    ------
    FileFormatError
        Naming the offending key for unknown keys, wrong types, missing
        required keys or out-of-range values.
    """
    if not isinstance(data, dict):
        raise FileFormatError("a rig must be a TOML table")
    unknown = sorted(set(data) - set(_SCHEMA) - set(_TOP))
    if unknown:
        raise FileFormatError(
            f"unknown key {unknown[0]}; allowed sections: {', '.join(_SCHEMA)} "
            f"and keys {', '.join(_TOP)}"
        )
    kwargs: dict[str, Any] = {}
    for key, spec in _TOP.items():
        kwargs[key] = _check_value(key, spec, data[key]) if key in data else spec.default
    for section in _SCHEMA:
        if section not in data:
            raise FileFormatError(f"missing required section [{section}]")
        kwargs[section] = _build(section, data[section])
    return Rig(**kwargs)


def load_rig(path: str | os.PathLike[str]) -> Rig:
    """Read and validate a rig TOML file.

    Raises
    ------
    FileFormatError
        For malformed TOML or invalid content (the message names the file and key).
    OSError
        When the file cannot be read.
    """
    return load_toml_file(path, parse_rig, what="rig file")


def paper_rig() -> Rig:
    """The packaged reconstruction of the paper's bench (``seapass/data/paper_rig.toml``)."""
    text = resources.files("seapass").joinpath("data/paper_rig.toml").read_text(encoding="utf-8")
    return parse_rig(tomllib.loads(text))
