"""The paper's experiment on the twin: metrics, linear predictions, sweeps, impacts, CLI."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from seapass.cli import main
from seapass.errors import ParameterError
from seapass.rig.experiment import (
    run_experiment,
    run_rig_sweep,
    run_rig_sweeps,
    settling_metrics,
)
from seapass.rig.impacts import rig_stiffness_response, run_impacts
from seapass.rig.predictions import critical_gain, sampled_loop_matrix
from seapass.rig.rigfile import paper_rig

RIG = paper_rig()
T = np.arange(1501) * 0.002


def test_settling_metrics_on_synthetic_signals():
    x = 0.02 * np.exp(-T / 0.1)
    st, ts, fin, err = settling_metrics(T, x, x0=0.02, band=0.0004, cap=2.0)
    # |x| <= band after t = 0.1 ln(50) = 0.391 s
    assert st == "settled" and ts == pytest.approx(0.1 * math.log(50), abs=0.003)
    assert err == pytest.approx(0.0, abs=1e-9) and fin == pytest.approx(0.0, abs=1e-9)
    assert settling_metrics(T, np.full_like(T, 0.02), x0=0.02, band=4e-4, cap=2.0)[0] == "stuck"
    slow = 0.02 * np.exp(-T / 0.8)
    assert settling_metrics(T, slow, x0=0.02, band=4e-4, cap=2.0)[0] == "slow"
    grow = 0.02 * np.exp(T) * np.sin(40 * T + 1)
    assert settling_metrics(T, grow, x0=0.02, band=4e-4, cap=2.0)[0] == "unstable"
    hunt = 0.0005 * np.sin(60 * T)
    assert settling_metrics(T, hunt, x0=0.02, band=4e-4, cap=2.0)[0] == "oscillating"
    offset = 0.003 + 0.017 * np.exp(-T / 0.05)
    st, ts, _fin, err = settling_metrics(T, offset, x0=0.02, band=4e-4, cap=2.0)
    assert st == "settled" and err == pytest.approx(0.003, abs=1e-6)


def _lp_char_poly_unstable(kd, ml):
    m, b, k1, b1 = RIG.actuator_mass, RIG.actuator_damping, RIG.damper.k1, RIG.damper.b1
    mL, bl = RIG.load_side_mass(ml), RIG.load.viscous
    # det of [[m s^2 + (b+b1) s + k1, kd - b1 s - k1], [-(b1 s + k1), mL s^2 + (bl+b1) s + k1]]
    p1 = np.array([m, b + b1, k1])
    p2 = np.array([mL, bl + b1, k1])
    poly = np.polyadd(np.polymul(p1, p2), np.polymul([b1, k1], [-b1, kd - k1]))
    return np.roots(poly).real.max() > 0


@pytest.mark.parametrize("ml", [0.1, 0.6])
def test_continuous_lp_limit_matches_characteristic_polynomial(ml):
    kc = critical_gain(RIG, design="LP", load_mass=ml, sampled=False)
    assert kc is not None
    assert not _lp_char_poly_unstable(0.99 * kc, ml)
    assert _lp_char_poly_unstable(1.01 * kc, ml)


def test_sampled_limit_below_continuous_and_converges_with_rate():
    for ml in (0.1, 0.6):
        kc = critical_gain(RIG, design="LP", load_mass=ml, sampled=False)
        ks = critical_gain(RIG, design="LP", load_mass=ml, sampled=True)
        assert ks < kc
    fast = RIG.replace(control={"rate": 50_000.0, "delay": 0})
    kc = critical_gain(fast, design="LP", load_mass=0.6, sampled=False)
    ks = critical_gain(fast, design="LP", load_mass=0.6, sampled=True)
    assert ks == pytest.approx(kc, rel=0.02)


def test_sampled_matrix_without_delay_is_zoh_loop():
    m0 = sampled_loop_matrix(RIG, load_mass=0.1, kp_load=500.0, loop=RIG.loop.replace(delay=0))
    m1 = sampled_loop_matrix(RIG, load_mass=0.1, kp_load=500.0, loop=RIG.loop.replace(delay=1))
    assert m0.shape == (9, 9)
    r0 = np.abs(np.linalg.eigvals(m0)).max()
    r1 = np.abs(np.linalg.eigvals(m1)).max()
    assert r0 < 1 and r1 < 1 and r1 > r0  # delay costs stability margin


def test_coarse_sweep_lp_and_ours():
    kd = [0.0, 300.0, 900.0, 2000.0]
    lp = run_rig_sweep(RIG, design="LP", load_mass=0.6, kd=kd)
    assert lp.status[0] == "stuck"
    assert lp.status[1] == "settled" and lp.status[3] == "unstable"
    assert lp.unstable_gain_twin == 2000.0
    assert 900.0 <= lp.unstable_gain_sampled <= lp.unstable_gain_continuous
    ours = run_rig_sweep(RIG, design="ours", load_mass=0.6, kd=kd, predictions=False)
    assert all(s == "settled" for s in ours.status[1:])
    assert ours.unstable_gain_twin is None
    # error set by dry friction: falls with gain
    assert ours.steady_state_error[1] > ours.steady_state_error[3]
    rows = ours.rows()
    assert rows[0]["settling_time"] is None and rows[1]["design"] == "ours"
    with pytest.raises(ParameterError, match="design"):
        run_rig_sweep(RIG, design="PD", load_mass=0.1, kd=kd)
    with pytest.raises(ParameterError, match="kd"):
        run_rig_sweep(RIG, design="LP", load_mass=0.1, kd=[[1.0]])


def test_one_batch_of_sweeps_equals_separate_sweeps():
    kd = [0.0, 300.0, 2000.0]
    batch = run_rig_sweeps(RIG, designs=("LP", "ours"), load_masses=(0.1, 0.6), kd=kd,
                           predictions=False)  # fmt: skip
    assert [(s.design, s.load_mass) for s in batch] == [
        ("LP", 0.1), ("LP", 0.6), ("ours", 0.1), ("ours", 0.6)
    ]  # fmt: skip
    for s in batch[1:3]:
        alone = run_rig_sweep(RIG, design=s.design, load_mass=s.load_mass, kd=kd,
                              predictions=False)  # fmt: skip
        # the twin's runs are independent element by element: bit for bit the same
        assert np.array_equal(s.x_L, alone.x_L)
        assert s.status == alone.status and s.unstable_gain_twin == alone.unstable_gain_twin
    with pytest.raises(ParameterError, match="load_mass"):
        run_rig_sweeps(RIG, designs=("LP",), load_masses=(-1.0,), kd=kd)


def test_experiment_findings_on_coarse_grid():
    res = run_experiment(RIG, kd=[0.0, 100.0, 150.0, 600.0, 1200.0, 2000.0])
    assert len(res.sweeps) == 4
    claims = {f.claim: f for f in res.findings}
    assert claims["LP becomes unstable at high gain"].match is True
    assert claims["As the gain rises, Ours settles faster than LP"].match is True
    assert claims["Ours has a larger error for kd < 200 that shrinks as the gain rises"].match
    json.dumps(res.to_dict(), allow_nan=False)


def test_stiffness_response_is_eq10():
    w = np.array([1e-3, 5.0, 50.0, 500.0])
    kd, bd = 1000.0, 25.0
    mag, with_load = rig_stiffness_response(RIG, w, kd=kd, bd=bd, load_mass=0.1)
    m, b, k1, b1 = RIG.actuator_mass, RIG.actuator_damping, RIG.damper.k1, RIG.damper.b1
    s = 1j * w
    a = m * s**2 + b * s
    eq10 = (k1 + b1 * s) * (a + bd * s + kd) / (a + (b1 + bd) * s + k1 + kd)
    assert np.allclose(mag, np.abs(eq10), rtol=1e-10)
    assert mag[0] == pytest.approx(k1 * kd / (k1 + kd), rel=1e-6)
    assert with_load[-1] > mag[-1]


def test_impacts_stiffer_than_spring_and_grow_with_b1():
    rig = RIG.replace(impacts={"count": 4, "duration": 0.1})
    res = run_impacts(rig, b1_values=[0.0, 30.0, 60.0], windows=[0.01, 0.02, 0.1])
    assert res.k_out.shape == (4,) and res.forces.shape == (4,)
    assert res.k_out_mean > res.k1
    assert np.all(np.diff(res.k_out_vs_b1) > 0)
    assert np.all(np.diff(res.k_out_vs_window) < 0)
    assert all(f.match for f in res.findings)
    json.dumps(res.to_dict(), allow_nan=False)
    with pytest.raises(ParameterError, match="windows"):
        run_impacts(rig, windows=[0.5])


def test_cli_sweep_json_and_outputs(tmp_path, capsys):
    out = tmp_path / "o"
    code = main(
        [
            "rig",
            "sweep",
            "--design",
            "LP",
            "--load-mass",
            "0.6",
            "--kd-max",
            "2000",
            "--kd-step",
            "1000",
            "--json",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    (sw,) = data["sweeps"]
    assert sw["design"] == "LP" and [r["kd"] for r in sw["runs"]] == [0.0, 1000.0, 2000.0]
    assert sw["runs"][2]["status"] == "unstable"
    for name in ("sweep.csv", "sweep.png", "sweep.pdf", "traces_LP_0.6kg.png"):
        assert (out / name).stat().st_size > 0
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    assert len(rows) == 3 and rows[2]["settling_time"] == ""
    assert main(["rig", "sweep", "--design", "XX"]) == 2
    assert main(["rig", "sweep", "--kd-step", "-1"]) == 2
    assert main(["rig", "sweep", "--kd-step", "0.001"]) == 2
    assert capsys.readouterr().err.count("error:") == 3


def test_cli_impacts_text(tmp_path, capsys):
    p = tmp_path / "r.toml"
    from importlib import resources

    text = resources.files("seapass").joinpath("data/paper_rig.toml").read_text()
    p.write_text(text.replace("count = 10", "count = 3"))
    assert main(["rig", "impacts", "--rig", str(p), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "k_out =" in out and "[match]" in out
    assert (tmp_path / "impacts.png").exists() and (tmp_path / "impacts.csv").exists()
