"""``seapass delay-margin`` and ``seapass check`` with a delay: end to end, and bad input."""

from __future__ import annotations

import contextlib
import io
import json

import pytest

from seapass.cli import main

MODEL = ["--D1", "k1 + b1*s", "--set", "m=1", "--set", "b=10", "--set", "k1=1000",
         "--set", "b1=20", "--set", "kd=500", "--set", "bd=25"]  # fmt: skip


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


def test_margin_of_ours_as_catalog_design_and_as_flags_agree():
    code, out, err = run(["delay-margin", "tau", "ours", "--set", "kd=500", "--set", "bd=25",
                          "--set", "b1=20", "--json"])  # fmt: skip
    assert code == 0 and err == ""
    d = json.loads(out)
    assert d["loss"] == "interior" and d["passive_at_zero"] and not d["delay_independent"]
    lo, hi = d["tau_star"]
    assert 0.0412 < lo < hi < 0.0413 and hi - lo <= 1e-6 * hi
    code, out2, _ = run(
        ["delay-margin", "tau", *MODEL, "--CA", "(kd + bd*s)*exp(-tau*s)", "--json"]
    )
    assert code == 0 and json.loads(out2)["tau_star"] == d["tau_star"]
    code, out3, _ = run(["delay-margin", "tau", *MODEL, "--CA", "kd + bd*s", "--json"])
    assert code == 0 and json.loads(out3)["tau_star"] == d["tau_star"]  # delay on the controller


def test_text_output_and_rtol():
    code, out, _ = run(["delay-margin", "tau", "--Z", "m*s + b + K*exp(-tau*s)/s", "--set", "m=1",
                        "--set", "b=2", "--set", "K=50", "--rtol", "1e-9"])  # fmt: skip
    assert code == 0 and "low_frequency" in out and "as w -> 0" in out
    lo, hi = (float(x) for x in out.split("[")[1].split("]")[0].split(","))
    assert lo < 0.04 <= hi and hi - lo <= 1e-9 * hi  # printed outward: it holds tau* = b/K
    below = float(out.split("tau <= ")[1].split()[0])  # the passive end, printed inward
    assert below <= lo < 0.04


def test_zero_margin_null_margin_and_delay_independent():
    code, out, _ = run(
        ["delay-margin", "tau", "APD", "--set", "kd=500", "--set", "bd=25", "--json"]
    )
    d = json.loads(out)
    assert code == 0 and d["tau_star"] == [0.0, 0.0] and d["loss"] == "unbounded_band"
    code, out, _ = run(["delay-margin", "tau", "LP", "--set", "kd=1500", "--json"])
    d = json.loads(out)
    assert code == 1 and d["tau_star"] is None and d["passive_at_zero"] is False
    code, out, _ = run(["delay-margin", "tau", "--Z", "m*s + b + B*exp(-tau*s)", "--set", "m=1",
                        "--set", "b=2", "--set", "B=1", "--json"])  # fmt: skip
    d = json.loads(out)
    assert code == 0 and d["tau_star"] is None and d["delay_independent"] is True


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["delay-margin", "tau", "ours"], "no value for parameter"),
        (["delay-margin", "tau", "bogus"], "neither a design file"),
        (["delay-margin", "tau"], "nothing to analyse"),
        (
            [
                "delay-margin",
                "tau",
                "ours",
                "--set",
                "tau=1",
                "--set",
                "kd=1",
                "--set",
                "bd=1",
                "--set",
                "b1=1",
            ],
            "do not give it a value",
        ),
        (["delay-margin", "tau", "LP", "--set", "kd=1", "--rtol", "nan"], "--rtol"),
        (
            ["delay-margin", "tau", "--Z", "m*s + b", "--set", "m=1", "--set", "b=1"],
            "no delay",
        ),
        (["delay-margin", "2x", "LP", "--set", "kd=1"], "NAME"),
        (["delay-margin", "kd", "LP", "--set", "b1=1"], "not a parameter"),
        (
            [
                "delay-margin",
                "tau",
                "--Z",
                "m*s + K*exp(-2*tau*s)/s",
                "--set",
                "m=1",
                "--set",
                "K=1",
            ],
            "first power",
        ),
        (
            ["delay-margin", "tau", "LP", "--D1", "k1", "--set", "kd=1"],
            "not DESIGN and",
        ),
    ],
)
def test_bad_input_is_one_error_line(argv, words):
    code, out, err = run(argv)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("error:") and words in err, err


@pytest.mark.parametrize(
    ("ca", "sets", "words"),
    [
        ("kd*exp(s)", ["tau=0.001"], "function call is not allowed"),
        ("kd*exp(-tau)", ["tau=0.001"], "function call is not allowed"),
        (
            "kd*exp(-tau*s)*exp(-t2*s)",
            ["tau=0.001", "t2=0.002"],
            "two different delays",
        ),
        ("kd*exp(-tau*s)", ["tau=-0.001"], "must be >= 0"),
        ("kd*exp(-tau*s)", ["tau=1e12"], "beyond the limit"),
        ("kd*exp(-tau*s)", [], "unknown symbol 'tau'"),
        ("kd*exp(tau*s)", ["tau=0.001"], "prediction"),
    ],
)
def test_check_bad_delays(ca, sets, words):
    argv = ["check", "--D1", "k1", "--CA", ca, "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--set", "kd=500"]  # fmt: skip
    for s in sets:
        argv += ["--set", s]
    code, out, err = run(argv)
    assert code == 2 and out == "" and err.count("\n") == 1 and words in err, err


