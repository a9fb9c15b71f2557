"""The passivity constraint of a tuning run: exact, at a fixed delay, or over a box of plants.

`constrained_problem` resolves a tuning problem together with the one
`PassivityConstraint` its options call for:

- ``exact``: the nominal design, decided by the exact rational test
  ([`is_passive`][seapass.analysis.passivity.is_passive]); with a sampled loop
  the tuner also requires sampled-data passivity (as before);
- ``delay``: the design has a delay factor ``exp(-NAME*s)`` with ``NAME`` given a
  value (seconds); every candidate must be passive at that delay, *certified* by
  [`delayed_passivity`][seapass.delay.passivity.delayed_passivity] (an
  ``undecided`` verdict counts as not passive).  The step response is that of the
  loop with its controller output delayed
  ([`simulate_delayed`][seapass.sim.delayed.simulate_delayed]); the problem holds the
  delay-free design (`delay_free`) and the constraint the delay;
- ``box``: uncertain plant parameters ``{name: (lo, hi)}``; every candidate must
  be passive for every plant in the box by
  [`robust_check`][seapass.robust.verdict.robust_check] (``undecided`` counts as
  not passive).  The step response is simulated at the nominal plant: the
  design's value of each uncertain parameter when it lies in the box, else the
  box's center (`nominal_values`).

A design file's loop latency ``[control] delay_time`` (the attribute `LATENCY` of its
`Design`, when the file gives one) is a delay ``exp(-delay_time*s)`` on both controllers.

The final gains are rounded for printing (`rounded_gains`) and the rounded
values are the ones verified, so a printed gain claimed passive is passive.

References
----------
.. [1] J. E. Colgate and G. Schenkel, "Passivity of a class of sampled-data
   systems: application to haptic interfaces", J. Robotic Systems 14(1), 1997.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from dataclasses import replace as dc_replace
from enum import StrEnum
from typing import TYPE_CHECKING, Any, TypeAlias

from ..analysis.passivity import PassivityResult, is_passive
from ..delay.passivity import DelayPassivityResult, delayed_passivity
from ..delay.structure import check_tau, controller_delay
from ..errors import ParameterError, SeapassError
from ..model.delayatom import model_delays
from ..model.loop import SampledLoop
from ..model.sea import SEA
from ..model.symbolic import Delay
from ..outcome import Outcome
from ..robust.box import UncertainBox, uncertain_box
from ..robust.verdict import RobustResult, robust_check

if TYPE_CHECKING:
    from ..robust.sampled_verdict import RobustSampledResult

from .problem import (
    BoxLike,
    DesignLike,
    TuningOptions,
    TuningProblem,
    design_parts,
    resolve_problem,
)

__all__ = [
    "LATENCY",
    "ConstraintKind",
    "PassivityConstraint",
    "constrained_problem",
    "delay_free",
    "gain_text",
    "nominal_values",
    "rounded_gains",
]

Verdict: TypeAlias = "PassivityResult | DelayPassivityResult | RobustResult | RobustSampledResult"

LATENCY = "delay_time"
"""The attribute of a design file's loop latency, ``[control] delay_time`` in seconds: it
multiplies both controllers by ``exp(-delay_time*s)``
([`controller_delay`][seapass.delay.structure.controller_delay])."""

DIGITS = (6, 8, 10, 12, 15, 17)
"""Significant digits tried, in order, for the printed (and verified) final gains."""


class ConstraintKind(StrEnum):
    """Which passivity test a tuning run imposes on every candidate."""

    EXACT = "exact"
    DELAY = "delay"
    BOX = "box"


@dataclass(frozen=True, kw_only=True, repr=False)
class PassivityConstraint:
    """The passivity test a candidate must pass (see the module docstring).

    Attributes
    ----------
    kind : ConstraintKind
    sea : SEA
        The design as the test sees it (with its delay factor; the tuned gains free).
    gains : tuple of str
        The tuned gains, in search order.
    delay : str or None
        The delay parameter (``kind == "delay"``).
    tau : float or None
        Its value [s].
    box : UncertainBox or None
        The uncertain parameters (``kind == "box"``).
    budget : int or None
        Budget of the certified test (ball evaluations of the delay test, boxes of the
        robust branch and bound); None: the test's default.
    loop : SampledLoop or None
        A controller given in z: the box is decided in its sampled loop by
        [`robust_sampled_check`][seapass.robust.sampled_verdict.robust_sampled_check]
        (sub-boxes, default 4; no continuous gate: the controller exists only in z).
    """

    kind: ConstraintKind
    sea: SEA
    gains: tuple[str, ...]
    delay: str | None = None
    tau: float | None = None
    box: UncertainBox | None = None
    budget: int | None = None
    loop: SampledLoop | None = None

    def design(self, x: Sequence[float]) -> SEA:
        """The design with the tuned gains set to ``x`` (the delay kept)."""
        return self.sea.with_values(**dict(zip(self.gains, (float(v) for v in x), strict=True)))

    def verdict(self, x: Sequence[float]) -> Verdict:
        """The full verdict of the constraint's test at the gains ``x``."""
        sea = self.design(x)
        if self.kind is ConstraintKind.DELAY:
            if self.budget is None:
                return delayed_passivity(sea)
            return delayed_passivity(sea, budget=self.budget)
        if self.kind is ConstraintKind.BOX and self.loop is not None:
            from ..robust.sampled_verdict import DEFAULT_SAMPLED_BUDGET, robust_sampled_check

            assert self.box is not None
            return robust_sampled_check(
                sea, loop=self.loop, box=self.box, continuous_gate=False,
                budget=DEFAULT_SAMPLED_BUDGET if self.budget is None else self.budget,
            )  # fmt: skip
        if self.kind is ConstraintKind.BOX:
            assert self.box is not None
            if self.budget is None:
                return robust_check(sea, box=self.box)
            return robust_check(sea, box=self.box, budget=self.budget)
        return is_passive(sea)

    def passive(self, x: Sequence[float]) -> bool:
        """True only for a proven ``passive``: undecided and errors count as not passive."""
        try:
            return self.verdict(x).outcome is Outcome.PASSIVE
        except (SeapassError, ArithmeticError, ValueError):
            return False

    @property
    def label(self) -> str:
        """``"exact"``, ``"certified at tau = 0.001 s"``, ``"certified for m in [0.9, 1.1]"``."""
        if self.kind is ConstraintKind.DELAY:
            return f"certified at {self.delay} = {self.tau:g} s"
        if self.kind is ConstraintKind.BOX and self.box is not None:
            span = ", ".join(f"{k} in [{a:g}, {b:g}]" for k, (a, b) in self.box.intervals.items())
            where = (
                "" if self.loop is None else f" in the sampled loop at T = {self.loop.period:g} s"
            )
            return f"certified{where} for every plant with {span}"
        return "exact"

    def to_dict(self) -> dict[str, Any]:
        """``{"kind", "delay", "tau", "box"}``, JSON-ready."""
        return {
            "kind": str(self.kind),
            "delay": self.delay,
            "tau": self.tau,
            "box": None if self.box is None else self.box.to_dict(),
        }

    def __repr__(self) -> str:
        return f"PassivityConstraint(kind={str(self.kind)!r}, label={self.label!r})"


