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
    LP_ARGV,
    forbid,
    one_error,
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
