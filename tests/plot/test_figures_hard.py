"""Figures that do not mislead (issue 23 item 5), on hard designs: a right-half-plane pole and
a high order.  Each test renders the plot and checks the data behind it against an independent
evaluation of ``Z(jω)`` (sympy, not the coefficient arrays the plots use)."""

from __future__ import annotations

import contextlib
import io
import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from matplotlib.backends.backend_agg import FigureCanvasAgg

from seapass.analysis.freqresp import (
    PeakKind,
    log_frequencies,
    phase_curve,
    stiffness_peak,
    stiffness_response,
    wrap_phase,
)
from seapass.analysis.portresponse import band_curves, impedance_response
from seapass.cli import main
from seapass.model.sea import SEA, Impedance
from seapass.plot.passivity import plot_bode, plot_nyquist, plot_real_part
from seapass.plot.style import bare_figures, fit_text, set_suptitle, set_title

# a right-half-plane pole, a right-half-plane resonance, a stiffness that grows without bound;
# np.unwrap takes its phase to 449.6°
HARD_Z = "(s+1)^2*(s+10)/((s-1)*(s^2-0.2*s+400))"
# high order: series-elastic chain with a PI-D force loop and a second spring
HIGH = SEA(
    D1="k1 + b1*s",
    D2="k2",
    CA="kd + bd*s + ki/s",
    CL="kl",
    values=dict(m=1, b=10, k1=1005, b1=30, k2=3000, kd=400, bd=20, ki=2e4, kl=3000),
)


def _z_exact(text: str) -> sp.Expr:
    s = sp.Symbol("s")
    return sp.sympify(text.replace("^", "**"), locals={"s": s})


def _re_z(text: str, w: np.ndarray) -> np.ndarray:
    """``Re Z(jω)`` evaluated independently (sympy, high precision), one point at a time."""
    z = _z_exact(text)
    s = sp.Symbol("s")
    return np.array([float(sp.re(z.subs(s, sp.I * sp.Float(x, 30)).evalf(30))) for x in w])


def test_wrap_phase_keeps_the_angle_and_the_window() -> None:
    p = np.linspace(-1000.0, 1000.0, 2001)
    w = wrap_phase(p)
    assert w.min() >= -90.0 and w.max() < 270.0
    assert np.allclose(np.cos(np.radians(w)), np.cos(np.radians(p)))
    assert np.allclose(np.sin(np.radians(w)), np.sin(np.radians(p)))


def test_bode_phase_reads_against_the_passive_band_on_an_unstable_design() -> None:
    fr = stiffness_response(
        Impedance(expr=HARD_Z.replace("^", "**")), log_frequencies(1e-2, 2e3, 400)
    )
    assert fr.phase.max() > 440.0  # unwrapped, as the JSON keeps it
    with bare_figures():
        _ax_m, ax_p = plot_bode(
            fr, bands=impedance_response(HARD_Z.replace("^", "**")).negative_bands
        )
        drawn = np.concatenate(
            [ln.get_ydata() for ln in ax_p.get_lines() if len(ln.get_ydata()) > 2]
        )
    drawn = drawn[np.isfinite(drawn)]
    assert drawn.min() >= -90.0 and drawn.max() < 270.0
    # the drawn phase is inside [0°, 180°] exactly where Re Z(jω) >= 0 (independent sympy values)
    w = fr.omega[::8]
    re = _re_z(HARD_Z, w)
    inside = (wrap_phase(fr.phase[::8]) >= 0) & (wrap_phase(fr.phase[::8]) <= 180)
    clear = np.abs(re) > 1e-9 * np.abs(fr.magnitude[::8] / w)
    assert np.array_equal(inside[clear], re[clear] >= 0)
    assert inside.any() and not inside.all()


def test_phase_curve_breaks_at_each_wrap() -> None:
    w, p = phase_curve([1.0, 2.0, 3.0, 4.0], [200.0, 265.0, 275.0, 300.0])
    assert np.isnan(p[2]) and np.isnan(w[2]) and p[3] == pytest.approx(-85.0)
    assert np.all(np.abs(np.diff(p[np.isfinite(p)][2:])) < 180)


@pytest.mark.parametrize("system", [HARD_Z.replace("^", "**"), HIGH], ids=["rhp", "high-order"])
def test_nyquist_band_is_drawn_from_dense_points_inside_the_exact_band(system: object) -> None:
    resp = impedance_response(system)  # type: ignore[arg-type]
    assert resp.negative_bands
    curves = band_curves(resp, points=150)
    assert len(curves) == len(resp.negative_bands)
    for c, (a, b) in zip(curves, resp.negative_bands, strict=True):
        assert c.omega.size >= 150  # not the ~8 grid points that fell inside the band
        assert c.omega.min() >= a and (c.omega.max() <= b)
        assert c.omega[0] == a and (math.isinf(b) or c.omega[-1] == b)  # exact edges included
        inner = c.omega[1:-1]
        z = np.polyval(resp.num, 1j * inner) / np.polyval(resp.den, 1j * inner)
        assert np.all(z.real < 0)  # every inner point is in the left half-plane
    if isinstance(system, str):
        (_first, second) = curves
        re = _re_z(HARD_Z, second.omega[1:-1][::25])
        assert np.all(re < 0)
    with bare_figures():
        ax = plot_nyquist(resp, bands=curves)
        red = [ln for ln in ax.get_lines() if ln.get_color() == "tab:red"]
    assert [len(ln.get_xdata()) for ln in red] == [c.omega.size for c in curves]


