"""Certified sampled-data passivity against the previous code (before issue 11).

The peer is the old seapass (mpmath alias sums, Sturm on rounded coefficients, a 17-point
scan for bounds), run from its own checkout and virtual environment: ``SEAPASS_OLD``
(default ``/work/base``).  Without it the peer columns are empty.  Times are CPU seconds
(this process, or the child processes for the command line), so other jobs on a shared
machine do not distort them.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

from _util import Row, timed
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.passivity import sampled_passivity

OLD = Path(os.environ.get("SEAPASS_OLD", "/work/base"))

RIG = {"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 30.0}
CHECK_ARGS = ["sampled", "check", "--period", "0.002", "--D1", "k1 + b1*s", "--CA", "kd + bd*s",
              "--set", "m=1.02", "--set", "b=10", "--set", "k1=1005", "--set", "b1=30",
              "--set", "bd=25", "--set", "kd=2000", "--json"]  # fmt: skip
BOUNDS = {
    "README: Ours (m = 1) kd in 0:5e4": (
        dict(D1="k1 + b1*s", CA="kd + bd*s"),
        {"m": 1.0, "bd": 25.0},
        {},
        (0.0, 5e4),
    ),
    "LP kd in 0:5000": (dict(D1="k1 + b1*s", CL="kd"), {}, {}, (0.0, 5000.0)),
    "Ours kd in 0:1e5, delay 1, 50 Hz filter": (
        dict(D1="k1 + b1*s", CA="kd + bd*s"),
        {"bd": 25.0},
        {"delay": 1, "velocity_filter": 50.0},
        (0.0, 1e5),
    ),
}

_OLD_SCRIPT = """
import json, sys, time
from seapass.model import SEA
from seapass import sampled
job = json.loads(sys.argv[1])
sea = SEA(**job["elements"], values=job["values"])
t0 = time.process_time()
if job["kind"] == "check":
    out = sampled.sampled_passivity(sea, period=0.002).passive
else:
    r = sampled.sampled_passive_bound(sea, "kd", period=0.002, lo=job["lo"], hi=job["hi"], **job["loop"])
    out = r.max_passive
print(json.dumps({"seconds": time.process_time() - t0, "result": out}))
"""


def _old(job: dict[str, Any]) -> tuple[float, Any] | None:
    exe = OLD / ".venv" / "bin" / "python"
    if not exe.exists():
        return None
    out = subprocess.run(
        [str(exe), "-c", _OLD_SCRIPT, json.dumps(job)], capture_output=True, text=True, check=True,
        cwd=OLD,
    )  # fmt: skip
    res = json.loads(out.stdout.strip().splitlines()[-1])
    return res["seconds"], res["result"]


_CLI_SCRIPT = """
import contextlib, io, json, sys, time
from seapass.cli import main
argv = json.loads(sys.argv[1])
warm = [a.replace("b1=30", "b1=31") for a in argv]  # same command, another plant
with contextlib.redirect_stdout(io.StringIO()):
    main(warm)  # start-up: imports, parser, lazy sympy modules
    t0 = time.process_time()
    main(argv)  # the check itself, plant and alias caches cold
