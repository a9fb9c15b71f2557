"""Tuning any design: boxes, fixed parameters, objectives, limits, edges, strict input, CLI."""

from __future__ import annotations

import contextlib
import io
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import seapass
from seapass.cli import main
from seapass.errors import ParameterError, TuningWarning
from seapass.model.design_file import load_design
from seapass.model.loop import SampledLoop
from seapass.sim.metrics import tracking_metrics
from seapass.sim.scenarios import Step
from seapass.sim.simulate import simulate
from seapass.tuning import TuningOptions, resolve_problem, tune
from seapass.tuning.optimize import verify

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
# not a catalog structure: a damped spring, a dashpot from the load to ground, actuator PD
CUSTOM = seapass.SEA(
    D1="k1 + b1*s", D2="b2*s", CA="kd + bd*s",
    values=dict(m=1.0, b=10.0, k1=1000.0, b1=30.0, b2=5.0, kd=1000.0, bd=25.0),
)  # fmt: skip
FAST = TuningOptions(maxiter=5, popsize=4, dt_search=1e-2)


def _quiet_tune(*args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TuningWarning)
        return tune(*args, **kw)


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def test_any_sea_is_tuned_in_its_box_with_the_other_parameters_fixed():
    r = _quiet_tune(CUSTOM, tune={"kd": (0.0, 3000.0), "bd": (0.0, 300.0)}, options=FAST)
    assert tuple(r.gains) == ("kd", "bd") and r.passive and r.feasible
    assert r.passive == seapass.is_passive(r.sea).passive
    for g, (lo, hi) in r.box.items():
        assert lo <= r.gains[g] <= hi
    fixed = {k: v for k, v in CUSTOM.values.items() if k not in r.gains}
    assert {k: r.sea.values[k] for k in fixed} == fixed
    again = _quiet_tune(CUSTOM, tune={"kd": (0.0, 3000.0), "bd": (0.0, 300.0)}, options=FAST)
    assert dict(again.gains) == dict(r.gains)  # seeded: reproducible
    d = r.to_dict()
    assert {"gains", "objective", "passive", "on_bound"} <= set(d)
    json.dumps(d, allow_nan=False)


def test_design_file_ranges_are_the_default_box_and_gains():
    design = load_design(EXAMPLES / "ours.toml")
    problem = resolve_problem(design)
    assert problem.gains == ("bd", "kd")  # the controller gains; b1 is hardware, fixed
    assert dict(problem.box) == {"bd": (0.0, 300.0), "kd": (0.0, 100000.0)}
    assert problem.options.load_mass == design.tuning_mass
    # a hardware parameter on request, with its [ranges] box; a name alone takes it
    both = resolve_problem(design, ["kd", "b1"])
    assert dict(both.box) == {"kd": (0.0, 100000.0), "b1": (0.0, 300.0)}
    assert both.sea.values["bd"] == design.values["bd"]


def test_catalog_names_keep_their_gains_and_boxes_and_take_plant_values():
    problem = resolve_problem("Ours", values={"k1": 1005.0})
    assert problem.gains == ("kd", "bd", "b1") and problem.sea.values["k1"] == 1005.0
    assert dict(problem.box) == {"kd": (0.0, 5000.0), "bd": (0.0, 300.0), "b1": (0.0, 300.0)}
    fixed_b1 = resolve_problem("ours", ["kd", "bd"], values={"b1": 30.0})
    assert fixed_b1.gains == ("kd", "bd") and fixed_b1.sea.values["b1"] == 30.0


def test_a_gain_that_wants_more_ends_on_the_edge_and_is_warned_about(capsys):
    with pytest.warns(TuningWarning, match="upper edge of its box"):
        r = tune(CUSTOM, tune={"bd": (0.0, 10.0)}, options=FAST)
    assert dict(r.on_bound) == {"bd": "upper"} and r.gains["bd"] == 10.0
    code, out, err = _cli(["tune", "--D1", "k1 + b1*s", "--D2", "b2*s", "--CA", "kd + bd*s",
                           *[f"--set={k}={v}" for k, v in CUSTOM.values.items() if k != "bd"],
                           "--tune", "bd=0:10", "--maxiter", "5", "--popsize", "4",
                           "--quick", "--json", "--no-progress"])  # fmt: skip
    assert code == 0 and json.loads(out)["on_bound"] == ["bd"]
    warned = [line for line in err.splitlines() if line.startswith("warning: bd = 10")]
    assert len(warned) == 1 and "upper edge" in warned[0]


