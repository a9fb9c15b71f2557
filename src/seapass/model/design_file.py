"""A user's SEA design as a strict TOML file, loaded into a frozen `Design`.

Format (every section but ``[model]`` and ``[parameters]`` is optional)::

    name = "ours"                       # short identifier (letters, digits, - _ .)
    title = "Damped spring + actuator-side PD"

    [model]                             # rational functions of s, safe text
    D1 = "k1 + b1*s"                    # transmission
    D2 = "0"                            # load to ground
    CA = "kd + bd*s"                    # actuator-side controller
    CL = "0"                            # load-side controller

    [parameters]                        # a value for every symbol used, m and b included
    m = 1.0
    b = 10.0
    k1 = 1000.0
    b1 = 20.0
    kd = 500.0
    bd = 25.0

    [ranges]                            # search ranges [lo, hi] for the passive sets
    kd = [0.0, 5000.0]

    [simulation]
    load_masses = [1.0, 10.0, 25.0]     # kg
    step = 0.5                          # m
    horizon = 10.0                      # s
    tune_mass = 10.0                    # kg; default: the median load mass

    [environment]                       # who or what holds the port, for the witness
    mass = [0.1, 10.0]                  # kg      (default: a human limb, 0.1-10 kg)
    damping = [0.0, 100.0]              # N*s/m   (default 0-100)
    stiffness = [0.0, 5000.0]           # N/m     (default 0-5000)

    [control]                           # sampled-data (digital) controller
    rate = 500.0                        # Hz (or period = 0.002, in s)
    delay = 0                           # samples
    velocity_filter = 50.0              # Hz, first-order low-pass on velocity
    method = "tustin"                   # or "zoh", "backward"

    [rig]
    file = "my_rig.toml"                # relative to the design file, or preset = "paper"

Validation is strict: an unknown key, a wrong type, a missing field or a
value out of range raises [`FileFormatError`][seapass.errors.FileFormatError] naming the
key (e.g. ``parameters.kd``), so a typo never falls back to a default.  Sizes are
capped at load time (file size, nesting, list lengths, text lengths, delay and
horizon: see [`seapass.files.limits`][seapass.files.limits]); the sampling rate
is 1 Hz to 1 MHz and the velocity filter stays below the Nyquist frequency (the
``[control]`` table is read by
[`SampledLoop.from_table`][seapass.model.loop.SampledLoop.from_table], the same
spelling as a rig file's).  What ``[simulation]`` leaves out comes from the paper's
experiment, [`PAPER_EXPERIMENT`][seapass.model.experiment.PAPER_EXPERIMENT].
Expressions go through the safe parser of [`seapass.model.expr`][seapass.model.expr].
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from ..errors import FileFormatError, SeapassError
from ..files.limits import (
    MAX_HORIZON,
    MAX_LIST_LENGTH,
    MAX_NAME_CHARS,
    MAX_TEXT_FILE_BYTES,
    MAX_TITLE_CHARS,
)
from ..files.textfile import check_input_file
from ..files.toml import load_toml_file
from .display import html_card, short_repr
from .experiment import PAPER_EXPERIMENT
from .loop import LOOP_KEYS, LoopAttributes, SampledLoop
from .sea import SEA

__all__ = ["Design", "load_design", "parse_design"]

_TOP = ("name", "title", "model", "parameters", "ranges", "simulation", "environment", "control",
        "rig")  # fmt: skip
_ENVIRONMENT = ("mass", "damping", "stiffness")
_MODEL = ("D1", "D2", "CA", "CL")
_SIM = ("load_masses", "step", "horizon", "tune_mass")
_RIG = ("file", "preset")
_NAME = re.compile(rf"^[A-Za-z0-9_.-]{{1,{MAX_NAME_CHARS}}}$")
_PARAM = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,31}$")
_MAX_MASS = 1e6  # kg
_MAX_STEP = 100.0  # m


@dataclass(frozen=True, repr=False)
class Design(LoopAttributes):
    """A complete SEA design: model, parameter values, ranges and test conditions.

    Attributes
    ----------
    name, title : str
    D1, D2, CA, CL : str
        Element expressions (rational in ``s``), ``"0"`` when absent.
    values : mapping of str to float
        A value for every parameter the model uses, ``m`` and ``b`` included.
    ranges : mapping of str to (float, float)
        Search ranges of the passive sets; parameters of ``CA``/``CL`` without
        an explicit range get a default (see `analysis_ranges`).
    load_masses : tuple of float
        Load masses (kg) for the step responses.
    step, horizon : float
        Reference step (m) and simulated time (s).
    tune_mass : float or None
        Load mass (kg) the gains are tuned at; None means the median load mass.
    loop : SampledLoop or None
        The digital controller's loop (``[control]``); None: continuous only.
    rig_file : str or None
        Rig TOML path (resolved against the design file) or ``"paper"``.
    environment : mapping of str to (float, float)
        Bounds of the environments the witness may use (``mass``, ``damping``,
        ``stiffness``); those not given keep the human-limb default of
        [`seapass.analysis.environment_box.HUMAN_LIMB`][seapass.analysis.environment_box.HUMAN_LIMB].
    """

    name: str
    D1: str
    CA: str
    values: Mapping[str, float]
    D2: str = "0"
    CL: str = "0"
    title: str = ""
    ranges: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    load_masses: tuple[float, ...] = PAPER_EXPERIMENT.load_masses
    step: float = PAPER_EXPERIMENT.step
    horizon: float = PAPER_EXPERIMENT.horizon
    tune_mass: float | None = None
    loop: SampledLoop | None = None
    rig_file: str | None = None
    environment: Mapping[str, tuple[float, float]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not _NAME.match(self.name):
            raise FileFormatError(
                f"name: {self.name!r} must be 1-64 letters, digits, '-', '_' or '.'"
            )
        _text(self.title, "title", MAX_TITLE_CHARS)
        object.__setattr__(self, "values", MappingProxyType(dict(self.values)))
        object.__setattr__(
            self, "ranges", MappingProxyType({k: tuple(v) for k, v in self.ranges.items()})
        )
        object.__setattr__(
            self, "environment",
            MappingProxyType({k: tuple(v) for k, v in self.environment.items()}),
        )  # fmt: skip
        if self.loop is not None and not isinstance(self.loop, SampledLoop):
            raise FileFormatError(f"loop: expected a SampledLoop, got {type(self.loop).__name__}")
        for key in ("m", "b"):
            if key not in self.values:
                raise FileFormatError(f"missing parameters.{key} (actuator mass / damping)")
        try:
            sea = self.sea()
        except SeapassError as exc:
            raise FileFormatError(_in_file_terms(exc)) from None
        missing = [p for p in sea.parameters if p not in self.values]
        if missing:
            raise FileFormatError(
                f"missing parameters.{missing[0]}: the model uses {', '.join(sea.parameters)}"
            )
        unused = sorted(set(self.values) - set(sea.parameters) - {"m", "b"})
        if unused:
            raise FileFormatError(
                f"parameters.{unused[0]} is not used by the model "
                f"(it uses {', '.join(sea.parameters)})"
            )
        for name, (lo, hi) in self.ranges.items():
            if name not in sea.parameters:
                raise FileFormatError(
                    f"ranges.{name}: not a parameter of the model ({', '.join(sea.parameters)})"
                )
            if not lo < hi:
                raise FileFormatError(f"ranges.{name}: need lo < hi, got [{lo}, {hi}]")
        if not self.load_masses:
            raise FileFormatError("simulation.load_masses must not be empty")

    def __repr__(self) -> str:
        elements = {
            k: getattr(self, k) for k in ("D1", "D2", "CA", "CL") if getattr(self, k) != "0"
        }
        return short_repr("Design", {"name": self.name, **elements, "values": dict(self.values)})

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [(k, getattr(self, k)) for k in ("D1", "D2", "CA", "CL")]
        rows += list(self.values.items())
        rows += [(f"range of {k}", f"[{lo:g}, {hi:g}]") for k, (lo, hi) in self.ranges.items()]
        if self.loop is not None:
            rows.append(("control rate", f"{self.loop.rate:g} Hz"))
        return html_card(f"Design {self.name}" + (f": {self.title}" if self.title else ""), rows)

    def sea(self) -> SEA:
        """The [`SEA`][seapass.model.sea.SEA] with every value of the file."""
        return SEA(
            D1=self.D1,
            D2=self.D2,
            CA=self.CA,
            CL=self.CL,
            values=dict(self.values),
            name=self.name,
        )

    @property
    def gains(self) -> tuple[str, ...]:
        """Parameters of the controllers ``CA`` and ``CL``, sorted."""
        sea = self.sea()
        syms = sea.CA.free_symbols | sea.CL.free_symbols
        return tuple(sorted(str(x) for x in syms if str(x) != "s"))

    @property
    def period(self) -> float | None:
        """Control period (s), or None for a continuous controller."""
        return None if self.loop is None else self.loop.period

    @property
    def control_rate(self) -> float | None:
        """Sampling rate (Hz) of the digital controller, or None (``loop.rate``)."""
        return None if self.loop is None else self.loop.rate

    @property
    def control_delay(self) -> int:
        """Computational delay (samples), 0 without a loop (``loop.delay``)."""
        return self.delay

    @property
    def tuning_mass(self) -> float:
        """Load mass used for tuning (kg)."""
        if self.tune_mass is not None:
            return self.tune_mass
        ordered = sorted(self.load_masses)
        return ordered[len(ordered) // 2]

    def analysis_ranges(self) -> dict[str, tuple[float, float]]:
        """Explicit ranges plus a default ``[0, max(10·value, 1000)]`` for every gain."""
        out = dict(self.ranges)
        for g in self.gains:
            if g not in out:
                out[g] = (0.0, max(10.0 * abs(self.values[g]), 1000.0))
        return dict(sorted(out.items()))

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "title": self.title,
            "model": {"D1": self.D1, "D2": self.D2, "CA": self.CA, "CL": self.CL},
            "parameters": dict(self.values),
            "ranges": {k: list(v) for k, v in self.ranges.items()},
            "simulation": {
                "load_masses": list(self.load_masses),
                "step": self.step,
                "horizon": self.horizon,
                "tune_mass": self.tuning_mass,
            },
            "control": {
                "rate": self.control_rate,
                "delay": self.control_delay,
                "velocity_filter": self.velocity_filter,
            },
            "environment": {k: list(v) for k, v in self.environment.items()},
            "rig": self.rig_file,
        }


def _in_file_terms(exc: SeapassError) -> str:
    """An `SEA` error in the words of the file: ``parameters.kd``, not ``values['kd']``."""
    msg = str(exc)
    arg = exc.argument or ""
    m = re.fullmatch(r"values\['(\w+)'\]", arg)
    if m and msg.startswith(f"{arg}: "):
        return f"parameters.{m.group(1)}: {msg[len(arg) + 2 :]}"
    msg = re.sub(r"e\.g\. values=\{'(\w+)': [^}]*\}", r"add \1 to [parameters]", msg)
    if arg in _MODEL and msg.startswith(f"{arg}: "):
        return f"model.{msg}"
    return f"model: {msg}"


def _table(data: Any, key: str) -> dict[str, Any]:
    if not isinstance(data, dict):
        raise FileFormatError(f"[{key}] must be a table, got {type(data).__name__}")
    return data


def _unknown(table: Mapping[str, Any], allowed: tuple[str, ...], section: str) -> None:
    extra = sorted(set(table) - set(allowed))
    if extra:
        where = f"{section}.{extra[0]}" if section else extra[0]
        raise FileFormatError(f"unknown key {where}; allowed: {', '.join(allowed)}")


def _number(value: Any, key: str, *, positive: bool = False, nonneg: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise FileFormatError(f"{key}: expected a number, got {type(value).__name__} {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise FileFormatError(f"{key}: must be finite, got {value!r}")
    if positive and v <= 0:
        raise FileFormatError(f"{key}: must be positive, got {value!r}")
    if nonneg and v < 0:
        raise FileFormatError(f"{key}: must be >= 0, got {value!r}")
    return v


def _string(value: Any, key: str) -> str:
    if not isinstance(value, str):
        raise FileFormatError(f"{key}: expected a string, got {type(value).__name__} {value!r}")
    return value


def _text(value: Any, key: str, limit: int) -> str:
    """A one-line human-readable text of at most ``limit`` characters."""
    text = _string(value, key)
    if len(text) > limit:
        raise FileFormatError(f"{key}: {len(text):,} characters; the limit is {limit}")
    bad = next((ch for ch in text if not (ch.isprintable() or ch == "\t")), None)
    if bad is not None:
        raise FileFormatError(
            f"{key}: contains the control character U+{ord(bad):04X}; use one line of plain text"
        )
    return text


def _bounded(value: Any, key: str, lo: float, hi: float, *, open_lo: bool = True) -> float:
    """A number in ``(lo, hi]`` (or ``[lo, hi]`` with ``open_lo=False``)."""
    v = _number(value, key)
    if (v <= lo if open_lo else v < lo) or v > hi:
        bracket = "(" if open_lo else "["
        raise FileFormatError(f"{key}: {value!r} is out of range {bracket}{lo:g}, {hi:g}]")
    return v


def parse_design(data: Mapping[str, Any], *, base_dir: str | os.PathLike[str] = ".") -> Design:
    """Validate a parsed TOML document and build a `Design`.

    Parameters
    ----------
    data : mapping
        The document, as returned by `tomllib.loads`.
    base_dir : path-like
        Directory that a relative ``rig.file`` is resolved against.

    Raises
    ------
    FileFormatError
        Naming the key for unknown keys, wrong types, missing fields or bad values.
    """
    data = _table(data, "design")
    _unknown(data, _TOP, "")
    for key in ("name", "model", "parameters"):
        if key not in data:
            raise FileFormatError(f"missing required key {key}")
    kw: dict[str, Any] = {"name": _string(data["name"], "name")}
    if "title" in data:
        kw["title"] = _text(data["title"], "title", MAX_TITLE_CHARS)
    model = _table(data["model"], "model")
    _unknown(model, _MODEL, "model")
    if "D1" not in model and "D2" not in model:
        raise FileFormatError('missing model.D1 (the transmission, e.g. "k1 + b1*s")')
    for key in _MODEL:
        text = _string(model.get(key, "0"), f"model.{key}")
        if not text.strip():
            raise FileFormatError(f'model.{key}: empty expression (write "0" for none)')
        kw[key] = text
    params = _table(data["parameters"], "parameters")
    values: dict[str, float] = {}
    for name, v in params.items():
        if not _PARAM.match(name) or name in ("s", "w", "I", "E", "pi", "oo"):
            raise FileFormatError(f"parameters.{name}: not a valid parameter name")
        values[name] = _number(v, f"parameters.{name}")
    if "m" in values and values["m"] <= 0:
        raise FileFormatError(
            f"parameters.m: the actuator mass must be positive, got {values['m']}"
        )
    kw["values"] = values
    if "ranges" in data:
        ranges = {}
        for name, v in _table(data["ranges"], "ranges").items():
            key = f"ranges.{name}"
            if not isinstance(v, list) or len(v) != 2:
                raise FileFormatError(f"{key}: expected [lo, hi], got {v!r}")
            ranges[name] = (_number(v[0], f"{key}[0]"), _number(v[1], f"{key}[1]"))
        kw["ranges"] = ranges
    if "simulation" in data:
        sim = _table(data["simulation"], "simulation")
        _unknown(sim, _SIM, "simulation")
        if "load_masses" in sim:
            masses = sim["load_masses"]
            if not isinstance(masses, list) or not masses:
                raise FileFormatError("simulation.load_masses: expected a non-empty list of kg")
            if len(masses) > MAX_LIST_LENGTH:
                raise FileFormatError(
                    f"simulation.load_masses: {len(masses):,} masses; the limit is "
                    f"{MAX_LIST_LENGTH}"
                )
            kw["load_masses"] = tuple(
                _bounded(m, f"simulation.load_masses[{i}]", 0.0, _MAX_MASS)
                for i, m in enumerate(masses)
            )
        if "step" in sim:
            kw["step"] = _number(sim["step"], "simulation.step")
            if kw["step"] == 0 or abs(kw["step"]) > _MAX_STEP:
                raise FileFormatError(
                    f"simulation.step: {sim['step']!r} m must be nonzero and at most "
                    f"{_MAX_STEP:g} m in size"
                )
        if "horizon" in sim:
            kw["horizon"] = _bounded(sim["horizon"], "simulation.horizon", 0.0, MAX_HORIZON)
        if "tune_mass" in sim:
            kw["tune_mass"] = _bounded(sim["tune_mass"], "simulation.tune_mass", 0.0, _MAX_MASS)
    if "environment" in data:
        kw["environment"] = _environment(_table(data["environment"], "environment"))
    if "control" in data:
        ctl = _table(data["control"], "control")
        _unknown(ctl, LOOP_KEYS, "control")
        kw["loop"] = SampledLoop.from_table(ctl)
    if "rig" in data:
        rig = _table(data["rig"], "rig")
        _unknown(rig, _RIG, "rig")
        if ("file" in rig) == ("preset" in rig):
            raise FileFormatError("rig: give exactly one of rig.file and rig.preset")
        if "preset" in rig:
            preset = _string(rig["preset"], "rig.preset")
            if preset != "paper":
                raise FileFormatError(f'rig.preset: only "paper" is known, got {preset!r}')
            kw["rig_file"] = "paper"
        else:
            path = Path(_string(rig["file"], "rig.file"))
            full = path if path.is_absolute() else Path(base_dir) / path
            try:  # a rig file is read later: refuse a device, a FIFO or a huge file now
                check_input_file(full, max_bytes=MAX_TEXT_FILE_BYTES, what="rig file")
            except OSError as exc:
                raise FileFormatError(f"rig.file: {full}: {exc.strerror}") from None
            except FileFormatError as exc:
                raise FileFormatError(f"rig.file: {exc}") from None
            kw["rig_file"] = str(full)
    return Design(**kw)


def _environment(table: Mapping[str, Any]) -> dict[str, tuple[float, float]]:
    _unknown(table, _ENVIRONMENT, "environment")
    out = {}
    for name, v in table.items():
        key = f"environment.{name}"
        if not isinstance(v, list) or len(v) != 2:
            raise FileFormatError(f"{key}: expected [lo, hi], got {v!r}")
        lo, hi = _number(v[0], f"{key}[0]", nonneg=True), _number(v[1], f"{key}[1]", nonneg=True)
        if not lo <= hi:
            raise FileFormatError(f"{key}: need lo <= hi, got [{lo}, {hi}]")
        out[name] = (lo, hi)
    return out


def load_design(path: str | os.PathLike[str]) -> Design:
    """Read and validate a design TOML file.

    Raises
    ------
    FileFormatError
        For invalid TOML or content (the message starts with the file name).
    OSError
        If the file cannot be read.
    """
    p = Path(path)
    return load_toml_file(p, lambda data: parse_design(data, base_dir=p.parent), what="design file")
