"""What one view of the explorer shows, validated field by field.

The browser sends the whole view as JSON (and keeps it in the URL); the server
checks every field with seapass's safe parser and returns either a normalized
`ExploreState` or one message per offending field, so each message can
be shown next to its box.  Nothing here evaluates user text: expressions go
through `seapass.model.expr.parse_expression` (an `ast` whitelist),
numbers through `float` with finiteness and range checks.
"""

from __future__ import annotations

import json
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from ..errors import ParameterError, SeapassError
from ..files.limits import MAX_DELAY_SECONDS
from ..model.design_file import Design, parse_design
from ..model.experiment import PAPER_EXPERIMENT
from ..model.loop import SampledLoop
from ..model.sea import SEA
from .sliders import default_range, slider_gains, slider_scale

__all__ = [
    "ELEMENTS",
    "LIMITS",
    "ExploreState",
    "default_range",
    "design_export",
    "slider_scale",
]

ELEMENTS = ("D1", "D2", "CA", "CL")
PARAM_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,31}$")
UNSAFE_NAME_CHARS = re.compile(r"[^A-Za-z0-9_.-]+")
RESERVED_NAMES = frozenset({"s", "w", "I", "E", "pi", "oo", "nan", "zoo"})

#: Bounds on every input, checked before any work starts.
LIMITS: Mapping[str, Any] = MappingProxyType(
    {
        "parameters": 16,  # parameters in one model
        "abs_value": 1e12,  # |parameter value| and |range end|
        "load_mass": (1e-6, 1e6),  # kg
        "step": 1e3,  # |step| in m
        "horizon": (1e-3, 1e4),  # s
        "period": (1e-5, 1.0),  # s
        "delay": 50,  # samples
        "velocity_filter": (1e-3, 1e7),  # Hz
        "text": 2000,  # characters of one expression
        "title": 200,  # characters
        "delay_time": (0.0, MAX_DELAY_SECONDS),  # s, the loop latency ([control] delay_time)
    }
)

EXPERIMENT_DEFAULTS = {k: getattr(PAPER_EXPERIMENT, k) for k in ("load_mass", "step", "horizon")}


