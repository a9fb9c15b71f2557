"""The explorer's view carries the one sampled loop: checked by it, written back exactly."""

from __future__ import annotations

from pathlib import Path

import pytest

from helpers import design_text
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


BOXED = design_text(
    "lpbox",
    model={"D1": "k1", "CL": "kd + bd*s"},
    parameters={"m": 1.0, "b": 10.0, "kd": 500.0, "bd": 5.0},
    plant={"k1": 1000.0},
    uncertainty={"m": [0.9, 1.1], "b": [8.0, 12.0]},
    control={"rate": 500.0, "delay": 1, "delay_time": 0.002},
)


def _view(design: object, **changes: object):  # type: ignore[no-untyped-def]
    import json

    from seapass.explore.presets import design_state

    raw = {**design_state(design), **changes}  # type: ignore[arg-type]
    check = check_state(json.loads(json.dumps(raw)))  # as the browser sends it
    assert check.state is not None, check.errors
    return check.state


def test_export_keeps_the_box_and_the_latency(tmp_path: Path) -> None:
    """Issue 26: load → view → export → load gives the same SEA, box and delay_time."""
    from seapass.delay.latency import latency_check
    from seapass.explore.delay_panel import delay_panel
    from seapass.explore.state import design_export

    src = tmp_path / "lpbox.toml"
    src.write_text(BOXED, encoding="utf-8")
    first = load_design(src)
    state = _view(first)
    assert state.delay_time == 0.002 and state.to_json()["delay_time"] == 0.002
    out = design_export(state)
    assert out["ok"] and out["filename"] == "lpbox.toml"
    again_path = tmp_path / "again.toml"
    again_path.write_text(out["text"], encoding="utf-8")
    again = load_design(again_path)
    assert again.sea().exact_elements() == first.sea().exact_elements()
    assert dict(again.values) == dict(first.values) and again.plant == first.plant
    assert dict(again.uncertainty) == dict(first.uncertainty) == {"b": (8.0, 12.0), "m": (0.9, 1.1)}
    assert again.delay_time == first.delay_time == 0.002 and again.loop == first.loop
    # the delay panel judges the file's latency as latency_check does on the file
    d = delay_panel(state)
    ref = latency_check(again)
    assert d["latency"] == 0.002 and d["latency_outcome"] == str(ref.outcome)
    assert d["at_latency"] == (None if ref.at_latency is None else ref.at_latency.status)
    # no latency and no box: the file has neither table
    plain = design_export(_view(first, delay_time=None, uncertainty={}))
    assert "[uncertainty]" not in plain["text"] and "delay_time" not in plain["text"]


def test_export_refuses_a_value_outside_its_box_and_a_bad_latency_names_the_field() -> None:
    from seapass.explore.state import design_export

    first = load_design_text(BOXED)
    out = design_export(_view(first, values={**first.values, "m": 2.0}))
    assert not out["ok"] and list(out["errors"]) == ["uncertainty.m"]
    assert "does not contain the file's value m = 2" in out["error"]
    for bad, says in [(-0.1, "between 0 and 1000 s"), ("soon", "not a number")]:
        check = check_state({**LP, "delay_time": bad})
        assert check.state is None and says in check.errors["delay_time"]
    taken = {"name": "d", "model": {"D1": "k1", "CL": "kd + delay_time*s"},
             "values": {"m": 1, "b": 10, "k1": 1000, "kd": 100, "delay_time": 1.0}}  # fmt: skip
    check = check_state({**taken, "delay_time": 0.002})
    assert check.state is None and "the name is taken" in check.errors["delay_time"]
    assert check_state({**taken, "delay_time": "off"}).state is not None


def load_design_text(text: str):  # type: ignore[no-untyped-def]
    import tomllib

    from seapass.model.design_file import parse_design

    return parse_design(tomllib.loads(text))
