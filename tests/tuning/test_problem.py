"""Tuning options are bounded when they are made (issue 20, item 5).

``seapass tune ours --horizon 1e12`` used to reach the optimizer, whose
workers failed and surfaced as ``internal error (RuntimeError ...)``.
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.errors import ParameterError, did_you_mean
from seapass.files.limits import MAX_HORIZON, MAX_SIM_STEPS
from seapass.model.design_file import load_design
from seapass.model.sea import SEA
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


# ------------------------------------------------------------------ plant parameters (issue 22)

CASCADE = Path(__file__).resolve().parents[2] / "examples" / "cascaded_impedance.toml"


def test_default_gains_leave_the_plant_alone() -> None:
    problem = resolve_problem(load_design(CASCADE))
    assert problem.gains == ("ba", "bv", "ki", "kp", "kv")
    assert problem.sea.values["k1"] == 2500.0
    sea = SEA(D1="k1 + b1*s", CA="(kp + ki/s)*k1 + ba*s",
              values=dict(m=0.4, b=3, k1=2500, b1=2, kp=2, ki=20, ba=20))  # fmt: skip
    assert resolve_problem(sea).gains == ("ba", "ki", "kp")
    declared = SEA(D1="k1", CA="kt*kd", values=dict(m=1, b=1, k1=1, kt=0.5, kd=1), plant=("kt",))
    assert resolve_problem(declared).gains == ("kd",)


@pytest.mark.parametrize("design", ["file", "sea"])
def test_a_plant_parameter_is_tuned_only_on_purpose(design: str) -> None:
    d = load_design(CASCADE)
    target = d if design == "file" else d.sea()
    with pytest.raises(ParameterError, match=r"tune\['k1'\]: k1 is a plant parameter \(k1 = 2500\)"
                       r".*allow_plant=True") as err:  # fmt: skip
        resolve_problem(target, {"k1": (1000.0, 3000.0)})
    assert ("[ranges]" in str(err.value)) == (design == "file")
    problem = resolve_problem(target, {"k1": (1000.0, 3000.0), "kp": None}, allow_plant=True)
    assert problem.gains == ("k1", "kp")
    with pytest.raises(ParameterError, match="actuator mass or damping"):
        resolve_problem(target, ["m"], allow_plant=True)  # never


def test_the_design_may_offer_a_plant_parameter() -> None:
    ours = load_design(CASCADE.parent / "ours.toml")  # [ranges] b1: which damper to fit
    assert resolve_problem(ours, ["b1"]).box["b1"] == (0.0, 300.0)
    assert "b1" in resolve_problem("ours").gains  # the catalog's gains name it
    with pytest.raises(ParameterError, match="plant parameter"):
        resolve_problem(ours, ["k1"])
