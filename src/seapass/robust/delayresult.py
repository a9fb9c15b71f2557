"""The result of a robust delay margin: `RobustDelayMargin` (computed by
[`seapass.robust.delayed`][seapass.robust.delayed])."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from flint import fmpq

from ..delay.marginresult import DelayMarginResult
from ..model.display import html_card, short_repr
from ..outcome import Outcome
from .box import UncertainBox

__all__ = ["DEFAULT_ROBUST_RTOL", "RobustDelayMargin"]

DEFAULT_ROBUST_RTOL = 1e-3
"""Relative width of the enclosure of the robust margin."""


@dataclass(frozen=True, kw_only=True, repr=False)
class RobustDelayMargin:
    """The delay margin over a box: ``τ*_robust = min_box τ*`` enclosed in ``tau_star``.

    Attributes
    ----------
    delay : str
    outcome : Outcome
        ``passive``: every plant of the box is passive for every delay up to
        ``tau_star[0]`` (certified); ``not_passive``: a plant of the box is not passive
        even without delay (`worst`); ``undecided`` otherwise.
    tau_star : (float, float) or None
        ``lo`` (rounded down) certified for every plant; ``hi`` (rounded up) the upper end
        of the verified worst plant's own ``τ*``.
    box : UncertainBox
    worst_values : mapping or None
        The worst plant found (its own margin is `worst_margin`).
    worst_margin : DelayMarginResult or None
    certified : bool
        ``hi - lo <= rtol·hi``.
    cells : int
        Cells spent by the branch and bound (the counted budget).
    """

    delay: str
    outcome: Outcome
    tau_star: tuple[float, float] | None
    box: UncertainBox
    worst_values: Mapping[str, float] | None = None
    worst_margin: DelayMarginResult | None = field(default=None, compare=False)
    certified: bool = False
    rtol: float = DEFAULT_ROBUST_RTOL
    cells: int = 0
    detail: str = ""
    exact: tuple[fmpq, fmpq] | None = field(default=None, compare=False)

    @property
    def passive(self) -> bool:
        return self.outcome.passive

    def to_dict(self) -> dict[str, Any]:
        wm = self.worst_margin
        worst = None
        if self.worst_values is not None and wm is not None:
            worst = {
                "values": dict(self.worst_values),
                "frequency": wm.frequency,
                "tau_star": None if wm.tau_star is None else list(wm.tau_star),
                "loss": None if wm.loss is None else str(wm.loss),
                "passive_at_zero": wm.passive_at_zero,
            }
        return {
            "robust": True,
            "delay": self.delay,
            "tau_star": None if self.tau_star is None else list(self.tau_star),
            "frequency": None if wm is None else wm.frequency,
            "loss": None if wm is None or wm.loss is None else str(wm.loss),
            "delay_independent": False,
            "passive_at_zero": True if wm is None else wm.passive_at_zero,
            "outcome": str(self.outcome),
            "status": str(self.outcome),
            "certified": self.certified,
            "rtol": self.rtol,
            "cause": "" if wm is None else str(wm.cause),
            "detail": self.detail,
            "evaluations": self.cells,
            "box": self.box.to_dict(),
            "worst": worst,
        }

    def __repr__(self) -> str:
        return short_repr(
            "RobustDelayMargin",
            {"tau_star": list(self.tau_star) if self.tau_star else None,
             "outcome": str(self.outcome), "worst": dict(self.worst_values or {}) or None},
        )  # fmt: skip

    def _repr_html_(self) -> str:
        star = (
            "none"
            if self.tau_star is None
            else f"[{self.tau_star[0]:.6g}, {self.tau_star[1]:.6g}] s"
        )
        rows: list[tuple[str, Any]] = [("robust τ*", star), ("verdict", self.outcome.label),
                                       ("detail", self.detail)]  # fmt: skip
        rows += [(k, f"[{lo:g}, {hi:g}]") for k, (lo, hi) in self.box.intervals.items()]
        return html_card(f"Robust delay margin of {self.delay}", rows, note="Certified enclosure.")

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """The worst plant's first failing delay per frequency (its `DelayMarginResult.plot`)."""
        if self.worst_margin is None:
            raise ValueError("no worst plant to plot")
        return self.worst_margin.plot(ax=ax, **kwargs)
