"""A user's SEA design as a strict TOML file, loaded into a frozen `Design`.

Format (every section but ``[model]`` and ``[parameters]`` is optional)::

    name = "ours"                       # short identifier (letters, digits, - _ .)
    title = "Damped spring + actuator-side PD"

    [model]                             # rational functions of s, safe text: D1 (transmission),
    D1 = "k1 + b1*s"                    # D2 (load to ground), CA and CL (actuator-/load-side
    CA = "kd + bd*s"                    # controller: f_A = CA*(theta - x_A) + CL*(theta - x_L))

    [parameters]                        # a value for every symbol used, m and b included
    m = 1.0
    b = 10.0
    k1 = 1000.0
    b1 = 20.0
    kd = 500.0
    bd = 25.0

The optional tables: ``[ranges]`` (search ranges ``kd = [0.0, 5000.0]``),
``[simulation]`` (``load_masses`` kg, ``step`` m, ``horizon`` s, ``tune_mass`` kg, default the
median load mass), ``[environment]`` (``mass``, ``damping``, ``stiffness`` ranges of the
witness search; default a human limb), ``[control]`` (the digital controller: ``rate`` Hz or
``period`` s, ``delay`` samples, ``velocity_filter`` Hz, ``method`` ``"tustin"``, ``"zoh"`` or
``"backward"``; ``delay_time`` s, a loop latency: [`seapass.model.latency`][seapass.model.latency]),
``[rig]`` (``file`` relative to the design file, or ``preset = "paper"``), ``[units]``
(``ki = "1/s"``, [`seapass.model.units`][seapass.model.units]), ``[uncertainty]``
(``m = [0.9, 1.1]``: a robust verdict's box, [`seapass.model.uncertainty`][seapass.model.uncertainty]);
``docs/index.md`` shows a file.

Instead of ``CA`` and ``CL``, a ``[controller]`` table (``kind = "impedance"``,
``force = "kp + ki/s"``, ``impedance = "kv + bv*s"``, ...; its keys are
[`CONTROLLER_FIELDS`][seapass.model.controller.CONTROLLER_FIELDS]) gives the
controller as blocks, compiled exactly into ``CA`` and ``CL``; a ``[discrete]`` table
(``rate``, ``CA``, ``CL`` in ``z``) gives it in z, run as is
([`ZController`][seapass.model.zcontroller.ZController]).  A ``[plant]`` table gives
hardware parameters besides ``m b k1 k2 b1 b2``: fixed, never gains.

Validation is strict: an unknown key, a wrong type, a missing field or a value out of
range raises [`FileFormatError`][seapass.errors.FileFormatError] naming the key (e.g.
``parameters.kd``).  Sizes are capped at load ([`seapass.files.limits`][seapass.files.limits]);
``[control]`` is read by [`SampledLoop.from_table`][seapass.model.loop.SampledLoop.from_table];
what ``[simulation]`` leaves out is [`PAPER_EXPERIMENT`][seapass.model.experiment.PAPER_EXPERIMENT]'s.
Expressions go through the safe parser of [`seapass.model.expr`][seapass.model.expr].
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from ..errors import FileFormatError, ParameterError, SeapassError
from ..files.limits import (
    MAX_HORIZON,
    MAX_NAME_CHARS,
    MAX_TITLE_CHARS,
)
from ..files.schema import Field, check_table, check_value
from ..files.toml import load_toml_file
from .catalog import CATALOG, CatalogDesign
from .catalog import design as catalog_design
from .controller import CONTROLLER_FIELDS, Controller, ControllerDerivation, derive_controller
from .display import html_card, short_repr
from .experiment import PAPER_EXPERIMENT
from .latency import check_latency, latency_sea
from .loop import METHODS, LoopAttributes, SampledLoop
from .rigpath import rig_file_path
from .sea import SEA
from .uncertainty import check_uncertainty
from .units import MAX_UNIT_CHARS, unit_map
from .zcontroller import Z_FIELDS, ZController, discrete_from_file, discrete_loop

__all__ = ["DESIGN_FIELDS", "Design", "load_design", "load_design_or_catalog", "parse_design"]

_ENVIRONMENT = ("mass", "damping", "stiffness")
_MODEL = ("D1", "D2", "CA", "CL")
_NAME = re.compile(rf"^[A-Za-z0-9_.-]{{1,{MAX_NAME_CHARS}}}$")
_PARAM = r"(?!(?:s|w|I|E|pi|oo)$)[A-Za-z][A-Za-z0-9_]{0,31}"  # s, w, I, E, pi, oo are taken
_MAX_MASS = 1e6  # kg
_MAX_STEP = 100.0  # m
_COPIED = ("name", "title", "ranges", "environment", "units", "uncertainty")


@dataclass(frozen=True, repr=False)
class Design(LoopAttributes):
    """A complete SEA design: model, parameter values, ranges and test conditions.

    Attributes
    ----------
    name, title : str
    D1, D2, CA, CL : str
        Element expressions (rational in ``s``), ``"0"`` when absent; with a
        ``controller``, ``CA`` and ``CL`` are derived from it.
    values : mapping of str to float
        A value for every parameter the model uses, ``m`` and ``b`` included
        (``[parameters]`` and ``[plant]``).
    controller : Controller or None
        The controller as blocks (``[controller]``), compiled into ``CA``, ``CL``.
    plant : tuple of str
        Parameters declared in ``[plant]``: hardware, like ``m b k1 k2 b1 b2`` and
        the parameters of ``D1``, ``D2`` (see `plant_parameters`).
    ranges : mapping of str to (float, float)
        Search ranges of the passive sets; parameters of ``CA``/``CL`` without
        an explicit range get a default (see `analysis_ranges`).
    load_masses, step, horizon, tune_mass
        Step responses: load masses (kg), reference step (m), simulated time (s), the
        load mass the gains are tuned at (None: the median load mass).
    loop : SampledLoop or None
        The digital controller's loop (``[control]``); None: continuous only.
    rig_file : str or None
        Rig TOML path (resolved against the design file) or ``"paper"``.
    uncertainty : mapping of str to (float, float)
        ``[uncertainty]``: the box of a robust verdict (checked, sorted by name).
    units : mapping of str to str
        Declared units (``[units]``) of parameters or of ``m_L``, checked by
        [`parse_unit`][seapass.model.units.parse_unit]; see `unit_map`.
    environment : mapping of str to (float, float)
        Witness environments' bounds (``mass``, ``damping``, ``stiffness``; default ``HUMAN_LIMB``).
    delay_time : float or None
        Loop latency [s] (``[control] delay_time``; None: not stated): see `delayed_sea`.
    """

    name: str
    D1: str
    values: Mapping[str, float]
    CA: str = "0"
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
    units: Mapping[str, str] = field(default_factory=dict)
    controller: Controller | None = None
    plant: tuple[str, ...] = ()
    delay_time: float | None = None
    uncertainty: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    discrete: ZController | None = None

    def __post_init__(self) -> None:
        if not _NAME.match(self.name):
            raise FileFormatError(
                f"name: {self.name!r} must be 1-64 letters, digits, '-', '_' or '.'"
            )
        check_value("title", DESIGN_FIELDS["title"], self.title)
        object.__setattr__(self, "values", MappingProxyType(dict(self.values)))
        object.__setattr__(
            self, "ranges", MappingProxyType({k: tuple(v) for k, v in self.ranges.items()})
        )
        for key in ("environment", "uncertainty"):
            pairs = {k: tuple(v) for k, v in getattr(self, key).items()}
            object.__setattr__(self, key, MappingProxyType(pairs))
        if self.loop is not None and not isinstance(self.loop, SampledLoop):
            raise FileFormatError(f"loop: expected a SampledLoop, got {type(self.loop).__name__}")
        for key in [k for k in ("m", "b") if k not in self.values]:
            raise FileFormatError(f"missing parameters.{key} (actuator mass / damping)")
        object.__setattr__(self, "plant", tuple(sorted(set(self.plant))))
        if self.controller is not None:
            if not isinstance(self.controller, Controller):
                raise FileFormatError(f"controller: expected a Controller, got {self.controller!r}")
            for key, text in zip(("CA", "CL"), self.controller.elements(self.values), strict=True):
                if getattr(self, key) not in ("0", text):
                    raise FileFormatError(f"give either [controller] or model.{key}, not both")
                object.__setattr__(self, key, text)
        object.__setattr__(self, "loop", discrete_loop(self.discrete, self.loop, file=True))
        try:
            sea = self.sea()
        except SeapassError as exc:
            raise FileFormatError(_in_file_terms(exc, self.plant)) from None
        missing = [p for p in sea.parameters if p not in self.values]
        if missing:
            raise FileFormatError(
                f"missing parameters.{missing[0]}: the model uses {', '.join(sea.parameters)}"
            )
        unused = sorted(set(self.values) - set(sea.parameters) - {"m", "b"})
        if unused:
            table = "plant" if unused[0] in self.plant else "parameters"
            raise FileFormatError(
                f"{table}.{unused[0]} is not used by the model "
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
        for name in self.units:
            if name not in sea.parameters and name not in ("m", "b", "m_L"):
                raise FileFormatError(
                    f"units.{name}: not a parameter of the model "
                    f"({', '.join((*sea.parameters, 'm_L'))})"
                )
        try:
            units = unit_map(self.units, self.units)
        except SeapassError as exc:
            raise FileFormatError(re.sub(r"^units\['(\w+)'\]", r"units.\1", str(exc))) from None
        object.__setattr__(self, "units", MappingProxyType(units))
        object.__setattr__(self, "delay_time", check_latency(self.delay_time, sea))  # latency
        box = check_uncertainty(self.uncertainty, sea.parameters, self.values, nominal=False)
        object.__setattr__(self, "uncertainty", MappingProxyType(box))  # sorted, checked

    def __repr__(self) -> str:
        elements = {
            k: getattr(self, k) for k in ("D1", "D2", "CA", "CL") if getattr(self, k) != "0"
        }
        return short_repr("Design", {"name": self.name, **elements, "values": dict(self.values)})

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [(k, getattr(self, k)) for k in ("D1", "D2", "CA", "CL")]
        if self.controller is not None:
            rows.insert(2, ("controller", self.controller.kind.description))
        rows += list(self.values.items())
        rows += [(f"range of {k}", f"[{lo:g}, {hi:g}]") for k, (lo, hi) in self.ranges.items()]
        if self.loop is not None:
            rows.append(("control rate", f"{self.loop.rate:g} Hz"))
        return html_card(f"Design {self.name}" + (f": {self.title}" if self.title else ""), rows)

    def sea(self) -> SEA:
        """The [`SEA`][seapass.model.sea.SEA] with every value of the file."""
        elements = {k: getattr(self, k) for k in _MODEL}
        return SEA(
            **elements, values=dict(self.values), name=self.name, plant=self.plant,
            discrete=self.discrete,
        )  # fmt: skip

    def delayed_sea(self) -> SEA:
        """`sea` with C_A, C_L times ``exp(-delay_time*s)`` ([`seapass.model.latency`][seapass.model.latency])."""
        return latency_sea(self)

    def derivation(self) -> ControllerDerivation | None:
        """How ``CA`` and ``CL`` follow from the ``[controller]`` blocks (None without one)."""
        if self.controller is None:
            return None
        return derive_controller(self.controller, parameters=self.values)

    @property
    def gains(self) -> tuple[str, ...]:
        """The controller gains ([`SEA.gains`][seapass.model.sea.SEA.gains]), sorted."""
        return self.sea().gains

    @property
    def plant_parameters(self) -> tuple[str, ...]:
        """The hardware's ([`SEA.plant_parameters`][seapass.model.sea.SEA.plant_parameters])."""
        return self.sea().plant_parameters

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

    def unit_map(self) -> dict[str, str]:
        """The unit of every parameter and of ``m_L``: ``[units]``, else the default, else ``""``."""
        return unit_map(self.units, (*self.sea().parameters, "m_L"))

    def analysis_ranges(self) -> dict[str, tuple[float, float]]:
        """Explicit ranges plus a default ``[0, max(10·value, 1000)]`` for every gain.

        A plant parameter is searched only with an explicit ``[ranges]`` entry.
        """
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
                **({} if self.delay_time is None else {"delay_time": self.delay_time}),
            },
            "environment": {k: list(v) for k, v in self.environment.items()},
            "rig": self.rig_file,
            "units": dict(self.units),
            "controller": None if self.controller is None else self.controller.to_table(),
            "plant": list(self.plant_parameters),
            "uncertainty": {k: list(v) for k, v in self.uncertainty.items()},
            "discrete": None if self.discrete is None else self.discrete.to_table(),
        }


