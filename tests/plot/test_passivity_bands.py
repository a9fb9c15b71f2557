"""Passivity plots: exact failing bands, Bode/real/Nyquist figures, ``seapass plot``, ``.plot()``."""

from __future__ import annotations

import itertools
import math
from fractions import Fraction as F
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.analysis.freqresp import stiffness_response
from seapass.analysis.passivity import Reason, is_passive
from seapass.analysis.portresponse import (
    impedance_response,
    negative_real_bands,
    real_part_x,
)
from seapass.cli import main
from seapass.model.catalog import REFERENCE_VALUES, SIMULATION_DESIGNS, TABLE_ROWS
from seapass.model.sea import SEA
from seapass.plot.style import bare_figures, figure_bytes, figure_style

INF = math.inf

# Z = N/D, descending decimal coefficients taken exactly -> the bands where Re Z(jω) < 0
BANDS = [
    ("1/(s+1)", ["1"], ["1", "1"], ()),
    ("(s-1)/(s+2)", ["1", "-1"], ["1", "2"], ((0.0, math.sqrt(2.0)),)),
    ("(s+2)/(s-1) unstable", ["1", "2"], ["1", "-1"], ((0.0, math.sqrt(2.0)),)),
    ("3/s lossless", ["3"], ["1", "0"], ()),
    # P(x) = (x - 100)(x - 100.0001): a band 5e-6 rad/s wide at ω = 10
    ("narrow", ["1", "9801.0099", "10000.01"], ["1", "1", "1"], ((10.0, math.sqrt(100.0001)),)),
    # P(x) = (x - 1)^2: touches zero at ω = 1, never negative
    ("touch", ["1", "0", "1"], ["1", "1", "1"], ()),
    # P(x) = -(x - 1)^2: negative everywhere but at ω = 1: one band
    ("negative touch", ["-1", "0", "-1"], ["1", "1", "1"], ((0.0, INF),)),
    # Re Z -> -1 at high frequency: P(x) = 2 - x
    ("(-s+2)/(s+1)", ["-1", "2"], ["1", "1"], ((math.sqrt(2.0), INF),)),
]


def _poly(desc: list[str]) -> tuple[F, ...]:
    return tuple(F(c) for c in reversed(desc))


@pytest.mark.parametrize(("name", "num", "den", "expected"), BANDS, ids=[b[0] for b in BANDS])
def test_negative_bands_reference_table(
    name: str, num: list[str], den: list[str], expected: tuple[tuple[float, float], ...]
) -> None:
    bands = negative_real_bands(_poly(num), _poly(den))
    assert len(bands) == len(expected)
    for (a, b), (ea, eb) in zip(bands, expected, strict=True):
        assert a == pytest.approx(ea, rel=1e-14, abs=0)
        assert b == pytest.approx(eb, rel=1e-14, abs=0) if eb < INF else b == INF


def test_narrow_band_is_found_exactly_where_a_grid_misses_it() -> None:
    z = ((F("1"), F("9801.0099"), F("10000.01")), (F(1), F(1), F(1)))  # descending, exact
    grid = np.logspace(-1, 3, 600)
    s = 1j * grid
    re = ((s**2 + 9801.0099 * s + 10000.01) / (s**2 + s + 1)).real
    assert np.all(re >= 0), "the grid alone sees no negative real part"
    resp = impedance_response(z, grid)
    ((a, b),) = resp.negative_bands
    assert a == 10.0 and b == math.sqrt(100.0001) and b - a < 1e-5
    assert a in resp.omega and b in resp.omega  # the edges are drawn exactly
    mid = 0.5 * (a + b)
    sm = 1j * mid
    assert ((sm**2 + 9801.0099 * sm + 10000.01) / (sm**2 + sm + 1)).real < 0
    assert not is_passive(z).passive


_coef = st.integers(-6, 6).map(F)


@settings(max_examples=60, deadline=None)
@given(st.lists(_coef, min_size=1, max_size=4), st.lists(_coef, min_size=1, max_size=4))
def test_bands_agree_with_the_verdict_and_with_sampling(num: list[F], den: list[F]) -> None:
    """Independent checks: the PR verdict, and Re Z evaluated in floats inside and outside."""
    if not any(den) or not any(num):
        return
    r = is_passive((list(reversed(num)), list(reversed(den))))
    resp = r.response()
    bands = resp.negative_bands
    if r.reason == Reason.NEGATIVE_REAL_PART:
        assert bands and any(a < r.omega < b for a, b in bands)
    if r.passive:
        assert not bands
    px = real_part_x(r.exact_num, r.exact_den)
    # the sign of P at a point inside every band and between bands, in exact arithmetic
    edges = [0.0] + [e for band in bands for e in band] + [INF]
    for lo, hi in itertools.pairwise(edges):
        if hi == lo:
            continue
        w = lo + 1.0 if hi == INF else (0.5 * hi if lo == 0 else math.sqrt(lo * hi))
        x = F(w) ** 2
        value = sum(F(int(c.p), int(c.q)) * x**i for i, c in enumerate(px.coeffs()))
        inside = any(a <= lo and hi <= b for a, b in bands)
        if inside:
            assert value <= 0
        else:
            assert value >= 0


