"""What goes on the hardware: the deployed controller of a design and its passivity envelope.

[`plan_deployment`][seapass.export.deployment.plan_deployment] turns a [`Design`][seapass.model.design_file.Design] into a
[`Deployment`][seapass.export.deployment.Deployment]: the exact difference equations the rig runs
([`realization`][seapass.export.realization]: actuator-side and load-side parts of the
Python controller, velocity filter included), the force saturation, the delay
line, and the envelope they were certified for ([`envelope`][seapass.export.envelope]:
period, delay, filter, gains and, when runtime gain changes are enabled, the
certified interval of each tunable gain).  Code generators only format a
``Deployment``; every decision is made here, exactly, before any file is written.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from ..errors import NotPassiveError, ParameterError
from ..files.limits import check_rtol
from ..model.design_file import Design
from ..model.loop import LoopAttributes, SampledLoop
from ..progress import ProgressLike, as_progress
from ..sampled.controllers import DiscreteController, filter_pole
from .envelope import GainEnvelope, certify_gains, sampled_verdict
from .realization import FilterSpec, realize
from .robust_envelope import (
    DEFAULT_ENVELOPE_BUDGET,
    RobustEnvelope,
    check_envelope_options,
    robust_envelopes,
)

__all__ = ["Deployment", "plan_deployment"]


@dataclass(frozen=True, kw_only=True)
class Deployment(LoopAttributes):
    """The deployed controller of a design with the envelope it was certified for.

    Attributes
    ----------
    design : Design
    loop : SampledLoop
        The certified loop: ``period`` (a Fraction, exactly as the analysis used it),
        ``delay`` (samples from sampling to applying the command) and ``velocity_filter``
        (cut-off in Hz of the low-pass on the finite-difference velocity) are its.
    code_delay : int
        Samples of that delay realized by the generated delay line
        (``delay − hardware_delay``).
    velocity_pole : Fraction
        Its pole ``exp(−2π f_c T)`` as the controller uses it (0 = no filter).
    force_limit : float
        Commands are saturated to ``±force_limit`` (N).
    filters : tuple of FilterSpec
        The difference equations; the command is the sum of their outputs.
    gains : tuple of GainEnvelope
        Every controller gain (sorted by name) with its certified range.
    set_gains : bool
        Whether the runtime may change the tunable gains.
    certified : bool
        The sampled-data check passed (False only with ``allow_nonpassive``).
    verdict : str
        The check's one-line finding.
    notes : tuple of str
    robust : RobustEnvelope or None
        With ``robust=True``: what was certified for every plant of the box (the guards'
        gain sets, the warnings of a fallback).
    """

    design: Design
    loop: SampledLoop
    code_delay: int
    velocity_pole: Fraction
    force_limit: float
    filters: tuple[FilterSpec, ...]
    gains: tuple[GainEnvelope, ...]
    set_gains: bool
    certified: bool
    verdict: str
    notes: tuple[str, ...] = field(default=())
    robust: RobustEnvelope | None = None

    @property
    def period(self) -> Fraction:
        """Certified sampling period (s), exactly as the analysis used it."""
        return self.loop.exact_period

    @property
    def hardware_delay(self) -> int:
        return self.delay - self.code_delay

    @property
    def tunable(self) -> tuple[str, ...]:
        return tuple(g.name for g in self.gains if g.tunable)

    def nominal_gains(self) -> dict[str, float]:
        return {g.name: g.nominal for g in self.gains}

    def reference_controller(self, gains: Mapping[str, float] | None = None) -> DiscreteController:
        """The Python controller this deployment realizes (at ``gains``, default the certified)."""
        sea = self.design.sea().with_values(**dict(gains or {}))
        return DiscreteController.for_loop(sea, self.loop)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready summary (exact values as strings ``"p/q"``)."""
        return {
            "design": self.design.name,
            "period": float(self.period),
            "period_exact": str(self.period),
            "delay": self.delay,
            "code_delay": self.code_delay,
            "hardware_delay": self.hardware_delay,
            "velocity_filter": self.velocity_filter,
            "force_limit": self.force_limit,
            "certified": self.certified,
            "verdict": self.verdict,
            "set_gains": self.set_gains,
            "gains": {
                g.name: {
                    "value": g.nominal,
                    "tunable": g.tunable,
                    "interval": [g.low, g.high],
                    "interval_exact": [str(g.exact[0]), str(g.exact[1])],
                    "searched": None if g.search is None else list(g.search),
                }
                for g in self.gains
            },
            "filters": len(self.filters),
            "states": sum(f.order for f in self.filters),
            "notes": list(self.notes),
            "robust": None if self.robust is None else self.robust.to_dict(),
        }

    def in_certified_set(self, gains: Mapping[str, float]) -> bool:
        """The rule the generated ``set_gains`` enforces, in Python."""
        changed = 0
        for g in self.gains:
            v = float(gains.get(g.name, g.nominal))
            if not (g.low <= v <= g.high):
                return False
            changed += v != g.nominal
        return changed <= 1