def delay_free(sea: SEA) -> SEA:
    """``sea`` with every delay factor ``exp(-NAME*s)`` replaced by 1 (the delay's value dropped).

    Examples
    --------
    >>> sea = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=1, k1=100, kd=5, tau=0.01))
    >>> delay_free(sea).CA
    kd
    """
    names = set(model_delays(sea))
    if not names:
        return sea
    parts = {}
    for attr, expr in sea.elements().items():
        parts[attr] = expr.xreplace({d: 1 for d in expr.atoms(Delay)})
    values = {k: v for k, v in sea.values.items() if k not in names}
    return SEA(**parts, values=values, name=sea.name, plant=sea.plant)


def nominal_values(
    sea: SEA, box: Mapping[str, tuple[float, float]], given: Mapping[str, float]
) -> dict[str, float]:
    """The plant simulated under a box: each uncertain parameter's value in the design when
    it lies in its interval, else the interval's center."""
    out = {}
    for name, (lo, hi) in box.items():
        v = given.get(name, sea.values.get(name))
        out[name] = float(v) if v is not None and lo <= v <= hi else (lo + hi) / 2
    return out


def constrained_problem(
    design: DesignLike,
    tune: BoxLike | None = None,
    options: TuningOptions | None = None,
    values: Mapping[str, float] | None = None,
    *,
    allow_plant: bool = False,
    uncertain: Mapping[str, Any] | None = None,
    budget: int | None = None,
) -> tuple[TuningProblem, PassivityConstraint]:
    """A validated tuning problem (for the simulation) and its passivity constraint.

    Parameters
    ----------
    design, tune, options, values, allow_plant
        As for [`resolve_problem`][seapass.tuning.problem.resolve_problem].  A delay
        parameter is never a default gain and cannot be tuned; it needs a value.
    uncertain : mapping of str to (lo, hi), optional
        Uncertain plant parameters: the constraint holds for every plant in the box.
    budget : int, optional
        Budget of the certified test (see `PassivityConstraint`).

    Raises
    ------
    ParameterError
        Naming the argument: a tuned delay, a negative delay, a box on an unknown or tuned
        name or one also given in ``values``, ``lo > hi``, a box or a delay together with
        a sampled loop, a box on a delayed design, a bad budget.
    """
    if budget is not None and (
        isinstance(budget, bool) or not isinstance(budget, int) or budget < 1
    ):
        raise ParameterError(
            f"budget must be a positive integer, got {budget!r}", argument="budget"
        )
    opts = options or TuningOptions()
    _, sea0, defaults, _ = design_parts(design)
    delays = model_delays(sea0)
    wanted: Any = tune
    if delays:
        if tune is None:
            wanted = tuple(g for g in defaults if g not in delays)
        else:
            for name in [tune] if isinstance(tune, str) else tune:
                if name in delays:
                    raise ParameterError(
                        f"tune[{name!r}]: {name} is the delay of exp(-{name}*s), not a gain; give "
                        f"it a value, e.g. values={{{name!r}: 0.001}}",
                        argument=f"tune[{name!r}]",
                    )
    box = None
    given = dict(values or {})
    if uncertain is not None:
        box = uncertain_box(sea0, uncertain)
        tuned = set(wanted) if wanted is not None and not isinstance(wanted, str) else set(defaults)
        for name in box.names:
            if name in given:
                raise ParameterError(
                    f"box[{name!r}]: {name} is uncertain, so its value (values[{name!r}]) would "
                    "be ignored; give one or the other",
                    argument="box",
                )
            if name in tuned:
                raise ParameterError(
                    f"box[{name!r}]: {name} is tuned; a tuned gain cannot also be uncertain",
                    argument="box",
                )
        given.update(nominal_values(sea0, box.intervals, given))
    problem = resolve_problem(design, wanted, opts, given or None, allow_plant=allow_plant)
    loop = problem.options.loop
    latency = getattr(design, LATENCY, None)  # a design file's [control] delay_time
    if latency and not delays:  # the loop latency delays both controllers
        delays = (LATENCY,)
        delayed = controller_delay(problem.sea, LATENCY).with_values(**{LATENCY: latency})
        problem = dc_replace(problem, sea=delayed)
    if delays:
        if box is not None:
            raise ParameterError(
                "box: a box of uncertain plants on a delayed design is not supported; tune "
                "at the delay or over the box"
            )
        (name,) = delays
        tau = float(check_tau(problem.sea.values[name], name))
        if loop is not None:
            raise ParameterError(
                f"a continuous delay exp(-{name}*s) and a sampled-data loop together "
                "are not supported; give one (loop=None for the continuous delay)",
                argument="loop",
            )
        constraint = PassivityConstraint(
            kind=ConstraintKind.DELAY, sea=problem.sea, gains=problem.gains, delay=name,
            tau=tau, budget=budget,
        )  # fmt: skip
        return dc_replace(problem, sea=delay_free(problem.sea)), constraint
    zc = problem.sea.discrete
    if box is not None and zc is not None:  # a controller in z: the robust sampled verdict
        return problem, PassivityConstraint(
            kind=ConstraintKind.BOX, sea=problem.sea, gains=problem.gains, box=box,
            budget=budget, loop=loop or SampledLoop(rate=float(zc.rate)),
        )  # fmt: skip
    if box is not None:
        if loop is not None:
            raise ParameterError(
                "sampled-data passivity over a box of uncertain plants is not supported by "
                "tune; drop the sampled loop (loop=None) or the box",
                argument="loop",
            )
        return problem, PassivityConstraint(
            kind=ConstraintKind.BOX, sea=problem.sea, gains=problem.gains, box=box, budget=budget
        )
    return problem, PassivityConstraint(
        kind=ConstraintKind.EXACT, sea=problem.sea, gains=problem.gains
    )


def gain_text(value: float) -> str:
    """The shortest ``g`` text that reads back as exactly ``value``.

    >>> gain_text(1234.5), gain_text(0.1 + 0.2), gain_text(1000.0)
    ('1234.5', '0.30000000000000004', '1000')
    """
    for digits in range(6, 18):
        text = f"{value:.{digits}g}"
        if float(text) == value:
            return text
    return repr(value)


def rounded_gains(
    x: Sequence[float],
    bounds: Sequence[tuple[float, float]],
    passive: Any,
) -> list[float]:
    """``x`` rounded to the fewest significant digits (`DIGITS`) that keep ``passive(x)`` true.

    The printed gains are these rounded values and they are the ones verified, so a
    printed gain claimed passive is passive.  When no rounding passes (the search's own
    gains failed, say), ``x`` is returned unchanged.
    """
    for digits in DIGITS:
        r = [
            min(max(float(f"{v:.{digits}g}"), lo), hi)
            for v, (lo, hi) in zip(x, bounds, strict=True)
        ]
        if r == list(x) or passive(tuple(r)):
            return r
    return [float(v) for v in x]
