"""``tune --objective rendering`` on the paper's designs (LP, APD, Ours) and a cascaded design.

Ours: `tune_objective` (both searches: under exact passivity and unconstrained), counted
as candidate evaluations per CPU second, and its total CPU time in the notes.  Peer: the
same objective per candidate computed the way a python-control user would, the design's
``to_control("stiffness")`` and ``control.frequency_response`` on the same band and grid,
on candidates drawn from the same box.  The two values agree (checked, to 1e-6 relative).

Run alone with ``python benchmarks/bench_tune.py [--quick]``.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _util import Row, rate, timed
from seapass.model.design_file import load_design
from seapass.tuning import InteractionObjective, tune_objective
from seapass.tuning.problem import resolve_problem

ROOT = Path(__file__).resolve().parent.parent
BAND = (1.0, 100.0)
POINTS = 200


def _designs() -> list[tuple[str, object, str]]:
    cascaded = load_design(str(ROOT / "examples" / "cascaded_impedance.toml"))
    return [
        ("LP", "LP", "1500 + 40*s"),
        ("APD", "APD", "1500 + 40*s"),
        ("Ours", "ours", "1500 + 40*s"),
        ("cascaded (PI force loop in an impedance loop)", cascaded, "kv + bv*s"),
    ]


def _peer(design: object, target: str, n: int) -> tuple[float, float]:
    """CPU seconds of ``n`` python-control rendering errors, and the largest disagreement."""
    import control

    from seapass.tuning.objectives import ObjectiveFunction, response_at

    problem = resolve_problem(design)  # type: ignore[arg-type]
    spec = InteractionObjective(kind="rendering", target=target, band=BAND, points=POINTS)
    fn = ObjectiveFunction(spec, problem.sea, problem.gains, load_masses=(10.0,))
    rng = np.random.default_rng(0)
    xs = [[rng.uniform(*problem.box[g]) for g in problem.gains] for _ in range(n)]
    w = fn.omega
    assert fn.target_expression is not None
    t = response_at(fn.target_expression, w)

    def peer() -> list[float]:
        out = []
        for x in xs:
            sea = problem.candidate(x)
            k = control.frequency_response(sea.to_control("stiffness"), w).complex.ravel()
            out.append(float(np.max(np.abs(k - t) / np.abs(t))))
        return out

    timing = timed(peer)
    ours = [fn.rendering_error(x)[0] for x in xs]
    diff = max(abs(a - b) / max(abs(b), 1e-300) for a, b in zip(ours, timing.result, strict=True))
    return timing.seconds, diff


def run(quick: bool) -> tuple[list[Row], list[str]]:
    budget = {"maxiter": 4, "popsize": 4} if quick else {"maxiter": 20, "popsize": 8}
    n_peer = 10 if quick else 40
    rows: list[Row] = []
    notes: list[str] = []
    for label, design, target in _designs():
        spec = InteractionObjective(kind="rendering", target=target, band=BAND, points=POINTS)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t = timed(lambda d=design, s=spec: tune_objective(d, s, **budget))  # type: ignore[misc]
        r = t.result
        evals = r.constrained.evaluations + r.unconstrained.evaluations
        peer_s, diff = _peer(design, target, n_peer)
        rows.append(
            Row(
                task=f"tune --objective rendering, {label}",
                ours=f"tune_objective, {len(r.gains)} gains, {evals} candidates",
                ours_rate=rate(evals, t.seconds),
                peer=f"to_control + control.frequency_response loop, {n_peer} candidates",
                peer_rate=rate(n_peer, peer_s),
                note=f"{t.seconds:.2f} s CPU for the whole tune; error {100 * r.value:.3g} %",
            )
        )
        notes.append(
            f"`tune --objective rendering` on {label} (target `{target}`, band "
            f"{BAND[0]:g}..{BAND[1]:g} rad/s, {POINTS} points, maxiter {budget['maxiter']}, "
            f"popsize {budget['popsize']}): {t.seconds:.2f} s CPU for both searches "
            f"({r.passivity_checks} exact passivity checks, {r.sampled_checks} sampled); "
            f"worst error {100 * r.value:.3g} % under passivity, "
            f"{100 * r.unconstrained.value:.3g} % without; python-control's rendering error "
            f"agrees to {diff:.1e} relative."
        )
    return rows, notes


if __name__ == "__main__":
    rows, notes = run("--quick" in sys.argv)
    for row in rows:
        print(row)
    for n in notes:
        print(n)
