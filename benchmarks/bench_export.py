"""Generated C controller step rate vs scipy's ``lfilter`` on the same difference equations."""

from __future__ import annotations

import tempfile

import numpy as np

from _util import Row, fmt_rate, rate, timed
from seapass.export import compile_c, equivalence_inputs, export_c, find_c_compiler
from seapass.model.design_file import parse_design

# The paper's proposal on the paper's bench: 500 Hz, one sample of delay, 50 Hz velocity filter.
OURS = {
    "name": "ours-bench",
    "model": {"D1": "k1 + b1*s", "CA": "kd + bd*s"},
    "parameters": {"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 30.0, "kd": 1000.0, "bd": 25.0},
    "control": {"rate": 500.0, "delay": 1, "velocity_filter": 50.0},
}


def run(quick: bool) -> tuple[list[Row], list[str]]:
    if find_c_compiler() is None:
        return [], ["generated C: skipped (no C compiler on PATH)"]
    design = parse_design(OURS)
    n = 1_000_000
    inputs = equivalence_inputs(n, seed=1)
    with tempfile.TemporaryDirectory() as tmp:
        exported = timed(lambda: export_c(design, tmp, force_limit=130.0))
        ctrl = compile_c(exported.result)
    dep = exported.result.deployment

    def c_run() -> np.ndarray:
        ctrl.reset()
        return ctrl.run(*inputs)

    ours = timed(c_run, repeat=5)

    from scipy.signal import lfilter

    # one scipy filter per (joint difference equation, input signal) it reads
    filters = [
        (
            sig,
            np.array([float(c) for c in f.transfer_function(sig).num]),
            np.array([float(c) for c in f.transfer_function(sig).den]),
        )
        for f in dep.filters
        for sig in f.inputs
    ]
    signal = {
        "error_A": inputs[2] - inputs[0],
        "measurement_A": -inputs[0],
        "error_L": inputs[3] - inputs[1],
        "measurement_L": -inputs[1],
    }

    def peer() -> np.ndarray:
        u = sum(lfilter(b, a, signal[sig]) for sig, b, a in filters)
        return np.clip(u, -130.0, 130.0)

    theirs = timed(peer, repeat=5)
    py = dep.reference_controller()
    m = 20_000 if quick else 100_000
    python = timed(lambda: [py.step((xa, xl), (ta, tl)) for xa, xl, ta, tl in inputs[:, :m].T])
    c_rate = rate(n, ours.seconds)
    rows = [
        Row(
            "deployed controller steps (Ours, 500 Hz, delay + filter)",
            "generated C99 (`seapass export c`), via ctypes",
            c_rate,
            "scipy.signal.lfilter, vectorized",
            rate(n, theirs.seconds),
            f"{n:,} steps; saturation and delay line included in ours only",
        )
    ]
    notes = [
        f"generated C: {1e9 / c_rate:.0f} ns per step on this machine, against "
        f"{fmt_rate(rate(m, python.seconds))} for seapass's Python `DiscreteController.step`; "
        f"`export_c` itself took {exported.seconds:.2f} s CPU (the exact sampled-data verdict "
        "dominates)."
    ]
    return rows, notes
