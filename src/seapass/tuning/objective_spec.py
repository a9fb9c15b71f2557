"""What an interaction-control tune optimizes: `Interaction` (the kinds) and
`InteractionObjective` (the kind with its target, band and budget), with the small rules
they share ([`stiffness_gain`][seapass.tuning.objective_spec.stiffness_gain], `squash`).

The objectives themselves are computed in
[`seapass.tuning.objectives`][seapass.tuning.objectives] (continuous controllers) and
[`seapass.tuning.sampled_objectives`][seapass.tuning.sampled_objectives] (controllers
given in z).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from ..analysis.freqresp import check_points
from ..errors import ParameterError
from ..model.expr import finite_number
from ..model.sea import SEA

__all__ = [
    "DEFAULT_BANDWIDTH_BAND",
    "Interaction",
    "InteractionObjective",
    "squash",
    "stiffness_gain",
]

DEFAULT_BANDWIDTH_BAND = (1e-2, 1e5)
"""Frequencies (rad/s) searched for the force bandwidth when no band is given."""


class Interaction(StrEnum):
    """The interaction-control objectives (see the module docstring)."""

    RENDERING = "rendering"
    FORCE_BANDWIDTH = "force-bandwidth"
    ZWIDTH = "zwidth"

    @property
    def maximize(self) -> bool:
        """True for the force bandwidth and the Z-width, False for the rendering error."""
        return self is not Interaction.RENDERING

    @property
    def label(self) -> str:
        return {
            Interaction.RENDERING: "worst relative rendering error",
            Interaction.FORCE_BANDWIDTH: "force bandwidth (clamped load, -3 dB)",
            Interaction.ZWIDTH: "largest passive virtual stiffness",
        }[self]


@dataclass(frozen=True, kw_only=True)
class InteractionObjective:
    """What to optimize, for [`tune_objective`][seapass.tuning.interaction.tune_objective].

    Attributes
    ----------
    kind : Interaction or str
        ``"rendering"``, ``"force-bandwidth"`` or ``"zwidth"``.
    target : str, optional
        The target stiffness ``F_L/X_L`` (rendering only, required), safe text in ``s``
        and the design's parameters, e.g. ``"1000 + 5*s"`` or ``"kv + bv*s"``.
    band : (float, float), optional
        Frequencies ``(lo, hi)`` in rad/s, ``0 < lo < hi``: the band of the rendering
        error (required) or the search band of the force bandwidth (default
        `DEFAULT_BANDWIDTH_BAND`).
    points : int, default 200
        Log-spaced frequencies on the band.
    stiffness : str, optional
        Z-width only: the virtual-stiffness gain (default: ``kv``, else ``kd``, else the
        first controller gain).
    max_boxes : int, default 2000
        Z-width only: the branch-and-bound budget per candidate (boxes, counted).
    rtol : float, default 1e-3
        Z-width only: the relative width of the stiffness bound's edge enclosure.
    load_masses : tuple of float, optional
        Load masses (kg) every candidate must be stable with; default the design
        file's ``[simulation] load_masses``, else the tuning load mass.
    """

    kind: Interaction | str
    target: str | None = None
    band: tuple[float, float] | None = None
    points: int = 200
    stiffness: str | None = None
    max_boxes: int = 2000
    rtol: float = 1e-3
    load_masses: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "kind", Interaction(str(self.kind).lower()))
        except ValueError:
            choices = ", ".join(o.value for o in Interaction)
            raise ParameterError(f"kind must be one of {choices}, got {self.kind!r}") from None
        if self.band is not None:
            object.__setattr__(self, "band", _band(self.band))
        check_points(self.points)
        if self.kind is Interaction.RENDERING:
            if not self.target or not str(self.target).strip():
                raise ParameterError(
                    "target: the rendering objective needs a target stiffness, "
                    "e.g. target='1000 + 5*s'",
                    argument="target",
                )
            if self.band is None:
                raise ParameterError(
                    "band: the rendering objective needs a band (lo, hi) in rad/s, "
                    "e.g. band=(1, 100)",
                    argument="band",
                )
        b = self.max_boxes
        if isinstance(b, bool) or not isinstance(b, int) or b < 1:
            raise ParameterError(f"max_boxes must be an integer >= 1, got {b!r}")
        if not 0 < finite_number(self.rtol, "rtol") <= 1e-2:
            raise ParameterError(f"rtol must be in (0, 1e-2], got {self.rtol!r}")
        if self.load_masses is not None:
            masses = tuple(finite_number(m, "load_masses", positive=True) for m in self.load_masses)
            if not masses:
                raise ParameterError("load_masses must not be empty")
            object.__setattr__(self, "load_masses", masses)

    @property
    def frequency_band(self) -> tuple[float, float]:
        """The band, or the default search band of the force bandwidth."""
        return self.band or DEFAULT_BANDWIDTH_BAND

    def to_dict(self) -> dict[str, Any]:
        return {
            "kind": str(self.kind),
            "target": self.target,
            "band": list(self.frequency_band) if self.kind is not Interaction.ZWIDTH else None,
            "points": self.points,
            "stiffness": self.stiffness,
            "max_boxes": self.max_boxes if self.kind is Interaction.ZWIDTH else None,
        }


def _band(band: Any) -> tuple[float, float]:
    try:
        lo, hi = band
    except (TypeError, ValueError):
        raise ParameterError(f"band: expected (lo, hi) in rad/s, got {band!r}") from None
    lo, hi = finite_number(lo, "band lower end"), finite_number(hi, "band upper end")
    if not 0 < lo < hi:
        raise ParameterError(
            f"band: need 0 < lo < hi (rad/s), got ({lo:g}, {hi:g})", argument="band"
        )
    return (lo, hi)


def stiffness_gain(sea: SEA, candidates: Sequence[str], given: str | None = None) -> str:
    """The virtual-stiffness gain of the Z-width objective (see `InteractionObjective`)."""
    if given is not None:
        if given not in sea.parameters:
            raise ParameterError(
                f"stiffness: {given!r} is not a parameter of the design ({', '.join(sea.parameters)})",
                argument="stiffness",
            )
        return given
    for name in ("kv", "kd"):
        if name in candidates:
            return name
    if not candidates:
        raise ParameterError(
            "stiffness: the design has no controller gain to map", argument="stiffness"
        )
    return candidates[0]


def squash(value: float, kind: Interaction) -> float:
    """The objective as a cost in ``[0, 1)``, smaller is better (monotone in ``value``)."""
    if not math.isfinite(value):
        return 1.0 if (value > 0) != kind.maximize else 0.0
    if kind.maximize:
        return 1.0 / (1.0 + max(value, 0.0))
    return value / (1.0 + value)
