"""A check that answers at once: command start-up and the numeric path without sympy.

Two measurements:

* wall-clock and CPU time of one ``seapass`` process for ``--version`` and for the
  numeric ``check`` (the README design, the PID-force-loop-in-impedance-loop design, a
  raw ``--Z``), ``bound`` (the README example) and ``sampled check``; the goal (issue 21,
  item 11) is at most 0.3 s over ``--version`` on an idle machine;
* library ``is_passive`` on every catalogued design: the first verdict of a design
  (derivation included) and repeated verdicts at new values, on the exact path and on
  the sympy path it replaced (frozen in ``legacy_impedance.py``), with the ``(N, D)``
  of both compared.

Run alone with ``python benchmarks/bench_startup.py [--quick]``.
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

import legacy_impedance
from _util import Row, rate
from seapass.analysis.impedance import evaluate_system
from seapass.analysis.passivity import is_passive, positive_real_test
from seapass.errors import SymbolicLimitError
from seapass.model.catalog import CATALOG, REFERENCE_VALUES
from seapass.model.sea import SEA

OURS = ["--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "m=1", "--set", "b=10",
        "--set", "k1=1000", "--set", "b1=20", "--set", "bd=25", "--set", "kd=5000"]  # fmt: skip
CF = "(kp + ki/s + kdf*s/(1 + s/wf))"
PID = {"D1": "k1 + b1*s", "CA": f"{CF}*k1 + ba*s", "CL": f"(1 + {CF})*(kv + bv*s) - {CF}*k1"}
PID_VALUES = {"m": 0.4, "b": 3.0, "k1": 2500.0, "b1": 2.0, "kp": 2.0, "ki": 20.0,
              "kdf": 0.01, "wf": 300.0, "ba": 50.0, "kv": 1000.0, "bv": 20.0}  # fmt: skip

COMMANDS: dict[str, list[str]] = {
    "seapass --version": ["--version"],
    "check (README design)": ["check", *OURS],
    "check (PID force loop in an impedance loop)": [
        "check",
        *[f"--{k}={v}" for k, v in PID.items()],
        *[f"--set={k}={v!r}" for k, v in PID_VALUES.items()],
    ],
    "check --Z": ["check", "--Z", "(s + 1)/(s + 2)"],
    "bound kd (README)": ["bound", "kd", "--D1", "k1 + b1*s", "--CL", "kd", "--set", "m=1",
                          "--set", "b=10", "--set", "k1=1000", "--set", "b1=20",
                          "--range", "0:1e5"],
    "sampled check (T = 2 ms)": ["sampled", "check", "--period", "0.002", "--D1", "k1 + b1*s",
                                 "--CA", "kd + bd*s", "--set", "m=1", "--set", "b=10",
                                 "--set", "k1=1005", "--set", "b1=30", "--set", "bd=25",
                                 "--set", "kd=5000"],
}  # fmt: skip

GOAL = 0.3


def _seapass() -> str:
    exe = Path(sys.executable).with_name("seapass")
    return str(exe) if exe.exists() else "seapass"


def _one(argv: list[str]) -> tuple[float, float]:
    """Wall-clock and CPU (user + system) seconds of one ``seapass`` process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([_seapass(), *argv], capture_output=True, check=False)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def startup(repeat: int) -> dict[str, tuple[float, float, float]]:
    """``{command: (min wall, median wall, min CPU)}`` over ``repeat`` runs (after a warm-up)."""
    out = {}
    for name, argv in COMMANDS.items():
        _one(argv)  # warm the file cache and the byte code
        runs = [_one(argv) for _ in range(repeat)]
        walls = [w for w, _c in runs]
        out[name] = (min(walls), statistics.median(walls), min(c for _w, c in runs))
    return out


def _clear_caches() -> None:
    """Forget every derivation, so the next verdict of a design is its first."""
    from seapass.analysis import impedance
    from seapass.model import elements, expr, freebody, sea, stiffness

    impedance._CACHE.clear()
    freebody._CACHE.clear()
    for fn in (expr._exact, expr._checked_tree, sea._model_elements, elements._checked_sympy,
               elements._exact_sympy, stiffness._derive, stiffness._impedance,
               legacy_impedance._compiled):  # fmt: skip
        fn.cache_clear()