@dataclass(frozen=True)
class ExploreState:
    """A validated view: model, values, slider ranges, selections and test conditions.

    Attributes
    ----------
    name, title : str
        Design name (letters, digits, ``- _ .``) and free-text title.
    model : mapping of str to str
        ``D1, D2, CA, CL`` as safe text (``"0"`` when absent).
    values : mapping of str to float
        A value for every parameter the model uses, ``m`` and ``b`` included.
    ranges : mapping of str to (float, float)
        Slider range of every parameter; it always contains the value.
    gain : str
        Parameter whose exact passive interval is shown.
    region : (str, str)
        Parameters on the x and y axes of the 2-D passive region.
    load_mass, step, horizon : float
        Step-response test: load mass (kg), reference step (m), simulated time (s).
    period : float or None
        Control period (s) of the sampled verdict; None for continuous control only.
    delay : int
        Computational delay (samples).
    velocity_filter : float or None
        Cut-off (Hz) of the velocity low-pass, None for none.
    loop : SampledLoop or None
        The three as the sampled loop (None for continuous control only).
    plant : tuple of str
        Parameters declared part of the hardware (a design file's ``[plant]``)
        besides ``m b k1 k2 b1 b2`` and those of ``D1``, ``D2``: plant parameters
        get the slider range of a fixed value and are never the default gain.
    uncertainty : mapping of str to (float, float)
        A box of uncertain parameters (a design file's ``[uncertainty]``): the
        ``robust`` panel's verdict ([`seapass.explore.robustview`][seapass.explore.robustview]).
    delay_time : float or None
        Loop latency [s] (a design file's ``[control] delay_time``; None: not stated):
        the ``delay`` panel's verdict for every delay up to it
        ([`seapass.explore.delay_panel`][seapass.explore.delay_panel]).
    """

    name: str
    model: Mapping[str, str]
    values: Mapping[str, float]
    ranges: Mapping[str, tuple[float, float]]
    gain: str
    region: tuple[str, str]
    title: str = ""
    load_mass: float = PAPER_EXPERIMENT.load_mass
    step: float = PAPER_EXPERIMENT.step
    horizon: float = PAPER_EXPERIMENT.horizon
    period: float | None = None
    delay: int = 0
    velocity_filter: float | None = None
    new_parameters: tuple[str, ...] = field(default=(), compare=False)
    plant: tuple[str, ...] = ()
    uncertainty: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    delay_time: float | None = None

    def __post_init__(self) -> None:  # every panel looks these names up
        if len(set(self.region)) != 2 or not {self.gain, *self.region} <= {*self.ranges}:
            raise ParameterError(
                f"gain {self.gain!r} and region {self.region!r} must be two different "
                f"parameters of the model ({', '.join(self.values)})"
            )

    @property
    def parameters(self) -> tuple[str, ...]:
        return tuple(self.values)

    @property
    def gains(self) -> tuple[str, ...]:
        """Parameters of the controllers ``CA`` and ``CL`` that are not plant parameters."""
        return slider_gains(self.model, self.values, self.plant)

    def sea(self) -> SEA:
        return SEA(**dict(self.model), values=dict(self.values), name=self.name, plant=self.plant)

    @property
    def loop(self) -> SampledLoop | None:
        p, d, f = self.period, self.delay, self.velocity_filter
        return None if p is None else SampledLoop(period=p, delay=d, velocity_filter=f)

    def key(self, *, without: tuple[str, ...] = (), extra: tuple[str, ...] = ()) -> str:
        """Canonical text of the model, the values except ``without`` and the fields ``extra``."""
        data: dict[str, Any] = {
            "model": dict(self.model),
            "values": {k: v for k, v in self.values.items() if k not in without},
        }
        for name in extra:
            data[name] = getattr(self, name)
        return json.dumps(data, sort_keys=True)

    def to_json(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "title": self.title,
            "model": dict(self.model),
            "values": dict(self.values),
            "ranges": {k: list(v) for k, v in self.ranges.items()},
            "scales": {k: slider_scale(*v) for k, v in self.ranges.items()},
            "gains": list(self.gains),
            "gain": self.gain,
            "region": list(self.region),
            "load_mass": self.load_mass,
            "step": self.step,
            "horizon": self.horizon,
            "period": self.period,
            "delay": self.delay,
            "velocity_filter": self.velocity_filter,
            "new_parameters": list(self.new_parameters),
            "plant": list(self.plant),
            "uncertainty": {k: list(v) for k, v in self.uncertainty.items()},
            "delay_time": self.delay_time,
        }

    def design(self) -> Design:
        """The design file content of this view (ranges kept for the controller gains).

        The box (``[uncertainty]``) and the loop latency (``[control] delay_time``) go
        along, so the file decides the same robust and delayed questions as the view.

        Raises
        ------
        FileFormatError
            When the view does not make a design file, e.g. a value moved outside its
            ``[uncertainty]`` interval (the message names ``uncertainty.NAME``).
        """
        return Design(
            name=self.name,
            title=self.title,
            D1=self.model["D1"],
            D2=self.model["D2"],
            CA=self.model["CA"],
            CL=self.model["CL"],
            values=dict(self.values),
            ranges={k: self.ranges[k] for k in self.gains},
            load_masses=(self.load_mass,),
            step=self.step,
            horizon=self.horizon,
            tune_mass=self.load_mass,
            loop=self.loop,
            plant=self.plant,
            delay_time=self.delay_time,
            uncertainty=dict(self.uncertainty),
        )

    def design_toml(self) -> str:
        """TOML text that ``seapass analyze`` accepts; checked by parsing it back."""
        d = self.design()
        lines = [
            "# written by `seapass explore`",
            f"name = {_toml_str(d.name)}",
            f"title = {_toml_str(d.title)}",
            "",
            "[model]",
            *(f"{k} = {_toml_str(getattr(d, k))}" for k in ELEMENTS),
            "",
            "[parameters]",
            *(f"{k} = {_toml_float(v)}" for k, v in d.values.items() if k not in d.plant),
        ]
        if d.plant:
            lines += ["", "[plant]", *(f"{k} = {_toml_float(d.values[k])}" for k in d.plant)]
        if d.ranges:
            lines += ["", "[ranges]"]
            lines += [
                f"{k} = [{_toml_float(lo)}, {_toml_float(hi)}]" for k, (lo, hi) in d.ranges.items()
            ]
        lines += [
            "",
            "[simulation]",
            f"load_masses = [{_toml_float(self.load_mass)}]",
            f"step = {_toml_float(d.step)}",
            f"horizon = {_toml_float(d.horizon)}",
            f"tune_mass = {_toml_float(self.load_mass)}",
        ]
        if d.uncertainty:
            lines += ["", "[uncertainty]"]
            lines += [
                f"{k} = [{_toml_float(lo)}, {_toml_float(hi)}]"
                for k, (lo, hi) in d.uncertainty.items()
            ]
        control = {} if d.loop is None else dict(d.loop.to_table())
        if d.delay_time is not None:
            control["delay_time"] = d.delay_time
        if control:
            lines += ["", "[control]"]
            lines += [  # rate or period, delay, velocity filter, latency (the method is Tustin)
                f"{k} = {_toml_value(v)}" for k, v in control.items()
            ]
        text = "\n".join(lines) + "\n"
        parse_design(tomllib.loads(text))  # what we write must load (nominal values in the box)
        return text


def design_export(state: ExploreState) -> dict[str, Any]:
    """The "Export design" answer: ``{"ok", "filename", "text"}`` or ``{"ok", "errors", "error"}``.

    The file keeps the view's box and loop latency (`ExploreState.design_toml`); a view
    that makes no design file (a value dragged outside its ``[uncertainty]`` interval)
    is refused with the message under the field it names (``uncertainty.m``).
    """
    try:
        text = state.design_toml()
    except SeapassError as exc:
        message = str(exc)
        where = message.split(":", 1)[0] if ":" in message else "model"
        return {"ok": False, "errors": {where: message}, "error": message}
    return {"ok": True, "filename": f"{state.name}.toml", "text": text}


def _toml_str(text: str) -> str:
    return json.dumps(text, ensure_ascii=False)  # a JSON string is a valid TOML basic string


def _toml_float(value: float) -> str:
    return repr(float(value))


def _toml_value(value: Any) -> str:
    """A ``[control]`` value: float, whole number or text."""
    if isinstance(value, str):
        return _toml_str(value)
    return _toml_float(value) if isinstance(value, float) else str(value)
