"""``rig fit LOG.csv`` reads the log through the guarded reader (issue 20, item 3).

It used to call ``Path.read_text``: a FIFO hung, ``/dev/zero`` read until memory
ran out, and a 150 MB log peaked at 1.2 GB.  Now the log streams through
`open_text_file` (only the numbers are kept) and the moments keep only int8
velocity signs of the fine grid.  Memory is measured here with tracemalloc
(allocation counts, not time); the hostile paths run in a subprocess whose
address space is capped, under CPU-time and blocked-wait watchdogs against a hang.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from cpu_budget import BLOCKED_S
from seapass.errors import FileFormatError
from seapass.files.limits import MAX_LOG_BYTES
from seapass.rig.log import RigLog, chirp_command, load_log, parse_log, twin_log
from seapass.rig.moments import (
    applied_force,
    log_moments,
    pack_windows,
    smoothed_velocity,
    stuck_samples,
    window_lengths,
)
from seapass.rig.rigfile import paper_rig

RIG = paper_rig()
UP = 8  # the moments' fine-grid points per sample


@pytest.fixture(scope="module")
def chirp() -> RigLog:
    return twin_log(RIG, chirp_command(RIG.control.rate, duration=12.0), load_mass=0.1, seed=3)


def synthetic_log(path: Path, rows: int) -> None:
    rng = np.random.default_rng(0)
    t = np.arange(rows) / RIG.control.rate
    data = np.column_stack([t, rng.normal(0, 10, (rows, 3))])
    np.savetxt(path, data, delimiter=",", fmt="%.9g", header="time,force,x_A,x_L", comments="")


def test_loading_a_log_keeps_only_the_numbers(tmp_path: Path) -> None:
    rows = 200_000
    f = tmp_path / "log.csv"
    synthetic_log(f, rows)
    text_bytes = f.stat().st_size  # about 35 bytes a row
    tracemalloc.start()
    try:
        log = load_log(f)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert log.size == rows
    numbers = rows * 4 * 8  # the four float64 columns
    # the text read whole plus a list of floats per row took > 7x the numbers (and the
    # text): now the growing buffer of numbers and the columns cut from it
    assert peak < 3 * numbers, (peak, numbers, text_bytes)
    assert np.array_equal(log.t, parse_log(f.read_text()).t)


def dense_moments(log: RigLog, length: int) -> np.ndarray:
    """The moments as first written: every signal on the whole fine grid (independent)."""
    from scipy.integrate import simpson
    from scipy.interpolate import CubicSpline

    t, h = log.t, log.period
    force = applied_force(log, RIG)
    delta = log.x_L - log.x_A
    fine = np.linspace(t[0], t[-1], (t.size - 1) * UP + 1)
    sig = {
        "x_A": CubicSpline(t, log.x_A)(fine),
        "delta": CubicSpline(t, delta)(fine),
        "sgn_A": np.sign(smoothed_velocity(t, log.x_A, fine)),
        "sgn_delta": np.sign(smoothed_velocity(t, delta, fine)),
    }
    reversal = np.zeros(fine.size, dtype=bool)
    for key in ("sgn_A", "sgn_delta"):
        reversal[1:] |= sig[key][1:] != sig[key][:-1]
    stuck = stuck_samples(log.x_A, RIG.motor_resolution) | stuck_samples(
        delta, RIG.linear_resolution
    )
    starts, sizes = pack_windows(reversal, stuck, window_lengths(length), UP)
    rows = np.zeros((starts.size, 8))
    for size in np.unique(sizes):
        pick = np.flatnonzero(sizes == size)
        n = int(size)
        T = n * h
        tau = np.arange(n * UP + 1) * (h / UP)
        phi = np.sin(np.pi * tau / T) ** 2
        d1 = (np.pi / T) * np.sin(2 * np.pi * tau / T)
        d2 = 2 * (np.pi / T) ** 2 * np.cos(2 * np.pi * tau / T)
        edges = np.arange(n + 1) * h
        hold = np.diff(edges / 2 - T / (4 * np.pi) * np.sin(2 * np.pi * edges / T))
        idx = starts[pick][:, None] * UP + np.arange(tau.size)[None, :]

        def m(w, key, idx=idx, tau=tau):
            return simpson(w[None, :] * sig[key][idx], x=tau, axis=1)

        cols = np.column_stack(
            [
                m(d2, "x_A"),
                -m(d1, "x_A"),
                m(phi, "sgn_A"),
                m(d1, "delta"),
                -m(phi, "sgn_delta"),
                np.full(pick.size, T / 2),
                force[starts[pick][:, None] + np.arange(n)[None, :]] @ hold,
                RIG.damper.k1 * m(phi, "delta"),
            ]
        )
        rows[pick] = cols / (T / 2)
    return rows


@pytest.mark.parametrize("length", [8, 16, 40])
def test_lean_moments_equal_the_dense_grid_bit_for_bit(chirp: RigLog, length: int) -> None:
    mom = log_moments(chirp, RIG, length)
    dense = dense_moments(chirp, length)
    assert mom.X.shape[0] > 30
    assert np.array_equal(mom.X, dense[:, :6])
    assert np.array_equal(mom.force, dense[:, 6]) and np.array_equal(mom.spring, dense[:, 7])


# ------------------------------------------------------------------ the command line

#: CPU seconds one hostile path may compute before the driver calls it a hang.
CPU_BUDGET_S = 60

DRIVER = r"""
import contextlib, io, json, resource, signal, sys
resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))
from seapass.cli import main

