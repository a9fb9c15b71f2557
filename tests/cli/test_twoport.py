"""``seapass twoport`` and ``seapass mimo`` end to end: JSON, exit codes, figures, bad input."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.model.sea import SEA
from seapass.ports.stability import absolute_stability

REPO = Path(__file__).resolve().parents[2]
SEA_ARGS = ["--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--CL", "kl", "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--set", "b1=20", "--set", "bd=25"]  # fmt: skip
TELEOP = ["--Z11", "mm*s + bm", "--Z12", "1", "--Z21", "-1", "--Z22", "1/(ms*s + bs + kc/s)",
          "--form", "h", "--set", "mm=0.5", "--set", "bm=2", "--set", "ms=1", "--set", "bs=5",
          "--set", "kc=400"]  # fmt: skip


def run(capsys: pytest.CaptureFixture[str], argv: list[str]) -> tuple[int, str, str]:
    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


def one_error(capsys: pytest.CaptureFixture[str], argv: list[str], match: str) -> None:
    code, out, err = run(capsys, argv)
    assert code == 2, (code, out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert match in lines[0], lines[0]
    assert out == ""


def test_check_json_keys_and_exit_codes(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(
        capsys, ["twoport", "check", *SEA_ARGS, "--set", "kd=500", "--set", "kl=5000", "--json"]
    )
    assert code == 1, err
    d = json.loads(out)
    for key in (
        "absolutely_stable",
        "passive",
        "reciprocal",
        "eta_min",
        "eta_min_frequency",
        "conditions",
        "witness",
    ):
        assert key in d
    assert d["absolutely_stable"] is False and d["passive"] is False and d["reciprocal"] is False
    assert d["eta_min"] == pytest.approx(0.442588, rel=1e-5) and d["eta_min_frequency"] > 0
    llew = next(c for c in d["conditions"] if c["name"] == "llewellyn")
    assert llew["holds"] is False and llew["bands"] and {"name", "holds", "bands"} <= set(llew)
    assert d["witness"]["found"] is True and d["witness"]["max_real_part"] > 0
    # the library says the same
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl",
              values=dict(m=1, b=10, k1=1000, b1=20, bd=25, kd=500, kl=5000))  # fmt: skip
    assert absolute_stability(sea, witness=False).to_dict()["eta_min"] == d["eta_min"]

    code, out, _ = run(
        capsys, ["twoport", "check", *SEA_ARGS, "--set", "kd=500", "--set", "kl=300", "--json"]
    )
    d = json.loads(out)
    assert code == 0 and d["absolutely_stable"] is True and d["witness"] is None
    assert d["eta_min_frequency"] is None and d["eta_min_kind"] == "limit"  # inf eta = 1 as w -> 0


def test_check_text_matrix_form_and_design_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    code, out, err = run(capsys, ["twoport", "check", *TELEOP])
    assert code == 0, err
    assert out.splitlines()[0] == "absolutely stable (Llewellyn, exact)"
    assert "reciprocal: yes" in out
    fig = tmp_path / "eta.png"
    code, out, err = run(
        capsys, ["twoport", "check", str(REPO / "examples" / "ours.toml"), "--plot", str(fig)]
    )
    assert code == 0, err
    assert fig.stat().st_size > 1000 and f"wrote {fig}" in err


def test_bound_and_region(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(
        capsys,
        ["twoport", "bound", "kl", *SEA_ARGS, "--set", "kd=500", "--range", "-1000:1e4", "--json"],
    )
    assert code == 0, err
    d = json.loads(out)
    assert d["param"] == "kl" and d["criterion"] == "absolute"
    ((lo, hi),) = d["intervals"]
    assert lo == -500.0 and hi == pytest.approx(1523.919226, rel=1e-9)
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl",
              values=dict(m=1, b=10, k1=1000, b1=20, bd=25, kd=500, kl=None))  # fmt: skip
    for v in (lo, hi):  # printed end points satisfy the criterion (rounded inward)
        assert absolute_stability(sea, values={"kl": v}, witness=False).absolutely_stable
    assert not absolute_stability(
        sea, values={"kl": hi * (1 + 1e-9)}, witness=False
    ).absolutely_stable
    code, out, _ = run(capsys, ["twoport", "bound", "kl", *SEA_ARGS, "--set", "kd=500", "--range", "0:1e4",
                                "--criterion", "passive"])  # fmt: skip
    assert code == 0 and out.startswith("passive for 0.0 <= kl <= 1446.35")
    code, out, err = run(capsys, ["twoport", "region", "kd", "kl", *SEA_ARGS, "--range", "0:2000",
                                  "--range2", "0:5000", "--nx", "3", "--json"])  # fmt: skip
    assert code == 0, err
    d = json.loads(out)
    assert d["x"] == [0.0, 1000.0, 2000.0] and len(d["intervals"]) == 3
    assert d["intervals"][1][0][1] == pytest.approx(2039.65, rel=1e-4)


def test_friction_and_convert(capsys: pytest.CaptureFixture[str]) -> None:
    base = [*SEA_ARGS[:4], *SEA_ARGS[6:], "--set", "kd=500"]  # no CL: a mechanical coupling
    code, out, err = run(capsys, ["twoport", "friction", *base, "--json"])
    assert code == 0, err
    assert json.loads(out)["certified"] is True
    code, out, _ = run(capsys, ["twoport", "friction", *SEA_ARGS, "--set", "kd=500", "--set", "kl=300",
                                "--at", "transmission"])  # fmt: skip
    assert code == 1 and "no proof" in out
    code, out, _ = run(capsys, ["twoport", "convert", *TELEOP, "--to", "z", "--json"])
    assert code == 0 and json.loads(out)["form"] == "z"


def test_mimo(capsys: pytest.CaptureFixture[str]) -> None:
    curl = [
        "--Z",
        "[[b + k/s, c/s], [-c/s, b + k/s]]",
        "--set",
        "b=10",
        "--set",
        "k=100",
        "--set",
        "c=50",
    ]
    code, out, _ = run(capsys, ["mimo", "check", *curl, "--json"])
    d = json.loads(out)
    assert code == 1 and d["passive"] is False and d["ports"] == 2
    assert {c["name"] for c in d["conditions"] if c["holds"] is False} == {"axis_poles", "minor_12"}
    code, out, _ = run(
        capsys,
        [
            "mimo",
            "check",
            "--axes",
            str(REPO / "examples" / "axes" / "two-axis.toml"),
            "--set",
            "kc=0",
        ],
    )
    assert code == 0 and out.startswith("2-port: passive")
    code, out, _ = run(capsys, ["mimo", "bound", "c", "--Z", "[[b + k/s, c/s], [c/s, b + k/s]]", "--set", "b=10",
                                "--set", "k=100", "--range", "-200:200", "--json"])  # fmt: skip
    assert code == 0 and json.loads(out)["intervals"] == [[-100.0, 100.0]]


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["twoport", "check"], "nothing to check"),
        (["twoport", "check", "--Z11", "1", "--Z12", "0", "--Z21", "0"], "--Z22 missing"),
        (["twoport", "check", "--form", "h", *SEA_ARGS, "--set", "kd=1", "--set", "kl=1"], "--form applies"),
        (["twoport", "check", *TELEOP, "--D1", "k1"], "not both"),
        (["twoport", "check", *TELEOP[:-2], "--set", "kcc=1"], "did you mean"),
        (["twoport", "check", "--Z11", "1", "--Z12", "kk", "--Z21", "0", "--Z22", "1"], "--Z12: unknown symbol"),
        (["twoport", "check", "--Z11", "1", "--Z12", "0", "--Z21", "0", "--Z22", "1", "--form", "q"], "invalid choice"),
        (["twoport", "convert", "--Z11", "1/s", "--Z12", "1/s", "--Z21", "1/s", "--Z22", "1/s", "--to", "y"],
         "the y form does not exist"),
        (["twoport", "bound", "kl", *SEA_ARGS, "--set", "kd=1", "--set", "kl=1"], "free parameter"),
        (["twoport", "bound", "kl", *SEA_ARGS, "--set", "kd=1", "--range", "5:1"], "LO must not exceed HI"),
        (["twoport", "region", "kd", "kd", *SEA_ARGS, "--range", "0:1", "--range2", "0:1"], "different"),
        (["twoport", "check", "no/such/file.toml"], "No such file"),
        (["mimo", "check", "--Z", "[[1, 2, 3], [4, 5, 6]]"], "must be square"),
        (["mimo", "check", "--Z", "[[1, 2], [3]]"], "must be square"),
        (["mimo", "check", "--Z", "[[__import__('os'), 0], [0, 1]]"], "function call"),
        (["mimo", "check", "--Z", "1 + s"], "matrix of rows"),
        (["mimo", "check"], "one of them"),
        (["mimo", "bound", "c", "--Z", "[[c, 0], [0, 1]]", "--range", "0:1", "--set", "c=1"], "free parameter"),
    ],
)  # fmt: skip
def test_bad_input_is_one_error_line(
    capsys: pytest.CaptureFixture[str], argv: list[str], match: str
) -> None:
    one_error(capsys, argv, match)


def test_bad_axes_files(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    text = (REPO / "examples" / "axes" / "two-axis.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('B = [["bd", 0], [0, "bd"]]', 'B = [["bd", 0, 0], [0, "bd", 0]]'))
    one_error(capsys, ["mimo", "check", "--axes", str(bad)], "2×2")
    bad.write_text(text.replace("kc = 100.0", "kcc = 100.0"))
    one_error(capsys, ["mimo", "check", "--axes", str(bad)], "kc")
    bad.write_text(text + "\n[extra]\nx = 1\n")
    one_error(capsys, ["mimo", "check", "--axes", str(bad)], "unknown key extra")