def test_on_bound_is_decided_on_the_given_box():
    problem = resolve_problem(CUSTOM, {"kd": (0.0, 3000.0), "bd": (0.0, 300.0)}, FAST)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # verify() reports; only tune() warns
        edge = verify(problem, [1500.0, 299.96], bounds=problem.box)
        inner = verify(problem, [1500.0, 290.0], bounds=problem.box)
    assert dict(edge.on_bound) == {"bd": "upper"} and "bd = 299.96" in edge.warnings[0]
    assert not inner.on_bound and not inner.warnings


def test_itae_objective_matches_an_independent_integral():
    r = _quiet_tune(CUSTOM, tune={"kd": (0.0, 3000.0), "bd": (0.0, 300.0)},
                    options=FAST.replace(objective="itae"))  # fmt: skip
    run = simulate(r.sea, load_mass=10.0, scenario=Step(0.5), horizon=10.0, dt=1e-3)
    expected = np.trapezoid(run.time * np.abs(run.x_L - 0.5), run.time)
    assert r.objective == pytest.approx(expected, rel=1e-9)
    assert r.to_dict()["objective_kind"] == "itae" and r.feasible


def test_settling_under_an_overshoot_limit():
    free = _quiet_tune(CUSTOM, tune={"kd": (0.0, 3000.0), "bd": (0.0, 300.0)}, options=FAST)
    limited = _quiet_tune(CUSTOM, tune={"kd": (0.0, 3000.0), "bd": (0.0, 300.0)},
                          options=FAST.replace(max_overshoot=0.002))  # fmt: skip
    assert limited.feasible and limited.metrics.overshoot <= 0.002
    assert limited.objective >= free.objective - 1e-12  # a constraint cannot help
    # the verified metrics are those of an independent simulation
    run = simulate(limited.sea, load_mass=10.0, scenario=Step(0.5), horizon=10.0, dt=1e-3)
    assert tracking_metrics(run).settling_time == pytest.approx(limited.objective, rel=1e-9)


def test_force_limit_is_a_constraint():
    r = _quiet_tune(CUSTOM, tune={"kd": (0.0, 3000.0), "bd": (0.0, 300.0)},
                    options=FAST.replace(force_limit=200.0))  # fmt: skip
    assert r.metrics.peak_force <= 200.0 * (1 + 1e-9) and r.feasible


def test_sampled_passivity_constraint_and_an_infeasible_problem(capsys):
    # LP on an undamped spring: sampled load feedback (kd > 0) is never passive at 500 Hz
    box = {"kd": (100.0, 1000.0)}
    r = _quiet_tune("LP", tune=box, options=FAST.replace(loop=SampledLoop(period=0.002), maxiter=1))
    assert r.passive and r.sampled_passive is False and not r.feasible
    assert r.violations == ("sampled passivity",) and r.sampled_checks > 0
    with pytest.raises(seapass.errors.NotPassiveError, match="sampled-data control"):
        _quiet_tune(
            "LP",
            tune=box,
            options=FAST.replace(loop=SampledLoop(period=0.002), maxiter=1),
            throw=True,
        )
    # kd = 0 (no control at all) is passive at any rate, and it is said not to settle
    problem = resolve_problem("LP", options=FAST.replace(loop=SampledLoop(period=0.002)))
    none = verify(problem, [0.0], bounds=problem.box)
    assert none.feasible and none.sampled_passive and none.on_bound == {"kd": "lower"}
    assert any("do not settle" in w for w in none.warnings)


