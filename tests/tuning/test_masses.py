"""The worst case over the load masses for the step-response objectives (seapass.tuning.masses).

Independent check: the step response of the tuned gains at every mass is simulated again by
python-control (``forced_response`` of the closed loop's state space, on its own grid) and the
2 % settling time is read off it by hand; the worst-case tune is compared with the tune at the
single tuning mass, both judged over every mass.
"""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import control
import numpy as np
import pytest

from seapass.cli import main
from seapass.errors import ParameterError, TuningWarning
from seapass.model.design_file import load_design
from seapass.model.realization import closed_loop
from seapass.tuning import QUICK_OPTIONS, MassPolicy, TuningOptions, tune
from seapass.tuning.masses import resolve_masses

OURS = Path(__file__).resolve().parents[2] / "examples" / "ours.toml"
BUDGET = QUICK_OPTIONS  # counted work: 12 generations of 6 per gain


def _settling_by_python_control(sea: object, mass: float, step: float, horizon: float) -> float:
    """Last time |x_L - step| leaves the 2 % band, on a python-control run at 2e-4 s."""
    sys = closed_loop(sea, load_mass=mass).to_control()  # type: ignore[arg-type]
    t = np.linspace(0.0, horizon, int(horizon / 2e-4) + 1)
    u = np.zeros((3, t.size))
    u[0] = step  # theta_A and theta_L both step for an actuator-side design
    u[1] = step
    resp = control.forced_response(sys, T=t, U=u)
    x_l = resp.outputs[2]
    outside = np.flatnonzero(np.abs(x_l - step) > 0.02 * abs(step))
    return float(t[outside[-1] + 1]) if outside.size else 0.0


@pytest.fixture(scope="module")
def tuned() -> tuple[object, object]:
    design = load_design(OURS)
    worst = tune(design, tune=["kd", "bd"], options=BUDGET)
    single = tune(design, tune=["kd", "bd"], options=BUDGET.replace(masses="tune"))
    return worst, single


def test_the_default_over_a_files_masses_is_the_worst_case(tuned: tuple) -> None:
    worst, single = tuned
    assert worst.options.masses == (1.0, 10.0, 25.0) and worst.options.mass_policy == "worst"
    assert single.options.masses == (10.0,) and single.options.mass_policy == "tune"
    assert [r.load_mass for r in worst.per_mass] == [1.0, 10.0, 25.0]
    assert worst.objective == max(r.objective for r in worst.per_mass)
    # the worst mass is not the tuning mass (10 kg): the heaviest load settles last
    assert worst.worst_mass == 25.0 != worst.options.load_mass
    assert worst.metrics == next(r.metrics for r in worst.per_mass if r.load_mass == 25.0)


def test_per_mass_metrics_agree_with_python_control(tuned: tuple) -> None:
    worst, _ = tuned
    for run in worst.per_mass:
        ref = _settling_by_python_control(worst.sea, run.load_mass, 0.5, 10.0)
        assert run.metrics.settling_time == pytest.approx(ref, abs=5e-4)  # the reference's grid


def test_the_worst_case_tune_beats_the_tuning_mass_tune_on_the_worst_mass(tuned: tuple) -> None:
    worst, single = tuned
    # the tune-mass optimum judged over every mass, independently of its own run
    with pytest.warns(TuningWarning):  # the one-point boxes: every gain "on an edge"
        judged = tune(
            load_design(OURS), tune={g: (v, v * (1 + 1e-12)) for g, v in single.gains.items()},
            options=BUDGET.replace(maxiter=1, popsize=2),
        )  # fmt: skip
    at_25 = next(r for r in judged.per_mass if r.load_mass == 25.0).metrics.settling_time
    assert worst.objective < at_25  # the worst-case gains settle the 25 kg load sooner
    assert single.objective < next(r.objective for r in worst.per_mass if r.load_mass == 10.0)


@pytest.mark.filterwarnings("ignore::seapass.errors.TuningWarning")  # a tiny budget's notes
def test_explicit_masses_and_a_given_load_mass() -> None:
    design = load_design(OURS)
    opts = BUDGET.replace(maxiter=2, popsize=3)
    r = tune(design, tune=["kd", "bd"], options=opts.replace(masses=[25, 2.5]))
    assert r.options.masses == (25.0, 2.5) and len(r.per_mass) == 2
    # a load mass given without a policy is the single tuning mass
    r = tune(design, tune=["kd", "bd"], options=opts.replace(load_mass=4.0))
    assert r.options.masses == (4.0,) and r.per_mass[0].load_mass == 4.0
    # a catalog design lists no masses: the tuning mass unless "worst" is asked for
    assert tune("LP", options=opts).options.masses == (10.0,)
    assert tune("LP", options=opts.replace(masses="worst")).options.masses == (1.0, 10.0, 25.0)


def test_resolve_masses_rules() -> None:
    listed = (1.0, 10.0, 25.0)
    assert resolve_masses(None, load_mass=10.0, given_mass=False, listed=listed) == listed
    assert resolve_masses(None, load_mass=3.0, given_mass=True, listed=listed) == (3.0,)
    assert resolve_masses(None, load_mass=10.0, given_mass=False, listed=(5.0,)) == (10.0,)
    assert resolve_masses("TUNE", load_mass=10.0, given_mass=False, listed=listed) == (10.0,)
    assert resolve_masses(MassPolicy.WORST, load_mass=3, given_mass=True, listed=None) == listed


@pytest.mark.parametrize(
    ("masses", "words"),
    [("bogus", "masses must be one of worst, tune"), ([], "give 1 to 64"), ([1, -2], "masses"),
     (3.0, "expected 'worst', 'tune' or a list"), ([1.0] * 65, "give 1 to 64")],
)  # fmt: skip
def test_bad_masses(masses: object, words: str) -> None:
    with pytest.raises(ParameterError, match=words):
        TuningOptions(masses=masses)  # type: ignore[arg-type]


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


CLI = ["tune", str(OURS), "--tune", "kd", "--tune", "bd", "--continuous", "--quick",
       "--maxiter", "6", "--popsize", "5", "--no-progress"]  # fmt: skip


def test_cli_json_reports_every_mass() -> None:
    code, out, err = _cli([*CLI, "--json"])
    assert code == 0, err
    d = json.loads(out)
    assert d["mass_policy"] == "worst" and d["masses"] == [1.0, 10.0, 25.0]
    assert d["worst_mass"] == 25.0 and d["load_mass"] == 10.0
    assert [r["load_mass"] for r in d["per_mass"]] == [1.0, 10.0, 25.0]
    assert d["objective"] == max(r["objective"] for r in d["per_mass"])
    assert d["settling_time"] == d["per_mass"][2]["settling_time"]  # the worst mass's metrics
    code, out, err = _cli([*CLI, "--mass-policy", "tune", "--json"])
    d = json.loads(out)
    assert code == 0 and d["mass_policy"] == "tune" and d["masses"] == [10.0]
    assert len(d["per_mass"]) == 1 and d["worst_mass"] == 10.0


def test_cli_text_lists_every_mass_and_refuses_a_bad_policy() -> None:
    code, out, err = _cli(CLI)
    assert code == 0, err
    assert "worst at m_L = 25 kg" in out
    assert sum(line.startswith("  m_L = ") for line in out.splitlines()) == 3
    code, out, err = _cli([*CLI, "--objective", "zwidth", "--mass-policy", "worst"])
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("error: --mass-policy works with --objective settling or itae")
    code, out, err = _cli([*CLI, "--mass-policy", "heaviest"])
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and err.startswith("error:") and "worst" in err
