"""The data behind the gain pictures at a fixed delay: the green spans are the certified
intervals, the grey ones the undecided gaps, the red ticks the gains proven not passive
(nothing is read off a grid)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np

from seapass.delay import gainbound
from seapass.delay.gainbound import passive_gain_intervals
from seapass.delay.gainmap import delay_passive_map
from seapass.model.sea import SEA

WALL = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=10, k1=1000, kd=None, tau=0.002))


def _spans(ax, color):
    out = []
    for p in ax.patches:
        if np.allclose(p.get_facecolor()[:3], matplotlib.colors.to_rgb(color)):
            if hasattr(p, "get_width"):  # a Rectangle (matplotlib >= 3.9)
                out.append((float(p.get_x()), float(p.get_x() + p.get_width())))
            else:
                xs = np.asarray(p.get_xy())[:, 0]
                out.append((float(np.min(xs)), float(np.max(xs))))
    return sorted(out)


def test_gain_interval_bar_shows_the_certified_sets(monkeypatch):
    r = passive_gain_intervals(WALL, "kd", 0, 8000, points=5)
    ax = r.plot()
    assert _spans(ax, "#9fd79f") == [tuple(iv) for iv in r.intervals]
    ticks = [line for line in ax.lines if line.get_marker() == "|"]
    assert list(ticks[0].get_xdata()) == list(r.not_passive)
    plt.close("all")
    monkeypatch.setattr(gainbound, "MAX_STEPS", 3)  # starved: undecided gaps drawn grey
    r = passive_gain_intervals(WALL, "kd", 0, 8000, points=5)
    ax = r.plot()
    assert r.undecided and _spans(ax, "0.75") == sorted(r.undecided)
    assert "DelayGainIntervals(" in repr(r) and "<table>" in r._repr_html_()
    plt.close("all")


def test_map_bars_are_the_columns():
    wall = WALL.with_values(b=None)
    m = delay_passive_map(wall, "b", [5, 10], "kd", (0, 8000), points=5)
    ax = m.plot()
    bars = sorted((p.get_x() + p.get_width() / 2, p.get_y(), p.get_y() + p.get_height())
                  for p in ax.patches)  # fmt: skip
    want = sorted(
        (x, a, b) for x, col in zip(m.x, m.columns, strict=True) for a, b in col.intervals
    )
    assert np.allclose(bars, want)
    assert "DelayPassiveMap(" in repr(m) and "<table>" in m._repr_html_()
    plt.close("all")


def test_gain_delay_region_picture_holds_the_certified_cells():
    from seapass.delay.gain import delay_region

    wall = WALL.with_values(tau=None)
    r = delay_region(wall, "kd", 1000, 4000, points=4, taus=[0.001, 0.003, 0.02])
    ax = r.plot()
    (mesh,) = ax.collections
    codes = np.asarray(mesh.get_array()).reshape(len(r.taus), len(r.gains))
    assert np.array_equal(codes, np.asarray(r.codes).T)
    (curve,) = [line for line in ax.lines if "margin" in str(line.get_label())]
    assert np.allclose(curve.get_ydata(), r.margins) and np.allclose(curve.get_xdata(), r.gains)
    assert np.allclose(r.margins, [10 / k for k in r.gains], rtol=1e-3)  # tau* = b/kd
    plt.close("all")