def test_no_peak_at_the_grid_edge() -> None:
    fr = stiffness_response(
        Impedance(expr=HARD_Z.replace("^", "**")), log_frequencies(1, 1.25e5, 300)
    )
    peak = stiffness_peak(fr)
    assert peak.kind is PeakKind.UNBOUNDED_HIGH and not peak.is_peak
    assert peak.omega == fr.omega[-1] and math.isinf(peak.limit)
    assert "grows without bound" in peak.describe() and "peak" not in peak.describe()
    # a true maximum inside the grid is a peak; the right edge of a bounded stiffness is not
    lp = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))
    assert stiffness_response(lp, log_frequencies(0.1, 1e4, 400)).peak().kind is PeakKind.INTERIOR
    edge = stiffness_response(lp, log_frequencies(25, 30, 50)).peak()
    assert edge.kind is PeakKind.EDGE_HIGH and edge.limit == pytest.approx(1000.0)
    assert edge.describe().startswith("no peak on the grid")
    low = stiffness_response(lp, log_frequencies(0.1, 10, 50)).peak()
    assert low.kind is PeakKind.EDGE_LOW and low.limit == pytest.approx(500.0)
    integ = stiffness_response(Impedance(expr="1/s**2 + 1"), log_frequencies(0.1, 10, 50)).peak()
    assert integ.kind is PeakKind.UNBOUNDED_LOW


def _run(argv: list[str]) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(argv) == 0
    return out.getvalue()


def test_cli_bode_reports_no_peak_and_the_wrapped_phase(tmp_path: Path) -> None:
    text = _run(
        ["plot", "bode", "--Z", HARD_Z, "--omega", "1:1.25e5", "--plot", str(tmp_path / "b.png")]
    )
    assert "peak" not in text and "grows without bound as w -> inf" in text
    line = next(ln for ln in text.splitlines() if ln.startswith("phase from"))
    lo, hi = (float(x) for x in line.split()[2:5:2])
    assert -90 <= lo and hi < 270
    lp = ["plot", "bode", "--D1", "k1", "--CL", "kd"] + [
        a for kv in ("m=1", "b=10", "k1=1000", "kd=500") for a in ("--set", kv)
    ]
    assert "peak |F_L/X_L| = 198" in _run(lp)


def _inside_figure(fig: object, texts: list[object]) -> None:
    FigureCanvasAgg(fig)  # type: ignore[arg-type]
    fig.canvas.draw()  # type: ignore[attr-defined]
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    width = fig.bbox.width  # type: ignore[attr-defined]
    for t in texts:
        box = t.get_window_extent(renderer)  # type: ignore[attr-defined]
        assert box.x0 >= 0 and box.x1 <= width, (t.get_text(), box.x0, box.x1, width)  # type: ignore[attr-defined]


def test_titles_are_never_clipped() -> None:
    long = "A design with a rather long name: rendered stiffness (dashed: spring stiffness k1)"
    resp = impedance_response(HIGH)
    with bare_figures():
        ax_m, _ = plot_bode(stiffness_response(HIGH, resp.omega), title=long)
        _inside_figure(ax_m.figure, [ax_m.title])
        ax = plot_real_part(resp)  # the default title lists every band
        _inside_figure(ax.figure, [ax.title])
        ax = plot_nyquist(resp, title=long + " " + long)
        _inside_figure(ax.figure, [ax.title])
    # a grid of small panels, as the report's table figures
    from seapass.plot.style import axes_grid

    with bare_figures():
        grid = axes_grid(None, 2, 3, figsize=(8.0, 5.0))
        for a in grid.flat:
            set_title(a, "Spring with damping, actuator-side PD\nk1=1005, b1=30, kd=1000, bd=25")
        fig = grid[0, 0].figure
        sup = set_suptitle(
            fig, "Table II: rendered stiffness F_L/X_L(jω), magnitude and phase " * 2
        )
        _inside_figure(fig, [a.title for a in grid.flat] + [sup])


def test_fit_text_only_breaks_at_spaces() -> None:
    text = "one two three four five six seven eight nine ten"
    assert fit_text(text, 1e4, 10).count("\n") == 0
    wrapped = fit_text(text, 80, 10)
    assert wrapped.replace("\n", " ") == text and wrapped.count("\n") >= 2


def test_cli_response_says_no_peak_at_the_edge() -> None:
    lp = ["response", "--D1", "k1 + b1*s", "--CA", "kd"] + [
        a for kv in ("m=1", "b=10", "k1=1000", "b1=20", "kd=500") for a in ("--set", kv)
    ]
    text = _run(lp)  # grows like b1*s: the largest value is the grid's right edge
    assert "peak" not in text and "grows without bound as w -> inf" in text
