"""Simulation scenarios: what drives the closed loop (reference steps, displaced load, forces, trajectories).

Each scenario is an immutable value object validated on construction; the
simulator in [`seapass.sim.simulate`][seapass.sim.simulate] turns it into initial conditions and an
input signal ``u(t) = (θ_A, θ_L, f_ext)``.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..errors import FileFormatError, ParameterError
from ..files.limits import MAX_TRAJECTORY_BYTES, MAX_TRAJECTORY_SAMPLES
from ..files.textfile import read_text_file
from ..model.experiment import PAPER_EXPERIMENT
from ..model.expr import finite_number

__all__ = [
    "ForceImpulse",
    "ForceStep",
    "LoadDisplaced",
    "Scenario",
    "Step",
    "Trajectory",
    "read_trajectory",
    "reference_values",
]


def reference_values(apply_to: str, value: float) -> tuple[float, float]:
    """``(θ_A, θ_L)`` references of a scenario that moves ``apply_to`` by ``value``."""
    if apply_to not in ("both", "actuator", "load"):
        raise ParameterError(f"apply_to must be 'both', 'actuator' or 'load', got {apply_to!r}")
    return (0.0 if apply_to == "load" else value, 0.0 if apply_to == "actuator" else value)


# --------------------------------------------------------------------------- scenarios


@dataclass(frozen=True)
class Step:
    """Reference step of ``size`` metres at ``t = 0`` from rest at the origin.

    ``size`` defaults to the paper's step
    ([`PAPER_EXPERIMENT`][seapass.model.experiment.PAPER_EXPERIMENT]); None means the
    same.  ``apply_to`` selects the references that step: ``"both"`` (θ_A = θ_L, the
    default), ``"actuator"`` (θ_A only) or ``"load"`` (θ_L only).  The load
    target for the tracking metrics is ``size``.
    """

    size: float = PAPER_EXPERIMENT.step
    apply_to: str = "both"

    def __post_init__(self) -> None:
        size = PAPER_EXPERIMENT.pick("step", self.size)
        object.__setattr__(self, "size", finite_number(size, "step size", nonzero=True))
        reference_values(self.apply_to, 1.0)


@dataclass(frozen=True)
class LoadDisplaced:
    """The load starts at ``displacement`` (actuator at rest at 0), references 0.

    The paper's hardware test (Sec. VI): load held at 20 mm and released.
    Internal states of mechanical elements start in equilibrium with the
    initial deflection; controller states start at zero.
    """

    displacement: float = 0.02

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "displacement", finite_number(self.displacement, "displacement", nonzero=True)
        )


@dataclass(frozen=True)
class ForceStep:
    """A constant force ``force`` (N) on the load from ``t = 0``; references 0."""

    force: float = 10.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "force", finite_number(self.force, "force", nonzero=True))


@dataclass(frozen=True)
class ForceImpulse:
    """An impulse ``impulse`` (N·s) on the resting load at ``t = 0``: ``v_L(0+) = J/m_L``."""

    impulse: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "impulse", finite_number(self.impulse, "impulse", nonzero=True))


@dataclass(frozen=True)
class Trajectory:
    """A reference trajectory given as samples ``(times, values)`` (s, m).

    Between samples the reference is held (``interpolation="zoh"``) or
    linearly interpolated (``"linear"``); before the first sample it equals
    the first value and after the last it holds the last.  The simulator
    evaluates it on its grid, which is exact when the sample times are
    multiples of the time step.  The metrics use the last value as target.
    """

    times: Sequence[float]
    values: Sequence[float]
    interpolation: Literal["zoh", "linear"] = "linear"
    apply_to: str = "both"

    def __post_init__(self) -> None:
        t = np.asarray(self.times, dtype=float)
        v = np.asarray(self.values, dtype=float)
        if t.ndim != 1 or v.ndim != 1 or t.shape != v.shape or t.size == 0:
            raise ParameterError(
                f"trajectory times and values must be 1-D of equal nonzero length, "
                f"got shapes {t.shape} and {v.shape}"
            )
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
            raise ParameterError("trajectory times and values must be finite")
        if np.any(np.diff(t) <= 0):
            raise ParameterError("trajectory times must be strictly increasing")
        if self.interpolation not in ("zoh", "linear"):
            raise ParameterError(
                f"interpolation must be 'zoh' or 'linear', got {self.interpolation!r}"
            )
        reference_values(self.apply_to, 1.0)
        object.__setattr__(self, "times", tuple(t.tolist()))
        object.__setattr__(self, "values", tuple(v.tolist()))

    def sample(self, t: np.ndarray) -> np.ndarray:
        """The reference on the grid ``t``."""
        ts, vs = np.asarray(self.times), np.asarray(self.values)
        if self.interpolation == "linear":
            return np.interp(t, ts, vs)
        idx = np.clip(np.searchsorted(ts, t + 1e-12 * (1 + abs(t)), side="right") - 1, 0, None)
        return vs[idx]


Scenario = Step | LoadDisplaced | ForceStep | ForceImpulse | Trajectory


def read_trajectory(
    path: str | os.PathLike[str],
    *,
    interpolation: Literal["zoh", "linear"] = "linear",
    apply_to: str = "both",
) -> Trajectory:
    """The `Trajectory` of a CSV file: two columns, time (s) and reference (m).

    Columns may be separated by commas, semicolons or tabs; a header row, blank
    lines and ``#`` comments are skipped.  The file is read through
    [`read_text_file`][seapass.files.textfile.read_text_file] (at most
    ``MAX_TRAJECTORY_BYTES``) and holds at most ``MAX_TRAJECTORY_SAMPLES`` rows.

    Raises
    ------
    FileFormatError
        Naming the file and line of a row that is not two finite numbers, or
        for a file without samples or with too many.
    OSError
        If the file cannot be read.
    """
    text = read_text_file(path, max_bytes=MAX_TRAJECTORY_BYTES, what="trajectory file")
    rows: list[tuple[float, float]] = []
    for n, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = [x.strip() for x in line.replace(";", ",").replace("\t", ",").split(",")]
        try:
            vals = [float(x) for x in parts if x]
        except ValueError:
            if not rows and n == 1:
                continue  # header
            raise FileFormatError(f"{path}:{n}: expected two numbers, got {line!r}") from None
        if len(vals) != 2 or not all(math.isfinite(v) for v in vals):
            raise FileFormatError(f"{path}:{n}: expected two finite numbers, got {line!r}")
        rows.append((vals[0], vals[1]))
        if len(rows) > MAX_TRAJECTORY_SAMPLES:
            raise FileFormatError(
                f"{path}: more than {MAX_TRAJECTORY_SAMPLES:,} samples; resample the trajectory"
            )
    if not rows:
        raise FileFormatError(f"{path}: no samples found")
    times, values = zip(*rows, strict=True)
    return Trajectory(times, values, interpolation=interpolation, apply_to=apply_to)
