"""The explorer's view carries the one sampled loop: checked by it, written back exactly."""

from __future__ import annotations

from pathlib import Path

import pytest

from seapass.explore.validation import check_state
from seapass.model.design_file import load_design
from seapass.model.loop import SampledLoop

LP = {"name": "LP", "model": {"D1": "k1", "CL": "kd"}, "values": {"m": 1, "b": 10, "k1": 1000}}


def test_a_filter_above_nyquist_is_a_message_on_its_box() -> None:
    check = check_state({**LP, "period": 0.002, "velocity_filter": 300.0})
    assert check.state is None
    assert list(check.errors) == ["velocity_filter"]
    assert "Nyquist frequency 250 Hz" in check.errors["velocity_filter"]


@pytest.mark.parametrize("period", [0.002, 1 / 49, 0.0013])
def test_the_loop_is_written_back_exactly(period: float, tmp_path: Path) -> None:
    state = check_state({**LP, "period": period, "delay": 2, "velocity_filter": 10.0}).state
    assert state is not None
    assert state.loop == SampledLoop(period=period, delay=2, velocity_filter=10.0)
    path = tmp_path / "d.toml"
    path.write_text(state.design_toml(), encoding="utf-8")
    assert load_design(path).loop == state.loop and load_design(path).period == period
    assert check_state(LP).state.loop is None  # type: ignore[union-attr]


EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_a_controller_design_keeps_k1_a_plant_value(tmp_path: Path) -> None:
    """Issue 22: the sliders of the cascaded design treat k1 as the hardware's, not a gain."""
    from seapass.explore.presets import design_state

    state = check_state(design_state(load_design(EXAMPLES / "cascaded_impedance.toml"))).state
    assert state is not None
    assert state.gains == ("ba", "bv", "ki", "kp", "kv")
    assert state.gain in state.gains
    k1 = state.values["k1"]
    assert state.ranges["k1"] == (k1 / 100, k1 * 100)  # a fixed value's range, not [0, 10·k1]
    path = tmp_path / "d.toml"
    path.write_text(state.design_toml(), encoding="utf-8")
    again = load_design(path)  # the explorer writes the compiled C_A, C_L
    assert again.gains == state.gains
    assert again.CA == load_design(EXAMPLES / "cascaded_impedance.toml").CA


def test_declared_plant_parameters_round_trip(tmp_path: Path) -> None:
    view = {"model": {"D1": "k1", "CA": "kt*kd"}, "values": {"kt": 0.5, "kd": 100.0},
            "plant": ["kt", "nope", 3]}  # fmt: skip
    state = check_state(view).state
    assert state is not None and state.plant == ("kt",) and state.gains == ("kd",)
    assert state.to_json()["plant"] == ["kt"]
    text = state.design_toml()
    assert "[plant]\nkt = 0.5" in text
    path = tmp_path / "d.toml"
    path.write_text(text, encoding="utf-8")
    assert load_design(path).plant == ("kt",)
    assert check_state({**view, "plant": []}).state.gains == ("kd", "kt")  # type: ignore[union-attr]
