"""Controller blocks on the command line, end to end, on the issue's designs (issue 22).

``check``, ``bound`` and ``simulate`` take the model as flags, so they run the
example files' controllers as the equivalent ``--controller`` flags (the first
test shows both compile to the same ``C_A``, ``C_L``); ``tune`` and ``analyze``
take the files themselves.
"""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest

from seapass.analysis.region import passive_intervals
from seapass.cli import build_parser, main
from seapass.cli.common import model_from_args
from seapass.model.design_file import load_design

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CASCADE = EXAMPLES / "cascaded_impedance.toml"
VELOCITY = EXAMPLES / "velocity_sourced.toml"

PLANT = ["--D1", "k1 + b1*s", "--set", "m=0.4", "--set", "b=3", "--set", "k1=2500",
         "--set", "b1=2"]  # fmt: skip
CASCADE_BLOCKS = ["--controller", "impedance", "--force-loop", "kp + ki/s", "--impedance",
                  "kv + bv*s", "--damping-injection", "ba", "--feedforward"]  # fmt: skip
CASCADE_GAINS = ["--set", "kp=2", "--set", "ki=20", "--set", "kv=1000", "--set", "bv=5",
                 "--set", "ba=20"]  # fmt: skip
VELOCITY_BLOCKS = ["--controller", "velocity-sourced", "--force-loop", "kf", "--impedance",
                   "kv + bv*s", "--velocity-loop", "kvp + kvi/s"]  # fmt: skip
VELOCITY_GAINS = ["--set", "kf=0.04", "--set", "kv=1000", "--set", "bv=5", "--set", "kvp=200",
                  "--set", "kvi=2000"]  # fmt: skip


def cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def one_error(argv: list[str], *needles: str) -> str:
    code, out, err = cli(argv)
    lines = err.splitlines()
    assert code == 2 and len(lines) == 1 and lines[0].startswith("error: "), (argv, err)
    assert not out
    for n in needles:
        assert n in lines[0], (n, err)
    return lines[0]


def without(argv: list[str], name: str) -> list[str]:
    """``argv`` without ``--set NAME=...``."""
    i = argv.index(next(a for a in argv if a.startswith(f"{name}=")))
    return argv[: i - 1] + argv[i + 1 :]


@pytest.mark.parametrize(
    ("path", "flags"),
    [(CASCADE, CASCADE_BLOCKS + CASCADE_GAINS), (VELOCITY, VELOCITY_BLOCKS + VELOCITY_GAINS)],
)
def test_flags_and_files_compile_alike(path: Path, flags: list[str]) -> None:
    design = load_design(path)
    sea = model_from_args(build_parser().parse_args(["check", *PLANT, *flags]))
    assert (str(sea.CA), str(sea.CL)) == (str(design.sea().CA), str(design.sea().CL))
    assert dict(sea.values) == dict(design.values)
    assert sea.gains == design.gains and "k1" not in sea.gains


def test_check_explains_the_cascade() -> None:
    code, out, err = cli(["check", *PLANT, *CASCADE_BLOCKS, *CASCADE_GAINS, "--explain"])
    assert code == 0, err
    assert "  C_A = C_f*K_s + b_a*s\n  C_L = -C_f*K_s + Z_v*(C_f + 1)\n" in out
    assert "  C_A = (kp + ki/s)*k1 + ba*s\n" in out
    assert out.splitlines()[-2] == "passive: positive real"
    code, out, _ = cli(["check", *PLANT, *VELOCITY_BLOCKS, *VELOCITY_GAINS, "--explain",
                        "--json"])  # fmt: skip
    data = json.loads(out)
    assert code == 0 and data["passive"] is True
    assert data["derivation"]["general"] == {
        "CA": "C_v*(C_f*K_s + s)",
        "CL": "C_f*C_v*(-K_s + Z_v)",
    }
    code, out, _ = cli(["check", *PLANT, "--CA", "kd", "--set", "kd=100", "--explain"])
    assert code == 0 and out.startswith("C_A = kd\nC_L = 0\n(given with --CA/--CL)\n")


