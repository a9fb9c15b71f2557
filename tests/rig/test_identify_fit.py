"""Your own rig: template, TOML show, logs, fitting m, b, b1 and Coulomb friction, no paper."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

from seapass.cli import main
from seapass.errors import FileFormatError, ParameterError
from seapass.rig.identify import fit_rig
from seapass.rig.impacts import run_impacts
from seapass.rig.log import (
    RigLog,
    chirp_command,
    load_log,
    parse_log,
    twin_log,
    twin_step_log,
)
from seapass.rig.moments import applied_force
from seapass.rig.packaged import is_paper_hardware, rig_template
from seapass.rig.rigfile import paper_rig, parse_rig
from seapass.rig.twin import simulate_loop

RIG = paper_rig()
TRUTH = {
    "m": RIG.actuator_mass,
    "b": RIG.actuator_damping,
    "coulomb": RIG.transmission.coulomb,
    "b1": RIG.damper.b1,
    "damper_coulomb": RIG.damper.coulomb,
}


@pytest.fixture(scope="module")
def chirp_log() -> RigLog:
    """8 s of a 5-25 Hz, 60 N chirp on the twin: friction, saturation, quantized encoders."""
    return twin_log(RIG, chirp_command(RIG.control.rate), load_mass=0.1, seed=7)


def test_twin_log_is_quantized_like_the_encoders(chirp_log: RigLog) -> None:
    counts_a = chirp_log.x_A / RIG.motor_resolution
    counts_d = (chirp_log.x_L - chirp_log.x_A) / RIG.linear_resolution
    assert np.allclose(counts_a, np.round(counts_a), atol=1e-6)
    assert np.allclose(counts_d - np.round(counts_d), (counts_d - np.round(counts_d))[0], atol=1e-6)
    assert chirp_log.period == pytest.approx(RIG.period) and chirp_log.size == 4000


def test_fit_recovers_the_twin_within_two_percent(chirp_log: RigLog) -> None:
    fit = fit_rig(chirp_log, RIG)
    for name in ("m", "b", "coulomb", "b1"):
        assert fit[name].value == pytest.approx(TRUTH[name], rel=0.02), name
    # the damper's Coulomb level is the least determined: within 5 % and its interval
    assert fit["damper_coulomb"].value == pytest.approx(TRUTH["damper_coulomb"], rel=0.05)
    for name, value in TRUTH.items():
        p = fit[name]
        assert p.low < value < p.high, f"{name}: {value} not in [{p.low}, {p.high}]"
        assert p.stderr < 0.02 * value
    assert fit.poorly_determined == () and fit.consistent_with_zero == ()
    assert fit.windows_used > 100 and fit.residual_std < 0.1
    for obj in (fit, chirp_log):
        assert len(repr(obj)) < 200 and "<table>" in obj._repr_html_()
    rig = fit.updated_rig()
    assert rig.actuator_mass == pytest.approx(fit["m"].value, rel=1e-12)
    assert (rig.actuator_damping, rig.damper.b1) == (fit["b"].value, fit["b1"].value)
    assert parse_rig(tomllib.loads(rig.to_toml())) == rig


def test_exact_model_is_recovered_exactly() -> None:
    """No friction, no quantization: the moments are exact up to quadrature (1e-4)."""
    log = twin_log(RIG, chirp_command(RIG.control.rate, duration=4.0), load_mass=0.1,
                   friction=False, quantize=False)  # fmt: skip
    fit = fit_rig(log, RIG)
    for name in ("m", "b", "b1"):
        assert fit[name].value == pytest.approx(TRUTH[name], rel=1e-3), name
    assert abs(fit["coulomb"].value) < 1e-3 and abs(fit["damper_coulomb"].value) < 1e-3


def test_a_rig_without_damper_fits_zero_without_alarm() -> None:
    rig = RIG.replace(damper={"b1": 0.0, "coulomb": 0.0})
    log = twin_log(rig, chirp_command(rig.control.rate, duration=4.0), load_mass=0.1, seed=2)
    fit = fit_rig(log, rig)
    assert set(fit.consistent_with_zero) >= {"b1", "damper_coulomb"}
    assert fit.poorly_determined == ()
    assert fit["m"].value == pytest.approx(rig.actuator_mass, rel=0.02)
    assert fit["b1"].high < 0.1 and fit["damper_coulomb"].high < 0.05


def test_a_square_wave_confounds_mass_and_friction() -> None:
    t = np.arange(2500) * RIG.period
    log = twin_log(RIG, 60.0 * np.sign(np.sin(2 * np.pi * 5 * t)), load_mass=0.1, seed=1)
    fit = fit_rig(log, RIG)
    assert "m" in fit.poorly_determined and fit.confounded("m")
    (note,) = [w for w in fit.warnings if w.startswith("m is poorly determined")]
    assert "correlated with" in note and len(fit.warnings) == len(fit.poorly_determined)


def test_a_ringing_closed_loop_step_recovers_the_twin() -> None:
    """LP (kd = 1000 N/m) on 0.6 kg rings after a 50 mm reference step: 1 s of it suffices.

    Measured on seeds 1-8 (1 s each): worst errors m 0.15 %, b 0.14 %, b1 0.36 %,
    actuator Coulomb 1.0 %, damper Coulomb 2.3 %.  The 95 % intervals of m and b1
    missed the truth on one seed of eight (this one: m off by 0.13 %, interval
    ±0.09 %), so for them only the value is pinned.
    """
    log = twin_step_log(RIG, design="LP", kd=1000.0, step=0.05, load_mass=0.6, seed=7)
    assert log.size == 500 and log.force[0] == pytest.approx(50.0, abs=0.02)  # kd (r - x̂_L)
    # the logged command, delayed and saturated as the fit assumes, is what the twin applied
    res = simulate_loop(RIG, load_mass=0.6, kp_load=1000.0, duration=1.0, reference=0.05, seed=7)
    assert np.array_equal(applied_force(log, RIG), res.force[0])
    assert np.array_equal(log.x_L, res.x_L_measured[0, :500])
    fit = fit_rig(log, RIG)
    for name in ("m", "b", "coulomb", "b1"):
        assert fit[name].value == pytest.approx(TRUTH[name], rel=0.02), name
    assert fit["damper_coulomb"].value == pytest.approx(TRUTH["damper_coulomb"], rel=0.05)
    for name in ("b", "coulomb", "damper_coulomb"):
        assert fit[name].low < TRUTH[name] < fit[name].high, name


def test_a_well_damped_step_is_refused_not_fitted() -> None:
    """Ours (kd = 1000, bd = 25) settles a 20 mm step in tens of ms, then sticks.

    Three windows slide: the fit refuses rather than return confident numbers.
    """
    log = twin_step_log(RIG, design="ours", kd=1000.0, step=0.02, load_mass=0.1, seed=7)
    assert log.force[0] == pytest.approx(20.0, abs=0.01)  # kd (r - x̂_A)
    with pytest.raises(ParameterError, match=r"only \d+ usable windows"):
        fit_rig(log, RIG)
    with pytest.raises(ParameterError, match="step"):
        twin_step_log(RIG, design="LP", kd=1000.0, step=0.0, load_mass=0.1)
    with pytest.raises(ParameterError, match="design"):
        twin_step_log(RIG, design="PD", kd=1000.0, step=0.02, load_mass=0.1)


def test_fit_rejects_logs_it_cannot_use(chirp_log: RigLog) -> None:
    with pytest.raises(ParameterError, match=r"control\.rate"):
        fit_rig(chirp_log, RIG.replace(control={"rate": 1000.0}))
    still = RigLog(chirp_log.t, np.zeros(4000), np.zeros(4000), np.zeros(4000))
    with pytest.raises(ParameterError, match="usable windows"):
        fit_rig(still, RIG)
    with pytest.raises(ParameterError, match="window"):
        fit_rig(chirp_log, RIG, window=2)
    heavy = RIG.replace(motor={"rotor_inertia": 1e-4})  # reflects 23 kg > the fitted m
    with pytest.raises(ParameterError, match="rotor inertia"):
        fit_rig(chirp_log, heavy).updated_rig()


def test_log_csv_round_trip_and_errors(tmp_path: Path, chirp_log: RigLog) -> None:
    path = tmp_path / "log.csv"
    path.write_text(chirp_log.to_csv())
    back = load_log(path)
    for key in ("t", "force", "x_A", "x_L"):
        assert np.array_equal(getattr(back, key), getattr(chirp_log, key))
    assert back.source == str(path)
    no_header = "# a comment\n0,1,0,0\n0.002,1,0,0\n\n0.004,1,0,0\n"
    assert parse_log(no_header).size == 3
    bad = {
        "t,f,a\n0,1,2\n": "expected 4 columns",
        "0,1,0,0\n0.002,x,0,0\n0.004,1,0,0\n": "'x' is not a number",
        "0,1,0,0\n0.002,nan,0,0\n0.004,1,0,0\n": "finite",
        "0,1,0,0\n0.002,1,0,0\n0.005,1,0,0\n": "sampled uniformly",
        "0,1,0,0\n": "at least 3 rows",
    }
    for text, msg in bad.items():
        with pytest.raises(FileFormatError, match=msg):
            parse_log(text)


def test_template_and_show_round_trip(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["rig", "template"]) == 0
    text = capsys.readouterr().out
    assert text == rig_template() and text.count("#") > 40
    template = parse_rig(tomllib.loads(text))
    assert is_paper_hardware(template) and template.name == "my-rig"
    path = tmp_path / "myrig.toml"
    path.write_text(text)
    assert main(["rig", "show", "--rig", str(path)]) == 0
    shown = capsys.readouterr().out
    assert parse_rig(tomllib.loads(shown)) == template  # TOML that reads back the same
    assert "# derived (not read back):" in shown
    assert main(["rig", "show", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["rig"]["name"] == "paper-rig"


def test_cli_fit_writes_plot_and_rig(
    tmp_path: Path, chirp_log: RigLog, capsys: pytest.CaptureFixture[str]
) -> None:
    log = tmp_path / "chirp.csv"
    log.write_text(chirp_log.to_csv())
    rig = tmp_path / "rig.toml"
    rig.write_text(rig_template())
    argv = ["rig", "fit", str(log), "--rig", str(rig), "--plot", str(tmp_path / "fit.svg"),
            "--rig-out", str(tmp_path / "fitted.toml"), "--json"]  # fmt: skip
    assert main(argv) == 0
    out, err = capsys.readouterr()
    data = json.loads(out)
    assert data["parameters"]["m"]["value"] == pytest.approx(TRUTH["m"], rel=0.02)
    assert err.splitlines() == [
        f"wrote {tmp_path / 'fit.svg'}",
        f"wrote {tmp_path / 'fitted.toml'}",
    ]
    assert (tmp_path / "fit.svg").read_text().startswith("<?xml")
    fitted = parse_rig(tomllib.loads((tmp_path / "fitted.toml").read_text()))
    assert fitted.damper.b1 == data["parameters"]["b1"]["value"]
    assert main(["rig", "fit", str(log), "--rig", str(rig)]) == 0
    text = capsys.readouterr().out
    assert "95 % intervals" in text and "b1" in text and "±" in text
    mm = RigLog(chirp_log.t, chirp_log.force, 1e3 * chirp_log.x_A, 1e3 * chirp_log.x_L)
    assert mm.warnings and "(millimetres given?)" in mm.warnings[0] and chirp_log.warnings == ()
    (tmp_path / "mm.csv").write_text(mm.to_csv())
    main(["rig", "fit", str(tmp_path / "mm.csv"), "--rig", str(rig)])
    assert "(millimetres given?)" in capsys.readouterr().err
    assert main(["rig", "fit", str(tmp_path / "missing.csv"), "--rig", str(rig)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error:") and err.count("\n") == 1


def test_a_users_rig_is_not_compared_with_the_paper(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    quick = {"count": 3, "duration": 0.05}
    mine = RIG.replace(damper={"k1": 2000.0}, impacts=quick, name="mine")
    assert not is_paper_hardware(mine) and is_paper_hardware(RIG.replace(impacts=quick))
    res = run_impacts(mine, windows=[0.01, 0.02])
    assert res.paper_k_out is None and res.findings == ()
    assert "paper" not in json.dumps(res.to_dict()) and "paper" not in res._repr_html_()
    assert repr(res).startswith("ImpactResult(impacts=3, k_out_mean=")
    paper = run_impacts(RIG.replace(impacts=quick), windows=[0.01, 0.02])
    assert paper.paper_k_out == (2292.0, 91.6) and len(paper.findings) == 2
    path = tmp_path / "mine.toml"
    path.write_text(mine.to_toml())
    assert main(["rig", "impacts", "--rig", str(path)]) == 0
    out = capsys.readouterr().out
    assert "k_out = " in out and "k_out against b1" in out and "paper" not in out
