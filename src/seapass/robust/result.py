"""The result of a robust (box) verdict: `RobustResult`, its `WorstCase` and `Method`.

What lives here: the result types shared by the continuous verdict
([`seapass.robust.verdict`][seapass.robust.verdict]) and the sampled-data one
([`seapass.robust.sampled_verdict`][seapass.robust.sampled_verdict]).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from typing import TYPE_CHECKING, Any

from ..analysis.passivity import PassivityResult
from ..model.display import Shown, html_card, short_repr
from ..outcome import Outcome
from .box import UncertainBox

if TYPE_CHECKING:  # the sampled kernel loads only with robust.sampled_verdict
    from ..delay.passivity import DelayPassivityResult
    from ..sampled.passivity import SampledPassivityResult

__all__ = ["Method", "RobustResult", "WorstCase"]


class Method(StrEnum):
    """How a robust verdict was reached (the JSON value is the string)."""

    EXACT = "exact"
    CERTIFIED = "certified"


@dataclass(frozen=True, kw_only=True)
class WorstCase:
    """A plant of the box at which the design is not passive (verified by the ordinary test).

    Attributes
    ----------
    values : mapping of str to float
        The uncertain parameters at that plant.
    frequency : float or None
        A frequency [rad/s] where the design fails there: ``Re Z(jω) < 0`` (continuous)
        or a proven ``N(ω) < 0`` (sampled); None when the plant fails for another
        reason, e.g. an unstable pole.
    result : PassivityResult, SampledPassivityResult or DelayPassivityResult
        The ordinary verdict at that plant: the exact test (`robust_check`), the
        certified sampled-data verdict (`robust_sampled_check`) or the certified
        delayed verdict (`robust_check` of a delayed design).
    """

    values: Mapping[str, float]
    frequency: float | None
    result: PassivityResult | SampledPassivityResult | DelayPassivityResult = field(
        repr=False, compare=False
    )

    def to_dict(self) -> dict[str, Any]:
        return {
            "values": dict(self.values),
            "frequency": self.frequency,
            "reason": str(self.result.reason),
        }


@dataclass(frozen=True, repr=False, kw_only=True)
class RobustResult:
    """Outcome of a robust (box) passivity verdict.

    Attributes
    ----------
    outcome : Outcome
        ``PASSIVE``: passive for every plant in the box; ``NOT_PASSIVE``: `worst` is
        a plant of the box that is not passive; ``UNDECIDED``: neither was proven.
    box : UncertainBox
        The uncertain parameters.
    worst : WorstCase or None
        The verified counterexample of a negative verdict.
    method : Method
        ``"exact"`` (one parameter) or ``"certified"`` (Bernstein branch and bound).
    boxes : int
        Boxes examined by the branch and bound (0 for the exact method).
    detail : str
        Why, in words.
    delay : mapping or None
        ``{"name": ..., "tau": seconds}`` for a delayed design (the verdict is at that delay).
    """

    outcome: Outcome
    box: UncertainBox
    worst: WorstCase | None = None
    method: Method = Method.CERTIFIED
    boxes: int = 0
    detail: str = ""
    delay: Mapping[str, Any] | None = None

    @property
    def passive(self) -> bool:
        return self.outcome.passive

    @property
    def status(self) -> str:
        return str(self.outcome)

    def to_dict(self) -> dict[str, Any]:
        return {
            "robust": True,
            "passive": self.passive,
            "status": self.status,
            "box": self.box.to_dict(),
            "worst": None if self.worst is None else self.worst.to_dict(),
            "method": str(self.method),
            "boxes": self.boxes,
            "detail": self.detail,
            **({} if self.delay is None else {"delay": dict(self.delay)}),
        }

    def plot(self, kind: str = "real", *, ax: Any = None, omega: Any = None, **kwargs: Any) -> Any:
        """``Re Z(jω)`` (or the Nyquist plot) of the worst-case plant, with its failing bands.

        Only for a negative verdict (a passive box has no single plant to show); returns
        the matplotlib Axes.
        """
        if self.worst is None:
            raise ValueError(f"no worst-case plant to plot: the verdict is {self.outcome.label}")
        result = self.worst.result
        from ..delay.passivity import DelayPassivityResult

        assert isinstance(result, PassivityResult | DelayPassivityResult)  # continuous ones
        return result.plot(kind, ax=ax, omega=omega, **kwargs)

    def __repr__(self) -> str:
        worst = None
        if self.worst is not None:
            worst = Shown(", ".join(f"{k}={v:.6g}" for k, v in self.worst.values.items()))
        return short_repr(
            "RobustResult",
            {"outcome": str(self.outcome), "worst": worst, "method": str(self.method)},
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [("verdict", self.outcome.label), ("detail", self.detail)]
        rows += [(k, f"[{lo:g}, {hi:g}]") for k, (lo, hi) in self.box.intervals.items()]
        if self.worst is not None:
            at = ", ".join(f"{k} = {v:.6g}" for k, v in self.worst.values.items())
            rows.append(("worst case", at))
        return html_card(
            f"Robust passivity: {self.outcome.label}",
            rows,
            note=f"{self.method} verdict for every plant in the box",
        )
