"""Batch settling times vs python-control ``step_info``/``step_response``/``forced_response`` loops."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from _util import Row, fmt_rate, rate, timed
from seapass.batch.step_metrics import batch_step_metrics, compile_step_response
from seapass.model.sea import SEA

PROPOSED = SEA(
    D1="k1 + b1*s",
    CA="kd + bd*s",
    values=dict(m=1.0, b=10.0, k1=1000.0, b1=None, kd=None, bd=None),
    name="proposed design",
)
STEP, HORIZON, LOAD = 0.5, 5.0, 10.0


def _designs(n: int, seed: int) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    return {
        "b1": rng.uniform(5.0, 200.0, n),
        "kd": rng.uniform(100.0, 5000.0, n),
        "bd": rng.uniform(5.0, 200.0, n),
    }


def _closed_loops(vals: dict[str, np.ndarray]) -> list[Any]:
    """X_L/Θ of each design as a python-control transfer function (built outside timing)."""
    import control

    kernel = compile_step_response(PROPOSED, tuple(vals))
    n = next(iter(vals.values())).size
    cols = [vals[p] for p in kernel.params[:-1]] + [np.full(n, LOAD)]
    coef, _ = kernel.bank.evaluate(cols, n)
    nb = kernel.num_deg + 1
    out = []
    for i in range(n):
        num = coef[:nb, i][::-1]
        den = coef[nb:, i][::-1]
        out.append(control.tf(num, den))
    return out


def _peer_step_info(systems: list[Any], dt: float) -> list[float]:
    import control

    T = np.linspace(0.0, HORIZON, round(HORIZON / dt) + 1)
    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for sys in systems:
            info = control.step_info(STEP * sys, T, SettlingTimeThreshold=0.02)
            out.append(float(info["SettlingTime"]))
    return out


def _peer_forced(systems: list[Any], dt: float) -> list[float]:
    import control

    T = np.linspace(0.0, HORIZON, round(HORIZON / dt) + 1)
    U = np.full(T.size, STEP)
    out = []
    for sys in systems:
        y = control.forced_response(sys, T, U).outputs
        outside = np.nonzero(np.abs(y - STEP) > 0.02 * abs(STEP))[0]
        last = outside[-1] if outside.size else -1
        out.append(math.nan if last == T.size - 1 else float(T[last + 1]) if last >= 0 else 0.0)
    return out


def run(quick: bool) -> tuple[list[Row], list[str]]:
    n_batch = 4_000 if quick else 40_000
    n_peer = 8 if quick else 40
    vals = _designs(n_batch, 0)
    batch_step_metrics(PROPOSED, {k: v[:4] for k, v in vals.items()}, load_mass=LOAD)
    t_b = timed(
        lambda: batch_step_metrics(PROPOSED, vals, load_mass=LOAD, step=STEP, horizon=HORIZON),
        repeat=2 if quick else 1,
    )
    res = t_b.result
    sub = {k: v[:n_peer] for k, v in vals.items()}
    systems = _closed_loops(sub)
    rows: list[Row] = []
    notes: list[str] = []
    ours_ts = res.settling_time.reshape(-1)[:n_peer]
    for label, fn, dt in (
        ("control.step_info loop, dt = 1 ms", _peer_step_info, 1e-3),
        ("control.step_info loop, dt = 0.1 ms", _peer_step_info, 1e-4),
        ("control.forced_response loop, dt = 0.1 ms", _peer_forced, 1e-4),
    ):
        t_p = timed(lambda fn=fn, dt=dt: fn(systems, dt))
        peer_ts = np.array(t_p.result, dtype=float)
        both = np.isfinite(peer_ts) & np.isfinite(ours_ts)
        diff = float(np.max(np.abs(peer_ts[both] - ours_ts[both]))) if both.any() else math.nan
        rows.append(
            Row(
                task=f"2 % settling time, {HORIZON:g} s horizon, m_L = {LOAD:g} kg",
                ours=f"batch_step_metrics, {n_batch:,} designs (0.1 ms precision)",
                ours_rate=rate(n_batch, t_b.seconds),
                peer=f"{label}, {n_peer} designs",
                peer_rate=rate(n_peer, t_p.seconds),
                note=f"largest absolute difference {diff * 1e3:.3f} ms over {int(both.sum())} "
                "settled designs (the peer's grid step bounds it)",
            )
        )
    notes.append(
        f"Batch settling metrics: {int(res.settled.sum())} of {n_batch:,} designs settled, "
        f"{int((~res.modal).sum())} needed the scalar fallback; "
        f"{fmt_rate(rate(n_batch, t_b.seconds))} including final error and overshoot."
    )
    return rows, notes
