"""``seapass sampled check`` on the numeric path imports no symbolic or plotting library.

The controllers are emulated exactly on flint polynomials and the plant read from the
exact elements (issue 21, item 11); the verdict is the certified one as before.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from helpers import (
    EXAMPLES,
    LP_ARGV,
    forbid,
    one_error,
    run_main,
)

HEAVY = ("sympy", "control", "matplotlib", "scipy")
MODEL = ["--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "m=1", "--set", "b=10",
         "--set", "k1=1005", "--set", "b1=30", "--set", "bd=25"]  # fmt: skip


def _run(argv: list[str]) -> tuple[int, list[str], str]:
    code = (
        "import json, sys; from seapass.cli import main; code = main(sys.argv[1:]); "
        f"print(json.dumps([code, [m for m in {HEAVY!r} if m in sys.modules]]))"
    )
    run = subprocess.run(
        [sys.executable, "-c", code, *argv], capture_output=True, text=True, check=True
    )
    exit_code, loaded = json.loads(run.stdout.strip().splitlines()[-1])
    return exit_code, loaded, run.stdout


@pytest.mark.parametrize(
    ("extra", "passive"),
    [
        (["--set", "kd=5000"], True),
        (["--set", "kd=5000", "--velocity-filter", "100", "--delay", "1"], True),
        (["--set", "kd=1e7"], False),
    ],
)
def test_a_numeric_sampled_check_imports_no_symbolic_or_plotting_library(extra, passive):
    code, loaded, out = _run(["sampled", "check", "--period", "0.002", *MODEL, *extra, "--json"])
    assert loaded == []
    assert code == (0 if passive else 1)
    assert json.loads(out[: out.rindex("\n[")])["passive"] is passive


# -------------- options checked before the work (moved from test_hardening, issue 12 items 1, 3, 5)


def test_sampled_bound_samples_are_capped(monkeypatch: pytest.MonkeyPatch) -> None:
    forbid(monkeypatch, "seapass.sampled.bound.sampled_passive_bound")
    one_error(
        ["sampled", "bound", "kd", *LP_ARGV, "--range", "kd=0:5000", "--samples", "100000000"],
        "--samples",
    )


def test_sampled_delay_is_capped(monkeypatch: pytest.MonkeyPatch) -> None:
    forbid(monkeypatch, "seapass.sampled.bound.sampled_passive_bound")
    forbid(monkeypatch, "seapass.sampled.passivity.sampled_passivity")
    one_error(
        ["sampled", "bound", "kd", *LP_ARGV, "--range", "kd=0:5000", "--delay", "1000000"],
        "--delay",
    )
    one_error(["sampled", "check", *LP_ARGV, "--set", "kd=5", "--delay", "1000000"], "--delay")


@pytest.mark.parametrize("rtol", ["0", "1e-300", "1e-13", "nan", "-1"])
def test_sampled_bound_rtol_is_validated(rtol: str, monkeypatch: pytest.MonkeyPatch) -> None:
    forbid(monkeypatch, "seapass.sampled.bound.sampled_passive_bound")
    one_error(
        ["sampled", "bound", "kd", *LP_ARGV, "--range", "kd=0:5000", "--rtol", rtol], "--rtol"
    )


def test_rtol_below_the_smallest_enclosure_width_is_refused(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the certified bound encloses each edge to rtol relative to the edge: any rtol from
    # MIN_RTOL up is reachable in doubles, even on a range far from 0
    forbid(monkeypatch, "seapass.sampled.bound.sampled_passive_bound")
    one_error(
        ["sampled", "bound", "kd", *LP_ARGV, "--range", "kd=1e15:1.0000001e15", "--rtol", "1e-13"],
        "--rtol 1e-13",
    )


# -------------- sampled bound of a plant parameter, and over a box (issue 26, item 4)

OURS = ["--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "b=10", "--set", "k1=1000",
        "--set", "b1=300", "--set", "bd=300", "--period", "0.002", "--delay", "1",
        "--velocity-filter", "50", "--no-progress"]  # fmt: skip


def test_sampled_bound_of_a_plant_parameter_end_to_end() -> None:
    from seapass.model.loop import SampledLoop
    from seapass.model.sea import SEA
    from seapass.sampled.passivity import sampled_passivity

    argv = ["sampled", "bound", "m", *OURS, "--set", "kd=1708", "--range", "m=1.02:1.020002"]
    code, out, err = run_main([*argv, "--budget", "2", "--json"])
    assert code == 0, err
    d = json.loads(out)
    assert d["robust"] is True and d["sampled"] is True and d["kind"] == "plant"
    assert d["intervals"] == [[1.02, 1.020002]] and d["outer"] == [[1.02, 1.020002]]
    assert d["budget"] == 2 and 1 <= d["budget_used"] <= 2 and d["box"] is None
    loop = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(b=10, k1=1000, b1=300, bd=300,
                                                            kd=1708))  # fmt: skip
    for m in (1.02, 1.020001, 1.020002):  # the printed ends are passive by the plain verdict
        assert sampled_passivity(sea, loop=loop, values={"m": m}).passive
    code, out, err = run_main([*argv, "--budget", "2"])
    assert code == 0, err
    # 1.02 is a double a little below 1.02: its 10-digit text rounds inward
    assert out.startswith("passive at T = 0.002 s (delay 1): m in [1.020000001, 1.020002]")
    assert "outer (certified)" in out


def test_sampled_bound_of_a_gain_over_a_box_prints_the_outer_set() -> None:
    argv = ["sampled", "bound", "kd", *OURS, "--set", "m=1", "--range", "kd=0:5000"]
    code, out, err = run_main([*argv, "--uncertain", "m=0.98:1.02", "--budget", "1", "--json"])
    # --set m and --uncertain m together are refused; without --set m the file value is free
    assert code == 2 and err.count("\n") == 1 and "--set m" in err
    argv = ["sampled", "bound", "kd", *OURS, "--range", "kd=0:5000"]
    code, out, err = run_main([*argv, "--uncertain", "m=1:1", "--budget", "1", "--json"])
    assert code == 0, err
    d = json.loads(out)
    assert d["kind"] == "gain" and d["box"] == {"m": [1.0, 1.0]} and d["intervals"]
    code, out, err = run_main([*argv, "--uncertain", "m=0.98:1.02", "--budget", "1"])
    assert code == 0, err
    assert "kd in none" in out and "undecided" in out


def test_the_cli_default_budget_is_the_library_default() -> None:
    from seapass.cli.cmd_sampled import DEFAULT_ROBUST_BUDGET
    from seapass.robust.sampled_intervals import DEFAULT_INTERVAL_BUDGET, MAX_INTERVAL_BUDGET

    assert DEFAULT_ROBUST_BUDGET == DEFAULT_INTERVAL_BUDGET and MAX_INTERVAL_BUDGET == 10_000


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["m", "--set", "kd=1708", "--range", "m=0:2"], "m must be positive"),
        (["m", "--set", "kd=1708", "--range", "m=2:1"], "--range m"),
        (["m", "--set", "kd=1708"], "give --range m=LO:HI"),
        (["mm", "--set", "kd=1708", "--range", "mm=1:2"], "did you mean 'm'"),
        (["m", "--set", "kd=1708", "--range", "m=1:2", "--budget", "100000"], "--budget"),
        (["m", "--set", "kd=1708", "--range", "m=1:2", "--budget", "0"], "--budget"),
        (
            ["m", "--set", "kd=1708", "--range", "m=1:2", "--uncertain", "m=1:2"],
            "bounded parameter",
        ),
        (["m", "--set", "kd=1708", "--range", "m=1:2", "--uncertain", "b=2:1"], "--uncertain b"),
        (["m", "--set", "kd=1708", "--range", "m=1:2", "--max-boxes", "5"], "--max-boxes"),
        (["m", "--set", "kd=1708", "--range", "m=1:2", "--out", "x"], "--out"),
        (["kd", "--set", "m=1", "--range", "kd=0:10", "--budget", "3"], "--budget applies"),
    ],
)
def test_sampled_bound_robust_bad_input(extra: list[str], needle: str, monkeypatch) -> None:
    forbid(monkeypatch, "seapass.robust.sampled_verdict.robust_sampled_check")
    forbid(monkeypatch, "seapass.sampled.bound.sampled_passive_bound")
    one_error(["sampled", "bound", extra[0], *OURS, *extra[1:]], needle)


def test_a_controller_parameter_in_the_box_is_refused(monkeypatch) -> None:
    forbid(monkeypatch, "seapass.robust.sampled_verdict.robust_sampled_check")
    ours = str(EXAMPLES / "ours.toml")
    argv = ["sampled", "bound", "m", ours, "--range", "m=1:2", "--uncertain", "bd=1:2"]
    one_error(argv, "--uncertain bd: not a plant parameter")


def test_sampled_bound_of_a_plant_parameter_is_interrupted_cleanly(monkeypatch) -> None:
    import seapass.robust.sampled_verdict as sv

    def stop(*args: object, **kwargs: object) -> object:
        raise KeyboardInterrupt

    monkeypatch.setattr(sv, "robust_sampled_check", stop)
    code, out, err = run_main(
        ["sampled", "bound", "m", *OURS, "--set", "kd=1708", "--range", "m=1:1.1"]
    )
    assert code == 130 and out == "" and err.startswith("error: interrupted")
