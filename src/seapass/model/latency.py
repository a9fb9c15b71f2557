"""The loop latency of a design file: ``[control] delay_time = τ`` (seconds).

What it means in the model, precisely: the controller acts ``τ`` seconds late on what it
measures, so **both** controllers are delayed,

    C_A(s) → C_A(s)·e^{-sτ},    C_L(s) → C_L(s)·e^{-sτ},

with the delay parameter named `LATENCY_PARAMETER` (``delay_time``) holding the value
``τ``.  The transmission ``D1``, ``D2``, the mass and the damping are hardware and are not
delayed.  This is the same delay that
[`seapass.delay.structure.controller_delay`][seapass.delay.structure.controller_delay]
puts on a delay-free design (``seapass delay-margin NAME DESIGN``), so the margin ``τ*``
of the design and the verdict at its latency speak of one model.

``τ = 0`` is no latency: the model is the file's own (``e^{0} = 1`` exactly), so every
rational analysis still applies; ``τ > 0`` makes the design a delayed design, decided by
[`seapass.delay`][seapass.delay] (certified; undecided is never passive).  A latency is
refused together with a delay written into the model (``exp(-tau*s)``): one delay per
model.  Bounds: ``0 <= τ <= MAX_DELAY_SECONDS`` (in
[`seapass.files.limits`][seapass.files.limits]).

This module imports no sympy and nothing above `seapass.model`.

Examples
--------
>>> latency_elements({"D1": "k1", "CA": "kd + bd*s", "CL": "0"}, 0.002)["CA"]
'(kd + bd*s)*exp(-delay_time*s)'
>>> latency_elements({"D1": "k1", "CA": "kd", "CL": "0"}, 0.0)["CA"]
'kd'
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from ..errors import FileFormatError, ParameterError, SeapassError
from ..files.limits import MAX_DELAY_SECONDS
from .delayatom import model_delays
from .sea import SEA

__all__ = [
    "LATENCY_PARAMETER",
    "check_delay_time",
    "check_latency",
    "latency_elements",
    "latency_sea",
    "latency_values",
]

LATENCY_PARAMETER = "delay_time"
"""The delay parameter of a design's loop latency (``exp(-delay_time*s)`` on ``C_A``, ``C_L``)."""

_DELAYED = ("CA", "CL")


def check_delay_time(value: Any, *, argument: str = "delay_time") -> float:
    """A loop latency in seconds: a finite number in ``[0, MAX_DELAY_SECONDS]``.

    Raises
    ------
    ParameterError
        Naming ``argument`` and the allowed range.

    Examples
    --------
    >>> check_delay_time(0.001)
    0.001
    >>> check_delay_time(-1)
    Traceback (most recent call last):
    ...
    seapass.errors.ParameterError: delay_time: must be a number of seconds in [0, 1000], got -1
    """
    ok = isinstance(value, int | float) and not isinstance(value, bool)
    if not ok or not math.isfinite(float(value)) or not 0.0 <= float(value) <= MAX_DELAY_SECONDS:
        raise ParameterError(
            f"{argument}: must be a number of seconds in [0, {MAX_DELAY_SECONDS:g}], got {value!r}",
            argument=argument,
        )
    return float(value)


def latency_elements(elements: Mapping[str, str], delay_time: float | None) -> dict[str, str]:
    """The elements with ``C_A`` and ``C_L`` times ``exp(-delay_time*s)`` (when ``τ > 0``).

    ``elements`` maps ``D1``, ``D2``, ``CA``, ``CL`` to their text; an absent or ``"0"``
    controller stays ``"0"``.  With ``delay_time`` None or 0 the elements are unchanged.
    """
    out = dict(elements)
    if not delay_time:
        return out
    for key in _DELAYED:
        text = out.get(key, "0")
        if text.strip() != "0":
            out[key] = f"({text})*exp(-{LATENCY_PARAMETER}*s)"
    return out


def latency_values(values: Mapping[str, Any], delay_time: float | None) -> dict[str, Any]:
    """``values`` plus ``delay_time = τ`` when the latency is on (``τ > 0``)."""
    out = dict(values)
    if delay_time:
        out[LATENCY_PARAMETER] = float(delay_time)
    return out


def latency_sea(design: Any) -> SEA:
    """The `SEA` of a design (``D1 D2 CA CL``, ``values``, ``name``, ``plant``,
    ``delay_time``) with the latency on its controllers (`latency_elements`)."""
    elements = {k: getattr(design, k) for k in ("D1", "D2", "CA", "CL")}
    return SEA(
        **latency_elements(elements, design.delay_time),
        values=latency_values(design.values, design.delay_time),
        name=design.name,
        plant=design.plant,
    )


def check_latency(delay_time: Any, sea: SEA, *, key: str = "control.delay_time") -> float | None:
    """A design file's ``delay_time`` checked against its model (`FileFormatError` naming ``key``).

    None stays None (no latency stated).  In range (`check_delay_time`); ``delay_time`` is not a parameter of the model; with
    ``τ > 0``, the model has a controller and no delay of its own.
    """
    if delay_time is None:
        return None
    try:
        tau = check_delay_time(delay_time, argument=key)
    except SeapassError as exc:
        raise FileFormatError(str(exc)) from None
    if LATENCY_PARAMETER in sea.parameters:
        raise FileFormatError(
            f"parameters.{LATENCY_PARAMETER}: the name is taken by {key} (the loop latency); "
            "rename the parameter"
        )
    if tau > 0 and model_delays(sea):
        raise FileFormatError(
            f"{key}: the model already has a delay exp(-{model_delays(sea)[0]}*s); give the "
            "latency once, either as delay_time or in the model"
        )
    if tau > 0 and sea.discrete is not None:  # the z-controllers run in a sampled loop
        raise FileFormatError(
            f"{key}: the controllers are given in z; state the loop latency in samples as "
            "[control] delay (a latency of n periods is delay = n)"
        )
    if tau > 0 and all(sea.exact_elements()[k].is_zero for k in _DELAYED):
        raise FileFormatError(f"{key}: the model has no controller (CA, CL) to delay")
    return tau