def _in_file_terms(exc: SeapassError, plant: tuple[str, ...] = ()) -> str:
    """An `SEA` error in the words of the file: ``parameters.kd``, not ``values['kd']``."""
    msg = str(exc)
    arg = exc.argument or ""
    m = re.fullmatch(r"values\['(\w+)'\]", arg)
    if m and msg.startswith(f"{arg}: "):
        table = "plant" if m.group(1) in plant else "parameters"
        return f"{table}.{m.group(1)}: {msg[len(arg) + 2 :]}"
    msg = re.sub(r"e\.g\. values=\{'(\w+)': [^}]*\}", r"add \1 to [parameters]", msg)
    if arg in _MODEL and msg.startswith(f"{arg}: "):
        return f"model.{msg}"
    return f"model: {msg}"


_PAIR = Field(tuple)
_MASS = Field(float, 0.0, _MAX_MASS, lo_open=True)
_ENVIRONMENT_RANGE = Field(tuple, 0.0, order="<=", required=False)

DESIGN_FIELDS: dict[str, Field] = {
    "name": Field(str),
    "title": Field(str, hi=MAX_TITLE_CHARS, line=True, required=False),
    "model": Field(dict, fields={k: Field(str, required=False) for k in _MODEL}),
    "parameters": Field(dict, keys=_PARAM, item=Field(float)),
    "plant": Field(dict, keys=_PARAM, item=Field(float), required=False),
    # the controller's own checks (Controller, derive_controller) give the rules between keys
    "controller": Field(dict, required=False, fields=CONTROLLER_FIELDS),
    "discrete": Field(dict, required=False, fields=Z_FIELDS),
    "ranges": Field(dict, keys=_PARAM, item=_PAIR, required=False),
    "uncertainty": Field(dict, keys=_PARAM, item=_PAIR, required=False),
    "simulation": Field(
        dict,
        required=False,
        fields={
            "load_masses": Field(list, 0.0, _MAX_MASS, lo_open=True, min_items=1, required=False),
            "step": Field(float, -_MAX_STEP, _MAX_STEP, nonzero=True, required=False),
            "horizon": Field(float, 0.0, MAX_HORIZON, lo_open=True, required=False),
            "tune_mass": Field(float, 0.0, _MAX_MASS, lo_open=True, required=False),
        },
    ),
    "environment": Field(
        dict, required=False, fields=dict.fromkeys(_ENVIRONMENT, _ENVIRONMENT_RANGE)
    ),
    # the loop's own checks (SampledLoop.from_table) give the ranges and their messages
    "control": Field(
        dict,
        required=False,
        fields={
            **{k: Field(float, required=False) for k in ("rate", "period", "velocity_filter")},
            "delay": Field(int, required=False),
            "method": Field(str, choices=METHODS, required=False),
            "delay_time": Field(float, required=False),  # seconds, see model.latency
        },
    ),
    "units": Field(
        dict, keys=_PARAM, item=Field(str, hi=MAX_UNIT_CHARS, line=True), required=False
    ),
    "rig": Field(
        dict,
        required=False,
        fields={
            "file": Field(str, required=False),
            "preset": Field(str, choices=("paper",), required=False),
        },
    ),
}
"""Every key of a design file, checked by [`check_table`][seapass.files.schema.check_table]."""


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
    doc = check_table(data, DESIGN_FIELDS, what="a design")
    model = doc["model"]
    if "D1" not in model and "D2" not in model:
        raise FileFormatError('missing model.D1 (the transmission, e.g. "k1 + b1*s")')
    kw: dict[str, Any] = {k: doc[k] for k in _COPIED if k in doc}
    for key in _MODEL:
        text = model.get(key, "0")
        if not text.strip():
            raise FileFormatError(f'model.{key}: empty expression (write "0" for none)')
        kw[key] = text
    if "controller" in doc:
        given = [f"model.{k}" for k in ("CA", "CL") if k in model]
        if given:
            raise FileFormatError(
                f"give either [controller] or {' and '.join(given)}, not both: the controller "
                "blocks are compiled into CA and CL"
            )
        kw["controller"] = Controller.from_table(doc["controller"])
    values = dict(doc["parameters"])
    plant = doc.get("plant", {})
    twice = sorted(set(plant) & set(values))
    if twice:
        raise FileFormatError(f"plant.{twice[0]} is also in [parameters]; give it once")
    values.update(plant)
    kw["plant"] = tuple(plant)
    if "m" in values and values["m"] <= 0:
        raise FileFormatError(f"parameters.m: must be positive (actuator mass), got {values['m']}")
    kw["values"] = values
    kw.update(doc.get("simulation", {}))
    kw["delay_time"] = doc.get("control", {}).get("delay_time")
    kw["discrete"] = discrete_from_file(doc) if "discrete" in doc else None
    if set(doc.get("control", {})) - {"delay_time"}:  # only delay_time: no sampled loop
        kw["loop"] = SampledLoop.from_table(doc["control"])
    if "rig" in doc:
        kw["rig_file"] = rig_file_path(doc["rig"], Path(base_dir))
    design = Design(**kw)  # a file's nominal values lie in its [uncertainty]:
    check_uncertainty(design.uncertainty, tuple(design.uncertainty), design.values)
    return design


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


def load_design_or_catalog(name: str | os.PathLike[str]) -> Design | CatalogDesign:
    """The design a user names: a catalog design (``LP``, ``APD``, ``ours``, any case) or a file.

    A catalog name means the catalog's design unless a file of that name
    exists; anything else is read as a design file.

    Raises
    ------
    ParameterError
        For a name that is neither (not a catalog name, and no such ``.toml`` file).
    FileFormatError, OSError
        As `load_design`.

    Examples
    --------
    >>> load_design_or_catalog("apd").key
    'APD'
    """
    path = Path(name)
    if not path.is_file() and str(name).lower() in {k.lower() for k in CATALOG}:
        return catalog_design(str(name))
    if path.suffix != ".toml" and not path.exists():
        raise ParameterError(
            f"design {str(name)!r} is neither a design file nor a catalog name "
            f"({', '.join(CATALOG)})"
        )
    return load_design(path)
