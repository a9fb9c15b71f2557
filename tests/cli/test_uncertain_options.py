"""``check``/``bound`` with ``--uncertain NAME=LO:HI``: robust verdicts end to end (issue 26)."""

from __future__ import annotations

import contextlib
import io
import json

import pytest

from helpers import design_text
from seapass.analysis.passivity import is_passive
from seapass.cli import main
from seapass.cli.uncertain_options import CLI_BUDGET
from seapass.model.sea import SEA
from seapass.robust.verdict import DEFAULT_BUDGET

LP = ["--D1", "k1", "--CL", "kd"]


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def test_check_with_a_box_prints_the_issue_json_and_exits_0_when_robustly_passive() -> None:
    argv = ["check", *LP, "--set", "k1=1000", "--set", "kd=500",
            "--uncertain", "m=0.9:1.1", "--uncertain", "b=8:12", "--json"]  # fmt: skip
    code, out, err = _cli(argv)
    d = json.loads(out)
    assert code == 0, err
    assert d["robust"] is True and d["passive"] is True and d["status"] == "passive"
    assert d["box"] == {"b": [8.0, 12.0], "m": [0.9, 1.1]} and d["worst"] is None


def test_check_with_a_box_gives_a_worst_case_that_the_plain_check_rejects() -> None:
    argv = ["check", *LP, "--set", "b=10", "--set", "kd=500",
            "--uncertain", "k1=100:1000", "--uncertain", "m=0.5:2", "--json"]  # fmt: skip
    code, out, _err = _cli(argv)
    d = json.loads(out)
    assert code == 1 and d["status"] == "not_passive" and d["passive"] is False
    worst = d["worst"]["values"]
    assert 100 <= worst["k1"] <= 1000 and 0.5 <= worst["m"] <= 2
    sea = SEA(D1="k1", CL="kd", values={"b": 10, "kd": 500, **worst})
    assert not is_passive(sea).passive
    plain = ["check", *LP, "--set", "b=10", "--set", "kd=500"]
    plain += [f"--set={k}={v!r}" for k, v in worst.items()]
    assert _cli(plain)[0] == 1  # the ordinary check says not passive too


def test_check_text_names_the_worst_case_and_the_frequency() -> None:
    argv = ["check", "--Z", "(s**2 + (10*(m - 1)**2 - 1/100)*s + k2)/(s**2 + s + 1)",
            "--set", "k2=1", "--uncertain", "m=0.9:1.1"]  # fmt: skip
    code, out, _err = _cli(argv)
    assert code == 1 and "worst case: m=1" in out and "rad/s" in out


def test_bound_with_a_box_gives_the_robust_set_and_the_outer_set() -> None:
    argv = ["bound", "kd", *LP, "--set", "m=1", "--set", "b=10", "--range", "0:2000",
            "--uncertain", "k1=800:1200", "--json"]  # fmt: skip
    code, out, err = _cli(argv)
    d = json.loads(out)
    assert code == 0, err
    assert d["intervals"] == [[0.0, 800.0]] and d["outer"] == [[0.0, 800.0]]
    assert d["method"] == "exact" and d["robust"] is True
    argv = ["bound", "kd", *LP, "--set", "b=10", "--range", "0:2000",
            "--uncertain", "k1=800:1200", "--uncertain", "m=0.5:2"]  # fmt: skip
    code, out, _err = _cli(argv)
    assert code == 0 and "certified" in out and "passive for every plant" in out


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        (["--uncertain", "m=1.1:0.9"], "LO must not exceed HI"),
        (["--uncertain", "mass=1:2"], "--uncertain mass"),
        (["--uncertain", "m=0:2"], "non-physical"),
        (["--uncertain", "b=-1:2"], "must not be negative"),
        (["--uncertain", "m=1e-3:1e4"], "too large"),
        (["--uncertain", "m=1"], "expected NAME=LO:HI"),
        (["--uncertain", "m=1:2", "--uncertain", "m=1:3"], "given twice"),
        (["--uncertain", "m=1:2", "--budget", "0"], "--budget"),
        (["--uncertain", "m=1:2", "--set", "m=1"], "--set m"),
    ],
)
def test_bad_boxes_give_one_error_line_and_exit_2(extra: list[str], words: str) -> None:
    base = ["check", *LP, "--set", "k1=1000", "--set", "kd=500"]
    if "b=-1:2" not in extra:
        base += ["--set", "b=10"]
    code, out, err = _cli([*base, *extra])
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and words in lines[0]
    assert "box[" not in lines[0] and "Traceback" not in err


