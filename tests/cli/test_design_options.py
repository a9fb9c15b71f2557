"""A design file on every command: flags override the file, one range vocabulary, units."""

from __future__ import annotations

import io
import json
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from helpers import LP_ARGV
from seapass.cli import main

ROOT = Path(__file__).resolve().parents[2]
OURS = str(ROOT / "examples" / "ours.toml")
LP = str(ROOT / "examples" / "lp.toml")
LPD = str(ROOT / "examples" / "load_pd_not_passive.toml")
LP_FLAGS = list(LP_ARGV)  # the paper's load-side P on its plant (tests/helpers.py)


def _run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


@pytest.fixture
def fast(tmp_path: Path) -> Path:
    """LP with a 1 kHz controller, declared units and ranges."""
    path = tmp_path / "fast.toml"
    path.write_text(
        'name = "fast"\n[model]\nD1 = "k1 + b1*s"\nCL = "kd"\n'
        "[parameters]\nm = 1.02\nb = 10.0\nk1 = 1005.0\nb1 = 30.0\nkd = 500.0\n"
        "[ranges]\nkd = [0.0, 2000.0]\n"
        "[simulation]\nstep = 0.1\nhorizon = 2.0\ntune_mass = 5.0\n"
        "[control]\nrate = 1000.0\n"
        '[units]\nkd = "N/mm"\n'
    )
    return path


def test_check_from_a_file_and_the_flags_override_it() -> None:
    code, out, _ = _run(["check", LP, "--json"])
    data = json.loads(out)
    assert code == 0 and data["passive"] and data["units"]["kd"] == "N/m"
    code, out, _ = _run(["check", LP, "--set", "kd=2000", "--json"])  # LP: passive iff kd <= k1
    assert code == 1 and not json.loads(out)["passive"]
    same, flags, _ = _run(["check", *LP_FLAGS, "--set", "kd=2000", "--json"])
    assert same == 1 and "units" not in json.loads(flags)  # inline: the JSON is unchanged
    code, out, _ = _run(["check", LP, "--CL", "0", "--set", "k1=1000", "--json"])
    assert code == 0  # an element replaced: the file's kd is no longer used


def test_bound_from_a_file_uses_its_range_and_units(fast: Path) -> None:
    code, out, _ = _run(["bound", "kd", str(fast)])
    assert code == 0 and out.startswith("passive for 0 <= kd <= ") and out.strip().endswith("N/mm")
    code, out, _ = _run(["bound", "kd", str(fast), "--range", "kd=0:10", "--json"])
    data = json.loads(out)
    assert data["intervals"] == [[0.0, 10.0]] and data["units"]["kd"] == "N/mm"


def test_sampled_check_uses_the_files_rate(fast: Path) -> None:
    code, out, _ = _run(["sampled", "check", str(fast)])
    assert code in (0, 1) and "T = 0.001 s" in out
    code, out, _ = _run(["sampled", "check", str(fast), "--period", "0.002"])
    assert code in (0, 1) and "T = 0.002 s" in out  # the flag overrides the file


def test_sampled_bound_has_the_default_range_of_bound(fast: Path) -> None:
    code, out, _ = _run(["sampled", "bound", "kd", str(fast), "--json"])
    data = json.loads(out)
    assert code == 0 and data["range"] == [0.0, 2000.0]
    assert data["period"] == 0.001 and data["units"]["kd"] == "N/mm"


def test_region_from_a_file(fast: Path) -> None:
    code, out, _ = _run(["region", "kd", "b1", str(fast), "--range", "b1=0:50", "--points", "3"])
    lines = out.splitlines()
    assert code == 0 and len(lines) == 3 and lines[0].startswith("kd = 0 N/mm: passive b1 in")


def test_simulate_plot_witness_sweep_tune_from_a_file(fast: Path, tmp_path: Path) -> None:
    code, out, _ = _run(["simulate", str(fast), "--json"])
    data = json.loads(out)
    assert code == 0 and data["load_mass"] == 5.0 and data["horizon"] == 2.0
    assert data["target"] == 0.1  # the file's step
    code, out, _ = _run(["simulate", str(fast), "--load-mass", "1", "--json"])
    assert json.loads(out)["load_mass"] == 1.0
    code, out, _ = _run(["plot", "real", str(fast)])
    assert code == 0 and out.startswith("Re Z_L(jw) >= 0 at every frequency")
    code, out, _ = _run(["witness", LPD, "--json"])
    assert code == 0 and json.loads(out)["found"]
    csv = tmp_path / "s.csv"
    code, _, _ = _run(["sweep", str(fast), "--grid", "kd=0:2000:1000", "--out", str(csv),
                       "--no-progress", "--no-metrics"])  # fmt: skip
    assert code == 0 and len(csv.read_text().splitlines()) == 4
    code, out, err = _run(["tune", str(fast), "--tune", "kd=0:800", "--quick", "--maxiter", "1",
                           "--popsize", "2", "--no-progress", "--json"])  # fmt: skip
    data = json.loads(out)
    assert (
        data["period"] == 0.001
        and data["sampled_passive"] is not None
        and data["units"] == {"kd": "N/mm"}
    )
    assert "1000 Hz" in err


