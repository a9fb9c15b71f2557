"""``seapass tune`` is thin: the rules of a tuning problem live in seapass.tuning."""

from __future__ import annotations

import contextlib
import io
import json
import warnings

import pytest

from seapass.cli import main
from seapass.errors import TuningWarning
from seapass.model.sea import SEA
from seapass.tuning.optimize import verify
from seapass.tuning.problem import TuningOptions, resolve_problem

PLANT = ["--set", "m=1", "--set", "b=10", "--set", "k1=1000", "--set", "b1=30"]
BUDGET = ["--quick", "--maxiter", "1", "--popsize", "2", "--horizon", "2", "--no-progress"]


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def test_a_gain_named_only_by_tune_needs_no_set() -> None:
    # issue 21: this failed with "unknown symbol 'tz'"
    argv = ["tune", "--D1", "k1 + b1*s", "--CA", "kd*(1 + tz*s)/(1 + 0.002*s)", *PLANT,
            "--tune", "kd=0:5000", "--tune", "tz=0:0.05", *BUDGET, "--json"]  # fmt: skip
    code, out, err = _cli(argv)
    result = json.loads(out)
    assert code in (0, 1) and set(result["gains"]) == {"kd", "tz"}, err
    assert 0 <= result["gains"]["tz"] <= 0.05


def test_a_model_tunes_its_controller_gains_by_default() -> None:
    # the CLI's own copy of this rule counted the symbol s as a gain ("--tune s=LO:HI")
    argv = ["tune", "--D1", "k1", "--CA", "kd + bd*s", "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--set", "kd=100", "--set", "bd=10", *BUDGET, "--json"]  # fmt: skip
    code, out, err = _cli(argv)
    assert code in (0, 1) and set(json.loads(out)["gains"]) == {"bd", "kd"}, err


@pytest.mark.parametrize(
    ("extra", "says"),
    [
        (["--tune", "kd=5:1"], "--tune kd: need lo < hi"),
        (["--load-mass", "-1"], "--load-mass must be positive"),
        (["--tune", "kx=0:1"], "--tune kx: 'kx' is not a parameter of the model"),
    ],
)
def test_bad_input_is_one_line_from_the_library(extra: list[str], says: str) -> None:
    argv = ["tune", "--D1", "k1", "--CA", "kd + bd*s", "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--set", "bd=10", *extra, *BUDGET]  # fmt: skip
    code, out, err = _cli(argv)
    assert code == 2 and out == "" and err.count("\n") == 1 and says in err, err


def test_library_rules_say_the_python_words() -> None:
    sea = SEA(D1="k1", CA="kd + bd*s", values=dict(m=1, b=10, bd=10, kd=None))
    with pytest.raises(ValueError, match=r"no value for k1: .*values\['k1'\]"):
        resolve_problem(sea, {"kd": (0, 1)})
    with pytest.raises(ValueError, match=r"tune\['kd'\]: need lo < hi"):
        resolve_problem(sea.with_values(k1=1000), {"kd": (5, 1)}, values={"bd": 10.0})
    problem = resolve_problem(sea.with_values(k1=1000, kd=5.0))
    assert problem.gains == ("bd", "kd")  # the controller gains, never the symbol s
    with pytest.raises(ValueError, match="load_mass must be positive") as info:
        TuningOptions(load_mass=-1.0)
    assert getattr(info.value, "argument", None) == "load_mass"


def test_the_edge_warning_names_the_python_argument_and_the_cli_its_flag() -> None:
    problem = resolve_problem("LP", {"kd": (0.0, 100.0)}, options=TuningOptions(horizon=2.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TuningWarning)
        result = verify(problem, [100.0], bounds=problem.box)
    (note,) = [w for w in result.warnings if "upper edge" in w]
    assert "tune={'kd': (lo, hi)}" in note and "--" not in note
    from seapass.cli.common import cli_words

    assert "(--tune kd=LO:HI)" in cli_words(note)
