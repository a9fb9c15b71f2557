"""Which load masses a step-response tune is judged on, and the step response at each.

A design file lists the load masses its actuator drives (``[simulation] load_masses``);
the step-response objectives (``settling``, ``itae``) of a tune can be judged at the
single tuning mass (``tune_mass``) or as the **worst case over the listed masses**: the
objective of a candidate is its largest objective (and penalty) over the masses, so the
tuned gains are the best ones for the hardest load.  `MassPolicy` names the two choices
and `resolve_masses` turns ``TuningOptions.masses`` into the masses of a run.

`step_run` simulates one step response (with the controller output delayed for a design
with a delay on its controllers, see
[`simulate_delayed`][seapass.sim.delayed.simulate_delayed]) and `MassRun` holds the
objective and metrics of the optimum at one mass.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import TYPE_CHECKING, Any

from ..errors import ParameterError
from ..files.limits import MAX_LIST_LENGTH
from ..model.experiment import PAPER_EXPERIMENT
from ..model.expr import finite_number
from ..model.sea import SEA
from ..sim.delayed import simulate_delayed
from ..sim.metrics import TrackingMetrics, tracking_metrics
from ..sim.scenarios import Step
from ..sim.simulate import SimulationResult

if TYPE_CHECKING:
    from .problem import ResolvedTuning

__all__ = ["MassPolicy", "MassRun", "check_masses", "resolve_masses", "step_run"]


class MassPolicy(StrEnum):
    """Which load masses judge a candidate of a step-response tune."""

    WORST = "worst"
    """The worst objective over the design's load masses (default when it lists several)."""
    TUNE = "tune"
    """The single tuning mass (``load_mass``, a design file's ``tune_mass``)."""

    @classmethod
    def of(cls, masses: Sequence[float]) -> MassPolicy:
        """``worst`` for several resolved masses, ``tune`` for one."""
        return cls.WORST if len(masses) > 1 else cls.TUNE


@dataclass(frozen=True, kw_only=True)
class MassRun:
    """The step response of the tuned gains at one load mass.

    Attributes
    ----------
    load_mass : float
        kg.
    objective : float
        The objective at this mass (settling time [s] or ITAE [m·s²]).
    metrics : TrackingMetrics
        Of the step response at ``dt_verify``.
    """

    load_mass: float
    objective: float
    metrics: TrackingMetrics

    def to_dict(self) -> dict[str, Any]:
        """``{"load_mass", "objective", "status", "settling_time", ...}``, JSON-ready."""
        return {"load_mass": self.load_mass, "objective": self.objective, **self.metrics.to_dict()}


def check_masses(masses: Any) -> tuple[float, ...] | MassPolicy | None:
    """``TuningOptions.masses`` checked: None, a `MassPolicy` or a tuple of positive masses.

    Examples
    --------
    >>> check_masses("worst"), check_masses([25, 1.0])
    (<MassPolicy.WORST: 'worst'>, (25.0, 1.0))
    """
    if masses is None or isinstance(masses, MassPolicy):
        return masses
    if isinstance(masses, str):
        try:
            return MassPolicy(masses.lower())
        except ValueError:
            choices = ", ".join(p.value for p in MassPolicy)
            raise ParameterError(
                f"masses must be one of {choices} or a list of load masses [kg], got {masses!r}",
                argument="masses",
            ) from None
    try:
        items = list(masses)
    except TypeError:
        raise ParameterError(
            f"masses: expected 'worst', 'tune' or a list of load masses [kg], got {masses!r}",
            argument="masses",
        ) from None
    if not 1 <= len(items) <= MAX_LIST_LENGTH:
        raise ParameterError(
            f"masses: give 1 to {MAX_LIST_LENGTH} load masses, got {len(items)}",
            argument="masses",
        )
    return tuple(finite_number(m, "masses", positive=True) for m in items)


def resolve_masses(
    masses: Sequence[float] | str | None,
    *,
    load_mass: float,
    given_mass: bool,
    listed: Sequence[float] | None,
) -> tuple[float, ...]:
    """The load masses a run judges candidates on (the worst case when several).

    Parameters
    ----------
    masses : sequence of float, MassPolicy or None
        The option (checked by `check_masses`): explicit masses, ``worst`` (the design's ``listed`` masses, else the
        paper's experiment's 1, 10, 25 kg), ``tune`` (``load_mass`` only) or None: the
        worst case when the design lists several masses and no ``load_mass`` was given
        (``given_mass``), else ``load_mass``.
    load_mass : float
        The resolved tuning mass.
    listed : sequence of float or None
        The design file's ``load_masses`` (None: not a design file).

    Examples
    --------
    >>> resolve_masses(None, load_mass=10.0, given_mass=False, listed=(1.0, 10.0, 25.0))
    (1.0, 10.0, 25.0)
    >>> resolve_masses(MassPolicy.TUNE, load_mass=10.0, given_mass=False, listed=(1.0, 25.0))
    (10.0,)
    """
    masses = check_masses(masses)
    if isinstance(masses, tuple):
        return masses
    if masses is MassPolicy.TUNE:
        return (load_mass,)
    if masses is MassPolicy.WORST:
        return tuple(float(m) for m in (listed or PAPER_EXPERIMENT.load_masses))
    if listed is not None and len(listed) > 1 and not given_mass:
        return tuple(float(m) for m in listed)
    return (load_mass,)


def step_run(
    sea: SEA, opts: ResolvedTuning, load_mass: float
) -> tuple[SimulationResult, TrackingMetrics]:
    """The verified step response of ``sea`` at ``load_mass`` and its metrics (``dt_verify``);
    a delay ``exp(-NAME*s)`` on the controllers delays their output."""
    res = simulate_delayed(
        sea, load_mass=load_mass, scenario=Step(opts.step), horizon=opts.horizon, dt=opts.dt_verify
    )
    return res, tracking_metrics(res, tolerance=opts.tolerance)
