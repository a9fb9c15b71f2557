"""Certified sampled-data passivity against the previous code (before issue 11).

The peer is the old seapass (mpmath alias sums, Sturm on rounded coefficients, a 17-point
scan for bounds), run from its own checkout and virtual environment: ``SEAPASS_OLD``
(default ``/work/base``).  Without it the peer columns are empty.  Times are CPU seconds
(this process, or the child processes for the command line), so other jobs on a shared
machine do not distort them.

Short periods (issue 20, item 6): LP designs at T = 0.2-0.35 ms, where the balls need more
than 128 bits near the edge.  The peer, in the same run, is the branch and bound before
issue 20 (every undecided box split at its precision down to the tolerance, more bits only
for the leaves): the current code with the per-box escalation switched off, stopped at
``PEER_BOXES`` boxes (it would otherwise run for many minutes).
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
from seapass.sampled import boxes
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.passivity import sampled_passivity
from seapass.sampled.verdict import SampledReason

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

LP = {"D1": "k1 + b1*s", "CL": "kd"}
#: (elements, values, period, loop): the issue's design and other ordinary LP designs.
SHORT_PERIOD = {
    "issue 20: LP T = 0.25 ms, m 1, b 10, k1 1000, b1 20": (
        LP, {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 20.0}, 0.00025, {},
    ),
    "LP T = 0.2 ms, delay 1, m 2.386, b 4.96, k1 1476, b1 50.4": (
        LP, {"m": 2.386, "b": 4.96, "k1": 1476.0, "b1": 50.4}, 0.0002, {"delay": 1},
    ),
    "LP T = 0.25 ms, m 2.337, b 16.17, k1 209, b1 37.4": (
        LP, {"m": 2.337, "b": 16.17, "k1": 209.0, "b1": 37.4}, 0.00025, {},
    ),
    "LP T = 0.35 ms, delay 1, m 2.897, b 3.71, k1 3499, b1 51.1": (
        LP, {"m": 2.897, "b": 3.71, "k1": 3499.0, "b1": 51.1}, 0.00035, {"delay": 1},
    ),
    "LP T = 0.3 ms, rig m 1.02, b 10, k1 1005, b1 30": (
        LP, {**RIG}, 0.0003, {},
    ),
}  # fmt: skip
#: Boxes the peer may examine before it is stopped (its time is then a lower bound).
PEER_BOXES = 1500


_CLASSIFY = boxes._classify


def _split_only(*args: Any, **kwargs: Any) -> Any:
    """`boxes._classify` as the search before issue 20 used it: never more bits for a box."""
    outcome, reason, part = _CLASSIFY(*args, **kwargs)
    return outcome, SampledReason.NONE if reason is SampledReason.PRECISION else reason, part


def _short_period_rows(quick: bool) -> list[Row]:
    rows = []
    cases = list(SHORT_PERIOD.items())[: 2 if quick else None]
    for name, (elements, values, period, options) in cases:
        sea = SEA(**elements, values={**values, "kd": None})
        loop = SampledLoop(period=period, **options)

        def bound(sea: SEA = sea, loop: SampledLoop = loop, **kw: Any) -> Any:
            return sampled_passive_bound(sea, "kd", loop=loop, lo=0.0, hi=20000.0, **kw)

        t_new = timed(bound)
        boxes._classify = _split_only
        try:
            t_old = timed(lambda bound=bound: bound(max_boxes=PEER_BOXES))
        finally:
            boxes._classify = _CLASSIFY
        r, o = t_new.result, t_old.result
        stopped = o.budget_exhausted
        note = (f"{t_new.seconds:.2f} s vs {'> ' if stopped else ''}{t_old.seconds:.1f} s"
                + (f" (stopped at {PEER_BOXES} boxes, {len(o.undecided)} undecided)" if stopped
                   else "") + f"; largest passive kd {r.max_passive!r}")  # fmt: skip
        rows.append(
            Row(f"sampled bound kd in 0:2e4, {name}", "per-box precision (issue 20)",
                1 / t_new.seconds, "split at the working precision (before)",
                1 / t_old.seconds, note)
        )  # fmt: skip
    return rows


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
    rows += _short_period_rows(quick)
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
    notes.append(
        "Short-period rows (issue 20): the peer is the branch and bound before issue 20 in the "
        f"same process, stopped after {PEER_BOXES} boxes (its rate is then an upper bound); it "
        "spent them splitting boxes next to the edge at 128 bits, where only more bits decide."
    )
    return rows, notes
