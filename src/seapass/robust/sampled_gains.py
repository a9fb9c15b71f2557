"""The robust sampled passive set of a controller gain over a box of plants (outer set).

`gain_intervals` is the gain case of
[`robust_sampled_intervals`][seapass.robust.sampled_intervals.robust_sampled_intervals].
The robust kernel ([`seapass.robust.sampled_verdict`][seapass.robust.sampled_verdict])
holds the deployed controller fixed, so no gain *interval* × box is certified here:
passivity at two gains says nothing between them.  What is certified:

* **outer**: the robust set is contained in the sampled passive set of the gain at every
  plant of the box; the certified one of
  [`sampled_passive_bound`][seapass.sampled.bound.sampled_passive_bound] (its passive
  intervals, edge enclosures and undecided pieces, one double wider) at the centre and
  the corners (up to ``budget`` plants) are intersected;
* **inner**: when the box is a point, the nominal certified passive set at that plant;
  otherwise the outer set is bisected and each sub-interval × box is decided by the kernel,
  which takes the gain as one more uncertain parameter
  ([`seapass.robust.sampled_control`][seapass.robust.sampled_control]); a sub-interval
  certified passive for every (gain, plant) joins the inner set (intersected with the
  continuous robust set, the deployment policy), ends rounded inward.  The sub-intervals
  share ``budget`` with the plants; what is not certified stays ``undecided``.
"""

from __future__ import annotations

from fractions import Fraction
from types import MappingProxyType
from typing import Any

from ..errors import ParameterError
from ..model.loop import SampledLoop
from ..model.sea import SEA
from ..outcome import Outcome
from .box import UncertainBox
from .pieces import Pieces, as_floats, intersect, merge, minus, widen
from .sampled_intervals import RobustSampledIntervals, continuous_sets, corners
from .verdict import WorstCase

__all__ = ["gain_intervals"]


def gain_intervals(
    sea: SEA, name: str, loop: SampledLoop, lo: Fraction, hi: Fraction,
    box: UncertainBox, budget: int, progress: Any,
) -> RobustSampledIntervals:  # fmt: skip
    """Outer set of the gain ``name`` from the plants of the box; inner only for a point box."""
    from ..sampled.bound import sampled_passive_bound
    from ..sampled.passivity import sampled_passivity

    point = all(a == b for a, b in box.intervals.values())
    plants = corners(box)[:budget]
    outer: Pieces = [(lo, hi)]
    inner: Pieces = []
    failing: list[WorstCase] = []
    with task_of(progress, name, len(plants)):
        for plant in plants:
            r = sampled_passive_bound(
                sea.with_values(**plant), name, loop=loop, lo=float(lo), hi=float(hi)
            )
            kept: Pieces = [(Fraction(a), Fraction(b)) for a, b in r.intervals]
            kept += [(Fraction(e.lo), Fraction(e.hi)) for e in r.edges]
            kept += [(Fraction(a), Fraction(b)) for a, b in r.undecided]
            new = intersect(outer, widen(kept, lo, hi))
            if new != outer:  # this plant cuts the robust set: a verified failing gain there
                cut = minus(outer, new)
                g = next((v for v in _inside(cut) if not _in(v, new)), None)
                if g is not None:
                    v = sampled_passivity(
                        sea, loop=loop, values={**plant, name: g}, continuous_gate=False
                    )
                    if v.outcome is Outcome.NOT_PASSIVE:
                        failing.append(
                            WorstCase(
                                values=MappingProxyType({**plant, name: g}),
                                frequency=v.omega, result=v,
                            )
                        )  # fmt: skip
            outer = new
            if point:
                inner = [(Fraction(a), Fraction(b)) for a, b in r.intervals]
            progress.advance(1, note=f"{len(failing)} failing gain(s) verified")
    used = len(plants)
    if not point and used < budget:
        inner, used = _certify(sea, name, loop, outer, box, budget - used, progress)
        inner, used = merge(inner), used + len(plants)
        c_inner, _c_outer = continuous_sets(sea, name, lo, hi, box)
        inner = intersect(inner, c_inner)
    inner = intersect(merge(inner), outer)
    return RobustSampledIntervals(
        param=name, kind="gain", lo=float(lo), hi=float(hi), box=box, loop=loop,
        intervals=as_floats(inner, inward=True), outer=as_floats(outer, inward=False),
        undecided=as_floats(minus(outer, inner), inward=False), failing=tuple(failing),
        budget=budget, budget_used=used,
    )  # fmt: skip


PER_BOX = 4
"""Kernel sub-boxes for each gain sub-interval × box."""


def _certify(
    sea: SEA, name: str, loop: SampledLoop, outer: Pieces, box: UncertainBox, budget: int,
    progress: Any,
) -> tuple[Pieces, int]:  # fmt: skip
    """Bisect the pieces of ``outer``; each gain sub-interval × box decided by the kernel."""
    from collections import deque

    from .sampled_verdict import robust_sampled_check

    others = dict(box.intervals)
    queue: deque[tuple[Fraction, Fraction]] = deque(
        (Fraction(float(a)), Fraction(float(b))) for a, b in outer if a < b
    )
    inner: Pieces = []
    used = 0
    while queue and used < budget:
        a, b = queue.popleft()
        used += 1
        try:
            r = robust_sampled_check(
                sea, loop=loop, box={name: (float(a), float(b)), **others}, budget=PER_BOX,
                continuous_gate=False,
            )  # fmt: skip
        except ParameterError:  # the gain is not affine in the controller: no inner set
            break
        progress.advance(0, note=f"{used} of {budget} gain sub-intervals")
        if r.outcome is Outcome.PASSIVE:
            inner.append((a, b))
            continue
        mid = Fraction(float((a + b) / 2))
        if a < mid < b and b - a > Fraction(1, 10**9) * max(abs(b), Fraction(1)):
            queue += [(a, mid), (mid, b)]
    return inner, used


def task_of(progress: Any, name: str, n: int) -> Any:
    from ..progress import task

    return task(progress, f"robust sampled bound of {name} ({n} plants of the box)", n)


def _inside(pieces: Pieces) -> list[float]:
    """A double strictly inside each piece (for a verified failing gain), when there is one."""
    out = []
    for a, b in pieces:
        m = float((a + b) / 2)
        if a < Fraction(m) < b:
            out.append(m)
    return out


def _in(v: float, pieces: Pieces) -> bool:
    return any(a <= Fraction(v) <= b for a, b in pieces)