def plan_deployment(
    design: Design,
    *,
    force_limit: float | None = None,
    hardware_delay: int = 0,
    set_gains: bool = False,
    tunable: Sequence[str] | None = None,
    allow_nonpassive: bool = False,
    rtol: float = 1e-6,
    progress: ProgressLike = None,
    robust: bool = False,
    robust_budget: int = DEFAULT_ENVELOPE_BUDGET,
    robust_fallback: str | None = None,
) -> Deployment:
    """Decide the deployed controller of ``design`` and certify its envelope.

    Parameters
    ----------
    design : Design
        Needs a ``[control] rate``; its ``delay`` and ``velocity_filter`` are
        the certified ones.
    force_limit : float, optional
        Saturation (N); default the peak force of the design's ``[rig]``.
    hardware_delay : int, default 0
        Samples of delay the platform adds by itself (e.g. a command written at
        tick ``k`` that takes effect at tick ``k + 1``); the generated delay
        line supplies the rest of the certified delay.
    set_gains : bool, default False
        Allow runtime gain changes inside the certified set.
    tunable : sequence of str, optional
        Gains the runtime may change (default: every controller gain).
    allow_nonpassive : bool, default False
        Export a design that fails the sampled-data check (marked NOT CERTIFIED).
    rtol : float
        Relative width of the edge enclosures of the per-gain intervals, certified by
        [`sampled_passive_bound`][seapass.sampled.bound.sampled_passive_bound].
    progress : Progress, optional
        Where the certification reports: one task with a step per tunable gain, each
        gain's certified bound a task inside it (default: none; ``True``/``False``
        still work for one release).
    robust : bool, default False
        Narrow the envelope to the design's ``uncertainty`` box: every gain the guards
        accept certified sampled passive (at the loop's rate, delay and velocity filter)
        for every plant of the box
        ([`robust_envelopes`][seapass.export.robust_envelope.robust_envelopes]).
    robust_budget : int, default 16
        Work of that certification: sub-intervals of each tunable gain, sub-boxes of the
        design's own check; what it leaves undecided is refused, never allowed.
    robust_fallback : {None, "pin", "nominal"}
        When a gain's value is not in its certified robust set: refuse (None), pin the gain
        to its value (``"pin"``, certified when the design is) or keep the nominal-plant
        envelope marked NOT certified for the box (``"nominal"``).

    Raises
    ------
    ParameterError
        For a design or option the export cannot honour (the message says how to fix it).
    NotPassiveError
        When the design is not passive at its sampled rate and ``allow_nonpassive`` is False.
    """
    loop = design.loop
    if loop is None:
        raise ParameterError(
            f"design {design.name!r} has no [control] rate; the exported controller needs its "
            "sampling rate: add [control] rate = 500.0 (Hz) to the design file"
        )
    check_rtol(rtol)  # before the (slow) certification
    if robust:
        check_envelope_options(robust_budget, robust_fallback)
    elif robust_budget != DEFAULT_ENVELOPE_BUDGET or robust_fallback is not None:
        raise ParameterError("robust_budget and robust_fallback need robust=True")
    period, delay = loop.period, loop.delay
    if (
        not isinstance(hardware_delay, int)
        or isinstance(hardware_delay, bool)
        or hardware_delay < 0
    ):
        raise ParameterError(
            f"hardware_delay must be a whole number of samples >= 0, got {hardware_delay!r}"
        )
    if hardware_delay > delay:
        raise ParameterError(
            f"the platform delay ({hardware_delay} samples) exceeds the certified delay ({delay}); "
            "set [control] delay in the design to the real delay and certify again"
        )
    limit = _force_limit(design, force_limit)
    names: list[str] = []
    if set_gains:
        if allow_nonpassive:
            raise ParameterError(
                "runtime gain changes need a certified design; drop allow_nonpassive"
            )
        names = list(design.gains if tunable is None else tunable)
        _check_tunable(design, names)
    elif tunable is not None:
        raise ParameterError("tunable gains need set_gains=True")
    filters = realize(design, tunable=names)  # refuses non-affine gains before the slow part
    verdict = sampled_verdict(design)
    vf = loop.velocity_filter
    if not verdict.passive and not allow_nonpassive:
        raise NotPassiveError(
            f"refusing to export {design.name!r}: not passive at {1 / period:g} Hz with delay "
            f"{delay} and velocity filter {vf or 'none'}: {verdict.detail}; lower the gains "
            "(see sampled_passive_bound) or pass allow_nonpassive=True"
        )
    shown = as_progress(progress, where="plan_deployment")
    envelopes, notes = certify_gains(design, names, rtol=rtol, progress=shown)
    box_envelope = None
    if robust:  # every plant of the box: the robust sampled gain envelope in the guards
        envelopes, box_envelope = robust_envelopes(
            design, envelopes, budget=robust_budget, fallback=robust_fallback, progress=shown
        )
    return Deployment(
        design=design,
        loop=loop,
        code_delay=delay - hardware_delay,
        velocity_pole=filter_pole(vf, period),
        force_limit=limit,
        filters=filters,
        gains=envelopes,
        set_gains=set_gains,
        certified=bool(verdict.passive),
        verdict=verdict.detail,
        notes=notes,
        robust=box_envelope,
    )


