"""The box budget of a certified bound (issue 23 item 2): counted, sound, reported."""

from __future__ import annotations

import itertools

import pytest

from seapass.errors import ParameterError
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.region import sampled_region
from seapass.sampled.verdict import SampledReason

OURS = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1005, b1=30, bd=25))
LOOP = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)


def _inside(small: list[list[float]], big: list[list[float]]) -> bool:
    return all(any(x <= a and b <= y for x, y in big) for a, b in small)


@pytest.mark.parametrize("budget", [1, 5, 12, 30])
def test_a_budget_never_adds_a_passive_value(budget: int) -> None:
    full = sampled_passive_bound(OURS, "kd", loop=LOOP, lo=0, hi=2e4, rtol=1e-6)
    part = sampled_passive_bound(OURS, "kd", loop=LOOP, lo=0, hi=2e4, rtol=1e-6, max_boxes=budget)
    assert not full.budget_exhausted and part.budget_exhausted
    assert _inside([list(iv) for iv in part.intervals], [list(iv) for iv in full.intervals])
    # every value is proven, an edge enclosure, or undecided: the budget hides nothing
    covered = sorted([(a, b) for a, b, _o in part.partition])
    assert covered[0][0] == 0 and covered[-1][1] == 2e4
    assert all(b1 == a2 for (_a1, b1), (a2, _b2) in itertools.pairwise(covered))
    undecided = [(a, b) for a, b, o in part.partition if o is Outcome.UNDECIDED]
    assert undecided and set(part.undecided) | {(e.lo, e.hi) for e in part.edges} >= set(undecided)
    assert part.to_dict()["budget_exhausted"] is True
    assert part.design_outcome is None


def test_the_budget_is_checked() -> None:
    for bad in (0, -3, 2.0, True):
        with pytest.raises(ParameterError, match="max_boxes must be a positive whole number"):
            sampled_passive_bound(OURS, "kd", loop=LOOP, lo=0, hi=2e4, max_boxes=bad)  # type: ignore[arg-type]


def test_budget_reason_is_never_an_edge() -> None:
    assert SampledReason.BUDGET == "budget"
    part = sampled_passive_bound(OURS, "kd", loop=LOOP, lo=0, hi=2e4, rtol=1e-6, max_boxes=12)
    full = sampled_passive_bound(OURS, "kd", loop=LOOP, lo=0, hi=2e4, rtol=1e-6)
    # edges found with a budget are edges of the full answer too
    for e in part.edges:
        assert any(f.lo <= e.hi and e.lo <= f.hi for f in full.edges)


def test_a_region_passes_its_budget_to_every_row() -> None:
    sea = OURS.with_values(kd=None, bd=None)
    ideal = LOOP.replace(delay=0, velocity_filter=None)
    z = sampled_region(
        sea, "kd", "bd", loop=ideal, p1_range=(0, 1e5), p2_range=(0, 50), n=2, setups=[ideal],
        max_boxes=4,
    )  # fmt: skip
    assert z.budget_exhausted and all(r.budget_exhausted for r in z.rows["ideal ZOH"])
    full = sampled_region(
        sea, "kd", "bd", loop=ideal, p1_range=(0, 1e5), p2_range=(0, 50), n=2, setups=[ideal]
    )
    assert not full.budget_exhausted
    for a, b in zip(z.rows["ideal ZOH"], full.rows["ideal ZOH"], strict=True):
        assert _inside([list(iv) for iv in a.intervals], [list(iv) for iv in b.intervals])
