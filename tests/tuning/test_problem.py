"""Tuning options are bounded when they are made (issue 20, item 5).

``seapass tune ours --horizon 1e12`` used to reach the optimizer, whose
workers failed and surfaced as ``internal error (RuntimeError ...)``.
"""

from __future__ import annotations

import contextlib
import io

import pytest

from seapass.cli import main
from seapass.errors import ParameterError, did_you_mean
from seapass.files.limits import MAX_HORIZON, MAX_SIM_STEPS
from seapass.tuning.problem import TuningOptions, resolve_problem


def test_did_you_mean_falls_back_to_the_case_insensitive_match() -> None:
    assert did_you_mean("KD", ["kd", "bd"]) == " (did you mean 'kd'?)"
    assert did_you_mean("KD", iter(["kd", "bd"])) == " (did you mean 'kd'?)"  # an iterator too
    assert did_you_mean("zzz", ["kd"]) == ""


def test_tuning_names_use_it() -> None:
    with pytest.raises(ParameterError, match=r"tune\['KD'\].*did you mean 'kd'"):
        resolve_problem("LP", {"KD": (0.0, 1.0)})
    with pytest.raises(ParameterError, match=r"unknown tuning option 'LOOP'.*'loop'"):
        TuningOptions().replace(LOOP=None)


def test_horizon_over_the_limit_is_refused_at_construction() -> None:
    assert TuningOptions(horizon=MAX_HORIZON).horizon == MAX_HORIZON
    for bad in (MAX_HORIZON * 1.0001, 1e12):
        with pytest.raises(ParameterError, match=r"horizon: .* longer than the limit of 1000 s"):
            TuningOptions(horizon=bad)


def test_time_steps_over_the_limit_are_refused_before_the_search() -> None:
    opts = TuningOptions(horizon=100.0, dt_verify=100.0 / (MAX_SIM_STEPS * 2))
    with pytest.raises(ParameterError, match="time steps, over the limit"):
        resolve_problem("ours", options=opts)


@pytest.mark.parametrize("horizon", ["1e12", "1000.5", "inf"])
def test_cli_tune_with_a_huge_horizon_is_one_error_line(horizon: str) -> None:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(["tune", "ours", "--horizon", horizon, "--no-progress"])
    text = err.getvalue()
    assert code == 2 and text.startswith("error: ") and text.count("\n") == 1, text
    assert "horizon" in text
    assert "internal error" not in text