def test_check_with_a_delay_json_and_exit_codes():
    base = ["check", *MODEL, "--CA", "(kd + bd*s)*exp(-tau*s)", "--json"]
    code, out, _ = run([*base, "--set", "tau=0.001"])
    d = json.loads(out)
    assert code == 0 and d["passive"] and d["outcome"] == "passive" and d["reason"] == ""
    assert d["witness_frequency"] is None and d["indices"] is None
    code, out, _ = run([*base, "--set", "tau=0.05"])
    d = json.loads(out)
    assert code == 1 and not d["passive"] and d["reason"] == "negative_real_part"
    assert 30 < d["witness_frequency"] < 40
    code, out, _ = run(["check", *MODEL, "--CA", "(kd + bd*s)*exp(-tau*s)", "--set", "tau=0.05"])
    assert code == 1 and out.startswith("not passive") and "witness" in out


def test_check_with_a_long_delay_is_bounded():
    # a 500 s delay on a wall that is not passive: decided at once by a witness
    code, out, _ = run(["check", "--Z", "m*s + b + K*exp(-tau*s)/s", "--set", "m=1", "--set", "b=1",
                        "--set", "K=1", "--set", "tau=500", "--json"])  # fmt: skip
    assert code == 1 and json.loads(out)["outcome"] == "not_passive"


def test_help_shows_examples():
    code, out, _ = run(["delay-margin", "--help"])
    assert code == 0 and "examples:" in out and "tau_star" in out


def test_design_file_gets_the_delay_on_its_controllers(tmp_path):
    path = tmp_path / "wall.toml"
    path.write_text(
        'name = "wall"\n[model]\nD1 = "k1"\nCA = "kd"\n'
        "[parameters]\nm = 1.0\nb = 10.0\nk1 = 1000.0\nkd = 2500.0\n",
        encoding="utf-8",
    )
    code, out, err = run(["delay-margin", "tau", str(path), "--json"])
    d = json.loads(out)
    assert code == 0 and err == "" and d["loss"] == "low_frequency"
    lo, hi = d["tau_star"]
    assert lo <= 10 / 2500 <= hi  # tau* = b/kd


@pytest.mark.parametrize(
    "command",
    [["witness"], ["response"], ["sampled", "check", "--period", "0.002"]],
    # tune, bound decide at the delay (issue 25); simulate delays the controller output
)  # fmt: skip
def test_commands_without_delay_support_refuse_clearly(command):
    delayed = ["--D1", "k1 + b1*s", "--CA", "(kd + bd*s)*exp(-tau*s)", "--set", "m=1",
               "--set", "b=10", "--set", "k1=1000", "--set", "b1=20", "--set", "bd=25",
               "--set", "tau=0.001"]  # fmt: skip
    if command[0] != "bound" and command[0] != "tune":
        delayed += ["--set", "kd=500"]
    code, _out, err = run([*command, *delayed])
    assert code == 2 and err.count("\n") == 1 and "does not handle a delay" in err, err


def test_plot_is_written_and_announced(tmp_path):
    fig = tmp_path / "margin.png"
    code, out, err = run(["delay-margin", "tau", "--Z", "m*s + b + (K + B*s)*exp(-tau*s)/s",
                          "--set", "m=1", "--set", "b=2", "--set", "K=50", "--set", "B=1",
                          "--plot", str(fig)])  # fmt: skip
    assert code == 0 and "tau* in" in out and fig.stat().st_size > 1000
    assert err == f"wrote {fig}\n"


# ---------------------------------------------------------------- --uncertain (issue 26)


def test_delay_margin_over_a_box_json(capsys) -> None:
    import json

    from seapass.cli import main

    code = main(["delay-margin", "tau", "ours", "--set", "kd=500", "--set", "bd=25",
                 "--set", "b1=20", "--uncertain", "m=0.95:1.05", "--rtol", "1e-2", "--json"])  # fmt: skip
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["robust"] is True and out["box"] == {"m": [0.95, 1.05]}
    assert out["status"] == "passive" and out["worst"]["values"]["m"] in (0.95, 1.05)
    lo, hi = out["tau_star"]
    assert 0 < lo <= hi and out["worst"]["tau_star"][1] == hi
    assert {"delay", "frequency", "loss", "certified", "rtol", "detail"} <= set(out)


def test_check_over_a_box_at_the_loop_latency(tmp_path, capsys) -> None:
    import json

    from seapass.cli import main

    f = tmp_path / "lat.toml"
    f.write_text('name = "lat"\n[model]\nD1 = "k1 + b1*s"\nCA = "kd + bd*s"\n[parameters]\n'
                 "m = 1.0\nb = 10.0\nk1 = 1000.0\nb1 = 20.0\nkd = 500.0\nbd = 25.0\n"
                 "[control]\ndelay_time = 0.01\n")  # fmt: skip
    assert main(["check", str(f), "--uncertain", "m=0.9:1.1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "passive" and out["delay"] == {"name": "delay_time", "tau": 0.01}
    assert main(["check", str(f), "--uncertain", "m=0.9:1.1", "--delay-time", "0.06"]) == 1
    text = capsys.readouterr().out
    assert "not passive" in text and "worst case: m=" in text


@pytest.mark.parametrize(
    "extra",
    [
        ["--uncertain", "m=1.1:0.9"],
        ["--uncertain", "tau=0:1"],
        ["--set", "m=1", "--uncertain", "m=0.9:1.1"],
        ["--uncertain", "m=0.9:1.1", "--budget", "0"],
        ["--uncertain", "zz=1:2"],
        ["--uncertain", "m=0:1"],
    ],
)
def test_delay_margin_box_bad_input_is_one_error_line(extra: list[str], capsys) -> None:
    from seapass.cli import main

    assert main(["delay-margin", "tau", "ours", "--set", "kd=500", "--set", "bd=25",
                 "--set", "b1=20", *extra]) == 2  # fmt: skip
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: "), err