def test_bound_refuses_a_box_on_the_bounded_parameter() -> None:
    argv = ["bound", "kd", *LP, "--set", "m=1", "--set", "b=10", "--set", "k1=1000",
            "--uncertain", "kd=1:2"]  # fmt: skip
    code, _out, err = _cli(argv)
    assert code == 2 and err.count("\n") == 1 and "already the parameter of `bound kd`" in err


def test_help_shows_uncertain_and_the_cli_budget_is_the_library_default() -> None:
    assert CLI_BUDGET == DEFAULT_BUDGET
    for cmd in ("check", "bound"):
        out = io.StringIO()
        with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
            main([cmd, "--help"])
        assert "--uncertain NAME=LO:HI" in out.getvalue() and "--uncertain" in out.getvalue()


BOXED_DESIGN = design_text(
    "lpbox",
    model={"D1": "k1 + b1*s", "CA": "kd + bd*s"},
    parameters={"m": 1.0, "b": 10.0, "kd": 500.0, "bd": 25.0},
    plant={"k1": 1000.0, "b1": 20.0},
)


@pytest.mark.parametrize(
    ("argv", "boxed"),
    [
        (["check", "{f}", "--uncertain", "b=9:11"], False),
        (["check", "{f}", "--robust"], True),
        (["check", "{f}"], True),  # the file's [uncertainty]
        (["check", "{f}"], False),  # no box: the plain check
        (["bound", "kd", "{f}", "--uncertain", "b=9:11"], True),
        (["bound", "kd", "{f}"], True),
        (["bound", "kd", "{f}"], False),
        (["region", "kd", "bd", "{f}", "--points", "3"], True),
        (["twoport", "check", "{f}"], True),
        (["twoport", "check", "{f}"], False),
        (["twoport", "bound", "kd", "{f}", "--range", "0:2000"], True),
    ],
)
def test_a_robust_command_reads_its_design_file_once(argv, boxed, tmp_path, monkeypatch) -> None:
    """Issue 21 (seams): the design file is read once, through the guarded reader."""
    import seapass.files.toml as toml_files

    path = tmp_path / "d.toml"
    path.write_text(BOXED_DESIGN + ("[uncertainty]\nm = [0.9, 1.1]\n" if boxed else ""))
    reads: list[str] = []
    real = toml_files.read_text_file

    def counting(p, *args, **kwargs):  # type: ignore[no-untyped-def]
        reads.append(str(p))
        return real(p, *args, **kwargs)

    monkeypatch.setattr(toml_files, "read_text_file", counting)
    code, out, err = _cli([a.replace("{f}", str(path)) for a in [*argv, "--json"]])
    assert code == 0, err
    assert reads == [str(path)]
    d = json.loads(out)
    robust = "--robust" in argv or "--uncertain" in argv or boxed
    assert ("box" in d) is robust or argv[0] == "region"


def test_check_decides_a_box_whose_faces_meet_at_a_lossless_corner() -> None:
    """LP with a damper: b in [0, 20] x b1 in [0, 50] is not passive (on b = 0), with a worst
    plant the plain check rejects; b1 in [0, 50] x m in [0.5, 2] is passive (a corner blow-up);
    both were undecided before."""
    lp = ["--D1", "k1 + b1*s", "--CL", "kd", "--set", "k1=1000", "--set", "kd=500"]
    argv = [
        "check",
        *lp,
        "--set",
        "m=1",
        "--uncertain",
        "b=0:20",
        "--uncertain",
        "b1=0:50",
        "--json",
    ]
    code, out, _err = _cli(argv)
    d = json.loads(out)
    assert code == 1 and d["status"] == "not_passive" and d["worst"]["values"]["b"] == 0
    plain = ["check", *lp, "--set", "m=1"]
    plain += [f"--set={k}={v!r}" for k, v in d["worst"]["values"].items()]
    assert _cli(plain)[0] == 1
    argv = ["check", *lp, "--set", "b=10", "--uncertain", "b1=0:50", "--uncertain", "m=0.5:2"]
    code, out, _err = _cli(argv)
    assert code == 0 and "passive for every plant" in out and "corner" in out


