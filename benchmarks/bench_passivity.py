"""Batch exact passivity vs python-control's ``ispassive`` (LMI via cvxopt) in a loop."""

from __future__ import annotations

import warnings
from fractions import Fraction
from typing import Any

import numpy as np

from _util import Row, fmt_rate, rate, timed
from seapass.analysis.impedance import exact_rational_function
from seapass.analysis.passivity import is_passive
from seapass.batch.verdicts import batch_is_passive
from seapass.model.sea import SEA

PROPOSED = SEA(
    D1="k1 + b1*s",
    CA="kd + bd*s",
    values=dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=None, bd=None),
    name="proposed (D1 = k1 + b1 s, C_A = kd + bd s)",
)
LOAD_SIDE = SEA(
    D1="k1 + b1*s",
    CL="kd",
    values=dict(m=1.0, b=10.0, k1=1000.0, b1=None, kd=None),
    name="load-side P with damped transmission",
)


PROPOSED_NOTE = (
    " The exact verdict is right: with C_A = kd + bd s acting on the actuator position the "
    "closed loop is a network of a mass, springs and dampers, passive for all positive gains "
    "(Q(x) = m²b1 x² + b1(B − 2m kd) x + b1 kd² + (b+bd)k1² with B = (b+bd)² + b b1 + b1 bd "
    "has discriminant b1²B² − 4b1²B m kd − 4m²b1(b+bd)k1², negative whenever the middle "
    "coefficient is); python-control's LMI reports False for many of these stiff designs."
)


def _designs(sea: SEA, n: int, seed: int) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    if "bd" in sea.free_parameters:
        return {"kd": rng.uniform(0.0, 20000.0, n), "bd": rng.uniform(0.0, 200.0, n)}
    return {"b1": rng.uniform(0.0, 100.0, n), "kd": rng.uniform(0.0, 3000.0, n)}


def _tf(sea: SEA, point: dict[str, float]) -> Any:
    import control

    num, den = exact_rational_function(sea, point)
    return control.tf([float(c) for c in reversed(num)], [float(c) for c in reversed(den)])


def _control_verdict(sys: Any) -> bool | str:
    import control

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return bool(control.ispassive(sys))
    except Exception as exc:  # the peer's failures are data here
        return f"error ({type(exc).__name__})"


def run(quick: bool) -> tuple[list[Row], list[str]]:
    rows: list[Row] = []
    notes: list[str] = []
    n_batch = 200_000 if quick else 2_000_000
    n_peer = 30 if quick else 200
    for sea in (PROPOSED, LOAD_SIDE):
        vals = _designs(sea, n_batch, 0)
        batch_is_passive(sea, {k: v[:10] for k, v in vals.items()})  # compile outside the timing
        t_v = timed(lambda sea=sea, vals=vals: batch_is_passive(sea, vals, margin=False), repeat=3)
        t_m = timed(lambda sea=sea, vals=vals: batch_is_passive(sea, vals), repeat=1)
        res = t_v.result
        sub = {k: v[:n_peer] for k, v in vals.items()}
        points = [{k: float(v[i]) for k, v in sub.items()} for i in range(n_peer)]
        systems = [_tf(sea, p) for p in points]
        t_peer = timed(lambda systems=systems: [_control_verdict(s) for s in systems])
        t_exact = timed(lambda sea=sea, points=points: [is_passive(sea, values=p) for p in points])
        peer_v = t_peer.result
        ours_v = [bool(v) for v in res.passive.reshape(-1)[:n_peer]]
        disagree = [i for i in range(n_peer) if peer_v[i] != ours_v[i]]
        exact_ok = all(r.passive == o for r, o in zip(t_exact.result, ours_v, strict=True))
        r_ours = rate(n_batch, t_v.seconds)
        r_peer = rate(n_peer, t_peer.seconds)
        rows.append(
            Row(
                task=f"passivity verdicts, {sea.name}",
                ours=f"batch_is_passive, {n_batch:,} designs",
                ours_rate=r_ours,
                peer=f"control.ispassive loop, {n_peer} designs",
                peer_rate=r_peer,
                note=f"{res.n_exact} of {n_batch:,} designs needed the exact fallback; "
                f"with margins {fmt_rate(rate(n_batch, t_m.seconds))}; "
                f"scalar exact is_passive loop {fmt_rate(rate(n_peer, t_exact.seconds))}",
            )
        )
        notes.append(
            f"{sea.name}: python-control disagreed with the exact verdict on "
            f"{len(disagree)} of {n_peer} random designs"
            + (
                f" (e.g. {points[disagree[0]]}: control says {peer_v[disagree[0]]})"
                if disagree
                else ""
            )
            + f"; batch verdicts equal the scalar exact ones: {exact_ok}."
            + (PROPOSED_NOTE if sea is PROPOSED and disagree else "")
        )
    t_mem = timed(
        lambda: batch_is_passive(PROPOSED, _designs(PROPOSED, 1_000_000, 1), margin=False),
        memory=True,
    )
    notes.append(
        f"Peak traced memory of batch_is_passive on 1,000,000 designs (default chunks of "
        f"65,536, inputs and outputs included): {(t_mem.peak_bytes or 0) / 2**20:.0f} MiB."
    )
    return rows, notes


