"""The one Bode plot of the rendered stiffness (seapass plot bode, both reports, .plot())."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from seapass.analysis.freqresp import stiffness_response
from seapass.model.sea import SEA
from seapass.plot.passivity import plot_bode
from seapass.plot.style import bare_figures

SRC = Path(__file__).resolve().parents[2] / "src" / "seapass"
LP = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))


def test_one_function_draws_every_bode_plot() -> None:
    # plot.response had a second Bode plot of the same stiffness, used by the reports
    users = sorted(
        str(p.relative_to(SRC)) for p in SRC.rglob("*.py") if "plot_bode(" in p.read_text()
    )
    assert users == [
        "analysis/freqresp.py",
        "plot/passivity.py",
        "report/stages/design_dynamics.py",
        "report/stages/design_frequency.py",
        "report/stages/tables.py",
    ]
    assert not [p for p in SRC.rglob("*.py") if "plot_stiffness_bode" in p.read_text()]


def test_legend_bands_and_phase_ticks() -> None:
    w = np.logspace(-1, 4, 200)
    a = stiffness_response(LP, w, label="LP")
    b = stiffness_response(LP.with_values(kd=100), w, label="kd = 100")
    with bare_figures():
        ax_m, ax_p = plot_bode([a, b], reference=1000.0, bands=[(30.0, 1e9)])
        labels = [t.get_text() for t in ax_m.get_legend().get_texts()]
        assert labels == ["LP", "kd = 100", "spring k1 = 1000 N/m", "Re Z < 0 (exact)"]
        assert ax_m.get_xlim() == (w[0], w[-1])  # the band is cut at the curve's ends
        ticks = ax_p.get_yticks()
        assert np.all(np.diff(ticks) == 45.0)
        ax_m, _ = plot_bode(a, reference=1000.0, legend=False, title="t")
        assert ax_m.get_legend() is None and ax_m.get_title() == "t"
