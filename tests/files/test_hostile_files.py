"""Hostile design and rig files through the command line, with bounded time and memory.

Every file runs through ``seapass analyze`` (design files) or ``seapass rig
show`` / ``rig sweep`` (rig files) in ONE subprocess whose address space is
capped with ``resource.setrlimit(RLIMIT_AS, 1 GiB)``: each must end with exit
code 2 and exactly one ``error:`` line, under a per-file watchdog, and the
peak resident memory of the whole run must stay under 512 MB.  A
``MemoryError`` turned into an error line would hide a blow-up, so the
"too large to process" message counts as a failure.

The files are the attacks of issue 12 plus seeded random amplifications of
the example design and the packaged rig (a line repeated, a number blown
up, brackets nested, bytes flipped).
"""

from __future__ import annotations

import contextlib
import json
import os
import random
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cpu_budget import BLOCKED_S
from hostile import (
    no_marker,  # noqa: F401 (a fixture)
    run_cli,
)
from seapass.errors import SeapassError

REPO = Path(__file__).resolve().parents[2]
OURS = (REPO / "examples" / "ours.toml").read_text()
RIG = (REPO / "src" / "seapass" / "data" / "paper_rig.toml").read_text()

ADDRESS_SPACE = 1 << 30  # RLIMIT_AS of the subprocess
PEAK_RSS_MB = 512
CPU_BUDGET_S = 60  # CPU seconds per file (work, not wall-clock time: see cpu_budget.py)

DRIVER = r"""
import contextlib, io, json, resource, signal, sys, time
resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
cases = json.load(open(sys.argv[1]))
# all the work of this process, in CPU time: the kernel stops it beyond that
total = CPU_BUDGET_S * (len(cases) + 1)
resource.setrlimit(resource.RLIMIT_CPU, (total, total + 5))
from seapass.cli import main

class OverBudget(Exception):
    pass

def fire(signum, frame):
    raise OverBudget()

class Blocked(Exception):
    pass

def blocked(signum, frame):
    raise Blocked()

signal.signal(signal.SIGPROF, fire)
signal.signal(signal.SIGALRM, blocked)
results = []
for argv in cases:
    err = io.StringIO()
    t0 = time.process_time()  # diagnostics only, never asserted
    signal.setitimer(signal.ITIMER_PROF, CPU_BUDGET_S)  # CPU time of this case
    # a case that waits without computing (a FIFO, a socket) spends no CPU time: an
    # hour stops it, 60 times its CPU budget, so no load on the machine can reach it
    signal.alarm(BLOCKED_S)
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            code = main(argv)
    except OverBudget:
        code = "over its CPU budget"
    except Blocked:
        code = "blocked without computing"
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.alarm(0)
    results.append({"argv": argv, "code": code, "stderr": err.getvalue(),
                    "cpu_seconds": time.process_time() - t0})
try:  # VmHWM is this process image's own peak; ru_maxrss also counts the forking parent
    status = open("/proc/self/status").read()
    peak = int(status.split("VmHWM:")[1].split()[0]) / 1024
except (OSError, IndexError, ValueError):
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({"results": results, "peak_mb": peak}))
"""


def _design_attacks(d: Path) -> dict[str, str | bytes]:
    masses = ", ".join(["1.0"] * 200_000)
    fifo = d / "fifo"
    os.mkfifo(fifo)
    return {
        "delay": OURS.replace("delay = 1 ", "delay = 1000000000 "),
        "load_masses": OURS.replace("[1.0, 10.0, 25.0]", f"[{masses}]"),
        "title_20MB": OURS.replace('title = "', 'title = "' + "x" * 20_000_000),
        "title_300": OURS.replace('title = "', 'title = "' + "x" * 300),
        "title_bell": OURS.replace('title = "', 'title = "\\u0007'),
        "nested_arrays": "a = " + "[" * 500 + "]" * 500 + "\n",
        "nested_tables": "a = " + "{b = " * 500 + "1" + "}" * 500 + "\n",
        "rig_dev_zero": OURS.replace('preset = "paper"', 'file = "/dev/zero"'),
        "rig_fifo": OURS.replace('preset = "paper"', f'file = "{fifo}"'),
        "rig_dir": OURS.replace('preset = "paper"', f'file = "{d}"'),
        "rate_tiny": OURS.replace("rate = 500.0", "rate = 1e-300"),
        "horizon_huge": OURS.replace("horizon = 10.0", "horizon = 1e12"),
        "underflow": OURS.replace("kd = 1708.0", "kd = 1e-400"),
        "int_5000_digits": OURS.replace("delay = 1 ", "delay = " + "9" * 5000 + " "),
        "lookalike_s": OURS.replace('D1 = "k1 + b1*s"', 'D1 = "k1 + b1*ｓ"'),
        "expr_3000": OURS.replace('CA = "kd + bd*s"', 'CA = "kd + bd*s' + " + s" * 1500 + '"'),
        "power_tower": OURS.replace('CA = "kd + bd*s"', 'CA = "(kd + bd*s)**12**12"'),
        "garbage": bytes(range(256)) * 64,
    }