CASES: list[tuple[str, list[float], list[float], str]] = [
    (
        "stiff spring Z = k/s, k = 1e8",
        [1e8],
        [1.0, 0.0],
        "passive: a spring is lossless with a simple pole at s = 0 of positive residue k",
    ),
    (
        "lossless Z = k s/(s^2 + k), k = 1e8",
        [1e8, 0.0],
        [1.0, 0.0, 1e8],
        "passive: simple imaginary-axis poles with positive residues, Re Z(jw) = 0",
    ),
    (
        "improper Z = m s + b + k/s (m=1, b=10, k=1000)",
        [1.0, 10.0, 1000.0],
        [1.0, 0.0],
        "passive: mass, damper and spring in parallel (pole at infinity with positive residue)",
    ),
    ("static gain Z = 2", [2.0], [1.0], "passive: a damper"),
    ("static gain Z = -1", [-1.0], [1.0], "not passive: Re Z = -1 < 0"),
    (
        "Z = 1/(s + 1) - 1e-9",
        [-1e-9, 1.0 - 1e-9],
        [1.0, 1.0],
        "not passive: Re Z(jw) = 1/(1 + w^2) - 1e-9 < 0 for w > 3.2e4 rad/s",
    ),
    ("Z = (s - 1)/(s + 2)", [1.0, -1.0], [1.0, 2.0], "not passive: Re Z(0) = -1/2"),
]


_PHYS = dict(m=1.0, b=10.0)
SEA_CASES: list[tuple[str, SEA, str]] = [
    (
        "SEA load-side P, stiff spring k1 = 1e8, kd = 5e7",
        SEA(D1="k1", CL="kd", values={**_PHYS, "k1": 1e8, "kd": 5e7}),
        "passive: load-side P with a pure spring is passive exactly when 0 <= kd <= k1",
    ),
    (
        "SEA load-side P, k1 = 1e8, kd = 2e8",
        SEA(D1="k1", CL="kd", values={**_PHYS, "k1": 1e8, "kd": 2e8}),
        "not passive: kd > k1",
    ),
    (
        "SEA actuator-side PD, k1 = 1e8, kd = 5000, bd = 25",
        SEA(D1="k1", CA="kd + bd*s", values={**_PHYS, "k1": 1e8, "kd": 5000.0, "bd": 25.0}),
        "passive: mass, springs and dampers only (actuator-side PD renders kd, bd to ground)",
    ),
    (
        "SEA proposed, k1 = 1e8, b1 = 20, kd = 5000, bd = 25",
        SEA(
            D1="k1 + b1*s",
            CA="kd + bd*s",
            values={**_PHYS, "k1": 1e8, "b1": 20.0, "kd": 5000.0, "bd": 25.0},
        ),
        "passive: a passive mechanical network for all positive gains",
    ),
]


def verdict_table() -> list[str]:
    """Markdown rows: case, ours, python-control, which is right."""
    import control

    lines = []
    for name, num, den, truth in CASES:
        ours = is_passive(([Fraction(x) for x in num], [Fraction(x) for x in den]))
        peer = _control_verdict(control.tf(num, den))
        right = "ours" if peer != ours.passive else "both"
        lines.append(f"| {name} | {ours.passive} | {peer} | {right} | {truth} |")
    for name, sea, truth in SEA_CASES:
        ours = is_passive(sea)
        n, d = exact_rational_function(sea)
        sys = control.tf([float(c) for c in reversed(n)], [float(c) for c in reversed(d)])
        peer = _control_verdict(sys)
        right = "ours" if peer != ours.passive else "both"
        lines.append(f"| {name} | {ours.passive} | {peer} | {right} | {truth} |")
    return lines