def test_force_control_loses_passivity_to_integral_action() -> None:
    """The worked example of docs/controllers.md: PI force control in zero-force mode."""
    force = ["--controller", "force", "--force-loop", "kp + ki/s", "--set", "kp=2"]
    code, out, _ = cli(["check", *PLANT, *force, "--set", "ki=20"])
    assert code == 1 and out.startswith("not passive")
    code, out, _ = cli(["bound", "ki", *PLANT, *force, "--range", "0:1000", "--json"])
    assert code == 0
    (lo, hi), = json.loads(out)["intervals"]  # fmt: skip
    assert lo == 0 and hi == pytest.approx(17.46989935, rel=1e-8)
    code, out, _ = cli(["check", *PLANT, *force, "--set", "ki=20", "--damping-injection", "ba",
                        "--set", "ba=5"])  # fmt: skip
    assert code == 0 and out.startswith("passive")


def test_bound_of_the_target_stiffness_is_the_files_passive_set() -> None:
    argv = ["bound", "kv", *PLANT, *CASCADE_BLOCKS, *without(CASCADE_GAINS, "kv"),
            "--range", "0:5000", "--json"]  # fmt: skip
    code, out, err = cli(argv)
    assert code == 0, err
    design = load_design(CASCADE)
    exact = passive_intervals(design.sea(), "kv", 0, 5000,
                              values={k: v for k, v in design.values.items() if k != "kv"})  # fmt: skip
    assert json.loads(out)["intervals"] == [list(iv) for iv in exact.intervals]
    assert exact.intervals[0][1] == pytest.approx(2145.190916, rel=1e-9)


@pytest.mark.parametrize(
    ("blocks", "gains", "integrator"),
    [(CASCADE_BLOCKS, CASCADE_GAINS, "ki"), (VELOCITY_BLOCKS, VELOCITY_GAINS, "kvi")],
)
def test_simulate_with_the_shared_integrator(
    blocks: list[str], gains: list[str], integrator: str
) -> None:
    """With and without integral action the compiled controllers simulate stable to the
    target: the integrator C_A and C_L share is realized once (issue 22 item 1)."""
    for extra in ([], [*without(gains, integrator), "--set", f"{integrator}=0"]):
        argv = ["simulate", *PLANT, *blocks, *(extra or gains), "--load-mass", "2", "--step",
                "0.02", "--horizon", "3", "--json"]  # fmt: skip
        code, out, err = cli(argv)
        data = json.loads(out)
        assert code == 0 and data["stable"] and not data["marginal"], err
        assert data["status"] == "settled" and abs(data["final_error"]) < 4e-4


def test_tune_the_file_tunes_gains_never_the_spring() -> None:
    code, out, err = cli(["tune", str(CASCADE), "--quick", "--maxiter", "2", "--popsize", "3",
                          "--no-progress", "--json"])  # fmt: skip
    assert code in (0, 1), err
    data = json.loads(out)
    assert set(data["gains"]) == {"ba", "bv", "ki", "kp", "kv"}
    one_error(["tune", str(CASCADE), "--tune", "k1=1000:3000", "--quick"],
              "--tune k1: k1 is a plant parameter (k1 = 2500)", "--allow-plant",
              "[ranges]")  # fmt: skip
    code, out, err = cli(["tune", str(CASCADE), "--tune", "k1=1000:3000", "--allow-plant",
                          "--quick", "--maxiter", "1", "--popsize", "2", "--no-progress",
                          "--json"])  # fmt: skip
    assert code in (0, 1) and set(json.loads(out)["gains"]) == {"k1"}, err


def test_plant_flag_declares_a_plant_parameter() -> None:
    argv = ["tune", "--D1", "k1", "--CA", "kd*kt", "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--set", "kd=500", "--plant", "kt=0.5"]  # fmt: skip
    one_error([*argv, "--tune", "kt=0:1"], "--tune kt: kt is a plant parameter (kt = 0.5)")
    code, out, err = cli([*argv, "--quick", "--maxiter", "1", "--popsize", "2", "--no-progress",
                          "--json"])  # fmt: skip
    assert code in (0, 1) and set(json.loads(out)["gains"]) == {"kd"}, err
    one_error(["check", "--D1", "k1", "--CA", "kd", "--set", "kd=1", "--plant", "kd=2"],
              "--plant kd: also given with --set")  # fmt: skip
    one_error(["check", "--D1", "k1", "--CA", "kd", "--plant", "kt=2"], "plant", "'kt'")


