"""One-line reprs, notebook HTML cards and ``.plot()`` of the analysis, sampled, tuning and
sweep results (the models and the other results are covered in tests/model/test_pycontrol_interop.py)."""

from __future__ import annotations

import dataclasses
import warnings
from typing import Any

import matplotlib
import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from seapass.analysis.coupled import Environment
from seapass.analysis.environment_box import HUMAN_LIMB
from seapass.analysis.indices import passivity_indices
from seapass.analysis.witness import WitnessResult, find_destabilizing_environment
from seapass.exact.rounding import decimal_down
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.plot.style import bare_figures
from seapass.sampled.bound import intervals_text, sampled_passive_bound
from seapass.sampled.passivity import sampled_passivity
from seapass.sampled.region import ZWidthMap, sampled_region
from seapass.sweep import GridAxis, SweepSpec, run_design_sweep
from seapass.tuning.optimize import tune

T = 0.002
LOOP = SampledLoop(period=T)
RIG = {"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 30.0}
HOSTILE = "<script>alert(1)</script>"


@pytest.fixture(scope="module")
def results(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """One of each result, computed once (a few seconds in all)."""
    lp = SEA(D1="k1 + b1*s", CL="kd", values={**RIG, "kd": None})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tuned = tune(
            SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1000, b1=30)),
            tune={"kd": (0, 3000), "bd": (0, 400)},
            maxiter=4,
            popsize=4,
            dt_search=1e-2,
        )
    sweep_spec = SweepSpec(
        sea=SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1.0, b=10.0, k1=1000.0)),
        grid=(GridAxis("b1", 0.0, 40.0, 20.0), GridAxis("kd", 500.0, 1500.0, 250.0)),
        chunk_size=4,
        horizon=1.0,
    )
    return {
        "tuning": tuned,
        "witness": find_destabilizing_environment(
            SEA(D1="k1", CL="kd", values={"m": 1, "b": 10, "k1": 1000, "kd": 2000})
        ),
        "indices": passivity_indices("s/(s**2 + 0.2*s + 1)"),
        "sampled": sampled_passivity(lp, loop=LOOP.replace(delay=1), values={"kd": 900.0}),
        "bound": sampled_passive_bound(lp, "kd", loop=LOOP, lo=0, hi=5000, design_value=500.0),
        "zwidth": sampled_region(
            SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG),
            "kd",
            "bd",
            loop=LOOP.replace(delay=1, velocity_filter=50.0),
            p1_range=(0, 5000),
            p2_range=(0, 20),
            n=3,
            rtol=1e-3,
        ),
        "sweep": run_design_sweep(sweep_spec, tmp_path_factory.mktemp("sweep") / "s.parquet"),
    }


KINDS = ["tuning", "witness", "indices", "sampled", "bound", "zwidth", "sweep"]


@pytest.mark.parametrize("kind", KINDS)
def test_repr_is_one_short_line(results: dict[str, Any], kind: str) -> None:
    obj = results[kind]
    text = repr(obj)
    assert text.startswith(type(obj).__name__ + "(") and text.endswith(")")
    assert "\n" not in text and len(text) <= 200, text
    for dump in ("array(", "mappingproxy", "<Reason.", "<Outcome.", "<Settling.", "Result("):
        assert dump not in text[len(type(obj).__name__) :], text


@pytest.mark.parametrize("kind", KINDS)
def test_html_card_is_a_table(results: dict[str, Any], kind: str) -> None:
    html = results[kind]._repr_html_()
    assert html.startswith("<div><strong>") and "<table>" in html and html.endswith("</div>")
    assert "array(" not in html and "<script" not in html


def test_reprs_say_the_key_facts(results: dict[str, Any]) -> None:
    r = results
    gains = r["tuning"].gains
    assert repr(r["tuning"]).startswith(
        f"TuningResult(design='design', gains={{'kd': {gains['kd']:.6g}, 'bd': {gains['bd']:.6g}}}, "
        f"settling={r['tuning'].objective:.6g}, feasible=True, passive=True"
    )
    m = r["witness"].environment.mass
    assert repr(r["witness"]) == (
        "WitnessResult(status='found', reason='negative_real_part', environment=Environment("
        f"mass={m:.6g}, damping=0, stiffness=0), "
        f"growth_rate={r['witness'].coupled.max_real_part:.6g})"
    )
    assert repr(r["indices"]) == "PassivityIndices(nu=0, rho=0.2)"
    assert repr(r["indices"].output) == "PassivityIndex(value=0.2, sign=1, omega=0)"
    assert repr(passivity_indices("(s - 1)/(s + 2)")) == (
        "PassivityIndices(nu=-0.5, rho=-inf, rho_reason='rhp_pole')"
    )
    assert repr(r["sampled"]) == (
        "SampledPassivityResult(status='not_passive', reason='low_frequency', "
        f"omega={r['sampled'].omega:.6g}, period=0.002, delay=1)"
    )
    top = r["bound"].max_passive
    assert 798 < top < 799
    assert repr(r["bound"]) == (
        # the largest passive value is shown rounded down (inward), issue 20
        f"SampledBoundResult(param='kd', period=0.002, delay=0, passive=[0, {decimal_down(top, 6)}], "
        f"max_passive={decimal_down(top, 6)}, design_passive=True)"
    )
    assert repr(r["zwidth"]) == "ZWidthMap(p1='kd', p2='bd', period=0.002, rows=3, setups=3)"
    sweep = r["sweep"]
    assert repr(sweep) == (
        f"DesignSweepResult(path={sweep.path!r}, designs=15, passive={sweep.n_passive}, "
        f"settled={sweep.n_settled}, complete=True, chunks=4)"
    )


