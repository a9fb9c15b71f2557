"""What a tuned design misses: the violated constraints and limits, one sentence each.

`limit_violations` lists what keeps the verified gains from being feasible (passivity,
sampled passivity, the force and overshoot limits) and `edge_note` explains a gain
that ended on an edge of its box.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..sampled.passivity import SampledPassivityResult
from ..sim.metrics import TrackingMetrics, overshoot_text
from .problem import TuningProblem

__all__ = ["edge_note", "limit_violations"]


def edge_note(problem: TuningProblem, name: str, value: float, edge: str) -> str:
    """One sentence for a gain at an edge of its box."""
    lo, hi = problem.box[name]
    where = f"{name} = {value:.6g} is at the {edge} edge of its box [{lo:g}, {hi:g}]"
    if edge == "lower" and lo == 0:
        return f"{where}: the best design wants little or none of it"
    return (
        f"{where}: the optimum may lie beyond it; widen the box if the physics allows "
        f"(tune={{{name!r}: (lo, hi)}})"
    )


def limit_violations(
    problem: TuningProblem,
    pr: Any,
    sampled: SampledPassivityResult | None,
    met: TrackingMetrics | Mapping[float, TrackingMetrics],
) -> tuple[list[str], list[str]]:
    """Violated constraints and one sentence for each.

    ``met``: the metrics of the step response, or ``{load_mass: metrics}`` for a run over
    several load masses (a limit is violated when it is at any mass; the sentence names it).
    """
    opts = problem.options
    violations, notes = [], []
    if not pr.passive:
        violations.append("passivity")
        notes.append(f"no passive gains found in the box: the best is not passive ({pr.detail})")
    if sampled is not None and not sampled.passive:
        violations.append("sampled passivity")
        notes.append(
            f"the best gains are not passive under sampled-data control at T = {sampled.period:g} s "
            f"({sampled.detail or sampled.reason})"
        )
    runs = met if isinstance(met, Mapping) else {None: met}
    for mass, m in runs.items():
        at = "" if mass is None or len(runs) == 1 else f" at m_L = {mass:g} kg"
        if opts.force_limit is not None and m.peak_force > opts.force_limit * (1 + 1e-9):
            violations.append("force limit")
            notes.append(
                f"peak force {m.peak_force:.4g} N{at} exceeds the limit {opts.force_limit:g} N"
            )
        if m.settling_time is None:
            notes.append(
                f"the best gains do not settle within the {opts.horizon:g} s horizon{at} "
                f"({m.status}): widen the boxes, relax the limits or lengthen the horizon"
            )
        overshoot = m.overshoot or 0.0
        if opts.max_overshoot is not None and overshoot > opts.max_overshoot * (1 + 1e-9):
            violations.append("overshoot")
            notes.append(
                f"overshoot {overshoot_text(overshoot)}{at} exceeds the limit "
                f"{100 * opts.max_overshoot:g} %"
            )
    return list(dict.fromkeys(violations)), notes