def test_analyze_the_cascade(tmp_path: Path) -> None:
    """The passivity section shows the derivation; the tuning and sampled stages run on the
    gains only (they failed with "k1 is a plant parameter" and tuned k1 before)."""
    out_dir = tmp_path / "r"
    code, out, err = cli(["analyze", str(CASCADE), "--out", str(out_dir), "--quick",
                          "--stages", "passivity,tuning,sampled", "--no-progress", "--json",
                          "--jobs", "1"])  # fmt: skip
    assert code == 0, err
    summary = json.loads(out)
    assert summary["failed"] == [] and {s["status"] for s in summary["sections"]} == {"ok"}
    html = (out_dir / "report.html").read_text(encoding="utf-8")
    assert "Controller blocks → C_A, C_L" in html
    assert 'alttext="-C_f*K_s + Z_v*(C_f + 1)"' in html  # MathML of the derived C_L
    controller = json.loads((out_dir / "data" / "controller.json").read_text(encoding="utf-8"))
    assert controller["CA"] == "(kp + ki/s)*k1 + ba*s"
    tuned = json.loads((out_dir / "data" / "tuning.json").read_text(encoding="utf-8"))
    assert "k1" not in json.dumps(tuned.get("gains", tuned))
    sampled = (out_dir / "data" / "sampled_ranges.csv").read_text(encoding="utf-8")
    assert {line.split(",")[0] for line in sampled.splitlines()[1:]} == {
        "ba", "bv", "ki", "kp", "kv"}  # fmt: skip


@pytest.mark.parametrize(
    ("argv", "needles"),
    [
        (["check", *PLANT, "--controller", "impedance", "--force-loop", "kp + kd*s",
          "--impedance", "kv", "--set", "kp=1", "--set", "kd=1", "--set", "kv=1"],
         ["--force-loop: the force-loop compensator 'kp + kd*s' is improper"]),
        (["check", *PLANT, *CASCADE_BLOCKS, *without(CASCADE_GAINS, "bv")],
         ["--impedance: unknown symbol 'bv'", "--set bv=VALUE"]),
        (["check", *PLANT, "--controller", "admittance", "--force-loop", "kp"],
         ["--controller", "invalid choice: 'admittance'"]),
        (["check", *PLANT, *CASCADE_BLOCKS, *CASCADE_GAINS, "--CA", "kd", "--set", "kd=1"],
         ["give either --controller with its blocks or --CA, not both"]),
        (["check", *PLANT, "--force-loop", "kp", "--set", "kp=1"],
         ["the controller blocks need --controller KIND"]),
        (["check", *PLANT, "--controller", "impedance", "--force-loop", "kp", "--set", "kp=1"],
         ["--impedance: kind 'impedance' needs the target impedance"]),
        (["check", *PLANT, "--controller", "force", "--force-loop", "kp", "--velocity-loop",
          "kvp", "--set", "kp=1", "--set", "kvp=1"], ["--velocity-loop: kind 'force' has no"]),
        (["check", "--Z", "1", "--controller", "force", "--force-loop", "1"],
         ["give either --Z or a design"]),
        (["simulate", *PLANT, "--controller", "impedance", "--force-loop", "kp + kd*s",
          "--impedance", "kv", "--set", "kp=1", "--set", "kd=1", "--set", "kv=1",
          "--load-mass", "1"], ["--force-loop:", "improper"]),
        (["bound", "kv", *PLANT, "--controller", "impedance", "--force-loop", "kp",
          "--impedance", "kv + bv*s", "--set", "kp=1"], ["--impedance: unknown symbol 'bv'"]),
    ],
)  # fmt: skip
def test_bad_controller_input_is_one_error_line(argv: list[str], needles: list[str]) -> None:
    one_error(argv, *needles)


