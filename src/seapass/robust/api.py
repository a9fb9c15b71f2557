"""``is_passive`` and ``passive_intervals`` with an optional box of uncertain parameters.

The top-level ``seapass.is_passive`` and ``seapass.passive_intervals`` are these:
without ``box`` they are the exact tests of
[`seapass.analysis.passivity`][seapass.analysis.passivity] and
[`seapass.analysis.region`][seapass.analysis.region] (same arguments, same
results); with ``box`` they are [`robust_check`][seapass.robust.verdict.robust_check]
and [`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals].
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ..analysis import region
from ..analysis.passivity import PassivityResult
from ..analysis.region import PassiveIntervals
from ..model.sea import SEA, Impedance
from .box import UncertainBox
from .intervals import RobustIntervals, robust_passive_intervals
from .verdict import DEFAULT_BUDGET, RobustResult, robust_check

if TYPE_CHECKING:  # annotations only: the front door loads no sympy
    import sympy as sp

    from ..delay.passivity import DelayPassivityResult

__all__ = ["is_passive", "passive_intervals"]


def is_passive(
    system: SEA | Impedance | str | sp.Expr | tuple[Sequence[Any], Sequence[Any]],
    *,
    values: Mapping[str, float] | None = None,
    box: Mapping[str, Any] | UncertainBox | None = None,
    budget: int = DEFAULT_BUDGET,
    throw: bool = False,
) -> PassivityResult | DelayPassivityResult | RobustResult:
    """Exact passivity of ``system``; with ``box``, for every plant in the box.

    Parameters
    ----------
    system, values, throw
        As for [`seapass.analysis.passivity.is_passive`][seapass.analysis.passivity.is_passive].
    box : mapping of str to (lo, hi), optional
        Uncertain parameters, e.g. ``{"m": (0.9, 1.1)}``: returns a
        [`RobustResult`][seapass.robust.result.RobustResult].
    budget : int
        Branch-and-bound budget of a box with several parameters.

    Examples
    --------
    >>> import seapass
    >>> sea = seapass.SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))
    >>> seapass.is_passive(sea).passive
    True
    >>> seapass.is_passive(sea, box={"m": (0.9, 1.1), "b": (8, 12)}).to_dict()["status"]
    'passive'
    """
    if box is None:  # rational: exact; with a delay exp(-NAME*s): certified
        from ..delay.passivity import is_passive as any_is_passive

        return any_is_passive(system, values=values, throw=throw)
    if not isinstance(system, SEA | Impedance):
        raise TypeError("box= applies to SEA and Impedance systems with named parameters")
    return robust_check(system, box=box, values=values, budget=budget, throw=throw)


def passive_intervals(
    system: SEA | Impedance,
    param: str,
    lo: float,
    hi: float,
    *,
    values: Mapping[str, float] | None = None,
    box: Mapping[str, Any] | UncertainBox | None = None,
    rtol: float = 1e-3,
    budget: int = DEFAULT_BUDGET,
) -> PassiveIntervals | RobustIntervals:
    """Exact passive set of ``param`` in ``[lo, hi]``; with ``box``, for every plant in it.

    Without ``box``: [`seapass.analysis.region.passive_intervals`][seapass.analysis.region.passive_intervals].
    With ``box``: [`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals]
    (``rtol`` and ``budget`` apply to several uncertain parameters).
    """
    if box is None:
        return region.passive_intervals(system, param, lo, hi, values=values)
    return robust_passive_intervals(
        system, param, lo, hi, box=box, values=values, rtol=rtol, budget=budget
    )