def test_plots_return_axes_and_leave_global_state_alone() -> None:
    import matplotlib.pyplot as plt

    sea = SEA(D1="k1", CL="kd + bd*s", values=dict(m=1, b=10, k1=1e3, kd=500, bd=20), name="PD")
    before = (dict(matplotlib.rcParams), plt.get_fignums(), matplotlib.get_backend())
    with figure_style(), bare_figures():
        r = is_passive(sea)
        ax = r.plot()
        assert ax.get_xscale() == "log" and ax.get_yscale() == "symlog"
        assert "Re Z < 0 (exact)" in [t.get_text() for t in ax.get_legend().get_texts()]
        ax2 = r.plot("nyquist")
        axes = stiffness_response(sea).plot(bands=r.response().negative_bands)
        assert axes.shape == (2,) and axes[1].get_ylabel().startswith("phase")
        resp = impedance_response(sea)
        assert resp.plot("nyquist").get_xlabel() == "Re Z [N·s/m]"
        assert figure_bytes(ax, "png").startswith(b"\x89PNG")
        for a in (ax2, axes):
            a.flat[0].figure.clear() if hasattr(a, "flat") else a.figure.clear()
    after = (dict(matplotlib.rcParams), plt.get_fignums(), matplotlib.get_backend())
    assert before == after
    with pytest.raises(ValueError, match="kind"):
        resp.plot("bode")


@pytest.mark.parametrize("design", [*SIMULATION_DESIGNS, *TABLE_ROWS], ids=lambda d: d.key)
def test_catalog_bands_match_the_verdicts(design: object) -> None:
    used = design.sea().parameters  # type: ignore[attr-defined]
    sea = design.sea({k: v for k, v in REFERENCE_VALUES.items() if k in used})  # type: ignore[attr-defined]
    r = is_passive(sea)
    resp = impedance_response(sea)
    assert resp.negative_bands == r.response().negative_bands
    if r.reason == Reason.NEGATIVE_REAL_PART:
        assert any(a < r.omega < b for a, b in resp.negative_bands)
    elif r.passive:
        assert not resp.negative_bands


def test_cli_plot_writes_png_svg_pdf(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    model = ["--D1", "k1", "--CL", "kd + bd*s", "--set", "m=1", "--set", "b=10",
             "--set", "k1=1000", "--set", "kd=500", "--set", "bd=20"]  # fmt: skip
    magic = {"real.png": b"\x89PNG", "nyquist.svg": b"<?xml", "bode.pdf": b"%PDF"}
    for name, head in magic.items():
        kind = name.split(".")[0]
        assert main(["plot", kind, *model, "--plot", str(tmp_path / name)]) == 0
        assert (tmp_path / name).read_bytes().startswith(head)
        out, err = capsys.readouterr()
        assert err.strip() == f"wrote {tmp_path / name}"
        assert "Re Z" in out and "(35.3553, inf)" in out
    assert main(["plot", "real", *model, "--plot", str(tmp_path / "noext")]) == 0
    assert (tmp_path / "noext.png").is_file()
    capsys.readouterr()


def test_cli_plot_json_and_errors(capsys: pytest.CaptureFixture[str]) -> None:
    import json

    assert main(["plot", "real", "--Z", "(s - 1)/(s + 2)", "--omega", "0.1:10",
                 "--points", "50", "--json"]) == 0  # fmt: skip
    data = json.loads(capsys.readouterr().out)
    assert data["negative_bands"] == [[0.0, pytest.approx(math.sqrt(2.0), rel=1e-15)]]
    assert len(data["omega"]) == 51 and math.sqrt(2.0) in data["omega"]
    assert main(["plot", "bode", "--Z", "(s + 1)/(s + 2)", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["negative_real_bands"] == [] and data["static"] == 0.0
    for argv, msg in [
        (["plot", "real", "--Z", "1/(s+1)", "--plot", "x.jpg"], "unknown figure format"),
        (
            ["plot", "real", "--Z", "1/(s+1)", "--omega", "0:10"],
            "--omega must be positive frequencies 0 < lo < hi",
        ),
        (["plot", "nyquist", "--Z", "1/(s+1)", "--points", "1"], "--points 1"),
    ]:
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("error:") and msg in err


def test_analyze_stage_draws_the_three_plots() -> None:
    from seapass.model.design_file import load_design
    from seapass.report.analyze import analyze

    examples = Path(__file__).resolve().parents[2] / "examples"
    design = load_design(examples / "load_pd_not_passive.toml")
    (sec,) = analyze(design, quick=True, stages=["frequency"]).sections[:1]
    assert sec.status == "ok"
    assert [f.name for f in sec.figures] == ["bode", "real_part", "nyquist"]
    exact = is_passive(design.sea()).response().negative_bands
    assert exact and sec.tables[0].rows == exact
    assert "Re Z_L(jω) < 0 for ω in" in sec.text
