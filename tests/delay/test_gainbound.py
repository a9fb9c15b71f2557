"""The certified passive set of a gain at a fixed delay (``seapass bound`` with a delay).

Cross-checks: the rigid wall's closed form ``kd <= b/τ``; an independent dense frequency
sweep with local refinement of ``Re Z_L(jω)`` (``tests/delay/reference.py``, numpy/scipy,
no ``seapass.delay``) at gains just inside and just outside each end, and across the
interval; a starved search never widens an interval (its gaps are undecided).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from flint import fmpq

from seapass.delay import gainbound
from seapass.delay.gainbound import passive_gain_intervals
from seapass.delay.gainfamily import family_certificate, gain_family
from seapass.delay.passivity import delayed_passivity
from seapass.errors import DelayError, ParameterError
from seapass.model.sea import SEA, Impedance
from seapass.outcome import Outcome

from .reference import min_real_part, sea_impedance

WALL = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=10, k1=1000, kd=None, tau=0.002))
OURS = SEA(
    D1="k1 + b1*s",
    CA="(kd + bd*s)*exp(-tau*s)",
    values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25, tau=0.01),
)


def _min_re(sea: SEA, tau: float) -> float:
    return min_real_part(lambda w: sea_impedance(sea, w, tau).real, 1e-2, 1e5)[0]


def test_wall_closed_form_b_over_tau():
    r = passive_gain_intervals(WALL, "kd", 0, 8000, points=5, rtol=1e-7)
    ((a, b),) = r.intervals
    ((lo_edge, hi_edge),) = r.edges
    assert a == 0.0 and lo_edge == (0.0, 0.0)
    assert hi_edge is not None and hi_edge[0] == b <= 5000 <= hi_edge[1]
    assert hi_edge[1] - hi_edge[0] <= 1e-7 * 5000 * 1.01
    assert r.outcome is Outcome.PASSIVE and r.undecided == ()
    # the printed (double) ends are themselves passive, the outer end is not
    assert delayed_passivity(WALL, values=dict(kd=b)).outcome is Outcome.PASSIVE
    assert delayed_passivity(WALL, values=dict(kd=hi_edge[1])).outcome is Outcome.NOT_PASSIVE


def test_ours_against_a_dense_sweep_inside_and_outside():
    r = passive_gain_intervals(OURS, "kd", 0, 1e4, rtol=1e-6)
    ((a, b),) = r.intervals
    ((_, (end, outer)),) = r.edges
    assert a == 0.0 and end == b and outer > b and outer - b <= 1e-6 * outer * 1.01
    for k in (*np.linspace(a, b, 4)[1:], b * (1 - 1e-4)):
        assert _min_re(OURS.with_values(kd=float(k)), 0.01) >= -1e-9, k
    assert _min_re(OURS.with_values(kd=outer * (1 + 1e-4)), 0.01) < 0
    assert _min_re(OURS.with_values(kd=1.1 * outer), 0.01) < 0
    out = r.to_dict()
    json.dumps(out, allow_nan=False)
    assert {"param", "range", "intervals", "edges", "undecided", "outcome", "delay"} <= set(out)
    assert out["delay"] == {"name": "tau", "tau": 0.01}


def test_a_second_gain_and_a_lower_end():
    r = passive_gain_intervals(OURS.with_values(kd=3000), "bd", 0, 300, points=7, rtol=1e-5)
    for (a, b), (le, he) in zip(r.intervals, r.edges, strict=True):
        assert le is not None and he is not None
        for k, inside in ((le[0], False), (a, True), (b, True), (he[1], False)):
            if le[0] == le[1] and k == le[0]:
                continue  # the end of the search range
            got = delayed_passivity(OURS.with_values(kd=3000, bd=k)).outcome
            assert got is (Outcome.PASSIVE if inside else Outcome.NOT_PASSIVE), (k, got)
        mid = (a + b) / 2
        assert _min_re(OURS.with_values(kd=3000, bd=mid), 0.01) >= -1e-9


@pytest.mark.parametrize("steps", [3, 8])
def test_a_starved_search_never_widens(monkeypatch, steps):
    monkeypatch.setattr(gainbound, "MAX_STEPS", steps)
    r = passive_gain_intervals(WALL, "kd", 0, 8000, points=5)
    assert r.intervals[0][0] == 0 and all(b <= 5000 for _, b in r.intervals)
    upper = r.edges[-1][1]
    if steps == 3:  # no family certificate, 6000 never decided: gaps undecided, not passive
        assert upper is None and r.outcome is Outcome.UNDECIDED
        assert r.undecided[-1] == (r.intervals[-1][1], 8000.0)
        assert r.intervals == ((0.0, 0.0), (2000.0, 2000.0), (4000.0, 4000.0))
    else:  # 6000 is proven not passive: a wide but certified enclosure
        assert upper is not None and upper[0] == r.intervals[-1][1] <= 5000 <= upper[1]


def test_family_certificate_fails_across_the_boundary():
    fam = gain_family(WALL, "kd", tau=fmpq(1, 500))
    assert family_certificate(fam, fmpq(4990), fmpq(5000)).ok
    assert not family_certificate(fam, fmpq(4990), fmpq(5001)).ok


@pytest.mark.parametrize(
    ("system", "kwargs", "error", "words"),
    [
        (WALL, dict(gain="kp"), ParameterError, "not a parameter"),
        (WALL, dict(gain="kd", tau=-0.001), ParameterError, ">= 0"),
        (WALL.with_values(tau=None), dict(gain="kd"), ParameterError, "no value for the delay"),
        (WALL, dict(gain="kd", delay="T"), ParameterError, "not the delay"),
        (SEA(D1="k1", CA="kd", values=dict(m=1, b=10, k1=1000, kd=None)), dict(gain="kd"),
         DelayError, "no delay"),
        (WALL, dict(gain="kd", points=1), ParameterError, "points"),
    ],
)  # fmt: skip
def test_bad_input(system, kwargs, error, words):
    with pytest.raises(error, match=words):
        passive_gain_intervals(system, lo=0, hi=8000, **kwargs)


def test_a_root_from_infinity_at_an_end_is_not_certified():
    # D = 2 - g s + e^{-s tau}: passive at g = 0, a root comes in from +infinity for g > 0
    z = Impedance(expr="1/(2 - g*s + exp(-tau*s))", values=dict(g=None, tau=0.01))
    fam = gain_family(z, "g", tau=fmpq(1, 100))
    assert delayed_passivity(z, values=dict(g=0)).outcome is Outcome.PASSIVE
    assert delayed_passivity(z, values=dict(g=0.5)).outcome is Outcome.NOT_PASSIVE
    assert not family_certificate(fam, fmpq(0), fmpq(1)).ok
    r = passive_gain_intervals(z, "g", 0, 1, points=3)
    assert r.intervals == ((0.0, 0.0),) and r.edges[0][1] is not None
