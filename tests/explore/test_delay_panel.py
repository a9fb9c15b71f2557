"""The explorer's ``delay`` panel: τ* at the slider values, the same as ``delay_margin``'s."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import seapass
from seapass.exact.rounding import decimal_down, decimal_up
from seapass.explore import delay_panel as panel_module
from seapass.explore import panels
from seapass.explore.panels import KINDS, compute
from seapass.explore.pool import AFFINITY, run_panel
from seapass.explore.presets import design_state
from seapass.explore.validation import check_state
from seapass.model.design_file import load_design

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
OURS = {"D1": "k1 + b1*s", "CA": "kd + bd*s"}
VALUES = {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 20.0, "kd": 500.0, "bd": 25.0}


def _state(model: dict[str, str], values: dict[str, float]):
    s = check_state({"model": model, "values": values}).state
    assert s is not None
    return s


def rez(w: np.ndarray, tau: float, kd: float) -> np.ndarray:
    """Re Z_L(jw) of the design with C_A = (kd + 25 s) e^{-s tau}, by hand (numpy)."""
    s = 1j * w
    d1, ca = 1000 + 20 * s, (kd + 25 * s) * np.exp(-s * tau)
    return (d1 * (s * s + 10 * s + ca) / (s * s + 10 * s + d1 + ca) / s).real


@pytest.mark.parametrize("kd", [500.0, 2000.0])
def test_tau_star_follows_the_slider_and_equals_delay_margin(kd: float) -> None:
    state = _state(OURS, {**VALUES, "kd": kd})
    d = compute("delay", state)
    m = seapass.delay_margin(state.sea(), "delay_time")
    assert d["analysed"] and d["outcome"] == "passive" and d["delay"] == "delay_time"
    assert d["tau_star"] == list(m.tau_star) and d["frequency"] == m.frequency
    assert d["shown"] == [decimal_down(m.tau_star[0], 6), decimal_up(m.tau_star[1], 6)]
    assert float(d["shown"][0]) <= m.tau_star[0] and float(d["shown"][1]) >= m.tau_star[1]
    # independent: a dense grid sees no negative Re Z below lo and one just above hi
    w = np.geomspace(1e-2, 1e5, 100_001)
    assert rez(w, float(d["shown"][0]), kd).min() >= 0
    assert rez(w, m.tau_star[1] * 1.002, kd).min() < 0


def test_a_larger_gain_lowers_tau_star() -> None:
    low = compute("delay", _state(OURS, {**VALUES, "kd": 500.0}))["tau_star"]
    high = compute("delay", _state(OURS, {**VALUES, "kd": 2000.0}))["tau_star"]
    assert high[1] < low[0]


def test_design_file_state_and_the_other_verdicts() -> None:
    state = check_state(design_state(load_design(EXAMPLES / "ours.toml"))).state
    assert state is not None
    d = compute("delay", state)
    m = seapass.delay_margin(load_design(EXAMPLES / "ours.toml"), "delay_time")
    assert d["tau_star"] == list(m.tau_star) and d["loss"] == "interior"
    zero = compute(
        "delay", _state({"D1": "k1", "CL": "kd"}, {"m": 1.0, "b": 10.0, "k1": 1e3, "kd": 500.0})
    )
    assert zero["tau_star"] == [0.0, 0.0] and zero["loss"] == "unbounded_band"  # tau* = 0, exact
    none = compute(
        "delay", _state({"D1": "k1 + b1*s"}, {"m": 1.0, "b": 10.0, "k1": 1e3, "b1": 20.0})
    )
    assert none == {"analysed": False, "detail": "no controller (C_A = C_L = 0) to delay"}


def test_not_passive_at_zero_and_undecided_are_shown_honestly(monkeypatch) -> None:
    bad = compute("delay", _state({"D1": "k1", "CL": "kd + bd*s"}, {**VALUES, "kd": 5000.0}))
    assert not bad["passive_at_zero"] and bad["tau_star"] is None and bad["status"] == "not passive"
    monkeypatch.setattr(panel_module, "PANEL_BUDGET", 50)  # too few pieces to settle tau*
    monkeypatch.setattr(panels, "_cache", panels.OrderedDict())
    d = compute("delay", _state(OURS, {**VALUES, "kd": 700.0}))
    assert d["outcome"] == "undecided" and d["status"] == "undecided" and d["budget"] == 50
    assert d["tau_star"][0] == 0.0  # nothing below an undecided margin is claimed


def test_the_panel_is_registered_like_the_others() -> None:
    assert "delay" in KINDS and AFFINITY["delay"] == AFFINITY["sampled"]
    r = run_panel("delay", {"model": OURS, "values": VALUES})
    assert r["ok"] and r["data"]["analysed"]
    r = run_panel("delay", {"model": {"D1": "k1", "CL": "kd + delay_time*s"},
                            "values": {"m": 1.0, "b": 10.0, "k1": 1e3, "kd": 1.0, "delay_time": 1.0}})  # fmt: skip
    assert not r["ok"] and "delay_time" in r["error"]  # the name is taken: failure is data
    html = (Path(panels.__file__).parent / "static" / "index.html").read_text(encoding="utf-8")
    js = (Path(panels.__file__).parent / "static" / "app.js").read_text(encoding="utf-8")
    assert 'id="verdict-delay"' in html and 'data-panel-err="delay"' in html
    assert "delay(d) {" in js and 'delay: "verdict"' in js
