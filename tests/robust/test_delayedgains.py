"""Robust gain sets at a fixed delay (seapass.robust.delayedgains, issue 26), cross-checked
with the plain certified delayed verdict (seapass.delay) plant by plant, the nominal delayed
gain set (a point box) and the delay-free robust gain set (tau = 0)."""

from __future__ import annotations

import numpy as np
import pytest

from seapass.delay.gainbound import passive_gain_intervals
from seapass.delay.passivity import delayed_passivity
from seapass.errors import ParameterError
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.robust.intervals import RobustIntervals, robust_passive_intervals
from seapass.robust.region import robust_passive_map

# a virtual wall behind a delay: passive for kd <= b/tau at every plant (tau = 2 ms)
WALL = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=None, k1=1000, kd=None, tau=0.002))
BOX = {"b": (9.0, 11.0)}


@pytest.fixture(scope="module")
def wall_set() -> RobustIntervals:
    return robust_passive_intervals(WALL, "kd", 0, 8000, box=BOX, rtol=1e-2)


def test_the_robust_set_is_enclosed_by_inner_and_outer_sets(wall_set: RobustIntervals) -> None:
    r = wall_set
    assert r.delay == {"name": "tau", "tau": 0.002} and str(r.method) == "certified"
    (a, b), = r.intervals  # fmt: skip
    (c, d), = r.outer  # fmt: skip
    # the robust end is min b / tau = 4500: inside [b, d], close on both sides
    assert c <= a and b <= 4500 <= d and 4500 - b < 0.05 * 4500 and d - 4500 < 1e-3
    js = r.to_dict()
    assert js["robust"] is True and js["delay_time"] == 0.002 and js["box"] == {"b": [9.0, 11.0]}
    assert set(js) >= {"intervals", "outer", "excluded", "delay", "method"}


def test_the_inner_set_is_passive_at_200_plants_by_the_plain_delayed_verdict(
    wall_set: RobustIntervals,
) -> None:
    rng = np.random.default_rng(26)
    (a, b), = wall_set.intervals  # fmt: skip
    ends = [(9.0, a), (9.0, b), (11.0, a), (11.0, b)]  # the corners of box x inner set
    draws = [(float(x), float(k)) for x, k in zip(rng.uniform(9, 11, 196), rng.uniform(a, b, 196), strict=True)]  # fmt: skip
    for bv, kd in ends + draws:
        res = delayed_passivity(WALL, values={"b": bv, "kd": kd})
        assert res.outcome is Outcome.PASSIVE, (bv, kd, res.detail)


def test_every_excluded_segment_has_a_verified_failing_plant(wall_set: RobustIntervals) -> None:
    assert wall_set.excluded
    covered = 0.0
    for x in wall_set.excluded:
        lo, hi = x["gains"]
        covered += hi - lo
        for kd in np.linspace(lo, hi, 3):
            res = delayed_passivity(WALL, values={**x["values"], "kd": float(kd)})
            assert res.outcome is Outcome.NOT_PASSIVE, (x, kd)
    # outside the outer set everything is excluded: [lo, hi] minus outer is covered
    (_c, d), = wall_set.outer  # fmt: skip
    assert covered >= 8000 - d - 1e-6


def test_a_point_box_is_the_nominal_delayed_bound() -> None:
    r = robust_passive_intervals(WALL, "kd", 0, 8000, box={"b": (10.0, 10.0)}, rtol=1e-3)
    nominal = passive_gain_intervals(WALL.with_values(b=10), "kd", 0, 8000, points=9, rtol=1e-3)
    assert r.intervals == nominal.intervals
    (_a, b), = r.intervals  # fmt: skip
    (_c, d), = r.outer  # fmt: skip
    assert b <= 5000 <= d < 5000 * (1 + 1e-6)


def test_at_zero_delay_it_agrees_with_the_delay_free_robust_bound() -> None:
    sea = SEA(D1="k1 + b1*s", CA="kd*exp(-tau*s)", CL="kl",
              values=dict(m=1, b=10, k1=1000, b1=20, kd=None, kl=300, tau=0))  # fmt: skip
    free = SEA(D1="k1 + b1*s", CA="kd", CL="kl", values=dict(m=1, b=10, k1=1000, b1=20, kl=300))
    box = {"b": (8.0, 12.0)}
    r0 = robust_passive_intervals(sea, "kd", 0, 2000, box=box, rtol=1e-2)
    rf = robust_passive_intervals(free, "kd", 0, 2000, box=box)
    # the delayed inner set lies inside the exact delay-free set and the outer sets agree
    for a, b in r0.intervals:
        assert any(c <= a and b <= d for c, d in rf.intervals)
    (a0, b0), = r0.intervals  # fmt: skip
    (af, bf), = rf.intervals  # fmt: skip
    assert b0 >= 0.95 * bf and r0.outer[0][1] >= bf - 1e-6 and a0 - af <= 0.02 * 2000


def test_the_robust_region_at_a_delay_is_each_column_robust_set() -> None:
    r = robust_passive_map(WALL, "m", [1.0], "kd", (0, 8000), box=BOX, rtol=1e-2)
    assert r.delay == {"name": "tau", "tau": 0.002} and r.to_dict()["delay_time"] == 0.002
    (_a, hi), = r.intervals[0]  # fmt: skip
    assert hi <= 9 / 0.002 <= r.outer[0][-1][1]  # min b / tau over the box
    assert 9 / 0.002 < r.nominal[0][0][1] <= 10 / 0.002  # the certified set at the centre


def test_bad_inputs_are_clear_errors() -> None:
    with pytest.raises(ParameterError, match="a delay must be >= 0"):
        robust_passive_intervals(WALL.with_values(tau=-0.001), "kd", 0, 8000, box=BOX)
    with pytest.raises(ParameterError, match="budget must be an integer"):
        robust_passive_intervals(WALL, "kd", 0, 8000, box=BOX, budget=10**9)
    with pytest.raises(ParameterError, match="tau is the delay"):
        robust_passive_intervals(WALL, "kd", 0, 8000, box={**BOX, "tau": (0.001, 0.002)})


def test_a_small_budget_never_widens_the_inner_set() -> None:
    r = robust_passive_intervals(WALL, "kd", 0, 8000, box=BOX, rtol=1e-2, budget=1)
    assert r.intervals == () or all(b <= 4500 for _a, b in r.intervals)
    assert r.outer and r.outer[0][1] >= 4500


def test_a_total_cell_cap_stops_the_work_and_never_widens_the_inner_set(
    wall_set: RobustIntervals,
) -> None:
    """``max_cells`` bounds every certificate together: with none, nothing is certified (the
    inner set is empty, ``exhausted``); with a few, the inner set is a subset of the full one."""
    none = robust_passive_intervals(WALL, "kd", 0, 8000, box=BOX, rtol=1e-2, max_cells=0)
    assert none.intervals == () and none.exhausted and none.cells == 0
    assert none.outer and none.outer[0][1] >= 4500  # the outer set stays an enclosure
    assert none.to_dict()["exhausted"] is True and wall_set.to_dict()["exhausted"] is False
    few = robust_passive_intervals(WALL, "kd", 0, 8000, box=BOX, rtol=1e-2, max_cells=2000)
    assert few.exhausted and few.cells <= 2000
    assert all(any(c <= a and b <= d for c, d in wall_set.outer) for a, b in few.intervals)
    assert all(b <= 4500 for _a, b in few.intervals)
    with pytest.raises(ParameterError, match="max_cells must be None or an integer"):
        robust_passive_intervals(WALL, "kd", 0, 8000, box=BOX, max_cells=-1)
