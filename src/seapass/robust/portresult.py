"""The results of robust two-port verdicts: one criterion over a box, both, a worst plant.

`RobustTwoPortResult` is what [`robust_two_port_check`][seapass.robust.twoport.robust_two_port_check]
returns: Llewellyn's absolute stability and the two-port's passivity over the box, each a
`RobustPortVerdict` (``passive`` / ``not_passive`` with a `PortWorstCase` verified by
the ordinary exact verdict / ``undecided``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from ..model.display import Shown, html_card, short_repr
from ..outcome import Outcome
from ..ports.bound import Criterion
from ..ports.check import TwoPortCheck
from ..ports.twoport import TwoPort
from .box import UncertainBox
from .verdict import Method

__all__ = ["PortWorstCase", "RobustPortVerdict", "RobustTwoPortResult"]


@dataclass(frozen=True, kw_only=True)
class PortWorstCase:
    """A plant of the box at which the exact two-port verdict fails.

    Attributes
    ----------
    values : mapping of str to float
        The uncertain parameters at that plant.
    frequency : float or None
        A frequency [rad/s] inside an exact failing band of ``condition`` there;
        None when the failing condition is not a frequency condition.
    condition : str
        The first exact condition that fails (``llewellyn``, ``minor_12``, ...).
    result : TwoPortCheck
        The ordinary exact verdict at that plant.
    """

    values: Mapping[str, float]
    frequency: float | None
    condition: str
    result: TwoPortCheck = field(repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "values", MappingProxyType(dict(self.values)))

    def to_dict(self) -> dict[str, Any]:
        return {
            "values": dict(self.values),
            "frequency": self.frequency,
            "condition": self.condition,
        }


@dataclass(frozen=True, kw_only=True, repr=False)
class RobustPortVerdict:
    """One criterion (absolute stability or passivity) over the box.

    Attributes
    ----------
    criterion : Criterion
    outcome : Outcome
        ``PASSIVE``: the criterion holds for every plant of the box;
        ``NOT_PASSIVE``: `worst` fails it; ``UNDECIDED``: neither was proven.
    worst : PortWorstCase or None
    method : Method
        ``"exact"`` (one uncertain parameter) or ``"certified"``.
    boxes : int
        Boxes examined by the branch and bound.
    detail : str
    """

    criterion: Criterion
    outcome: Outcome
    worst: PortWorstCase | None = None
    method: Method = Method.CERTIFIED
    boxes: int = 0
    detail: str = ""

    @property
    def holds(self) -> bool:
        return self.outcome.passive

    def to_dict(self) -> dict[str, Any]:
        return {
            "criterion": self.criterion.value,
            "status": str(self.outcome),
            "worst": None if self.worst is None else self.worst.to_dict(),
            "method": str(self.method),
            "boxes": self.boxes,
            "detail": self.detail,
        }

    def __repr__(self) -> str:
        return short_repr(
            "RobustPortVerdict",
            {
                "criterion": self.criterion.value,
                "outcome": str(self.outcome),
                "method": str(self.method),
            },
        )


def _status_word(v: RobustPortVerdict) -> str:
    if v.outcome is Outcome.UNDECIDED:
        return "undecided"
    return v.criterion.label if v.holds else f"not {v.criterion.label}"


@dataclass(frozen=True, kw_only=True, repr=False)
class RobustTwoPortResult:
    """Absolute stability and passivity of a two-port for every plant of a box.

    Attributes
    ----------
    box : UncertainBox
    stability : RobustPortVerdict
        Llewellyn's absolute stability over the box (it decides the exit code of
        ``seapass twoport check``, and `outcome`, `status` and `worst`).
    passivity : RobustPortVerdict
        Passivity of the immittance matrix over the box.
    two_port : TwoPort
        What was checked.
    """

    box: UncertainBox
    stability: RobustPortVerdict
    passivity: RobustPortVerdict
    two_port: TwoPort = field(compare=False)

    @property
    def outcome(self) -> Outcome:
        return self.stability.outcome

    @property
    def status(self) -> str:
        return str(self.outcome)

    @property
    def absolutely_stable(self) -> bool:
        return self.stability.holds

    @property
    def passive(self) -> bool:
        return self.passivity.holds

    @property
    def worst(self) -> PortWorstCase | None:
        return self.stability.worst

    def to_dict(self) -> dict[str, Any]:
        """The JSON of ``seapass twoport check --uncertain ...``."""
        pas = None if self.passivity.outcome is Outcome.UNDECIDED else self.passive
        stab = None if self.stability.outcome is Outcome.UNDECIDED else self.absolutely_stable
        return {
            "robust": True,
            "status": self.status,
            "absolutely_stable": stab,
            "passive": pas,
            "box": self.box.to_dict(),
            "worst": None if self.worst is None else self.worst.to_dict(),
            "absolute_stability": self.stability.to_dict(),
            "passivity": self.passivity.to_dict(),
        }

    def plot(self, kind: str = "eta", *, ax: Any = None, **kwargs: Any) -> Any:
        """The exact verdict of a worst plant: ``kind="eta"`` (absolute stability's) or
        ``"minors"`` (passivity's); returns the Axes (ValueError without a worst plant)."""
        verdict = self.passivity if kind == "minors" else self.stability
        if verdict.worst is None:
            raise ValueError(f"no worst plant to plot: {_status_word(verdict)} over the box")
        return verdict.worst.result.plot(kind, ax=ax, **kwargs)

    def __repr__(self) -> str:
        worst = None
        if self.worst is not None:
            worst = Shown(", ".join(f"{k}={v:.6g}" for k, v in self.worst.values.items()))
        return short_repr(
            "RobustTwoPortResult",
            {
                "absolute_stability": str(self.stability.outcome),
                "passivity": str(self.passivity.outcome),
                "worst": worst,
            },
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [
            (k, f"[{lo:g}, {hi:g}]") for k, (lo, hi) in self.box.intervals.items()
        ]
        for v in (self.stability, self.passivity):
            rows.append((v.criterion.label, f"{_status_word(v)} ({v.method}): {v.detail}"))
            if v.worst is not None:
                at = ", ".join(f"{k} = {x:.6g}" for k, x in v.worst.values.items())
                rows.append(("worst plant", at))
        return html_card(
            f"Robust two-port {self.two_port.name}".strip(),
            rows,
            note="verdicts for every plant in the box",
        )