print(time.process_time() - t0)
"""


def _beyond_startup(python: Path, repeat: int) -> float | None:
    """CPU seconds of one ``sampled check`` in a fresh interpreter after a first check of
    another plant (start-up: imports, parser, sympy's lazy modules), best of ``repeat``."""
    if not python.exists():
        return None
    best = float("inf")
    for _ in range(repeat):
        out = subprocess.run(
            [str(python), "-c", _CLI_SCRIPT, json.dumps(CHECK_ARGS)], capture_output=True,
            text=True, check=True, cwd=python.parent,
        )  # fmt: skip
        best = min(best, float(out.stdout.strip().splitlines()[-1]))
    return best


CASCADE = {
    "elements": {
        "D1": "k1 + b1*s",
        "CA": "(kf + ki/s)*k1 + ba*s",
        "CL": "(1 + kf + ki/s)*(kv + bv*s) - (kf + ki/s)*k1",
    },
    "values": {"m": 0.4, "b": 3.0, "k1": 2500.0, "b1": 2.0, "kf": 0.5, "ki": 10.0,
               "kv": 1000.0, "bv": 5.0, "ba": 5.0},
}  # fmt: skip
#: Issue 22's target for the cascaded design (PI force loop inside an impedance loop).
CASCADE_TARGET_S = 5.0


def cascade_rows(quick: bool) -> list[Row]:
    """The PI force loop inside an impedance loop of issue 22, whose integrator is in both
    C_A and C_L: check and bound of kv at 1 kHz, CPU seconds against the 5 s target."""
    loop = SampledLoop(period=0.001)
    sea = SEA(**CASCADE["elements"], values=CASCADE["values"])
    t_c = timed(lambda: sampled_passivity(sea, loop=loop), repeat=1 if quick else 3)
    free = sea.with_values(kv=None)
    t_b = timed(lambda: sampled_passive_bound(free, "kv", loop=loop, lo=0.0, hi=5000.0),
                repeat=1 if quick else 3)  # fmt: skip
    rows = []
    for task, t, what in (
        ("sampled check, cascaded PI force + impedance loop (issue 22)", t_c,
         f"verdict {t_c.result.outcome.value}"),
        ("sampled bound kv in 0:5000, cascaded design (issue 22)", t_b,
         f"largest passive kv {t_b.result.max_passive:.6g}"),
    ):  # fmt: skip
        ok = "meets" if t.seconds <= CASCADE_TARGET_S else "MISSES"
        rows.append(
            Row(task, "one minimal controller realization", 1 / t.seconds,
                "C_A, C_L as two filters (before issue 22)", float("nan"),
                f"{t.seconds:.2f} s CPU ({ok} the {CASCADE_TARGET_S:g} s target); {what}; "
                "the two-filter realization gave 'unstable' and a bound that ran 13 min "
                "without an answer (issue 22 report)")
        )  # fmt: skip
    return rows


def run(quick: bool) -> tuple[list[Row], list[str]]:
    rows: list[Row] = []
    notes: list[str] = []
    repeat = 3 if quick else 7
    # one check, cold caches for the plant (a new kd each time would hit the plant cache,
    # a new b1 does not)
    count = iter(range(1000))

    def fresh_check() -> bool:
        b1 = 30.0 + next(count) * 1e-6
        sea = SEA(
            D1="k1 + b1*s", CA="kd + bd*s", values={**RIG, "b1": b1, "bd": 25.0, "kd": 2000.0}
        )
        return sampled_passivity(sea, loop=SampledLoop(period=0.002)).passive

    fresh_check()  # imports outside the timing
    t_new = timed(fresh_check, repeat=repeat)
    job = {"kind": "check", "elements": {"D1": "k1 + b1*s", "CA": "kd + bd*s"},
           "values": {**RIG, "bd": 25.0, "kd": 2000.0}}  # fmt: skip
    old = _old(job)
    rows.append(
        Row("sampled check, README design (cold plant cache)", "certified verdict (in process)",
            1 / t_new.seconds, "previous seapass (in process)",
            float("nan") if old is None else 1 / old[0],
            f"{t_new.seconds * 1e3:.1f} ms vs "
            + ("n/a" if old is None else f"{old[0] * 1e3:.0f} ms; same verdict: {old[1] == t_new.result}"))
    )  # fmt: skip
    for name, (elements, gains, loop, (lo, hi)) in BOUNDS.items():
        sea = SEA(**elements, values={**RIG, **gains, "kd": None})
        t_b = timed(lambda sea=sea, loop=loop, lo=lo, hi=hi: sampled_passive_bound(
            sea, "kd", loop=SampledLoop(period=0.002, **loop), lo=lo, hi=hi), repeat=1 if quick else 3)  # fmt: skip
        r = t_b.result
        job = {"kind": "bound", "elements": elements, "values": {**RIG, **gains, "kd": None},
               "lo": lo, "hi": hi, "loop": loop}  # fmt: skip
        old = _old(job)
        note = f"{t_b.seconds:.2f} s vs " + ("n/a" if old is None else f"{old[0]:.2f} s")
        if r.edges:
            note += f"; edge in [{r.edges[0].lo:.10g}, {r.edges[0].hi:.10g}]"
        if old is not None:
            note += f"; old largest passive kd {old[1]:.6g}"
        rows.append(
            Row(f"sampled bound, {name}", "certified branch and bound (rtol 1e-9)", 1 / t_b.seconds,
                "previous scan + bisection (17 points, rtol 1e-6)",
                float("nan") if old is None else 1 / old[0], note)
        )  # fmt: skip
    rows += cascade_rows(quick)
    new_cli = _beyond_startup(Path(sys.executable), repeat)
    old_cli = _beyond_startup(OLD / ".venv" / "bin" / "python", repeat)
    if new_cli is not None:
        rows.append(
            Row("`seapass sampled check` beyond CLI start-up (CPU)", "certified", 1 / max(new_cli, 1e-4),
                "previous", float("nan") if old_cli is None else 1 / max(old_cli, 1e-4),
                f"{new_cli * 1e3:.0f} ms vs " + ("n/a" if old_cli is None else f"{old_cli * 1e3:.0f} ms")
                + f" (CPU of a second `main(argv)` with a new plant in a fresh interpreter, best of {repeat})")
        )  # fmt: skip
    notes.append(
        "Sampled-data rows: rates are calls per CPU second; the peer is the previous seapass "
        f"({OLD}), whose verdict on slow-pole designs was decided by rounding noise (issue 11)."
    )
    return rows, notes
