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


# ------------------------------------------------------------------ robust (issue 26)

ROBUST = ["--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--CL", "kl", "--set", "k1=1000",
          "--set", "b1=20", "--set", "kd=500", "--set", "bd=25"]  # fmt: skip
BOX = ["--uncertain", "m=0.9:1.1", "--uncertain", "b=8:12"]


def test_robust_check_json_text_and_exit_codes(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, ["twoport", "check", *ROBUST, "--set", "kl=300", *BOX, "--json"])
    assert code == 0, err
    d = json.loads(out)
    assert d["robust"] is True and d["status"] == "passive" and d["worst"] is None
    assert d["box"] == {"b": [8.0, 12.0], "m": [0.9, 1.1]}
    assert d["absolutely_stable"] is True and d["passive"] is True
    assert d["absolute_stability"]["method"] == "certified"
    code, out, err = run(capsys, ["twoport", "check", *ROBUST, "--set", "kl=1500", *BOX, "--json"])
    assert code == 1, err
    d = json.loads(out)
    assert d["status"] == "not_passive" and d["absolutely_stable"] is False
    worst = d["worst"]
    assert 0.9 <= worst["values"]["m"] <= 1.1 and 8 <= worst["values"]["b"] <= 12
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl",
              values=dict(k1=1000, b1=20, kd=500, bd=25, kl=1500, **worst["values"]))  # fmt: skip
    assert not absolute_stability(sea, witness=False).absolutely_stable  # the plain verdict
    code, out, _ = run(capsys, ["twoport", "check", *ROBUST, "--set", "kl=1500", *BOX])
    assert code == 1 and out.startswith("not absolutely stable for every plant with b in [8, 12]")
    assert "worst plant: " in out


def test_robust_check_from_the_design_files_uncertainty(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    text = (REPO / "examples" / "ours.toml").read_text() + "\n[uncertainty]\nm = [0.9, 1.1]\n"
    path = tmp_path / "ours_box.toml"
    path.write_text(text)
    code, out, err = run(capsys, ["twoport", "check", str(path), "--json"])
    assert code == 0, err
    d = json.loads(out)
    assert d["robust"] is True and d["box"] == {"m": [0.9, 1.1]}
    assert d["absolute_stability"]["method"] == "exact"
    code, out, err = run(capsys, ["twoport", "check", str(path), "--set", "m=1", "--json"])
    assert code == 0 and "robust" not in json.loads(out)  # --set m fixes it: the plain check


def test_robust_bound_json(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    argv = ["twoport", "bound", "kd", "--D1", "k1", "--CA", "kd", "--set", "b=10", "--set",
            "k1=1000", "--uncertain", "m=0.9:1.1", "--range", "100:5000", "--json"]  # fmt: skip
    code, out, err = run(capsys, argv)
    assert code == 0, err
    d = json.loads(out)
    assert d["robust"] is True and d["param"] == "kd" and d["method"] == "certified"
    assert d["intervals"] == [[100.0, 5000.0]] and d["outer"] == [[100.0, 5000.0]]
    assert d["box"] == {"m": [0.9, 1.1]}
    code, out, err = run(capsys, argv[:-1])
    assert code == 0 and out.startswith("absolutely stable for every plant (m in [0.9, 1.1])")
    # the worst plant's eta as a figure; none to draw when the box passes
    fig = tmp_path / "worst.png"
    code, _, err = run(capsys, ["twoport", "check", *ROBUST, "--set", "kl=1500", *BOX,
                                "--plot", str(fig)])  # fmt: skip
    assert code == 1 and fig.stat().st_size > 1000, err
    fig2 = tmp_path / "none.png"
    code, _, err = run(capsys, ["twoport", "check", *ROBUST, "--set", "kl=300", *BOX,
                                "--plot", str(fig2)])  # fmt: skip
    assert code == 0 and not fig2.exists() and "no worst plant" in err


@pytest.mark.parametrize(
    ("extra", "match"),
    [
        (["--uncertain", "m=1.1:0.9"], "LO must not exceed HI"),
        (["--uncertain", "zz=1:2"], "zz"),
        (["--uncertain", "m=0:2"], "non-physical"),
        (["--uncertain", "m=-1:2"], "non-physical"),
        (["--set", "m=1", "--uncertain", "m=0.9:1.1"], "--set m"),
        (["--uncertain", "m=0.9"], "NAME=LO:HI"),
        (["--uncertain", "m=0.9:1.1", "--budget", "0"], "--budget"),
    ],
)
def test_robust_bad_input_is_one_error_line(
    capsys: pytest.CaptureFixture[str], extra: list[str], match: str
) -> None:
    one_error(
        capsys, ["twoport", "check", *ROBUST, "--set", "kl=300", "--set", "b=10", *extra], match
    )


def test_robust_bound_bad_input(capsys: pytest.CaptureFixture[str]) -> None:
    base = ["twoport", "bound", "kl", *ROBUST[:-2], "--set", "bd=25", "--set", "b=10"]
    one_error(capsys, [*base, "--uncertain", "kl=0:1"], "--uncertain kl")
    one_error(capsys, [*base, "--uncertain", "m=2:1"], "LO must not exceed HI")


def test_region_house_vocabulary_and_old_spellings(capsys: pytest.CaptureFixture[str]) -> None:
    base = ["twoport", "region", "kd", "kl", *SEA_ARGS]
    code, new, err = run(capsys, [*base, "--range", "kd=0:2000", "--range", "kl=0:5000",
                                  "--points", "3", "--json"])  # fmt: skip
    assert code == 0 and err == ""
    code, old, err = run(capsys, [*base, "--range", "0:2000", "--range2", "0:5000", "--nx", "3",
                                  "--json"])  # fmt: skip
    assert code == 0 and old == new
    assert err.count("warning: ") == 3 and "--range2 0:5000 is deprecated" in err
    assert json.loads(new)["x"] == [0.0, 1000.0, 2000.0]
    one_error(capsys, [*base, "--range", "kl=0:1", "--range2", "0:1"], "--range2")
    one_error(capsys, [*base, "--points", "3", "--nx", "3"], "--points")
    one_error(capsys, [*base, "--range", "kd=2:1"], "LO must not exceed HI")
    one_error(capsys, [*base, "--points", "0"], "--points 0")
    with pytest.raises(SystemExit):
        main(["twoport", "region", "--help"])
    shown = capsys.readouterr().out.split("examples:")[0]  # the options, not the epilog
    assert "--points" in shown and "--range2" not in shown and "--nx" not in shown