def _rig_attacks() -> dict[str, str | bytes]:
    masses = ", ".join(["0.1"] * 2000)  # the design file has the 200,000 of the issue
    return {
        "step_counts": RIG.replace("rate = 500.0", "rate = 1000000.0")
        .replace("substeps = 10", "substeps = 10000")
        .replace("horizon = 3.0", "horizon = 10000.0"),
        "load_masses": RIG.replace("load_masses = [0.1, 0.6]", f"load_masses = [{masses}]"),
        "description_20MB": RIG.replace('description = "', 'description = "' + "y" * 20_000_000),
        "description_5000": RIG.replace('description = "', 'description = "' + "y" * 5000),
        "nested": "name = " + "[" * 500 + "]" * 500 + "\n",
        "impacts_count": RIG.replace("count = 10", "count = 1000000000"),
        "garbage": bytes(range(255, -1, -1)) * 64,
    }


def _amplified(text: str, rng: random.Random) -> str:
    """One seeded hostile edit of a valid file."""
    lines = text.splitlines()
    i = rng.randrange(len(lines))
    kind = rng.choice(["repeat", "blow_up", "nest", "flip"])
    if kind == "repeat":
        lines[i:i] = [lines[i]] * rng.choice([2, 1000, 30_000])
    elif kind == "blow_up":
        lines[i] = (
            lines[i].split("=")[0] + "= " + rng.choice(["1e308", "1e-400", "9" * 400, "-1e300"])
        )
    elif kind == "nest":
        depth = rng.choice([9, 100, 3000])
        lines[i] = lines[i].split("=")[0] + "= " + "[" * depth + "1" + "]" * depth
    else:
        raw = bytearray("\n".join(lines).encode())
        for _ in range(rng.randrange(1, 20)):
            raw[rng.randrange(len(raw))] = rng.randrange(256)
        return raw.decode("latin-1")
    return "\n".join(lines) + "\n"


def _write(path: Path, content: str | bytes) -> Path:
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8")
    return path


def _cases(tmp: Path) -> tuple[list[list[str]], set[int]]:
    """Command lines, and the indices that may also succeed (random edits can be harmless)."""
    out = str(tmp / "out")
    cases: list[list[str]] = []
    lenient: set[int] = set()
    for name, content in _design_attacks(tmp).items():
        f = _write(tmp / f"design_{name}.toml", content)
        cases.append(["analyze", str(f), "--out", out, "--stages", "core", "--no-progress"])
    for name, content in _rig_attacks().items():
        f = _write(tmp / f"rig_{name}.toml", content)
        cases.append(["rig", "show", "--rig", str(f)])
        if name in ("step_counts", "nested", "impacts_count"):
            cases.append(["rig", "sweep", "--rig", str(f), "--no-progress"])
    for special in ("/dev/zero", str(tmp / "fifo"), str(tmp)):
        cases.append(["analyze", special, "--out", out])
        cases.append(["rig", "show", "--rig", special])
    rng = random.Random(12)
    for k in range(8):
        f = _write(tmp / f"design_random_{k}.toml", _amplified(OURS, rng))
        lenient.add(len(cases))
        cases.append(["analyze", str(f), "--out", out, "--stages", "passivity", "--no-progress"])
        f = _write(tmp / f"rig_random_{k}.toml", _amplified(RIG, rng))
        lenient.add(len(cases))
        cases.append(["rig", "show", "--rig", str(f)])
    return cases, lenient


def test_hostile_files_end_in_one_line_with_bounded_memory(tmp_path: Path) -> None:
    cases, lenient = _cases(tmp_path)
    argv_file = tmp_path / "cases.json"
    argv_file.write_text(json.dumps(cases))
    driver = (
        DRIVER.replace("ADDRESS_SPACE", str(ADDRESS_SPACE))
        .replace("CPU_BUDGET_S", str(CPU_BUDGET_S))
        .replace("BLOCKED_S", str(BLOCKED_S))
    )
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    proc = subprocess.run(
        [sys.executable, "-c", driver, str(argv_file)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    report = json.loads(proc.stdout.splitlines()[-1])
    problems = []
    for i, r in enumerate(report["results"]):
        err, code = r["stderr"], r["code"]
        lines = err.splitlines()
        ok_error = code == 2 and len(lines) == 1 and lines[0].startswith("error:")
        ok_error = ok_error and "too large to process" not in err and "internal error" not in err
        if i in lenient and code == 0 and "Traceback" not in err:
            continue
        if not ok_error:
            problems.append((r["argv"][:3], code, err[-500:]))
    assert not problems, problems
    assert report["peak_mb"] < PEAK_RSS_MB, report["peak_mb"]


def test_rig_attacks_fail_at_load_time_in_process(tmp_path: Path) -> None:
    """The same rig files, in-process: a `SeapassError` from the loader (before any run)."""
    from seapass.errors import SeapassError
    from seapass.rig.rigfile import load_rig

    for name, content in _rig_attacks().items():
        f = _write(tmp_path / f"{name}.toml", content)
        with pytest.raises(SeapassError):
            load_rig(f)


# -------------------------------------- garbage and mutated files in-process (moved from test_fuzz)


@pytest.mark.usefixtures("no_marker")
@settings(
    max_examples=100, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    text=st.one_of(
        st.text(max_size=200), st.binary(max_size=200).map(lambda b: b.decode("latin-1"))
    )
)
def test_garbage_files_through_loaders_and_cli(text, tmp_path):
    f = tmp_path / "garbage.toml"
    f.write_bytes(text.encode("utf-8", "surrogatepass"))
    from seapass.rig.rigfile import load_rig

    with contextlib.suppress(SeapassError):
        load_rig(f)
    design = pytest.importorskip("seapass.model.design_file")
    with contextlib.suppress(SeapassError):
        design.load_design(f)
    run_cli(["rig", "show", "--rig", str(f)])
