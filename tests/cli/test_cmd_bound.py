"""``seapass bound`` with one free gain imports no symbolic or plotting library.

The critical values of the free gain come from bivariate flint polynomials
(``analysis.critical``; cross-checked against the sympy version in
``tests/analysis/test_critical.py``), and the README's answer is unchanged.
"""

from __future__ import annotations

import json
import subprocess
import sys

HEAVY = ("sympy", "control", "matplotlib", "scipy")


def test_a_numeric_bound_imports_no_symbolic_or_plotting_library():
    argv = ["bound", "kd", "--D1", "k1 + b1*s", "--CL", "kd", "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--set", "b1=20", "--range", "0:1e5", "--json"]  # fmt: skip
    code = (
        "import json, sys; from seapass.cli import main; code = main(sys.argv[1:]); "
        f"print(json.dumps([code, [m for m in {HEAVY!r} if m in sys.modules]]))"
    )
    run = subprocess.run(
        [sys.executable, "-c", code, *argv], capture_output=True, text=True, check=True
    )
    out = run.stdout
    exit_code, loaded = json.loads(out.strip().splitlines()[-1])
    assert (exit_code, loaded) == (0, [])
    result = json.loads(out[: out.rindex("\n[")])
    assert result["intervals"] == [[0.0, 849.1933384829667]]
