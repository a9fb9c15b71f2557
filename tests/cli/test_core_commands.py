"""CLI: check, bound, region, help, and bad input (one line on stderr, exit code 2)."""

import json

import pytest

from seapass.cli import build_parser, main

OURS = [
    "--D1",
    "k1 + b1*s",
    "--CA",
    "kd + bd*s",
    "--set",
    "m=1",
    "--set",
    "b=10",
    "--set",
    "k1=1000",
    "--set",
    "b1=20",
    "--set",
    "bd=25",
]


def run(capsys, args):
    code = main(args)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_check_json_from_the_issue(capsys):
    code, out, err = run(capsys, ["check", *OURS, "--set", "kd=5000", "--json"])
    assert code == 0, err
    d = json.loads(out)
    assert d["passive"] is True and d["reason"] == "" and d["omega"] is None
    assert "tolerance" in d


def test_check_raw_impedance(capsys):
    code, out, _ = run(capsys, ["check", "--Z", "(s + 1)/(s + 2)", "--json"])
    assert code == 0 and json.loads(out)["passive"] is True
    code, out, _ = run(capsys, ["check", "--Z", "1/(s + 1) - 1e-9", "--json"])
    d = json.loads(out)
    assert d["passive"] is False and d["omega"] > 1e4
    code, out, _ = run(capsys, ["check", "--Z", "k*s/(s**2 + k)", "--set", "k=1e8"])
    assert code == 0 and out.startswith("passive")


def test_bound_json(capsys):
    code, out, _ = run(
        capsys,
        [
            "bound",
            "kd",
            "--D1",
            "k1",
            "--CL",
            "kd",
            "--set",
            "m=1",
            "--set",
            "b=10",
            "--set",
            "k1=1000",
            "--range",
            "0:1e5",
            "--json",
        ],
    )
    assert code == 0
    assert json.loads(out)["intervals"] == [[0.0, 1000.0]]
    code, out, _ = run(capsys, ["bound", "kd", *OURS, "--range", "kd=0:1e6"])
    assert "passive for 0 <= kd <= 1000000" in out


def test_region_figure(capsys, tmp_path):
    fig = tmp_path / "region.png"
    code, out, err = run(
        capsys,
        [
            "region",
            "kd",
            "b1",
            "--D1",
            "k1 + b1*s",
            "--CL",
            "kd",
            "--set",
            "m=1",
            "--set",
            "b=10",
            "--set",
            "k1=1000",
            "--x-range",
            "0:1200",
            "--y-range",
            "0:60",
            "--nx",
            "5",
            "--out",
            str(fig),
            "--json",
        ],
    )
    assert code == 0, err
    assert fig.stat().st_size > 1000
    assert len(json.loads(out)["intervals"]) == 5


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["check", "--D1", "k1 + foo", "--set", "m=1"], "unknown symbol 'foo'"),
        (["check", "--D1", "sin(s)"], "function call"),
        (["check", "--Z", "__import__('os').system('true')"], "function call"),
        (
            [
                "check",
                "--D1",
                "k1",
                "--CL",
                "kd",
                "--set",
                "m=0",
                "--set",
                "b=1",
                "--set",
                "k1=1",
                "--set",
                "kd=1",
            ],
            "mass m must be positive",
        ),
        (["check", "--D1", "k1", "--CL", "kd", "--set", "m=-2"], "mass m must be positive"),
        (["check", "--D1", "k1", "--set", "m=nan"], "not finite"),
        (["check", "--D1", "k1", "--set", "k1=inf"], "not finite"),
        (["check", "--D1", "k1", "--set", "m="], "missing value"),
        (["check", "--D1", "k1", "--set", "m"], "expected NAME=VALUE"),
        (["check", "--CA", "kd"], "degenerate model"),
        (["check", "--D1", "k1", "--CL", "kd", "--set", "m=1"], "no value for parameter"),
        (["check", "--Z", "1/s", "--D1", "k1"], "either --Z or"),
        (["bound", "kd", "--D1", "k1", "--CL", "kd", "--range", "kd=5:1"], "must not exceed"),
        (["bound", "kd", "--D1", "k1", "--CL", "kd", "--range", "kd=abc"], "expected NAME=LO:HI"),
        (["bound", "kd", "--D1", "k1", "--CL", "kd", "--set", "kd=1"], "free parameter"),
        (["nonsense"], "invalid choice"),
        (["check", "--bogus"], "unrecognized arguments"),
    ],
)
def test_bad_input_is_one_line_exit_2(capsys, args, fragment):
    code, _out, err = run(capsys, args)
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("error:")
    assert fragment in err
    assert "Traceback" not in err


def test_every_command_help_shows_an_example():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    for name, p in sub.choices.items():
        assert "seapass" in (p.epilog or ""), f"{name} --help has no example"
        assert "example" in p.epilog.lower(), name
