"""The explorer's panels against seapass's entry points and independent checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from seapass.analysis.freqresp import stiffness_response
from seapass.analysis.passivity import is_passive
from seapass.explore.panels import compute, slider_grid
from seapass.explore.validation import check_state
from seapass.model.catalog import SIMULATION_DESIGNS, TABLE_ROWS, design
from seapass.model.sea import SEA


def _state(model: dict[str, str], values: dict[str, float], **extra: object):
    s = check_state({"model": model, "values": values, **extra}).state
    assert s is not None
    return s


LP = {"D1": "k1", "CL": "kd"}
PLANT = {"m": 1.0, "b": 10.0, "k1": 1000.0}


@pytest.mark.parametrize(
    ("kd", "passive"), [(500.0, True), (1000.0, True), (1000.0000001, False), (2000.0, False)]
)
def test_lp_verdict_flips_at_k1(kd: float, passive: bool) -> None:
    d = compute("verdict", _state(LP, {**PLANT, "kd": kd}))
    assert d["passive"] is passive
    assert d["passive"] == is_passive(SEA(**LP, values={**PLANT, "kd": kd})).passive


def test_lp_interval_is_exactly_up_to_k1() -> None:
    d = compute("interval", _state(LP, {**PLANT, "kd": 500.0}, ranges={"kd": [0, 5000]}))
    assert d["param"] == "kd" and d["intervals"] == [[0.0, 1000.0]]
    assert 1000.0 in d["critical_values"]
    assert d["shown"] == [["0", "1000"]]  # the text the page prints, rounded inward


def test_interval_text_is_rounded_inward() -> None:
    """The issue-20 design: every end the page prints is inside its interval and passive."""
    from seapass.analysis.passivity import is_passive
    from seapass.model.sea import SEA

    values = dict(m=14.214, b=11.6744, b1=15.1808, bd=387.517, k1=108.642)
    model = {"D1": "k1 + b1*s", "CA": "kd + bd*s", "CL": "kd"}
    d = compute("interval", _state(model, {**values, "kd": 50.0}, ranges={"kd": [0, 20000]}))
    sea = SEA(**model, values=values)
    for (a, b), (ta, tb) in zip(d["intervals"], d["shown"], strict=True):
        assert a <= float(ta) <= float(tb) <= b
        assert is_passive(sea.with_values(kd=float(tb))).passive
    assert d["shown"][0] == ["0", "118.467"]


@pytest.mark.parametrize(
    ("model", "values", "bands"),
    [
        (LP, {**PLANT, "kd": 500.0}, []),
        (LP, {**PLANT, "kd": 2000.0}, [(0.0, math.inf)]),
        # load-side PD: Re Z < 0 for w^2 > (b k1 + bd k1 - b kd)/(bd m) = 1200 (paper Table II)
        (
            {"D1": "k1", "CL": "kd + bd*s"},
            {**PLANT, "kd": 500.0, "bd": 25.0},
            [(math.sqrt(1200), math.inf)],
        ),
    ],
)
def test_failing_bands_exact(model: dict[str, str], values: dict[str, float], bands: list) -> None:
    d = compute("frequency", _state(model, values))
    got = [(a, math.inf if b is None else b) for a, b in d["bands"]]
    assert len(got) == len(bands)
    for (a, b), (ea, eb) in zip(got, bands, strict=True):
        assert a == pytest.approx(ea, rel=1e-12, abs=1e-12) and b == eb


@pytest.mark.parametrize("key", [d.key for d in (*SIMULATION_DESIGNS, *TABLE_ROWS)])
def test_stiffness_agrees_with_the_symbolic_frequency_response(key: str) -> None:
    # the panel evaluates s*N/D of the exact impedance; freqresp derives F_L/X_L with sympy
    entry = design(key)
    s = _state(entry.elements(), {})
    d = compute("frequency", s)
    ref = stiffness_response(s.sea(), np.array(d["omega"]))
    assert np.allclose(d["magnitude"], ref.magnitude, rtol=1e-9, atol=0)
    assert np.allclose(d["phase"], ref.phase, rtol=0, atol=1e-6)
    for got, want in ((d["static"], ref.static), (d["high_frequency"], ref.high_frequency)):
        assert (got is None and math.isinf(want)) or got == pytest.approx(want, rel=1e-12, abs=0)


def test_failing_band_agrees_with_the_sampled_real_part() -> None:
    # an independent look: the sign of Re Z on the plotted grid, away from the band edges
    # disjointed spring-damper: P/x = b2 m^2 x^2 + b2 (b^2 - 2 k1 m) x + k1^2 (b + b2) - b k1 kd
    d = compute(
        "frequency",
        _state({"D1": "k1", "D2": "b2*s", "CL": "kd"}, {**PLANT, "b2": 20.0, "kd": 2000.0}),
    )
    x1, x2 = sorted(np.roots([20.0, 20.0 * (100 - 2000), 1e6 * 30 - 10 * 1000 * 2000]).real)
    assert [(a, b) for a, b in d["bands"]] == [
        pytest.approx((math.sqrt(x1), math.sqrt(x2)), rel=1e-12)
    ]
    w = np.array(d["omega"])
    re = np.array([np.nan if v is None else v for v in d["re_z"]])
    inside = np.zeros(w.size, dtype=bool)
    near = np.zeros(w.size, dtype=bool)
    for a, b in d["bands"]:
        b = math.inf if b is None else b
        inside |= (w > a) & (w < b)
        near |= (np.abs(w - a) < 1e-6 * a) | (np.abs(w - b) < 1e-6 * min(b, 1e300))
    assert np.all(re[inside & ~near] < 0) and np.all(re[~inside & ~near] >= 0)


def test_region_matches_exact_verdicts() -> None:
    s = _state(
        {"D1": "k1", "CL": "kd + bd*s"}, {**PLANT, "kd": 500.0, "bd": 25.0}, region=["kd", "bd"]
    )
    d = compute("region", s)
    xs, ys = np.array(d["xs"]), np.array(d["ys"])
    assert d["x"] == "kd" and d["y"] == "bd" and len(d["passive"]) == ys.size
    rng = np.random.default_rng(3)
    for _ in range(25):
        i, j = int(rng.integers(xs.size)), int(rng.integers(ys.size))
        exact = is_passive(
            SEA(D1="k1", CL="kd + bd*s", values={**PLANT, "kd": xs[i], "bd": ys[j]})
        ).passive
        assert (d["passive"][j][i] == "1") == exact
    # bd = 0 is load-side P: passive exactly for kd <= k1
    assert d["passive"][0] == "".join("1" if x <= 1000 else "0" for x in xs)


def test_slider_grid_log_with_zero_stop() -> None:
    g = slider_grid(0.0, 5000.0, 5)
    assert g[0] == 0.0 and g[1] == pytest.approx(0.5) and g[-1] == pytest.approx(5000.0)
    assert np.allclose(slider_grid(1.0, 3.0, 3), [1.0, 2.0, 3.0])


def test_step_and_witness_panels() -> None:
    stable = _state(
        {"D1": "k1 + b1*s", "CA": "kd + bd*s"}, {**PLANT, "b1": 300.0, "kd": 1708.0, "bd": 300.0}
    )
    step = compute("step", stable)
    assert step["status"] == "settled" and 0 < step["settling_time"] < 1.0
    assert step["peak_force"] == pytest.approx(854.0, rel=1e-6)  # kd * step at t = 0
    assert compute("witness", stable)["passive"] is True

    lp = _state(LP, {**PLANT, "kd": 2000.0})
    w = compute("witness", lp)
    assert w["found"] and w["growth_rate"] > 0
    env = w["environment"]
    assert min(env.values()) >= 0  # a passive environment
    assert w["simulation"]["growth_factor"] > 1
    assert compute("step", lp)["status"] == "unstable"


def test_sampled_panel() -> None:
    assert compute("sampled", _state(LP, {**PLANT, "kd": 500.0}))["analysed"] is False
    d = compute("sampled", _state(LP, {**PLANT, "kd": 500.0}, period=0.002))
    assert d["analysed"] and d["passive"] is False and d["reason"] == "alias_injection"


def test_cache_ignores_the_dragged_value() -> None:
    a = _state(LP, {**PLANT, "kd": 100.0}, ranges={"kd": [0, 5000]})
    b = _state(LP, {**PLANT, "kd": 300.0}, ranges={"kd": [0, 5000]})
    assert compute("interval", a) is compute("interval", b)
    assert compute("region", a) is compute("region", b)  # axes kd and k1
    assert compute("verdict", a) is not compute("verdict", b)
