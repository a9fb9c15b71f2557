"""Plants at points of the box: the exact test there, and the verified worst case.

What lives here: the ordinary exact test
([`is_passive`][seapass.analysis.passivity.is_passive]) at a point of the box
(`worst_at`), the search for a failing plant moved inwards from a face
(`inside_near`), and the not-passive verdict at a verified plant (`failing`),
shared by the certified verdict ([`seapass.robust.verdict`][seapass.robust.verdict])
and its corner resolution.  A point becomes a worst case only when the exact test
says *not passive* there.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from flint import fmpq

from ..analysis.passivity import is_passive
from ..exact import poly as ep
from ..model.sea import SEA, Impedance
from ..outcome import Outcome
from .box import UncertainBox
from .family import Condition, ConditionKind
from .result import RobustResult, WorstCase

__all__ = ["as_floats", "failing", "inside_near", "with_values", "worst_at"]


def worst_at(
    system: SEA | Impedance, fixed: Mapping[str, float], at: Mapping[str, float]
) -> WorstCase | None:
    """The exact test at ``at``: a `WorstCase` when not passive there.

    >>> sea = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))
    >>> worst_at(sea, {}, {"kd": 2000.0}).values
    {'kd': 2000.0}
    >>> worst_at(sea, {}, {"kd": 100.0}) is None
    True
    """
    res = is_passive(system, values={**fixed, **at})
    if res.passive:
        return None
    return WorstCase(values=dict(at), frequency=res.omega, result=res)


def as_floats(names: tuple[str, ...], point: tuple[fmpq, ...]) -> dict[str, float]:
    """``{name: float}`` of an exact point of the box (one coordinate per name)."""
    return {n: float(ep.to_fraction(q)) for n, q in zip(names, point, strict=True)}


def with_values(system: SEA | Impedance, values: Mapping[str, float]) -> SEA | Impedance:
    """``system`` with ``values`` fixed."""
    if isinstance(system, SEA):
        return system.with_values(**values)
    return Impedance(expr=system.expr, values={**system.values, **values})


def inside_near(
    system: SEA | Impedance,
    fixed: Mapping[str, float],
    box: UncertainBox,
    at: dict[str, float],
) -> tuple[WorstCase | None, dict[str, float]]:
    """A failing plant near ``at`` inside the box: the coordinates of ``at`` on a face moved
    towards the centre by ``2^-k`` of the width (a condition that is zero on a face and
    negative just inside it); ``(None, at)`` when every one is passive."""
    center = box.center()
    for k in range(1, 9):
        near = {
            n: v + (center[n] - v) * 2.0 ** (1 - k) if v in box.intervals[n] else v
            for n, v in at.items()
        }
        w = worst_at(system, fixed, near)
        if w is not None:
            return w, near
    return None, at


def failing(
    w: WorstCase,
    at: Mapping[str, float],
    cond: Condition,
    point: tuple[fmpq, ...],
    box: UncertainBox,
    used: int,
) -> RobustResult:
    """The not-passive verdict at the verified plant ``w``; for the real part, the
    frequency of the failing point ``x = t/(1 − t)`` when the test gave none."""
    if cond.kind is ConditionKind.REAL_PART and w.frequency is None and point[0] < 1:
        t = point[0]
        w = WorstCase(values=w.values, frequency=math.sqrt(float(t / (1 - t))), result=w.result)
    return RobustResult(
        outcome=Outcome.NOT_PASSIVE,
        box=box,
        worst=w,
        boxes=used,
        detail=f"not passive at {', '.join(f'{k}={v:.6g}' for k, v in at.items())}: "
        f"{w.result.detail}",
    )
