"""`tune` of a design whose controller is given in z (``seapass.tuning.sampled_design``).

Independent cross-checks: the tuned gains are certified again by ``sampled_passivity``;
the settling time is recomputed by a loop written here (scipy's ZOH plant at T/40, the
PD difference equation by hand, the force one sample late) and read off the fine grid.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.signal import cont2discrete

import seapass
from seapass.errors import ParameterError, TuningWarning
from seapass.model.design_file import load_design
from seapass.model.loop import SampledLoop
from seapass.sampled.passivity import sampled_passivity
from seapass.sampled.response import sampled_response
from seapass.sim.scenarios import Step
from seapass.tuning.sampled_design import sampled_loop_of

PLANT = {"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 30.0}
RATE, STEP, HORIZON = 500.0, 0.05, 2.0
FILE = """
name = "zpd"
[model]
D1 = "k1 + b1*s"
[parameters]
m = 1.02
b = 10.0
k1 = 1005.0
b1 = 30.0
kd = 2000.0
bd = 25.0
{ranges}
[discrete]
rate = 500.0
CA = "kd + bd*500*(1 - z^-1)"
[control]
delay = 1
"""
RANGES = "[ranges]\nkd = [0.0, 4000.0]\nbd = [0.0, 100.0]"
FAST = dict(maxiter=3, popsize=4, masses=[1.0], horizon=HORIZON, step=STEP, seed=2)


def _design(tmp_path: Path, ranges: str = RANGES) -> seapass.Design:
    p = tmp_path / "zpd.toml"
    p.write_text(FILE.format(ranges=ranges), encoding="utf-8")
    return load_design(p)


def _independent_settling(kd: float, bd: float, sub: int = 40) -> float:
    """The 2 % settling time of the sampled PD loop (delay 1), by hand on a fine grid."""
    m, b, k1, b1, ml = PLANT["m"], PLANT["b"], PLANT["k1"], PLANT["b1"], 1.0
    A = np.array([[0, 1, 0, 0], [-k1 / m, -(b + b1) / m, k1 / m, b1 / m], [0, 0, 0, 1],
                  [k1 / ml, b1 / ml, -k1 / ml, -b1 / ml]])  # fmt: skip
    B = np.array([[0.0], [1 / m], [0.0], [0.0]])
    T = 1.0 / RATE
    Ad, Bd, *_ = cont2discrete((A, B, np.eye(4), np.zeros((4, 1))), T / sub, method="zoh")
    x, e_prev, u_prev = np.zeros(4), 0.0, 0.0
    xl = [0.0]
    for _ in range(round(HORIZON * RATE)):
        e = STEP - x[0]  # K_A acts on θ_A − x_A; K_L = 0
        u = kd * e + bd * RATE * (e - e_prev)
        e_prev, applied, u_prev = e, u_prev, u  # one sample of computational delay
        for _ in range(sub):
            x = Ad @ x + Bd[:, 0] * applied
            xl.append(x[2])
    xl_a = np.array(xl)
    out = np.flatnonzero(np.abs(xl_a - STEP) > 0.02 * STEP)
    return (out[-1] + 1) * T / sub


def test_tuned_z_design_is_certified_settles_as_computed_and_beats_the_start(
    tmp_path: Path,
) -> None:
    design = _design(tmp_path)
    r = seapass.tune(design, loop=design.loop, **FAST)
    assert sorted(r.gains) == ["bd", "kd"] and r.feasible
    assert r.sampled_passive is True and r.passive is True
    loop = SampledLoop(rate=RATE, delay=1)
    assert r.options.loop == loop
    again = sampled_passivity(r.sea, loop=loop)  # certified again at the tuned values
    assert again.passive and str(again.outcome) == "passive"
    assert r.metrics.settling_time == pytest.approx(r.objective)
    want = _independent_settling(r.gains["kd"], r.gains["bd"])
    assert abs(r.objective - want) <= 1.0 / RATE / 40
    start = sampled_response(design.sea(), loop=loop, load_mass=1.0, scenario=Step(STEP),
                             horizon=HORIZON).metrics()  # fmt: skip
    assert start.settling_time is not None and r.objective < start.settling_time
    assert r.sampled_checks >= 1 and r.passivity_checks == 0


def test_itae_objective_and_the_default_loop(tmp_path: Path) -> None:
    design = _design(tmp_path)
    with pytest.warns(TuningWarning, match="upper edge"):
        r = seapass.tune(design, tune={"kd": None}, objective="itae", **FAST)
    assert r.options.loop == SampledLoop(rate=RATE)  # no loop given: the controller's rate
    assert r.sampled_passive and 0 < r.objective


def test_bad_input_names_the_argument(tmp_path: Path) -> None:
    bare = _design(tmp_path, ranges="")
    with pytest.raises(ParameterError, match="no default box") as exc:
        seapass.tune(bare, **FAST)
    assert exc.value.argument == "tune"
    r = seapass.tune(bare, tune={"kd": (0.0, 3000.0)}, **FAST)  # a box given: fine
    assert r.sampled_passive
    with pytest.raises(ParameterError, match="not a gain of the controller in z"):
        seapass.tune(_design(tmp_path), tune={"b1": (0.0, 50.0)}, allow_plant=True, **FAST)
    with pytest.raises(ParameterError, match="1000 Hz"):
        seapass.tune(_design(tmp_path), loop=SampledLoop(rate=1000.0), **FAST)
    with pytest.raises(ParameterError, match="not given in z"):
        sampled_loop_of(
            seapass.tuning.problem.resolve_problem(
                seapass.SEA(D1="k1", CA="kd", values={"m": 1, "b": 1, "k1": 1, "kd": 1}),
                None, seapass.tuning.problem.TuningOptions(),
            )
        )  # fmt: skip


NARROW = {"m": (1.0199, 1.0201)}  # about 1e-4 relative: what the robust sampled verdict certifies
ROBUST = dict(maxiter=1, popsize=2, masses=[1.0], horizon=1.0, step=STEP, seed=0)


def test_robust_z_tune_is_certified_over_the_box_and_beside_the_nominal(tmp_path: Path) -> None:
    design = _design(tmp_path)
    r = seapass.tune(design, tune={"kd": (0.0, 4000.0)}, loop=design.loop, uncertain=NARROW,
                     budget=2, **ROBUST)  # fmt: skip
    c = r.constraint
    assert c is not None and str(c.kind) == "box" and c.loop == SampledLoop(rate=RATE, delay=1)
    assert r.feasible and r.passive and str(r.passivity.outcome) == "passive"  # type: ignore[union-attr]
    # independent: the point verdict at plants spread over the box, the ends included
    for m in np.linspace(*NARROW["m"], 5):
        assert sampled_passivity(r.sea.with_values(m=float(m)), loop=c.loop).passive
    assert r.nominal is not None and r.nominal.constraint is None  # the nominal z-tune: no box
    assert r.nominal.sampled_passive
    assert r.robustness_cost is not None and r.robustness_cost >= 0
    assert r.robustness_cost == pytest.approx(r.objective - r.nominal.objective)
    d = r.to_dict()
    assert d["constraint"]["box"] == {"m": [1.0199, 1.0201]} and d["certified"] == "passive"


def test_robust_z_tune_counts_undecided_as_not_passive(tmp_path: Path) -> None:
    design = _design(tmp_path)
    with pytest.warns(
        TuningWarning,
        match="certified in the sampled loop at T = 0.002 s for every plant with m in",
    ):
        r = seapass.tune(design, tune={"kd": (0.0, 4000.0)}, loop=design.loop,
                         uncertain={"m": (0.3, 1.02)}, budget=1, **ROBUST)  # fmt: skip
    assert not r.feasible and "sampled passivity" in r.violations
    assert str(r.passivity.outcome) == "undecided"  # type: ignore[union-attr]
    with pytest.raises(ParameterError, match="tuned"):
        seapass.tune(design, tune={"kd": (0.0, 4000.0)}, uncertain={"kd": (1.0, 2.0)}, **ROBUST)


def test_robust_z_tune_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import json

    from seapass.cli import main

    f = str(tmp_path / "zpd.toml")
    _design(tmp_path)
    argv = ["tune", f, "--tune", "kd=0:4000", "--uncertain", "m=1.0199:1.0201", "--budget", "2",
            "--maxiter", "1", "--popsize", "2", "--horizon", "1", "--load-mass", "1",
            "--mass-policy", "tune", "--step", str(STEP), "--no-progress"]  # fmt: skip
    assert main([*argv, "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["constraint"]["kind"] == "box" and d["certified"] == "passive"
    assert d["robustness_cost"] >= 0 and d["nominal"] is not None and d["robust"] == d["objective"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "for every plant with m in [1.0199, 1.0201]): yes" in out and "robustness cost" in out
    assert main([*argv[:4], "--uncertain", "m=1.0201:1.0199", "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1


def test_latency_in_whole_samples_is_certified_in_the_longer_loop(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from seapass.cli import main

    design = _design(tmp_path)
    r = seapass.tune(design, tune={"kd": (0.0, 4000.0)}, loop=design.loop, delay_time=0.004,
                     **ROBUST)  # fmt: skip
    longer = SampledLoop(rate=RATE, delay=3)  # the file's one sample and two more
    assert r.options.loop == longer and r.sampled_passive
    assert sampled_passivity(r.sea, loop=longer).passive  # certified again, independently
    res = sampled_response(r.sea, loop=longer, load_mass=1.0, scenario=Step(STEP), horizon=1.0)
    assert r.metrics.settling_time == pytest.approx(res.metrics().settling_time)
    with pytest.raises(ParameterError, match="whole periods") as exc:
        seapass.tune(design, tune={"kd": (0.0, 4000.0)}, delay_time=0.003, **ROBUST)
    assert exc.value.argument == "delay_time"
    sea = seapass.SEA(D1="k1", CA="kd", values={"m": 1, "b": 1, "k1": 100, "kd": 1})
    with pytest.raises(ParameterError, match="design file's \\[control\\] delay_time"):
        seapass.tune(sea, tune={"kd": (0.0, 10.0)}, delay_time=0.001, **ROBUST)
    f = str(tmp_path / "zpd.toml")
    for extra, words in ((["--delay-time", "0.003"], "--delay-time: a controller given in z "
                          "at 500 Hz takes a loop latency only in whole periods"),
                         (["--objective", "force-bandwidth", "--delay-time", "0.002"],
                          "--delay-time works with --objective settling or itae")):  # fmt: skip
        assert main(["tune", f, "--tune", "kd=0:4000", *extra, "--no-progress"]) == 2
        out, err = capsys.readouterr()
        assert out == "" and err.startswith(f"error: {words}") and err.count("\n") == 1


def test_latency_on_a_design_that_is_not_a_file_is_one_error_line(
    capsys: pytest.CaptureFixture[str],
) -> None:
    from seapass.cli import main

    assert main(["tune", "LP", "--delay-time", "0.001", "--quick", "--no-progress"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert "put the delay in the model, e.g. --CA '(kd + bd*s)*exp(-tau*s)' --set tau=0.001" in err
