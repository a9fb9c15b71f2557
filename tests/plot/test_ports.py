"""Figures of the two-port results: Axes in, Axes out, exact bands shaded, no global state."""

from __future__ import annotations

import matplotlib
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from seapass.model.sea import SEA
from seapass.plot.ports import plot_eta, plot_minors, plot_port_region
from seapass.plot.style import bare_figures
from seapass.ports.bound import port_region
from seapass.ports.check import check_two_port
from seapass.ports.friction import friction_certificate
from seapass.ports.mimo import mimo_is_passive

RIG = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)
SEA_5000 = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": 5000.0})


def _red_spans(ax: Axes) -> int:
    return sum(1 for p in ax.patches if p.get_facecolor()[0] > 0.7 and p.get_facecolor()[1] < 0.3)


def test_eta_and_minor_plots_shade_the_exact_bands() -> None:
    before = dict(matplotlib.rcParams)
    check = check_two_port(SEA_5000, witness=False)
    with bare_figures():
        ax = check.plot()
        assert isinstance(ax, Axes) and _red_spans(ax) == len(check.stability.bands)
        assert "η" in ax.get_title() and "not absolutely stable" in ax.get_title()
        ax2 = check.plot("minors")
        assert _red_spans(ax2) == len(check.passivity.bands) > 0
        fig = Figure()
        mine = fig.add_subplot()
        assert plot_eta(check.stability, ax=mine) is mine
        assert plot_minors(check.passivity, ax=fig.add_subplot(2, 1, 2)).figure is fig
    assert dict(matplotlib.rcParams) == before


def test_mimo_friction_and_region_plots() -> None:
    r = mimo_is_passive(
        [["b + k/s", "c/s"], ["-c/s", "b + k/s"]], values={"b": 10, "k": 100, "c": 50}
    )
    reg = port_region(
        SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kd": None, "kl": None}),
        "kd", [0.0, 1000.0, 2000.0], "kl", (0.0, 5000.0),
    )  # fmt: skip
    with bare_figures():
        assert _red_spans(r.plot()) == len(r.bands) > 0
        assert isinstance(friction_certificate(SEA_5000.with_values(kl=0.0)).plot(), Axes)
        ax = plot_port_region(reg)
        assert len(ax.patches) == 3 and ax.get_xlabel() == "kd"
