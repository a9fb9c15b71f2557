"""Tuning problems: names checked with the one did-you-mean of seapass.errors."""

from __future__ import annotations

import pytest

from seapass.errors import ParameterError, did_you_mean
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