def test_html_cards_hold_the_key_numbers(results: dict[str, Any]) -> None:
    r = results
    html = r["tuning"]._repr_html_()
    assert all(f"{v:.6g}" in html for v in r["tuning"].gains.values())
    assert f"{r['tuning'].objective:.6g} s" in html and "feasible" in html
    html = r["witness"]._repr_html_()
    assert f"m_e = {r['witness'].environment.mass:.4g} kg" in html and "unstable" in html
    assert "ρ = 0.2" in r["indices"]._repr_html_()
    html = r["sampled"]._repr_html_()
    assert "not passive" in html and f"ω = {r['sampled'].omega:.6g}" in html
    html = r["bound"]._repr_html_()
    assert f"[0, {decimal_down(r['bound'].max_passive, 6)}]" in html and "design kd = 500" in html
    html = r["zwidth"]._repr_html_()
    z = r["zwidth"]
    for s in z.setups:
        assert decimal_down(np.nanmax(z.upper_boundary(s.label)), 6) in html
    html = r["sweep"]._repr_html_()
    assert f"{r['sweep'].n_passive} (" in html and "4 of 4" in html


def test_html_escapes_user_text(results: dict[str, Any]) -> None:
    r = results
    z = r["zwidth"]
    renamed = ZWidthMap(
        p1=HOSTILE, p2=z.p2, p1_range=z.p1_range, p2_values=z.p2_values,
        setups=z.setups, rows=z.rows,
    )  # fmt: skip
    hostile = [
        dataclasses.replace(r["tuning"], design=HOSTILE),
        dataclasses.replace(r["witness"], detail=HOSTILE),
        dataclasses.replace(r["sampled"], detail=HOSTILE),
        dataclasses.replace(r["bound"], param=HOSTILE),
        dataclasses.replace(r["sweep"], path=HOSTILE),
        renamed,
    ]
    for obj in hostile:
        html = obj._repr_html_()
        assert "<script" not in html and "&lt;script&gt;alert(1)&lt;/script&gt;" in html


def test_witness_not_found_and_passive() -> None:
    passive = find_destabilizing_environment("(s + 1)/(s + 2)")
    assert repr(passive) == "WitnessResult(status='passive')"
    assert "Destabilizing environment: passive" in passive._repr_html_()
    proven = WitnessResult(
        outcome=Outcome.NOT_PASSIVE,
        reason="negative_real_part",
        found=False,
        candidates=40,
        detail="none in the bounds (proven)",
        bounds=HUMAN_LIMB,
        certified=True,
        outside=Environment(0.004, 0.0, 0.0),
    )
    assert repr(proven) == (
        "WitnessResult(status='none in bounds (proven)', reason='negative_real_part', "
        "outside=Environment(mass=0.004, damping=0, stiffness=0))"
    )
    html = proven._repr_html_()
    assert "outside the bounds" in html and "m_e = 0.004 kg" in html


def test_intervals_text_is_bounded() -> None:
    assert intervals_text([], most=2) == "none"
    many = [(float(i), i + 0.5) for i in range(5)]
    assert intervals_text(many, most=2) == "[0, 0.5] ∪ [1, 1.5] ∪ 3 more"


@pytest.mark.parametrize(
    ("kind", "keyword", "panels"),
    [("tuning", "ax", 1), ("witness", "axes", 2), ("bound", "ax", 1), ("zwidth", "ax", 1)],
)
def test_plot_draws_on_given_axes_and_leaves_rcparams(
    results: dict[str, Any], kind: str, keyword: str, panels: int
) -> None:
    before = dict(matplotlib.rcParams)
    given = Figure().subplots(1, panels)
    out = results[kind].plot(**{keyword: given})
    if panels == 1:
        assert out is given and given.has_data()
    else:
        assert list(np.asarray(out).flat) == list(given)
    with bare_figures():
        fresh = results[kind].plot()
    assert all(isinstance(a, Axes) for a in np.asarray(fresh, dtype=object).flat)
    assert dict(matplotlib.rcParams) == before


def test_tuning_plot_draws_one_line_per_load_mass(results: dict[str, Any]) -> None:
    ax = Figure().subplots()
    results["tuning"].plot(ax=ax, load_masses=[1.0, 10.0], title="two masses")
    labels = [line.get_label() for line in ax.get_lines()]
    assert labels[:2] == [labels[0], labels[1]] and labels[0].startswith("m_L = 1 kg")
    assert labels[1].startswith("m_L = 10 kg") and ax.get_title() == "two masses"