@pytest.mark.parametrize(
    ("old", "new", "note"),
    [
        (["bound", "kd", *LP_FLAGS, "--range", "0:2000"],
         ["bound", "kd", *LP_FLAGS, "--range", "kd=0:2000"], "--range 0:2000 is deprecated"),
        (["region", "kd", "b", *LP_FLAGS[:-4], "--set", "k1=1000", "--x-range", "0:2000",
          "--y-range", "1:20", "--nx", "2"],
         ["region", "kd", "b", *LP_FLAGS[:-4], "--set", "k1=1000", "--range", "kd=0:2000",
          "--range", "b=1:20", "--points", "2"], "--x-range 0:2000 is deprecated"),
        (["sampled", "region", "kd", "b1", "--D1", "k1 + b1*s", "--CL", "kd", "--set", "m=1",
          "--set", "b=10", "--set", "k1=1000", "--range", "0:1000", "--range2", "1:50",
          "--rows", "2", "--rtol", "1e-3", "--no-progress"],
         ["sampled", "region", "kd", "b1", "--D1", "k1 + b1*s", "--CL", "kd", "--set", "m=1",
          "--set", "b=10", "--set", "k1=1000", "--range", "kd=0:1000", "--range", "b1=1:50",
          "--points", "2", "--rtol", "1e-3", "--no-progress"], "--rows 2 is deprecated"),
    ],
)  # fmt: skip
def test_old_spellings_still_work_with_a_note(old: list[str], new: list[str], note: str) -> None:
    code_old, out_old, err_old = _run([*old, "--json"])
    code_new, out_new, err_new = _run([*new, "--json"])
    assert code_old == code_new == 0 and out_old == out_new
    assert note in err_old and "deprecated" not in err_new
    assert all(line.startswith("warning: ") for line in err_old.splitlines())


def test_units_on_the_command_line_and_in_the_analyze_report(fast: Path, tmp_path: Path) -> None:
    code, out, _ = _run(["check", str(fast), "--unit", "kd=N*s/m", "--json"])
    assert json.loads(out)["units"]["kd"] == "N*s/m"
    code, out, _ = _run(["analyze", str(fast), "--out", str(tmp_path / "r"), "--stages", "core",
                         "--no-progress", "--json"])  # fmt: skip
    report = (tmp_path / "r" / "report.md").read_text()
    assert code == 0 and "kd = 500 N/mm" in report and "SI units" not in report
    assert json.loads(out)["units"]["kd"] == "N/mm"
    design = json.loads((tmp_path / "r" / "data" / "design.json").read_text())
    assert design["units"] == {"kd": "N/mm"}


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["check", OURS, "--unit", "kd=N/xx"], "error: --unit kd: 'N/xx' is not a unit"),
        (["check", OURS, "--unit", "zz=N"], "error: --unit zz: not a parameter"),
        (["check", OURS, "--unit", "kd"], "error: --unit 'kd': expected NAME=UNIT"),
        (["check", OURS, "--unit", "kd=N", "--unit", "kd=N"], "twice"),
        (["check", OURS, "--Z", "1/s"], "error: give either --Z or a design"),
        (["bound", "kd", OURS, "--set", "kd=1"], "kd is a free parameter here"),
        (["bound", "kd", OURS, "--range", "bd=0:1"], "--range bd: not a free parameter"),
        (["bound", "kd", *LP_FLAGS, "--range", "0:1", "--range", "kd=0:2"], "given twice"),
        (["region", "kd", "b", *LP_FLAGS, "--nx", "3", "--points", "3"], "give --points only"),
        (["simulate", *LP_FLAGS, "--set", "kd=1"], "error: give the load mass"),
        (["tune", OURS, "--continuous", "--period", "0.001"], "--period or --continuous"),
    ],
)
def test_bad_input_is_one_error_line(argv: list[str], needle: str) -> None:
    code, out, err = _run(argv)
    lines = [x for x in err.splitlines() if not x.startswith("warning: ")]
    assert code == 2 and out == "" and len(lines) == 1 and needle in lines[0], err


def test_a_bad_units_table_is_one_error_line(tmp_path: Path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text(Path(LP).read_text() + '\n[units]\nkd = "N per m"\n')
    code, out, err = _run(["check", str(bad)])
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("error: ") and "units.kd" in err