def _best(fn: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    best, result = float("inf"), None
    for _ in range(repeat):
        t0 = time.process_time()
        result = fn()
        best = min(best, time.process_time() - t0)
    return best, result


def _designs() -> list[tuple[str, dict[str, str], dict[str, float]]]:
    out = []
    for key, d in CATALOG.items():
        used = SEA(**d.elements()).parameters
        out.append((key, d.elements(), {p: REFERENCE_VALUES[p] for p in used}))
    out.append(("PID force loop in impedance loop", PID, PID_VALUES))
    return out


def library(quick: bool) -> tuple[list[Row], list[str]]:
    """First and repeated verdicts, exact path vs the sympy path, on every design."""
    n = 200 if quick else 2000
    lines = [
        "| design | first verdict, exact [ms] | first verdict, sympy [ms] | repeated, exact "
        "[verdicts/s] | repeated, sympy [verdicts/s] | same N, D |",
        "|---|---:|---:|---:|---:|---|",
    ]
    tot = {"first_new": 0.0, "first_old": 0.0, "rep_new": 0.0, "rep_old": 0.0, "count": 0}
    for name, elements, values in _designs():
        sea = SEA(**elements, values=values)
        scale = [1 + 0.37 * (i % 7) / 7 for i in range(n)]
        points = [{k: v * scale[i] for k, v in values.items()} for i in range(n)]

        def first_new(
            elements: dict[str, str] = elements, values: dict[str, float] = values
        ) -> Any:
            _clear_caches()
            return is_passive(SEA(**elements, values=values))

        def first_old(sea: SEA = sea) -> Any:
            _clear_caches()
            return positive_real_test(*legacy_impedance.evaluate_system(sea, {})[:2])

        t_first_new, _r = _best(first_new, 3)
        try:
            t_first_old, _r = _best(first_old, 1 if quick else 3)
            old_nd = legacy_impedance.evaluate_system(sea, {})
            same = old_nd == evaluate_system(sea, None)
        except SymbolicLimitError:
            t_first_old, same = float("nan"), None
        t_rep_new, _r = _best(
            lambda sea=sea, pts=points: [is_passive(sea, values=p) for p in pts], 1
        )
        if same is not None:

            def rep_old(sea: SEA = sea, pts: list[dict[str, float]] = points) -> Any:
                out = []
                for p in pts:
                    num, den, support = legacy_impedance.evaluate_system(sea, p)
                    out.append(positive_real_test(num, den, support=support))
                return out

            t_rep_old, _r = _best(rep_old, 1)
            tot["first_new"] += t_first_new
            tot["first_old"] += t_first_old
            tot["rep_new"] += t_rep_new
            tot["rep_old"] += t_rep_old
            tot["count"] += 1
            old_text = f"{t_first_old * 1e3:.1f}"
            old_rate = f"{rate(n, t_rep_old):,.0f}"
        else:
            old_text, old_rate = "refused (model too large)", "-"
        lines.append(
            f"| {name} | {t_first_new * 1e3:.1f} | {old_text} | {rate(n, t_rep_new):,.0f} | "
            f"{old_rate} | {'-' if same is None else same} |"
        )
    k = tot["count"]
    rows = [
        Row(
            task="is_passive, first verdict of a design (derivation included)",
            ours="exact path (flint, no sympy)",
            ours_rate=k / tot["first_new"],
            peer="sympy derivation (before)",
            peer_rate=k / tot["first_old"],
            note=f"designs per second over the {k} catalogued designs",
        ),
        Row(
            task="is_passive, repeated verdicts at new values",
            ours="exact path (flint, no sympy)",
            ours_rate=k * n / tot["rep_new"],
            peer="sympy-compiled coefficients (before)",
            peer_rate=k * n / tot["rep_old"],
            note=f"{n} values per design, {k} catalogued designs",
        ),
    ]
    return rows, lines


def run(quick: bool) -> tuple[list[Row], list[str], list[str]]:
    """Rows for the results table, notes, and a markdown section on start-up."""
    times = startup(3 if quick else 10)
    base = times["seapass --version"][0]
    lines = [
        "| command | wall, best [s] | wall, median [s] | CPU, best [s] | over `--version` "
        f"(best wall) [s] | goal ≤ {GOAL} s |",
        "|---|---:|---:|---:|---:|---|",
    ]
    for name, (best, med, cpu) in times.items():
        over = best - base
        ok = "-" if name == "seapass --version" else ("yes" if over <= GOAL else "no")
        lines.append(f"| `{name}` | {best:.3f} | {med:.3f} | {cpu:.3f} | {over:+.3f} | {ok} |")
    rows, lib = library(quick)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    section = [
        "## A check that answers at once",
        "",
        "One `seapass` process per command (best and median of "
        f"{3 if quick else 10} runs after a warm-up; load average {load:.2f} on "
        f"{os.cpu_count()} CPUs when measured, so wall-clock times include the machine's "
        "other work).  Numeric `check`, `bound` and `sampled check` import neither sympy nor "
        "python-control nor matplotlib (`tests/cli/test_cmd_*.py` guard it): expressions "
        "are parsed straight into exact rational functions and `Z_L` is solved by Cramer's "
        "rule on the free-body equations (`seapass.model.freebody`).",
        "",
        *lines,
        "",
        "Library `is_passive` on every catalogued design at its reference values, before "
        "(the sympy derivation and sympy-compiled coefficients, frozen in "
        "`benchmarks/legacy_impedance.py`) and after (the exact path): the first verdict of "
        "a design with every cache cleared, and repeated verdicts at new values; CPU time.",
        "",
        *lib,
        "",
    ]
    return rows, [], section


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    r, _n, sec = run(quick)
    print("\n".join(sec))
    for row in r:
        print(row)
