"""``--delay-time SECONDS`` and ``[control] delay_time`` on the commands that take a design file."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import seapass
from seapass.cli import main
from seapass.model.design_file import load_design

DESIGN = """name = "ours"
[model]
D1 = "k1 + b1*s"
CA = "kd + bd*s"
[parameters]
m = 1.0
b = 10.0
k1 = 1000.0
b1 = 20.0
kd = 500.0
bd = 25.0
[control]
delay_time = {tau}
"""


def run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = int(exc.code or 0)
    e = err.getvalue()
    assert "Traceback" not in e
    return code, out.getvalue(), e


def design(tmp_path: Path, tau: float = 0.01) -> str:
    p = tmp_path / "ours.toml"
    p.write_text(DESIGN.format(tau=tau), encoding="utf-8")
    return str(p)


def test_check_file_gives_the_certified_delayed_verdict(tmp_path):
    path = design(tmp_path, 0.01)
    code, out, err = run(["check", path, "--json"])
    d = json.loads(out)
    assert (
        code == 0
        and err == ""
        and d["passive"]
        and d["delay"] == {"name": "delay_time", "tau": 0.01}
    )
    lib = seapass.is_passive(load_design(path).delayed_sea())
    assert d["status"] == lib.status == "passive"
    # tau* of this design is 0.04126 s: at 0.05 s the verdict flips, with a proven witness
    code, out, _ = run(["check", path, "--delay-time", "0.05", "--json"])
    d = json.loads(out)
    assert code == 1 and d["status"] == "not passive" and d["witness_frequency"] > 0
    assert d["delay"]["tau"] == 0.05


def test_delay_time_zero_is_the_rational_verdict(tmp_path):
    code, out, _ = run(["check", design(tmp_path), "--delay-time", "0", "--json"])
    d = json.loads(out)
    assert code == 0 and d["indices"] is not None and "delay" not in d  # the exact rational test


def test_delay_time_flag_on_a_model_without_a_file():
    code, out, _ = run(["check", "--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "m=1",
                        "--set", "b=10", "--set", "k1=1000", "--set", "b1=20", "--set", "kd=500",
                        "--set", "bd=25", "--delay-time", "0.05", "--json"])  # fmt: skip
    assert code == 1 and json.loads(out)["status"] == "not passive"


def test_bad_delay_time_is_one_error_line(tmp_path):
    for value in ("-1", "1e9", "nan"):
        code, out, err = run(["check", design(tmp_path), "--delay-time", value])
        assert code == 2 and out == ""
        assert err.count("\n") == 1 and err.startswith("error: --delay-time: must be a number")
    code, _, err = run(["check", design(tmp_path), "--delay-time", "1ms"])
    assert code == 2 and "--delay-time" in err and err.count("\n") == 1


def test_bad_delay_time_in_the_file_is_one_error_line(tmp_path):
    code, out, err = run(["check", design(tmp_path, -0.5)])
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "control.delay_time: must be a number of seconds in [0, 1000]" in err


def test_commands_without_delay_support_refuse_the_latency_and_say_how(tmp_path):
    path = design(tmp_path, 0.002)
    code, out, err = run(["witness", path])
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "delay_time = 0.002 s" in err and "--delay-time 0" in err
    code, out, _ = run(["witness", path, "--delay-time", "0", "--json"])
    assert code in (0, 1) and json.loads(out)


def test_bound_decides_the_gain_at_the_files_latency(tmp_path):
    # bound at a fixed delay is certified (seapass.delay.gainbound); the latency changes it
    path = design(tmp_path, 0.002)
    code, out, _ = run(["bound", "kd", path, "--json"])
    delayed = json.loads(out)
    code0, out0, _ = run(["bound", "kd", path, "--delay-time", "0", "--json"])
    assert code == 0 and code0 == 0 and delayed["intervals"] and json.loads(out0)["intervals"]
    assert delayed["delay"] == {"name": "delay_time", "tau": 0.002}


def test_delay_time_is_listed_in_help():
    code, out, _ = run(["check", "--help"])
    assert code == 0 and "--delay-time SECONDS" in out


def test_simulate_delays_the_controller_output_by_the_files_latency(tmp_path):
    from seapass.sim.delayed import simulate_delayed
    from seapass.sim.metrics import tracking_metrics

    path = design(tmp_path, 0.01)
    code, out, err = run(["simulate", path, "--load-mass", "10", "--json"])
    d = json.loads(out)
    assert code == 0 and err == "" and d["delay_time"] == 0.01 and d["status"] == "settled"
    code0, out0, _ = run(["simulate", path, "--load-mass", "10", "--delay-time", "0", "--json"])
    free = json.loads(out0)
    assert code0 == 0 and "delay_time" not in free
    assert d["settling_time"] != free["settling_time"] and d["overshoot"] > free["overshoot"]
    # the library call the command makes, on the file's model with the latency
    sea = load_design(path).sea().with_values(kd=500.0)
    ref = tracking_metrics(simulate_delayed(sea, load_mass=10.0, delay_time=0.01, horizon=10.0))
    assert d["settling_time"] == ref.settling_time
    # passivity is certified at the latency: the file's gains are passive up to b/kd-ish
    code, out, _ = run(["check", path, "--json"])
    assert d["passive"] == json.loads(out)["passive"]
    code, out, err = run(["simulate", path, "--load-mass", "10", "--delay-time", "0.02"])
    assert code == 0 and "loop latency: 0.02 s" in out and "settling time:" in out


def test_simulate_refuses_a_delay_it_cannot_simulate_in_one_line():
    code, out, err = run(["simulate", "--D1", "k1", "--CA", "kd*exp(-tau*s)", "--CL", "kl",
                          "--set", "m=1", "--set", "b=10", "--set", "k1=1000", "--set", "kd=100",
                          "--set", "kl=50", "--set", "tau=0.01", "--load-mass", "1"])  # fmt: skip
    assert code == 2 and out == "" and err.count("\n") == 1 and err.startswith("error:")
    assert "delays the controller output only" in err
    code, out, err = run(["simulate", "--D1", "k1", "--CA", "kd", "--set", "m=1", "--set", "b=10",
                          "--set", "k1=1000", "--set", "kd=100", "--load-mass", "1",
                          "--delay-time", "-0.5"])  # fmt: skip
    assert code == 2 and err.count("\n") == 1 and "--delay-time" in err


def test_tune_a_file_with_a_latency_reports_the_delayed_step_response(tmp_path):
    path = design(tmp_path, 0.02)
    code, out, err = run(["tune", path, "--tune", "kd=0:3000", "--tune", "bd=0:300", "--quick",
                          "--maxiter", "6", "--popsize", "5", "--no-progress", "--json"])  # fmt: skip
    d = json.loads(out)
    assert code == 0, err
    assert d["constraint"]["kind"] == "delay" and d["constraint"]["tau"] == 0.02
    assert d["mass_policy"] == "worst" and [r["load_mass"] for r in d["per_mass"]] == [1, 10, 25]
    from seapass.sim.delayed import simulate_delayed
    from seapass.sim.metrics import tracking_metrics

    sea = load_design(path).sea().with_values(**d["gains"])
    for run_ in d["per_mass"]:
        r = simulate_delayed(sea, load_mass=run_["load_mass"], delay_time=0.02, horizon=10.0)
        assert run_["settling_time"] == tracking_metrics(r).settling_time