# a virtual wall behind a loop latency: passive for kd <= b/tau at every plant (issue 26)
WALL_DESIGN = """name = "wall"
[model]
D1 = "k1"
CA = "kd"
[parameters]
m = 1.0
b = 10.0
k1 = 1000.0
kd = 500.0
[ranges]
kd = [0.0, 8000.0]
[uncertainty]
b = [9.0, 11.0]
[control]
delay_time = 0.002
"""


def test_bound_with_a_box_at_the_files_latency_gives_inner_and_outer_sets(tmp_path) -> None:
    path = tmp_path / "wall.toml"
    path.write_text(WALL_DESIGN)
    code, out, err = _cli(
        ["bound", "kd", str(path), "--range", "kd=4000:4600", "--budget", "3000", "--json"]
    )
    assert code == 0, err
    d = json.loads(out)
    assert d["robust"] is True and d["box"] == {"b": [9.0, 11.0]} and d["delay_time"] == 0.002
    assert d["delay"] == {"name": "delay_time", "tau": 0.002} and d["method"] == "certified"
    (a, b), = d["intervals"]  # fmt: skip
    (c, e), = d["outer"]  # fmt: skip
    assert c <= a < b <= 4500 <= e < 4500.01  # min b / tau
    assert all(x["values"]["b"] == 9.0 or x["reason"] for x in d["excluded"])
    code, text, err = _cli(["bound", "kd", str(path), "--range", "kd=4000:5000", "--budget", "50"])
    assert code == 0 and "at delay_time = 0.002 s" in text and "no value outside" in text, err


@pytest.mark.parametrize(
    ("extra", "match"),
    [
        (["--delay-time", "-1"], "--delay-time"),
        (["--budget", "100000000"], "--budget must be an integer in [1, 1000000]"),
        (["--uncertain", "delay_time=0:1"], "delay_time"),
    ],
)
def test_bad_delayed_bounds_are_one_error_line(tmp_path, extra: list[str], match: str) -> None:
    path = tmp_path / "wall.toml"
    path.write_text(WALL_DESIGN)
    code, out, err = _cli(["bound", "kd", str(path), *extra])
    assert code == 2 and out == "" and err.count("\n") == 1 and match in err, err
    assert err.startswith("error: ")


def test_sampled_commands_refuse_a_continuous_latency_with_a_box_and_say_how(tmp_path) -> None:
    path = tmp_path / "wall.toml"
    path.write_text(WALL_DESIGN)
    for argv in (["sampled", "check", str(path), "--uncertain", "b=9:11"],
                 ["sampled", "bound", "kd", str(path), "--robust"]):  # fmt: skip
        code, out, err = _cli(argv)
        assert code == 2 and out == "" and err.count("\n") == 1, err
        assert "whole samples" in err and "--delay N" in err and "--delay-time 0" in err


def test_bound_rtol_applies_with_a_box_only_and_is_checked() -> None:
    code, out, err = _cli(["bound", "kd", *LP, "--set", "m=1", "--set", "b=10",
                           "--set", "k1=1000", "--rtol", "1e-2"])  # fmt: skip
    assert code == 2 and out == "" and err.startswith("error: --rtol applies with a box only")
    assert err.count("\n") == 1
    code, out, err = _cli(["bound", "kd", "--D1", "k1 + b1*s", "--CL", "kd", "--set", "m=1",
                           "--set", "b=10", "--uncertain", "k1=800:1200", "--uncertain", "b1=0:5",
                           "--rtol", "0.5"])  # fmt: skip
    assert code == 2 and err.startswith("error: --rtol must be in") and "Traceback" not in err