def _force_limit(design: Design, force_limit: float | None) -> float:
    if force_limit is None:
        if design.rig_file is None:
            raise ParameterError(
                f"design {design.name!r} names no [rig] to take the force limit from; "
                "give the actuator's peak force with force_limit=..."
            )
        from ..rig.rigfile import load_rig, paper_rig

        rig = paper_rig() if design.rig_file == "paper" else load_rig(design.rig_file)
        force_limit = rig.force_limit
    f = float(force_limit)
    if not (math.isfinite(f) and f > 0):
        raise ParameterError(
            f"force limit must be a positive finite force in N, got {force_limit!r}"
        )
    return f


def _check_tunable(design: Design, names: Sequence[str]) -> None:
    gains = design.gains
    if not gains:
        raise ParameterError(
            f"design {design.name!r} has no controller gains to change at runtime "
            "(C_A and C_L are numeric); export without set_gains"
        )
    if not names:
        raise ParameterError("tunable must name at least one gain")
    plant = design.plant_parameters
    for n in names:
        if n in plant:
            raise ParameterError(
                f"tunable gain {n!r} is a plant parameter of {design.name!r} (the hardware); "
                "it cannot change at runtime"
            )
        if n not in gains:
            raise ParameterError(
                f"tunable gain {n!r} is not a controller gain of {design.name!r} "
                f"(its gains: {', '.join(gains)})"
            )
    if len(set(names)) != len(names):
        raise ParameterError("tunable lists a gain twice")
