"""``seapass sampled check`` on the numeric path imports no symbolic or plotting library.

The controllers are emulated exactly on flint polynomials and the plant read from the
exact elements (issue 21, item 11); the verdict is the certified one as before.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

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
