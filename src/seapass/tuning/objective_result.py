"""What `tune_objective` returns: `ObjectiveOptimum` (one optimum) and `ObjectiveTuningResult`
(the optimum under passivity, the unconstrained one and what passivity cost).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from ..analysis.freqresp import log_frequencies
from ..model.display import Shown, html_card, short_repr
from ..model.sea import SEA
from ..outcome import Outcome
from .objectives import (
    Interaction,
    InteractionObjective,
    ObjectiveFunction,
    response_at,
)
from .problem import ResolvedTuning

__all__ = ["ObjectiveOptimum", "ObjectiveTuningResult", "value_text"]


@dataclass(frozen=True, repr=False, kw_only=True)
class ObjectiveOptimum:
    """One optimum of `tune_objective` (the constrained one or the unconstrained one).

    Attributes
    ----------
    gains : mapping of str to float
        Every tuned gain (for the Z-width also the stiffness gain, at its bound).
    value : float
        The objective, verified on a grid four times denser than the search's.
    outcome, sampled_outcome : Outcome, Outcome or None
        Exact continuous verdict; certified sampled-data verdict (None without a loop).
    stable : bool
        Stable with every load mass.
    at : float or None
        The rendering objective: the frequency (rad/s) of the worst error.
    evaluations, generations : int
        Of the search that found it (0 for the constrained optimum taken as unconstrained).
    """

    gains: Mapping[str, float]
    value: float
    outcome: Outcome
    sampled_outcome: Outcome | None
    stable: bool
    at: float | None = None
    evaluations: int = 0
    generations: int = 0

    @property
    def passive(self) -> bool:
        """Passive, and sampled-passive when a loop is given."""
        return self.outcome.passive and (
            self.sampled_outcome is None or self.sampled_outcome.passive
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "gains": dict(self.gains),
            "value": _json_number(self.value),
            "passive": self.outcome.passive,
            "outcome": str(self.outcome),
            "sampled_passive": None
            if self.sampled_outcome is None
            else self.sampled_outcome.passive,
            "stable": self.stable,
            "at": self.at,
            "evaluations": self.evaluations,
            "generations": self.generations,
        }

    def __repr__(self) -> str:
        return short_repr(
            "ObjectiveOptimum",
            {"gains": dict(self.gains), "value": self.value, "passive": self.passive},
        )


def _json_number(v: float) -> float | None:
    return v if math.isfinite(v) else None


@dataclass(frozen=True, repr=False, kw_only=True)
class ObjectiveTuningResult:
    """Outcome of `tune_objective`.

    Attributes
    ----------
    design : str
    objective : InteractionObjective
    unit : str
        Of the value: ``"1"`` (relative error), ``"rad/s"`` or the stiffness gain's unit.
    constrained, unconstrained : ObjectiveOptimum
        The optimum under passivity and the one without (see the module docstring).
    passivity_cost : float
        What passivity costs in the objective (never negative); ``relative_cost`` the
        same as a fraction of the unconstrained value (None when that is 0).
    feasible : bool
        The constrained optimum is passive (and sampled-passive) and stable with every
        load mass.
    violations : tuple of str
    load_masses : tuple of float
    stiffness : str or None
        The Z-width's stiffness gain.
    box, bounds : mapping of str to (float, float)
        The box per searched gain; the box the constrained search used.
    passivity_checks, sampled_checks : int
    budget_exhausted : int
        Z-width bounds that stopped at ``max_boxes`` (their value is still proven).
    sea : SEA
        The design at the constrained optimum.
    options : ResolvedTuning
    warnings : tuple of str
    """

    design: str
    objective: InteractionObjective
    unit: str
    constrained: ObjectiveOptimum
    unconstrained: ObjectiveOptimum
    passivity_cost: float
    relative_cost: float | None
    feasible: bool
    violations: tuple[str, ...]
    load_masses: tuple[float, ...]
    stiffness: str | None = None
    box: Mapping[str, tuple[float, float]] = field(default_factory=lambda: MappingProxyType({}))
    bounds: Mapping[str, tuple[float, float]] = field(default_factory=lambda: MappingProxyType({}))
    passivity_checks: int = 0
    sampled_checks: int = 0
    budget_exhausted: int = 0
    sea: SEA = field(repr=False)
    options: ResolvedTuning = field(repr=False)
    warnings: tuple[str, ...] = ()
    function: ObjectiveFunction | None = field(default=None, repr=False, compare=False)

    @property
    def kind(self) -> Interaction:
        return Interaction(self.objective.kind)

    @property
    def gains(self) -> Mapping[str, float]:
        return self.constrained.gains

    @property
    def value(self) -> float:
        return self.constrained.value

    @property
    def passive(self) -> bool:
        return self.constrained.outcome.passive

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the constrained optimum at the top level, ``unconstrained`` and
        ``passivity_cost`` beside it."""
        o = self.options
        c = self.constrained
        return {
            "design": self.design,
            "objective_kind": str(self.kind),
            "objective": _json_number(c.value),
            "objective_unit": self.unit,
            "maximize": self.kind.maximize,
            **self.objective.to_dict(),
            "kind": str(self.kind),
            "gains": dict(c.gains),
            "passive": c.outcome.passive,
            "sampled_passive": None if c.sampled_outcome is None else c.sampled_outcome.passive,
            "stable": c.stable,
            "at": c.at,
            "feasible": self.feasible,
            "violations": list(self.violations),
            "unconstrained": self.unconstrained.to_dict(),
            "passivity_cost": _json_number(self.passivity_cost),
            "relative_passivity_cost": self.relative_cost,
            "load_masses": list(self.load_masses),
            "stiffness": self.stiffness,
            "box": {k: list(v) for k, v in self.box.items()},
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "evaluations": c.evaluations,
            "unconstrained_evaluations": self.unconstrained.evaluations,
            "generations": c.generations,
            "passivity_checks": self.passivity_checks,
            "sampled_checks": self.sampled_checks,
            "budget_exhausted": self.budget_exhausted,
            "period": None if o.loop is None else o.loop.period,
            "controller_in_z": self.sea.discrete is not None,
            "seed": o.seed,
            "maxiter": o.maxiter,
            "popsize": o.popsize,
            "warnings": list(self.warnings),
        }

    def plot(self, *, ax: Any = None, points: int = 400) -> Any:
        """The constrained and unconstrained optima's responses (rendering: ``|F_L/X_L|`` and
        the target; force bandwidth: ``|G/G(0)|`` and −3 dB; Z-width: ``|F_L/X_L|``).

        Returns
        -------
        matplotlib.axes.Axes
        """
        from ..plot.tuning import plot_objective_response

        return plot_objective_response(
            self.response(points), ax=ax, title=f"{self.design}: {self.kind}"
        )

    def response(self, points: int = 400) -> dict[str, Any]:
        """The curves behind `plot`: ``omega`` and ``{label: magnitude}``, plus the kind."""
        fn = self.function
        assert fn is not None
        lo, hi = (
            self.objective.frequency_band if self.kind is not Interaction.ZWIDTH else (0.1, 1e4)
        )
        if fn.nyquist is not None:  # a controller in z: its responses end at the Nyquist
            lo, hi = fn.omega[0], min(hi, fn.omega[-1] if self.kind is not Interaction.ZWIDTH
                                      else 0.999 * fn.nyquist)  # fmt: skip
        w = log_frequencies(lo, hi, points)
        curves: dict[str, np.ndarray] = {}
        for label, opt in (
            ("passive optimum", self.constrained),
            ("unconstrained", self.unconstrained),
        ):
            full = tuple(opt.gains[g] for g in fn.full_gains)
            if self.kind is Interaction.FORCE_BANDWIDTH:
                curve = fn.force_magnitude(full)
                curves[label] = curve(w) if callable(curve) else np.full(w.size, float(curve))
            else:
                curves[label] = np.abs(fn.stiffness_response(full, w))
        if self.kind is Interaction.RENDERING and fn.target_expression is not None:
            curves["target"] = np.abs(response_at(fn.target_expression, w))
        return {"omega": w, "curves": curves, "kind": str(self.kind), "unit": self.unit}

    def __repr__(self) -> str:
        return short_repr(
            "ObjectiveTuningResult",
            {
                "design": self.design,
                "objective": str(self.kind),
                "gains": dict(self.gains),
                "value": self.value,
                "unconstrained": self.unconstrained.value,
                "passivity_cost": self.passivity_cost,
                "feasible": self.feasible,
                "violations": Shown(", ".join(self.violations)) if self.violations else None,
            },
        )

    def _repr_html_(self) -> str:
        c, u = self.constrained, self.unconstrained
        rows: list[tuple[str, Any]] = [(k, f"{v:.6g}") for k, v in c.gains.items()]
        rows += [
            (f"{self.kind.label} (passive)", value_text(self.kind, c.value, self.unit)),
            ("unconstrained optimum", value_text(self.kind, u.value, self.unit)),
            ("passivity cost", value_text(self.kind, self.passivity_cost, self.unit)),
            (
                "passive (sampled, certified)"
                if self.sea.discrete is not None
                else "passive (exact)",
                "yes" if c.outcome.passive else "no",
            ),
            ("load masses [kg]", ", ".join(f"{m:g}" for m in self.load_masses)),
        ]
        verdict = "feasible" if self.feasible else "not feasible: " + ", ".join(self.violations)
        return html_card(f"Tuning {self.design} for {self.kind}: {verdict}", rows,
                         note=" ".join(self.warnings))  # fmt: skip


def value_text(kind: Interaction, value: float, unit: str = "") -> str:
    """The objective's value for people: a percent, rad/s (and Hz) or a stiffness."""
    if kind is Interaction.RENDERING:
        return f"{100 * value:.4g} %"
    if kind is Interaction.FORCE_BANDWIDTH:
        return f"{value:.6g} rad/s ({value / (2 * math.pi):.4g} Hz)"
    return f"{value:.6g} {unit}".strip()