def test_cli_tune_feasible_and_infeasible_exit_codes():
    code, out, _ = _cli(["tune", "LP", "--tune", "kd=100:1000", "--period", "0.002",
                         "--quick", "--maxiter", "2", "--json", "--no-progress"])  # fmt: skip
    assert code == 1 and json.loads(out)["feasible"] is False
    code, out, _ = _cli(["tune", str(EXAMPLES / "apd.toml"), "--tune", "kd=0:2000",
                           "--set", "bd=100", "--step", "-0.5", "--quick", "--no-progress"])  # fmt: skip
    assert code == 0 and out.startswith("APD: kd = ") and "passive: yes" in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["ours", "--tune", "kx=0:5"], "--tune kx: not a parameter of the design"),
        (["ours", "--bound", "kdd=0:5"], "did you mean 'kd'"),
        (["ours", "--tune", "kd=0:5", "--tune", "kd=0:9"], "twice"),
        (["ours", "--tune", "kd=5:1"], "--tune kd: need lo < hi"),
        (["ours", "--set", "kdd=5000"], "did you mean 'kd'"),
        (["ours", "--set", "k1=1", "--set", "k1=2"], "twice"),
        (["LP", "--set", "kd=3"], "kd is tuned"),
        (["ours", "--tune", "m=0:2"], "actuator mass"),
        (["PID"], "neither a design file nor a catalog name"),
        ([], "nothing to tune"),
        (["--D1", "k1", "--CL", "kd", "--set", "m=1", "--set", "b=1"], "no value for k1"),
        (
            ["--D1", "k1", "--CL", "kd", "--set", "m=1", "--set", "b=1", "--set", "k1=1"],
            "--tune kd=LO:HI",
        ),
        (["ours", "--objective", "fast"], "invalid choice"),
    ],
)
def test_cli_tune_rejects_bad_input_in_one_line(argv, message):
    code, out, err = _cli(["tune", *argv, "--quick", "--no-progress"])
    assert code == 2 and out == "" and err.count("\n") == 1 and message in err, err


def test_python_errors_name_the_python_argument():
    with pytest.raises(ParameterError, match=r"tune\['kdd'\].*did you mean 'kd'"):
        resolve_problem(CUSTOM, {"kdd": (0, 1)})
    with pytest.raises(ParameterError, match=r"values\['kd'\]: kd is tuned"):
        resolve_problem(CUSTOM, {"kd": (0, 1)}, values={"kd": 5.0})
    with pytest.raises(ParameterError, match=r"unknown tuning option 'lop'.*'loop'"):
        tune(CUSTOM, tune={"kd": (0, 1)}, lop=SampledLoop(period=0.002))
    free = CUSTOM.with_values(kd=None)
    with pytest.raises(ParameterError, match=r"tune\['kd'\]: kd has no value and no search box"):
        resolve_problem(free)
    assert resolve_problem(free, {"kd": (0, 10)}).gains == ("kd",)


def test_interrupt_is_clean_in_the_cli(monkeypatch):
    import seapass.tuning.optimize as optimize

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(optimize, "differential_search", interrupted)
    code, out, err = _cli(["tune", "ours", "--quick", "--json"])
    assert code == 130 and out == "" and err.count("\n") == 1


def test_analyze_tunes_a_custom_design(tmp_path):
    path = tmp_path / "custom.toml"
    path.write_text(
        'name = "custom"\n[model]\nD1 = "k1 + b1*s"\nD2 = "b2*s"\nCA = "kd + bd*s"\n'
        "[parameters]\nm = 1.0\nb = 10.0\nk1 = 1000.0\nb1 = 30.0\nb2 = 5.0\nkd = 800.0\n"
        "bd = 40.0\n[ranges]\nkd = [0.0, 3000.0]\nbd = [0.0, 300.0]\n"
    )
    report = seapass.analyze(load_design(path), quick=True, stages=["tuning"])
    sec = report.sections[0]
    assert sec.key == "tuning" and sec.status == "ok" and sec.findings[0].verdict == "agrees"
    assert {row[0] for row in sec.tables[0].rows} == {"bd", "kd"}
    assert json.loads(sec.files["tuning.json"])["passive"] is True
