"""Our chunked sweep vs the same sweep done naively (scalar is_passive + scalar simulation)."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from _util import Row, rate, timed
from seapass.analysis.passivity import is_passive
from seapass.model.sea import SEA
from seapass.sim.metrics import tracking_metrics
from seapass.sim.simulate import Step, simulate
from seapass.sweep import GridAxis, SweepSpec, run_design_sweep

SEA_ = SEA(
    D1="k1 + b1*s",
    CA="kd + bd*s",
    values=dict(m=1.0, b=10.0, k1=1000.0, b1=50.0, kd=None, bd=None),
    name="proposed design",
)


def _naive(points: list[dict[str, float]]) -> list[tuple[bool, float | None]]:
    out = []
    for p in points:
        verdict = is_passive(SEA_, values=p).passive
        sim = simulate(SEA_, load_mass=10.0, scenario=Step(0.5), horizon=5.0, dt=1e-3, values=p)
        out.append((verdict, tracking_metrics(sim).settling_time))
    return out


def run(quick: bool) -> tuple[list[Row], list[str]]:
    steps = (100.0, 5.0) if quick else (25.0, 2.0)
    spec = SweepSpec(
        sea=SEA_,
        grid=(GridAxis("kd", 100.0, 5000.0, steps[0]), GridAxis("bd", 2.0, 200.0, steps[1])),
        chunk_size=8192,
    )
    with tempfile.TemporaryDirectory() as tmp:
        t_ours = timed(lambda: run_design_sweep(spec, Path(tmp) / "s.parquet"))
    idx, vals = spec.chunk_values(0)
    n_naive = 6 if quick else 30
    pick = np.linspace(0, idx.size - 1, n_naive).astype(int)
    points = [{k: float(v[i]) for k, v in vals.items()} for i in pick]
    t_naive = timed(lambda: _naive(points))
    n = spec.n_designs
    row = Row(
        task="sweep: verdict + margin + step metrics per design, written to Parquet",
        ours=f"seapass sweep (run_design_sweep), {n:,} designs",
        ours_rate=rate(n, t_ours.seconds),
        peer=f"naive loop (is_passive + simulate + tracking_metrics), {n_naive} designs",
        peer_rate=rate(n_naive, t_naive.seconds),
        note="single process; --scheduler local runs one worker process per core",
    )
    return [row], []
