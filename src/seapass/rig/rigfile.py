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

from ..errors import FileFormatError, ParameterError
from ..files import limits
from ..files.schema import check_table
from ..files.toml import dump_toml, load_toml_file
from ..model.loop import SampledLoop, rename_rig_control_keys
from .intervals import FitIntervals
from .schema import (
    SCHEMA,
    ControlSpec,
    DamperSpec,
    EncoderSpec,
    ExperimentSpec,
    ImpactSpec,
    LoadSpec,
    MotorSpec,
    TransmissionSpec,
    rig_fields,
)

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
    loop : SampledLoop
        The bench's sampled loop: ``[control]`` rate, delay and velocity filter.
    intervals : FitIntervals or None
        ``[intervals]``: the confidence intervals of a fit (``rig fit --rig-out``),
        read by ``--robust``; see [`seapass.rig.intervals`][seapass.rig.intervals].
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
    intervals: FitIntervals | None = None

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
        try:
            self.loop  # noqa: B018 - checks the velocity filter against the Nyquist frequency
        except ParameterError as exc:
            raise FileFormatError(f"control.{exc}") from None
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

    @property
    def loop(self) -> SampledLoop:
        """The bench's sampled loop (`SampledLoop`) from ``[control]``."""
        c = self.control
        return SampledLoop(rate=c.rate, delay=c.delay, velocity_filter=c.velocity_filter)

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
            if key in SCHEMA:
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
        for sec in SCHEMA:
            d = dataclasses.asdict(getattr(self, sec))
            out[sec] = {
                k: (list(v) if isinstance(v, tuple) else v) for k, v in d.items() if v is not None
            }
        if self.intervals is not None:
            out["intervals"] = self.intervals.to_table()
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


def parse_rig(data: dict[str, Any]) -> Rig:
    """Validate a parsed TOML document (nested dict) and build a `Rig`.

    Raises
    ------
    FileFormatError
        Naming the offending key for unknown keys, wrong types, missing
        required keys or out-of-range values.
    """
    if isinstance(data.get("control"), dict):  # the loop's one spelling; old rig files still load
        data = {**data, "control": rename_rig_control_keys(data["control"])}
    fitted = data.get("intervals") if isinstance(data, dict) else None
    if fitted is not None:  # a fit's intervals (rig fit --rig-out), checked on their own
        data = {k: v for k, v in data.items() if k != "intervals"}
    kwargs = check_table(data, rig_fields(), what="a rig")
    if fitted is not None:
        kwargs["intervals"] = FitIntervals.from_table(fitted)
    for section, (cls, _fields) in SCHEMA.items():
        kwargs[section] = cls(**kwargs[section])
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
