"""The result of a step-response tune: `TuningResult`.

Its ``metrics`` and ``objective`` are those of the worst load mass when the run judged
candidates on several masses (``options.masses``); ``per_mass`` holds the objective and
metrics at every mass.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ..analysis.passivity import PassivityResult
from ..model.display import Shown, html_card, short_repr
from ..model.sea import SEA
from ..outcome import Outcome
from ..sampled.passivity import SampledPassivityResult
from ..sim.metrics import TrackingMetrics, overshoot_text
from .constraints import PassivityConstraint, Verdict
from .masses import MassRun, step_run
from .problem import Objective, ResolvedTuning

__all__ = ["TuningResult"]


@dataclass(frozen=True, repr=False, kw_only=True)
class TuningResult:
    """Outcome of `tune`.

    Attributes
    ----------
    design : str
        The design's name.
    gains : mapping of str to float
        The tuned gains.
    objective : float
        The objective at the gains, verified at ``options.dt_verify``: the
        settling time (s) or ITAE (m·s²), see ``options.objective``; the worst over the
        load masses ``options.masses`` when there are several.
    outcome : Outcome
        Exact continuous-time verdict at the gains (``passive`` is ``outcome.passive``).
    sampled_outcome : Outcome or None
        Certified verdict under sampled-data control in ``options.loop`` (None without a
        loop; ``sampled_passive`` is its ``passive``).
    feasible : bool
        Passive (and sampled-passive) and within the force and overshoot limits.
    violations : tuple of str
        What is not met: ``"passivity"``, ``"sampled passivity"``, ``"force limit"``,
        ``"overshoot"``.
    on_bound : mapping of str to str
        Gains within 1 % of an edge of their box (``"lower"`` or ``"upper"``).
    metrics : TrackingMetrics
        Of the step response at ``options.dt_verify``, at the worst load mass
        (`worst_mass`; the tuning mass when the run used one mass).
    box : mapping of str to (float, float)
        The box given (or defaulted) per gain.
    bounds : mapping of str to (float, float)
        The box actually searched (a single gain's box narrowed to its passive set).
    cost : float
        The best search cost (objective plus penalties, at ``options.dt_search``).
    evaluations, passivity_checks, sampled_checks : int
        Simulations, exact continuous and sampled passivity tests run.
    generations : int
        Generations the search ran: ``options.maxiter`` unless it converged earlier.
    sea : SEA
        The design with the tuned gains.
    options : ResolvedTuning
        With the load mass, step, horizon and digital-controller settings resolved.
    passivity, sampled : PassivityResult, SampledPassivityResult or None
        The verdicts in full (``passivity``: the constraint's test, certified at a delay
        or over a box, see `constraint`).
    warnings : tuple of str
        One sentence per gain on a bound and per violated limit.
    constraint : PassivityConstraint or None
        The passivity constraint imposed (exact, at a delay, over a box).
    nominal : TuningResult or None
        Over a box: the nominal tune with the same budget (`robustness_cost`).
    per_mass : tuple of MassRun
        The objective and metrics at each load mass of ``options.masses``.
    """

    design: str
    gains: Mapping[str, float]
    objective: float
    outcome: Outcome
    sampled_outcome: Outcome | None
    feasible: bool
    violations: tuple[str, ...]
    on_bound: Mapping[str, str]
    metrics: TrackingMetrics
    box: Mapping[str, tuple[float, float]]
    bounds: Mapping[str, tuple[float, float]]
    cost: float
    evaluations: int
    passivity_checks: int
    sampled_checks: int
    generations: int = 0
    sea: SEA = field(repr=False)
    options: ResolvedTuning = field(repr=False)
    passivity: PassivityResult | Verdict | None = field(default=None, repr=False)
    sampled: SampledPassivityResult | None = field(default=None, repr=False)
    warnings: tuple[str, ...] = ()
    constraint: PassivityConstraint | None = field(default=None, repr=False)
    nominal: TuningResult | None = field(default=None, repr=False)
    per_mass: tuple[MassRun, ...] = ()

    @property
    def worst_mass(self) -> float:
        """The load mass [kg] with the largest objective (the tuning mass with one mass)."""
        if not self.per_mass:
            return self.options.load_mass
        return max(self.per_mass, key=lambda r: r.objective).load_mass

    @property
    def robustness_cost(self) -> float | None:
        """Objective here minus the nominal tune's (over a box, both feasible; else None)."""
        ok = self.nominal is not None and self.feasible and self.nominal.feasible
        return self.objective - self.nominal.objective if ok else None  # type: ignore[union-attr]

    @property
    def passive(self) -> bool:
        return self.outcome.passive

    @property
    def sampled_passive(self) -> bool | None:
        return None if self.sampled_outcome is None else self.sampled_outcome.passive

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``gains``, ``objective``, ``passive``, ``on_bound`` and the rest."""
        o = self.options
        return {
            "design": self.design,
            "gains": dict(self.gains),
            "objective": self.objective,
            "objective_kind": str(o.objective),
            "objective_unit": Objective(o.objective).unit,
            "passive": self.passive,
            "sampled_passive": self.sampled_passive,
            "feasible": self.feasible,
            "violations": list(self.violations),
            "on_bound": sorted(self.on_bound),
            "on_bound_edges": dict(self.on_bound),
            "box": {k: list(v) for k, v in self.box.items()},
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "cost": self.cost,
            "evaluations": self.evaluations,
            "passivity_checks": self.passivity_checks,
            "sampled_checks": self.sampled_checks,
            "generations": self.generations,
            "load_mass": o.load_mass,
            "mass_policy": str(o.mass_policy),
            "masses": list(o.masses),
            "worst_mass": self.worst_mass,
            "per_mass": [r.to_dict() for r in self.per_mass],
            "step": o.step,
            "horizon": o.horizon,
            "force_limit": o.force_limit,
            "max_overshoot": o.max_overshoot,
            "period": None if o.loop is None else o.loop.period,
            "delay": None if o.loop is None else o.loop.delay,
            "velocity_filter": None if o.loop is None else o.loop.velocity_filter,
            "seed": o.seed,
            "warnings": list(self.warnings),
            "constraint": None if self.constraint is None else self.constraint.to_dict(),
            "certified": None if self.passivity is None else str(self.passivity.outcome),
            "nominal": None if self.nominal is None else self.nominal.objective,
            "robust": None if self.nominal is None else self.objective,
            "robustness_cost": self.robustness_cost,
            **self.metrics.to_dict(),
        }

    def plot(self, *, ax: Any = None, load_masses: Any = None, **kwargs: Any) -> Any:
        """The step response at the tuned gains, simulated at ``options.dt_verify``.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure if None.
        load_masses : sequence of float, optional
            Load masses [kg], one line each (default: the masses of the run).
        **kwargs
            Passed to [`plot_step_responses`][seapass.plot.sim.plot_step_responses]
            (``title``).

        Returns
        -------
        matplotlib.axes.Axes
        """
        from ..plot.sim import plot_step_responses

        o = self.options
        masses = o.masses if load_masses is None else tuple(load_masses)
        runs = [(float(mass), *step_run(self.sea, o, float(mass))) for mass in masses]
        kwargs.setdefault("title", f"{self.design}: tuned gains")
        return plot_step_responses(runs, step=o.step, ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "TuningResult",
            {
                "design": self.design,
                "gains": dict(self.gains),
                str(self.options.objective): self.objective,
                "feasible": self.feasible,
                "passive": self.passive,
                "sampled_passive": self.sampled_passive,
                "violations": Shown(", ".join(self.violations)) if self.violations else None,
                "on_bound": dict(self.on_bound) or None,
            },
        )

    def _repr_html_(self) -> str:
        o, m = self.options, self.metrics
        verdict = "feasible" if self.feasible else "not feasible: " + ", ".join(self.violations)
        how = self.constraint.label if self.constraint else "exact"
        rows: list[tuple[str, Any]] = [
            (
                name,
                f"{value:.6g} (searched [{self.bounds[name][0]:.6g}, {self.bounds[name][1]:.6g}]"
                + (f", at the {self.on_bound[name]} edge)" if name in self.on_bound else ")"),
            )
            for name, value in self.gains.items()
        ]
        rows += [
            ("verdict", verdict),
            (f"objective ({o.objective})", f"{self.objective:.6g} {Objective(o.objective).unit}"),
            (f"passive ({how})", "yes" if self.passive else "no"),
        ]
        if self.sampled_passive is not None and o.loop is not None:
            rows.append(
                (
                    f"sampled passive (T = {o.loop.period:g} s)",
                    "yes" if self.sampled_passive else "no",
                )
            )
        settle = "-" if m.settling_time is None else f"{m.settling_time:.4g} s"
        over = overshoot_text(m.overshoot)
        if len(self.per_mass) > 1:
            rows.append(
                ("worst over m_L [kg]", ", ".join(f"{r.load_mass:g}" for r in self.per_mass))
            )
        rows += [
            (
                f"step {o.step:g} m, m_L = {self.worst_mass:g} kg",
                f"{m.status}, settles in {settle}",
            ),
            ("overshoot, peak force", f"{over}, {m.peak_force:.4g} N"),
            ("simulations", self.evaluations),
        ]
        return html_card(f"Tuning {self.design}: {verdict}", rows, note=" ".join(self.warnings))
