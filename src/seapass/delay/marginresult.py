"""The result of a delay margin: `DelayMarginResult`, how passivity is lost (`MarginLoss`)
and what fails first (`MarginCause`).

Computed by [`seapass.delay.margin`][seapass.delay.margin]; printed ends round inward
(the passive end down, the enclosure outward) with
[`seapass.exact.rounding`][seapass.exact.rounding].
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum
from fractions import Fraction
from typing import Any

import numpy as np
from flint import fmpq

from ..exact import poly as ep
from ..exact.axis import safe_float
from ..exact.rounding import decimal_down, enclosure_text
from ..model.display import html_card, short_repr
from ..outcome import Outcome
from .balls import arb_of, precision
from .bands import dangerous_bands
from .firstdelay import FirstDelay
from .highfreq import high_frequency
from .structure import DelayedImpedance
from .trig import real_part

__all__ = ["DEFAULT_RTOL", "LOSS_KINDS", "DelayMarginResult", "MarginCause", "MarginLoss"]

DEFAULT_RTOL = 1e-6
"""Relative width of the enclosure of ``τ*``."""


class MarginLoss(StrEnum):
    """How passivity is lost at ``τ*`` (the JSON ``loss``)."""

    INTERIOR = "interior"
    """At a frequency ``0 < ω < ∞`` (``frequency``)."""
    LOW_FREQUENCY = "low_frequency"
    """In the limit ``ω → 0``."""
    UNBOUNDED_BAND = "unbounded_band"
    """``τ* = 0``: every delay ``> 0`` fails at arbitrarily high frequencies."""


class MarginCause(StrEnum):
    """What fails first at ``τ*``: the sign of ``Re Z(jω)``, the loop's stability, or ``ω → ∞``."""

    NONE = ""
    REAL_PART = "real_part"
    STABILITY = "stability"
    INFINITY = "infinity"


LOSS_KINDS = tuple(MarginLoss)


@dataclass(frozen=True, kw_only=True, repr=False)
class DelayMarginResult:
    """The passivity delay margin of a design.

    Attributes
    ----------
    delay : str
        The delay parameter.
    outcome : Outcome
        The verdict for every delay in ``[0, tau_star[0]]``: ``passive`` (certified;
        also when the design is passive for every delay), ``not_passive`` (not even at
        zero delay) or ``undecided``.
    tau_star : (float, float) or None
        ``[lo, hi]`` [s] enclosing ``τ*``; None when the design is not passive at zero delay
        or is passive for every delay (`delay_independent`).  ``lo`` is rounded down and
        certified passive together with every smaller delay; at ``hi`` (rounded up) the
        design is proven not passive, or ``hi`` is the exact first root of the
        low-frequency coefficient.
    frequency : float or None
        Where passivity is lost [rad/s] (None for a limit ``ω → 0`` or ``∞``).
    loss : str or None
        ``"interior"``, ``"low_frequency"`` or ``"unbounded_band"``.
    delay_independent : bool
        Passive for every delay ``τ ≥ 0`` (exact).
    passive_at_zero : bool
        Passive without delay (exact).
    certified : bool
        ``hi - lo <= rtol·hi`` was reached (False: the enclosure is valid but wider).
    """

    delay: str
    outcome: Outcome
    tau_star: tuple[float, float] | None = None
    frequency: float | None = None
    loss: MarginLoss | None = None
    delay_independent: bool = False
    passive_at_zero: bool = True
    certified: bool = True
    rtol: float = DEFAULT_RTOL
    cause: MarginCause = MarginCause.NONE
    detail: str = ""
    evaluations: int = 0
    exact: tuple[fmpq, fmpq] | None = field(default=None, compare=False)
    impedance: DelayedImpedance | None = field(default=None, compare=False)

    def to_dict(self) -> dict[str, Any]:
        return {
            "delay": self.delay,
            "tau_star": list(self.tau_star) if self.tau_star is not None else None,
            "frequency": self.frequency,
            "loss": None if self.loss is None else str(self.loss),
            "delay_independent": self.delay_independent,
            "passive_at_zero": self.passive_at_zero,
            "outcome": str(self.outcome),
            "certified": self.certified,
            "rtol": self.rtol,
            "cause": str(self.cause),
            "detail": self.detail,
            "evaluations": self.evaluations,
        }

    def curve(self, points: int = 400) -> tuple[np.ndarray, np.ndarray]:
        """The first failing delay ``g(ω)`` sampled over the dangerous band (for pictures)."""
        if self.impedance is None:
            return np.zeros(0), np.zeros(0)
        f = real_part(self.impedance)
        if f.order != 1 or high_frequency(f).kind != "positive":
            return np.zeros(0), np.zeros(0)
        g = FirstDelay(f)
        ws: list[float] = []
        gs: list[float] = []
        for lo, hi in dangerous_bands(f):
            a = max(safe_float(lo), safe_float(hi) * 1e-4)
            for w in np.geomspace(a, safe_float(hi), points):
                with precision(64):
                    v = g.at(ep.rational(float(w)))
                    if g.safe(arb_of(ep.rational(float(w)))) or not v.is_finite():
                        continue
                    ws.append(float(w))
                    gs.append(float(v.mid()))
        return np.array(ws), np.array(gs)

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """``g(ω)`` over the dangerous band with the enclosure of ``τ*``; returns the Axes."""
        from ..plot.delay import plot_delay_margin

        return plot_delay_margin(self, ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "DelayMarginResult",
            {
                "delay": self.delay,
                "tau_star": list(self.tau_star) if self.tau_star else None,
                "loss": None if self.loss is None else str(self.loss),
                "frequency": self.frequency,
                "delay_independent": self.delay_independent or None,
                "passive_at_zero": None if self.passive_at_zero else False,
                "outcome": str(self.outcome) if self.outcome is not Outcome.PASSIVE else None,
            },
        )

    def _repr_html_(self) -> str:
        if self.tau_star is not None:
            lo, hi = self.exact or (
                Fraction(self.tau_star[0]),
                Fraction(self.tau_star[1]),
            )
            star = f"{enclosure_text(lo, hi, digits=6)} s (passive up to {decimal_down(lo, 6)} s)"
        else:
            star = "every delay" if self.delay_independent else "none (not passive at 0)"
        rows: list[tuple[str, Any]] = [
            ("delay margin τ*", star),
            ("loss", self.loss or "none"),
            (
                "frequency",
                "limit" if self.frequency is None else f"{self.frequency:.6g} rad/s",
            ),
            ("verdict on [0, lo]", self.outcome.label),
            ("detail", self.detail),
        ]
        return html_card(f"Delay margin of {self.delay}", rows, note="Certified enclosure.")
