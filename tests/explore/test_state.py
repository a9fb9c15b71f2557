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