def test_a_bad_controller_file_is_one_error_line(tmp_path: Path) -> None:
    text = CASCADE.read_text(encoding="utf-8").replace(
        'D1 = "k1 + b1*s"', 'D1 = "k1 + b1*s"\nCL = "kd"'
    )
    bad = tmp_path / "both.toml"
    bad.write_text(text, encoding="utf-8")
    one_error(["tune", str(bad), "--quick"], "give either [controller] or model.CL, not both")
    improper = tmp_path / "improper.toml"
    improper.write_text(CASCADE.read_text(encoding="utf-8").replace("kp + ki/s", "kp + ki*s"),
                        encoding="utf-8")  # fmt: skip
    one_error(["analyze", str(improper), "--out", str(tmp_path / "o")],
              "controller.force:", "improper")  # fmt: skip


def test_help_states_the_convention_and_the_blocks() -> None:
    parser = build_parser()
    for command in ("check", "bound", "simulate", "tune", "sweep", "sampled"):
        sub = parser._subparsers._group_actions[0].choices[command]  # type: ignore[union-attr]
        if command == "sampled":
            sub = sub._subparsers._group_actions[0].choices["check"]  # type: ignore[union-attr]
        text = sub.format_help()
        assert "f_A = CA*(theta - x_A) + CL*(theta - x_L)" in text, command
        for flag in ("--controller", "--force-loop", "--impedance", "--damping-injection",
                     "--feedforward", "--plant"):  # fmt: skip
            assert flag in text, (command, flag)


def test_sampled_without_the_shared_integrator() -> None:
    """The sampled analyses run the compiled controllers (with integral action shared by C_A
    and C_L they need the minimal realization of issue 22 item 1)."""
    p_force = ["--controller", "impedance", "--force-loop", "kp", "--impedance", "kv + bv*s",
               "--damping-injection", "ba", "--feedforward", "--set", "kp=2", "--set", "bv=5",
               "--set", "ba=20"]  # fmt: skip
    code, out, err = cli(["sampled", "bound", "kv", "--period", "0.001", *PLANT, *p_force,
                          "--range", "0:5000", "--json"])  # fmt: skip
    assert code == 0, err
    (lo, hi), = json.loads(out)["intervals"]  # fmt: skip
    assert lo == 0 and hi == pytest.approx(2037.357425, rel=1e-8)
    code, out, err = cli(["sampled", "check", "--period", "0.001", *PLANT, *VELOCITY_BLOCKS,
                          *without(VELOCITY_GAINS, "kvi"), "--set", "kvi=0"])  # fmt: skip
    assert code == 0 and out.startswith("passive"), err


def test_the_docs_page_commands_parse_and_say_what_they_print() -> None:
    """docs/controllers.md: every command parses; a ``# ...`` line after a check or bound is
    what it prints (the explained check's output block too)."""
    import re
    import shlex

    text = (EXAMPLES.parent / "docs" / "controllers.md").read_text(encoding="utf-8")
    parser = build_parser()
    checked = 0
    for block in re.findall(r"```bash\n(.*?)```", text, re.S):
        lines = block.replace("\\\n", " ").splitlines()
        for i, line in enumerate(lines):
            cmd = line.split("#")[0].strip()
            if not cmd.startswith(".venv/bin/seapass "):
                continue
            argv = shlex.split(cmd)[1:]
            assert callable(parser.parse_args(argv).func)
            said = lines[i + 1].strip() if i + 1 < len(lines) else ""
            if argv[0] in ("check", "bound") and said.startswith("# "):
                _, out, _ = cli(argv)
                assert said[2:] in out.splitlines(), argv
                checked += 1
    assert checked == 4
    explained = re.search(r"--explain \\\n.*?```\n\n```text\n(.*?)```", text, re.S)
    assert explained is not None
    _, out, _ = cli(["check", *PLANT, *CASCADE_BLOCKS, *CASCADE_GAINS, "--explain"])
    assert out.startswith(explained.group(1))