def over(signum, frame):
    raise TimeoutError("over its CPU budget")

def blocked(signum, frame):
    raise TimeoutError("blocked without computing")

signal.signal(signal.SIGPROF, over)
signal.signal(signal.SIGALRM, blocked)
cpu_s, blocked_s = json.loads(sys.argv[2])
out = []
for argv in json.loads(sys.argv[1]):
    err = io.StringIO()
    # watchdogs against a hang, not timing assertions: CPU time for work (no load on the
    # machine reaches it), an hour of wall-clock time for a wait that computes nothing
    signal.setitimer(signal.ITIMER_PROF, cpu_s)
    signal.alarm(blocked_s)
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            code = main(argv)
    except TimeoutError as exc:
        code = str(exc)
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.alarm(0)
    out.append([code, err.getvalue()])
print(json.dumps(out))
"""


def test_rig_fit_refuses_hostile_logs_in_one_line(tmp_path: Path) -> None:
    rig = tmp_path / "rig.toml"
    rig.write_text(RIG.to_toml())
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    binary = tmp_path / "bin.csv"
    binary.write_bytes(b"time,force,x_A,x_L\n0,1,2,\xff\n")
    huge = tmp_path / "huge.csv"
    with huge.open("wb") as fh:
        fh.truncate(MAX_LOG_BYTES + 1)
    cases = {
        str(fifo): "is a pipe (FIFO), not a log file",
        "/dev/zero": "is a character device, not a log file",
        str(tmp_path): "is a directory, not a log file",
        str(binary): "not a UTF-8 text file",
        str(huge): "larger than the limit of 268,435,456 bytes for a log file",
        str(tmp_path / "missing.csv"): "No such file or directory",
    }
    argvs = [["rig", "fit", path, "--rig", str(rig)] for path in cases]
    proc = subprocess.run(
        [sys.executable, "-c", DRIVER, json.dumps(argvs), json.dumps([CPU_BUDGET_S, BLOCKED_S])],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    for (path, message), (code, err) in zip(cases.items(), json.loads(proc.stdout), strict=True):
        assert code == 2, (path, code, err)
        assert err.startswith("error: ") and err.count("\n") == 1, (path, err)
        assert message in err, (path, err)


def test_library_refuses_the_same(tmp_path: Path) -> None:
    with pytest.raises(FileFormatError, match="character device"):
        load_log("/dev/zero")
