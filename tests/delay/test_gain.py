"""Gain against delay: certified columns and certified edges (wall closed form tau* = b/kd)."""

from __future__ import annotations

import json

import matplotlib.pyplot as plt
import pytest

from seapass.delay.gain import delay_gain_edges, delay_region
from seapass.delay.passivity import delayed_passivity
from seapass.errors import ParameterError
from seapass.model.sea import SEA
from seapass.outcome import Outcome

WALL = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=10, k1=1000, kd=None, tau=None))


def test_region_columns_follow_b_over_kd():
    r = delay_region(WALL, "kd", 1000, 4000, points=4, taus=[0.001, 0.003, 0.02])
    for k, m, codes in zip(r.gains, r.margins, r.codes, strict=True):
        assert m == pytest.approx(10 / k, rel=1e-3)
        assert codes == tuple(1.0 if t < 10 / k * (1 - 1e-3) else 0.0 for t in r.taus)
    json.dumps(r.to_dict(), allow_nan=False)
    assert "DelayRegion(" in repr(r) and "<table>" in r._repr_html_()
    r.plot()
    plt.close("all")


def test_edges_are_certified_at_both_ends():
    e = delay_gain_edges(WALL, "kd", 1000, 7000, tau=0.004, points=4, rtol=1e-4)
    ((good, bad),) = e.edges
    assert good < 2500 < bad and bad - good <= 1e-4 * bad
    sea = WALL.with_values(tau=0.004)
    assert delayed_passivity(sea.with_values(kd=good)).outcome is Outcome.PASSIVE
    assert delayed_passivity(sea.with_values(kd=bad * (1 + 1e-9))).outcome is Outcome.NOT_PASSIVE
    json.dumps(e.to_dict(), allow_nan=False)


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [(dict(gain="bogus", lo=0, hi=1), "not a parameter"), (dict(gain="kd", lo=2, hi=1), "lo < hi"),
     (dict(gain="kd", lo=0, hi=1, points=1), "points")],
)  # fmt: skip
def test_bad_region_arguments(kwargs, words):
    with pytest.raises(ParameterError, match=words):
        delay_region(WALL, **kwargs)
