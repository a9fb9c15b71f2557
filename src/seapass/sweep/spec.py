"""What a design-space sweep is: the swept axes and the `SweepSpec`.

Designs are numbered ``0 … n−1``; chunk ``c`` holds designs
``[c·chunk_size, (c+1)·chunk_size)`` and its parameters are computed from the
indices alone (grid: ``numpy.unravel_index`` in C order, first axis slowest;
random: a generator seeded with ``(seed, c)``), so the full design set is never
materialized and any chunk can be recomputed independently and identically, on
any machine.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..files.limits import MAX_DESIGNS
from ..model.experiment import PAPER_EXPERIMENT
from ..model.expr import parse_value
from ..model.sea import SEA

__all__ = [
    "LOAD_MASS",
    "MAX_DESIGNS",
    "GridAxis",
    "RangeAxis",
    "SweepSpec",
    "parse_grid",
    "parse_range",
    "spec_from_state",
    "spec_state",
]


LOAD_MASS = "m_L"


@dataclass(frozen=True)
class GridAxis:
    """Values ``lo, lo + step, …`` up to ``hi`` inclusive (within 1e-9 steps)."""

    name: str
    lo: float
    hi: float
    step: float

    def __post_init__(self) -> None:
        for attr in ("lo", "hi", "step"):
            v = float(getattr(self, attr))
            if not math.isfinite(v):
                raise ParameterError(f"grid axis {self.name}: {attr} must be finite")
            object.__setattr__(self, attr, v)
        if self.step <= 0:
            raise ParameterError(f"grid axis {self.name}: step must be positive, got {self.step:g}")
        if self.hi < self.lo:
            raise ParameterError(
                f"grid axis {self.name}: hi ({self.hi:g}) is below lo ({self.lo:g})"
            )

    @property
    def size(self) -> int:
        return math.floor((self.hi - self.lo) / self.step + 1e-9) + 1

    def values(self, idx: np.ndarray) -> np.ndarray:
        return self.lo + self.step * idx.astype(np.float64)


@dataclass(frozen=True)
class RangeAxis:
    """Uniform random values in ``[lo, hi]``."""

    name: str
    lo: float
    hi: float

    def __post_init__(self) -> None:
        for attr in ("lo", "hi"):
            v = float(getattr(self, attr))
            if not math.isfinite(v):
                raise ParameterError(f"range {self.name}: {attr} must be finite")
            object.__setattr__(self, attr, v)
        if self.hi < self.lo:
            raise ParameterError(f"range {self.name}: hi ({self.hi:g}) is below lo ({self.lo:g})")


def _split_spec(text: str, flag: str, parts: int) -> tuple[str, list[float]]:
    example = "kd=0:5000:200" if parts == 3 else "kd=0:5000"
    if "=" not in text:
        raise ParameterError(
            f"{flag} {text!r}: expected NAME=LO:HI{':STEP' * (parts == 3)}, e.g. {example}"
        )
    name, rhs = (x.strip() for x in text.split("=", 1))
    fields = rhs.split(":")
    if not name.isidentifier() or len(fields) != parts:
        raise ParameterError(
            f"{flag} {text!r}: expected NAME=LO:HI{':STEP' * (parts == 3)}, e.g. {example}"
        )
    return name, [parse_value(f, f"{flag} {name}") for f in fields]


def parse_grid(text: str) -> GridAxis:
    """``"kd=0:5000:200"`` → `GridAxis` (``lo:hi:step``, inclusive)."""
    name, (lo, hi, step) = _split_spec(text, "--grid", 3)
    return GridAxis(name, lo, hi, step)


def parse_range(text: str) -> RangeAxis:
    """``"kd=0:5000"`` → `RangeAxis`."""
    name, (lo, hi) = _split_spec(text, "--range", 2)
    return RangeAxis(name, lo, hi)


def _sea_state(sea: SEA) -> dict[str, Any]:
    return {"elements": sea.describe(), "values": dict(sea.values), "name": sea.name}


def _sea_from_state(state: Mapping[str, Any]) -> SEA:
    e = state["elements"]
    return SEA(
        D1=e["D1"], D2=e["D2"], CA=e["CA"], CL=e["CL"], m=e["m"], b=e["b"],
        values=dict(state["values"]), name=state["name"],
    )  # fmt: skip


@dataclass(frozen=True)
class SweepSpec:
    """What to sweep and what to compute for every design.

    Parameters
    ----------
    sea : SEA
        The configuration; swept parameters override its values.
    grid : sequence of GridAxis
        Full factorial grid (C order: the first axis varies slowest).
    ranges : sequence of RangeAxis
        Random uniform sampling with ``samples`` designs (exclusive with ``grid``).
    samples : int or None
    seed : int
    load_mass, step, horizon, tolerance : float
        Metric options; ``m_L`` may also be swept as a parameter.  Default (and for
        None): the paper's load mass, step and tolerance and a 5 s screening horizon
        ([`PAPER_EXPERIMENT`][seapass.model.experiment.PAPER_EXPERIMENT]).
    metrics : bool
        Compute settling time, final error and overshoot (else passivity only).
    margin : bool
        Compute the passivity margin (about 3x the cost of the verdict alone);
        the column holds NaN otherwise.
    chunk_size : int
        Designs per chunk (memory and the unit of resumption).
    """

    sea: SEA
    grid: tuple[GridAxis, ...] = ()
    ranges: tuple[RangeAxis, ...] = ()
    samples: int | None = None
    seed: int = 0
    load_mass: float = PAPER_EXPERIMENT.load_mass
    step: float = PAPER_EXPERIMENT.step
    horizon: float = PAPER_EXPERIMENT.screening_horizon
    tolerance: float = PAPER_EXPERIMENT.tolerance
    metrics: bool = True
    margin: bool = True
    chunk_size: int = 65536

    def __post_init__(self) -> None:
        for name, key in (("load_mass", "load_mass"), ("step", "step"),
                          ("horizon", "screening_horizon"), ("tolerance", "tolerance")):  # fmt: skip
            object.__setattr__(self, name, PAPER_EXPERIMENT.pick(key, getattr(self, name)))
        object.__setattr__(self, "grid", tuple(self.grid))
        object.__setattr__(self, "ranges", tuple(self.ranges))
        if bool(self.grid) == bool(self.ranges):
            raise ParameterError(
                "give either grid axes (grid: NAME=LO:HI:STEP) or random ranges and a number "
                "of samples (ranges: NAME=LO:HI, samples: N), not both or neither"
            )
        if self.ranges and (self.samples is None or self.samples < 1):
            raise ParameterError(
                "samples: random sampling needs a number of samples N >= 1", argument="samples"
            )
        if self.grid and self.samples is not None:
            raise ParameterError(
                "samples: only for random ranges; a grid has its own size", argument="samples"
            )
        names = self.names
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ParameterError(f"parameter(s) {', '.join(dup)} swept more than once")
        allowed = set(self.sea.parameters) | {LOAD_MASS}
        unknown = [n for n in names if n not in allowed]
        if unknown:
            raise ParameterError(
                f"swept parameter(s) {', '.join(unknown)} do not appear in the model; "
                f"its parameters are {', '.join(self.sea.parameters)} (and {LOAD_MASS})"
            )
        missing = [p for p in self.sea.free_parameters if p not in names]
        if missing:
            raise ParameterError(
                f"parameter(s) {', '.join(missing)} have no value: sweep them or give "
                f"them a value, e.g. values={{{missing[0]!r}: 1.0}}"
            )
        if not 1 <= self.chunk_size <= 10**7:
            raise ParameterError(f"chunk size must be in [1, 1e7], got {self.chunk_size}")
        if self.n_designs > MAX_DESIGNS:
            raise ParameterError(
                f"the sweep has {self.n_designs:.3g} designs, more than the limit of "
                f"{MAX_DESIGNS:.0e}; use coarser steps"
            )
        if self.metrics:
            if not (math.isfinite(self.load_mass) and self.load_mass > 0):
                raise ParameterError(
                    f"load_mass: must be positive, got {self.load_mass}", argument="load_mass"
                )
            if not (math.isfinite(self.horizon) and self.horizon > 0):
                raise ParameterError(
                    f"horizon: must be positive, got {self.horizon}", argument="horizon"
                )
            if not (math.isfinite(self.step) and self.step != 0):
                raise ParameterError(f"step: must be nonzero, got {self.step}", argument="step")

    @property
    def names(self) -> list[str]:
        return [a.name for a in self.grid] + [a.name for a in self.ranges]

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(a.size for a in self.grid) if self.grid else (int(self.samples or 0),)

    @property
    def n_designs(self) -> int:
        return math.prod(self.shape)

    @property
    def n_chunks(self) -> int:
        return -(-self.n_designs // self.chunk_size)

    def describe(self) -> dict[str, Any]:
        """A JSON-able description (the fingerprint is its hash)."""
        return {
            "model": _sea_state(self.sea),
            "grid": [asdict(a) for a in self.grid],
            "ranges": [asdict(a) for a in self.ranges],
            "samples": self.samples,
            "seed": self.seed,
            "load_mass": self.load_mass,
            "step": self.step,
            "horizon": self.horizon,
            "tolerance": self.tolerance,
            "metrics": self.metrics,
            "margin": self.margin,
            "chunk_size": self.chunk_size,
            "n_designs": self.n_designs,
        }

    def fingerprint(self) -> str:
        text = json.dumps(self.describe(), sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def chunk_values(self, c: int) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Design indices and parameter arrays of chunk ``c``."""
        if not 0 <= c < self.n_chunks:
            raise ParameterError(f"chunk {c} is outside 0..{self.n_chunks - 1}")
        start = c * self.chunk_size
        stop = min(self.n_designs, start + self.chunk_size)
        idx = np.arange(start, stop, dtype=np.int64)
        if self.grid:
            sub = np.unravel_index(idx, self.shape)
            return idx, {a.name: a.values(i) for a, i in zip(self.grid, sub, strict=True)}
        rng = np.random.default_rng([self.seed, c])
        u = rng.random((len(self.ranges), idx.size))
        return idx, {a.name: a.lo + (a.hi - a.lo) * u[k] for k, a in enumerate(self.ranges)}


def spec_state(spec: SweepSpec) -> dict[str, Any]:
    d = {k: getattr(spec, k) for k in spec.__dataclass_fields__ if k != "sea"}
    d["sea_state"] = _sea_state(spec.sea)
    return d


def spec_from_state(d: Mapping[str, Any]) -> SweepSpec:
    kw = {k: v for k, v in d.items() if k != "sea_state"}
    return SweepSpec(sea=_sea_from_state(d["sea_state"]), **kw)
