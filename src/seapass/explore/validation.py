"""Validation of the view the browser sends: a state, or one message per field.

`check_state` checks every field with seapass's safe parser (an `ast`
whitelist for expressions; numbers with finiteness and range checks, see
`seapass.explore.state.LIMITS`) and returns a normalized
[`ExploreState`][seapass.explore.state.ExploreState] or the messages, so each can
be shown next to its box.  Nothing here evaluates user text.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from ..errors import SeapassError
from ..model.catalog import REFERENCE_VALUES
from ..model.expr import STANDARD_SYMBOLS, parse_expression
from ..model.latency import check_latency
from .robustview import parse_box
from .sliders import default_range, names_in, slider_gains
from .state import (
    ELEMENTS,
    EXPERIMENT_DEFAULTS,
    LIMITS,
    PARAM_NAME,
    RESERVED_NAMES,
    UNSAFE_NAME_CHARS,
    ExploreState,
)

__all__ = ["StateCheck", "check_state"]


@dataclass(frozen=True, kw_only=True)
class StateCheck:
    """Result of `check_state`: a state, or one message per offending field."""

    state: ExploreState | None
    errors: Mapping[str, str]

    def to_json(self) -> dict[str, Any]:
        return {
            "ok": self.state is not None,
            "state": None if self.state is None else self.state.to_json(),
            "errors": dict(self.errors),
        }


def _number(raw: Any, key: str, errors: dict[str, str]) -> float | None:
    if isinstance(raw, bool) or not isinstance(raw, int | float | str):
        errors[key] = f"expected a number, got {type(raw).__name__}"
        return None
    if isinstance(raw, str):
        if len(raw) > 64:
            errors[key] = "not a number (too long)"
            return None
        try:
            val = float(raw.strip())
        except ValueError:
            errors[key] = f"{raw.strip()!r} is not a number"
            return None
    else:
        val = float(raw)
    if not math.isfinite(val):
        errors[key] = "must be finite"
        return None
    if abs(val) > LIMITS["abs_value"]:
        errors[key] = f"|value| must be at most {LIMITS['abs_value']:g}"
        return None
    return val


def _bounded(raw: Any, key: str, errors: dict[str, str], unit: str) -> float | None:
    lo, hi = LIMITS[key]
    val = _number(raw, key, errors)
    if val is not None and not lo <= val <= hi:
        errors[key] = f"must be between {lo:g} and {hi:g} {unit}"
        return None
    return val


def _optional(raw: Any) -> bool:
    return raw is None or (isinstance(raw, str) and raw.strip().lower() in ("", "off", "none"))


def check_state(data: Any) -> StateCheck:
    """Validate a view sent by the browser.

    Missing fields get defaults (a parameter new to the model gets the paper's
    reference value, or 1, and a default range), values outside their slider
    range widen the range, and a selection that no longer exists moves to the
    first controller gain.

    Parameters
    ----------
    data : mapping
        JSON object with the keys of `ExploreState.to_json`; numbers may
        be given as text (as typed in a box).

    Returns
    -------
    StateCheck
        ``errors`` maps field keys such as ``"model.CL"``, ``"values.kd"`` or
        ``"period"`` to one-line messages.

    Examples
    --------
    >>> check = check_state({"model": {"D1": "k1", "CL": "kd"}, "values": {"kd": "2e3"}})
    >>> check.state.values["kd"], check.state.gain, check.state.ranges["kd"]
    (2000.0, 'kd', (0.0, 20000.0))
    >>> dict(check_state({"model": {"D1": "k1 +"}}).errors)
    {'model.D1': "cannot parse expression 'k1 +': invalid syntax"}
    """
    errors: dict[str, str] = {}
    if not isinstance(data, Mapping):
        return StateCheck(state=None, errors=MappingProxyType({"state": "expected a JSON object"}))
    model_in = data.get("model", {})
    if not isinstance(model_in, Mapping):
        model_in = {}
        errors["model"] = "expected an object with D1, D2, CA, CL"
    values_in = data.get("values", {})
    if not isinstance(values_in, Mapping):
        values_in = {}
        errors["values"] = "expected an object of parameter values"
    ranges_in = data.get("ranges", {})
    if not isinstance(ranges_in, Mapping):
        ranges_in = {}

    # values typed so far (validated below, only for the parameters the model uses)
    known = {str(k) for k in values_in if isinstance(k, str) and PARAM_NAME.match(k)}
    model: dict[str, str] = {}
    used: list[str] = ["m", "b"]
    new: list[str] = []
    for key in ELEMENTS:
        raw = model_in.get(key, "0")
        if not isinstance(raw, str):
            errors[f"model.{key}"] = f"expected text, got {type(raw).__name__}"
            continue
        text = raw.strip() or "0"
        if len(text) > LIMITS["text"]:
            errors[f"model.{key}"] = f"{len(text)} characters; the limit is {LIMITS['text']}"
            continue
        names = names_in(text)
        fresh = [
            n
            for n in names
            if n not in STANDARD_SYMBOLS and n not in known and PARAM_NAME.match(n)
            if n not in RESERVED_NAMES
        ]
        try:
            parse_expression(text, {*STANDARD_SYMBOLS, *known, *fresh})
        except SeapassError as exc:
            errors[f"model.{key}"] = str(exc)
            continue
        model[key] = text
        for n in names:
            if n not in used:
                used.append(n)
        new += [n for n in fresh if n not in new]
    if len(used) > LIMITS["parameters"]:
        errors["model"] = f"{len(used)} parameters; the limit is {LIMITS['parameters']}"

    values: dict[str, float] = {}
    for name in used:
        if name in values_in:
            val = _number(values_in[name], f"values.{name}", errors)
            if val is not None:
                values[name] = val
        else:
            values[name] = float(REFERENCE_VALUES.get(name, 1.0))
    if "m" in values and values["m"] <= 0:
        errors["values.m"] = "the actuator mass must be positive"

    plant_in = data.get("plant", [])
    plant = tuple(
        sorted({p for p in plant_in if isinstance(p, str) and p in values})
        if isinstance(plant_in, list | tuple)
        else ()
    )
    gains = slider_gains(model, values, plant)
    ranges: dict[str, tuple[float, float]] = {}
    for name, val in values.items():
        raw = ranges_in.get(name)
        rng: tuple[float, float] | None = None
        if raw is not None:
            if isinstance(raw, list | tuple) and len(raw) == 2:
                lo = _number(raw[0], f"ranges.{name}", errors)
                hi = _number(raw[1], f"ranges.{name}", errors)
                if lo is not None and hi is not None:
                    if lo < hi:
                        rng = (lo, hi)
                    else:
                        errors[f"ranges.{name}"] = f"need lo < hi, got [{lo:g}, {hi:g}]"
            else:
                errors[f"ranges.{name}"] = "expected [lo, hi]"
        if rng is None:
            rng = default_range(name, val, gain=name in gains)
        ranges[name] = (min(rng[0], val), max(rng[1], val))

    conditions: dict[str, Any] = {}
    for key, default in EXPERIMENT_DEFAULTS.items():
        raw = data.get(key, default)
        if key == "step":
            val = _number(raw, key, errors)
            if val is not None and (val == 0 or abs(val) > LIMITS["step"]):
                errors[key] = f"must be nonzero and at most {LIMITS['step']:g} m in size"
                val = None
        else:
            val = _bounded(raw, key, errors, "kg" if key == "load_mass" else "s")
        conditions[key] = val
    period_raw = data.get("period")
    conditions["period"] = (
        None if _optional(period_raw) else _bounded(period_raw, "period", errors, "s")
    )
    delay_raw = data.get("delay")
    delay_raw = 0 if _optional(delay_raw) else delay_raw
    delay = _number(delay_raw, "delay", errors)
    if delay is not None and (delay != int(delay) or not 0 <= delay <= LIMITS["delay"]):
        errors["delay"] = f"must be a whole number of samples from 0 to {LIMITS['delay']}"
    conditions["delay"] = int(delay) if delay is not None and "delay" not in errors else 0
    vf_raw = data.get("velocity_filter")
    conditions["velocity_filter"] = (
        None if _optional(vf_raw) else _bounded(vf_raw, "velocity_filter", errors, "Hz")
    )

    uncertainty = parse_box(data.get("uncertainty"), list(values), errors)  # the box panel
    dt_raw = data.get("delay_time")  # the loop latency of the delay panel
    conditions["delay_time"] = (
        None if _optional(dt_raw) else _bounded(dt_raw, "delay_time", errors, "s")
    )
    if errors:
        return StateCheck(state=None, errors=MappingProxyType(errors))
    name = (
        UNSAFE_NAME_CHARS.sub("-", str(data.get("name", "") or "custom")).strip("-.")[:64]
        or "custom"
    )
    title = str(data.get("title", "") or "")[: LIMITS["title"]]
    params = list(values)
    gain = data.get("gain")
    if gain not in params:
        gain = "kd" if "kd" in gains else (gains[0] if gains else params[-1])
    region_in = data.get("region")
    region = tuple(region_in) if isinstance(region_in, list | tuple) and len(region_in) == 2 else ()
    if (
        len(region) != 2
        or region[0] not in params
        or region[1] not in params
        or region[0] == region[1]
    ):
        x = gain
        # the other gains, then k1 (if the model has one), the other plant parameters, m, b
        hardware = [p for p in ("k1", *params) if p in params and p not in ("m", "b")] + ["m", "b"]
        rest = [g for g in gains if g != x] + [p for p in hardware if p != x and p not in gains]
        region = (x, rest[0])
    try:
        state = ExploreState(
            name=name,
            title=title,
            model=MappingProxyType(model),
            values=MappingProxyType(values),
            ranges=MappingProxyType(ranges),
            gain=str(gain),
            region=(str(region[0]), str(region[1])),
            new_parameters=tuple(new),
            plant=plant,
            uncertainty=MappingProxyType(uncertainty),
            **conditions,
        )
        sea = state.sea()
        state.loop  # noqa: B018 - the filter below the Nyquist frequency of the period
    except SeapassError as exc:
        arg = exc.argument or ""
        if arg in ("period", "delay", "velocity_filter"):
            return StateCheck(state=None, errors=MappingProxyType({arg: str(exc)[len(arg) + 2 :]}))
        return StateCheck(state=None, errors=MappingProxyType({_field_of(str(exc)): str(exc)}))
    try:  # as a design file's [control] delay_time: a controller to delay, no model delay
        check_latency(state.delay_time, sea, key="delay_time")
    except SeapassError as exc:
        return StateCheck(state=None, errors=MappingProxyType({"delay_time": str(exc)}))
    return StateCheck(state=state, errors=MappingProxyType({}))


def _field_of(message: str) -> str:
    """The box a model-level error belongs to (``"D1: ..."`` → ``model.D1``)."""
    for key in ELEMENTS:
        if message.startswith(f"{key}:") or message.startswith(f"{key} has"):
            return f"model.{key}"
    if "D1 = D2 = 0" in message:
        return "model.D1"
    if "mass" in message:
        return "values.m"
    return "model"
