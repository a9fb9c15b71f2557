"""Robust passive intervals of a gain over a box of plants (issue 26)."""

from __future__ import annotations

import numpy as np
import pytest

import seapass
from seapass.analysis.passivity import is_passive
from seapass.analysis.region import passive_intervals
from seapass.errors import ParameterError
from seapass.model.sea import SEA
from seapass.robust.intervals import robust_passive_intervals
from seapass.robust.verdict import robust_check

LP = SEA(D1="k1", CL="kd", values=dict(m=1.0, b=10.0, k1=1000.0))
DAMPED = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1.0, b=10.0, k1=1000.0, b1=20.0))


def _intersection(system: SEA, gain: str, lo: float, hi: float, name: str, values: np.ndarray):
    """The passive set of ``gain`` intersected over plants (exact per plant, independent of robust)."""
    out = [(lo, hi)]
    for v in values:
        ivs = passive_intervals(system, gain, lo, hi, values={name: float(v)}).intervals
        out = [(max(a, c), min(b, d)) for a, b in out for c, d in ivs if max(a, c) <= min(b, d)]
    return out


def test_one_uncertain_parameter_gives_the_exact_robust_set_of_load_side_p() -> None:
    # load-side P on a pure spring is passive iff kd <= k1 (Table I): the robust set is kd <= 800
    r = robust_passive_intervals(LP, "kd", 0, 2000, box={"k1": (800.0, 1200.0)})
    assert r.method == "exact" and r.intervals == ((0.0, 800.0),) and r.outer == ((0.0, 800.0),)
    assert r.intervals == tuple(_intersection(LP, "kd", 0, 2000, "k1", np.linspace(800, 1200, 9)))


def test_irrational_ends_are_rounded_inward_and_match_the_intersection_over_plants() -> None:
    r = robust_passive_intervals(DAMPED, "kd", 0, 5000, box={"b": (5.0, 15.0)})
    assert r.method == "exact" and len(r.intervals) == 1
    ((a, b),) = r.intervals
    (ref,) = _intersection(DAMPED, "kd", 0, 5000, "b", np.linspace(5, 15, 21))
    assert a == ref[0] and b <= ref[1] and b == pytest.approx(ref[1], rel=1e-12)
    # every printed end is passive for every plant of the box, one ulp beyond is not
    assert robust_check(DAMPED, box={"b": (5.0, 15.0)}, values={"kd": b}).passive
    beyond = float(np.nextafter(np.nextafter(b, np.inf), np.inf))
    assert not robust_check(DAMPED, box={"b": (5.0, 15.0)}, values={"kd": beyond}).passive


def test_several_uncertain_parameters_give_certified_inner_and_outer_sets() -> None:
    box = {"k1": (800.0, 1200.0), "m": (0.5, 2.0)}
    r = robust_passive_intervals(LP, "kd", 0, 2000, box=box, rtol=1e-3)
    assert r.method == "certified"
    (inner,) = r.intervals
    (outer,) = r.outer
    assert outer[0] <= inner[0] and inner[1] <= outer[1]
    assert outer[1] == pytest.approx(800.0) and inner[1] >= 800.0 - 2.0  # rtol * 2000
    for kd in (inner[0], inner[1], (inner[0] + inner[1]) / 2):
        assert robust_check(LP, box=box, values={"kd": kd}).passive
    # above the outer set some plant of the box is not passive
    assert not is_passive(LP, values={"kd": outer[1] + 1.0, "k1": 800.0, "m": 1.0}).passive
    d = r.to_dict()
    assert d["robust"] is True and d["outer"] == [list(outer)] and d["intervals"] == [list(inner)]


def test_top_level_passive_intervals_takes_a_box() -> None:
    r = seapass.passive_intervals(LP, "kd", 0, 2000, box={"k1": (800.0, 1200.0)})
    assert r.intervals == ((0.0, 800.0),)
    plain = seapass.passive_intervals(LP, "kd", 0, 2000)
    assert plain.intervals == ((0.0, 1000.0),)


def test_bad_robust_interval_inputs_are_refused() -> None:
    with pytest.raises(ParameterError, match="cannot also be uncertain"):
        robust_passive_intervals(LP, "kd", 0, 2000, box={"kd": (1.0, 2.0)})
    with pytest.raises(ParameterError, match="empty range"):
        robust_passive_intervals(LP, "kd", 2000, 0, box={"k1": (800.0, 1200.0)})
    with pytest.raises(ParameterError, match="does not appear"):
        robust_passive_intervals(LP, "bd", 0, 1, box={"k1": (800.0, 1200.0)})


def test_robust_results_plot_on_given_axes() -> None:
    import matplotlib.pyplot as plt

    from seapass.robust.verdict import robust_check

    fig, (ax1, ax2) = plt.subplots(1, 2)
    r = robust_passive_intervals(LP, "kd", 0, 2000, box={"k1": (800.0, 1200.0)})
    assert r.plot(ax=ax1) is ax1
    bad = robust_check(LP.with_values(kd=500.0), box={"k1": (100.0, 1000.0)})
    assert bad.plot(ax=ax2) is ax2
    good = robust_check(LP.with_values(kd=500.0), box={"k1": (800.0, 1000.0)})
    with pytest.raises(ValueError, match="no worst-case plant"):
        good.plot()
    plt.close(fig)
