"""The robust gain envelope of a deployment: the guards certified for every plant of a box.

With ``export_c(..., robust=True)`` (``seapass export c --robust [RIGFILE]``) the
design's box (its ``uncertainty``: the file's ``[uncertainty]``, or a fitted rig's
intervals resolved by [`robust_box`][seapass.rig.robustbox.robust_box]) narrows
the envelope that ``seapass_ctrl_set_gains`` enforces.  A gain the guard accepts
must be passive *at the sampling rate, with the loop's delay and velocity filter*,
for every plant of the box:

* the design must be passive for every plant of the box in continuous time
  ([`robust_check`][seapass.robust.verdict.robust_check]), else the export is refused;
* each tunable gain's interval is the intersection of
  (1) its sampled-data certified interval at the nominal plant
  ([`seapass.export.envelope`][seapass.export.envelope]),
  (2) the continuous robust passive interval containing its value
  ([`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals]) and
  (3) the piece of the certified **inner** robust *sampled* set containing its value
  ([`robust_sampled_intervals`][seapass.robust.sampled_intervals.robust_sampled_intervals],
  searched inside (1) ∩ (2), the loop's delay included), ends rounded inward;
* without tunable gains (or when no gain's inner set holds its value), the design at its
  gains must be certified sampled passive for every plant of the box
  ([`robust_sampled_check`][seapass.robust.sampled_verdict.robust_sampled_check]).

The certification is slow on wide boxes; ``budget`` counts its work (sub-intervals of
each gain, sub-boxes of the design's check).  When a gain's value is not in a certified
inner piece (undecided within the budget, or a failing plant) the export is refused
(`NotPassiveError`), unless ``fallback`` accepts less:

* ``"pin"``: that gain is pinned to its value (the guard refuses any change of it), which
  is certified only when the design at its gains is certified for the box; else refused;
* ``"nominal"``: that gain keeps (1) ∩ (2), **not certified** for the box at the sampled
  rate; the deployment's `RobustEnvelope` has ``certified`` False and ``warnings``, which
  the C header, the JSON and the summary print in capitals.  Never the default.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from enum import StrEnum
from fractions import Fraction
from typing import Any

from ..errors import NotPassiveError, ParameterError
from ..exact.rounding import exact_text
from ..model.design_file import Design
from ..model.display import Shown, html_card, short_repr
from ..outcome import Outcome
from ..progress import ProgressLike, as_progress, task
from ..robust.box import UncertainBox, uncertain_box
from ..robust.intervals import robust_passive_intervals
from ..robust.pieces import text
from ..robust.sampled_intervals import DEFAULT_INTERVAL_BUDGET, RobustSampledIntervals
from ..robust.verdict import DEFAULT_BUDGET, WorstCase, robust_check
from .envelope import GainEnvelope, inward_interval

__all__ = [
    "DEFAULT_ENVELOPE_BUDGET",
    "FALLBACKS",
    "GainStatus",
    "RobustEnvelope",
    "RobustGain",
    "design_box",
    "robust_envelopes",
]

DEFAULT_ENVELOPE_BUDGET = DEFAULT_INTERVAL_BUDGET
"""Sub-intervals per tunable gain (and sub-boxes of the design's check) by default."""

FALLBACKS = ("pin", "nominal")
"""What ``fallback`` accepts when a gain's value is not in its certified robust set."""

Interval = tuple[float, float]


class GainStatus(StrEnum):
    """How a tunable gain's guard was decided."""

    CERTIFIED = "certified"
    """Inside the certified robust sampled set (every plant of the box, the real rate)."""
    PINNED = "pinned"
    """Fixed at its value (``fallback="pin"``), the design certified for the box there."""
    NOMINAL = "nominal_fallback"
    """``fallback="nominal"``: sampled rate at the nominal plant only. NOT certified."""


@dataclass(frozen=True, kw_only=True)
class RobustGain:
    """The evidence behind one tunable gain's robust guard.

    Attributes
    ----------
    name : str
    status : GainStatus
    searched : (float, float)
        The range the robust sampled set was searched in: the nominal sampled interval
        ∩ the continuous robust interval (``outer`` is relative to it).
    continuous : (float, float) or None
        The continuous robust interval containing the value (inward).
    inner, outer, undecided : tuple of (float, float)
        Of [`robust_sampled_intervals`][seapass.robust.sampled_intervals.robust_sampled_intervals].
    failing : tuple of WorstCase
        Verified failing plants (``values`` includes the gain).
    budget_used : int
    """

    name: str
    status: GainStatus
    searched: Interval
    continuous: Interval | None
    inner: tuple[Interval, ...] = ()
    outer: tuple[Interval, ...] = ()
    undecided: tuple[Interval, ...] = ()
    failing: tuple[WorstCase, ...] = ()
    budget_used: int = 0

    def to_dict(self) -> dict[str, Any]:
        return {
            "status": str(self.status),
            "searched": list(self.searched),
            "continuous": None if self.continuous is None else list(self.continuous),
            "inner": [list(iv) for iv in self.inner],
            "outer": [list(iv) for iv in self.outer],
            "undecided": [list(iv) for iv in self.undecided],
            "failing": [w.to_dict() for w in self.failing],
            "budget_used": self.budget_used,
        }


@dataclass(frozen=True, repr=False, kw_only=True)
class RobustEnvelope:
    """What ``robust=True`` certified about a deployment's guards (`robust_envelopes`).

    Attributes
    ----------
    box : UncertainBox
    certified : bool
        Every gain the guards accept is certified sampled passive for every plant of the
        box (False only with ``fallback="nominal"``).
    continuous : str
        The continuous robust verdict's finding.
    sampled : str
        How the design at its gains is certified at the sampled rate over the box.
    gains : tuple of RobustGain
    warnings : tuple of str
        Printed loudly wherever the deployment is shown.
    budget : int
    fallback : str or None
    """

    box: UncertainBox
    certified: bool
    continuous: str
    sampled: str
    gains: tuple[RobustGain, ...] = ()
    warnings: tuple[str, ...] = ()
    budget: int = DEFAULT_ENVELOPE_BUDGET
    fallback: str | None = None

    @property
    def span(self) -> str:
        """``m in [1, 1.0001], ...``: each end the shortest text reading back as its double."""
        return ", ".join(
            f"{k} in [{exact_text(a)}, {exact_text(b)}]" for k, (a, b) in self.box.intervals.items()
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "box": self.box.to_dict(),
            "certified": self.certified,
            "continuous": self.continuous,
            "sampled": self.sampled,
            "gains": {g.name: g.to_dict() for g in self.gains},
            "warnings": list(self.warnings),
            "budget": self.budget,
            "fallback": self.fallback,
        }

    def banner(self) -> list[str]:
        """Lines for the C header (the warnings first, in capitals)."""
        lines = [
            f"*** WARNING: NOT CERTIFIED FOR EVERY PLANT OF THE BOX: {w} ***" for w in self.warnings
        ]
        how = "certified" if self.certified else "NOT certified"
        lines.append(f"Robust envelope ({how}) for every plant with {self.span}:")
        lines.append(f"  continuous time: {self.continuous}")
        lines.append(f"  sampled rate: {self.sampled}")
        for g in self.gains:
            lines.append(
                f"  {g.name}: {g.status}; certified inner set {text(g.inner)}, outer "
                f"{text(g.outer)} within [{g.searched[0]:.10g}, {g.searched[1]:.10g}]"
            )
        return lines

    def __repr__(self) -> str:
        return short_repr(
            "RobustEnvelope",
            {"box": Shown(self.span), "certified": self.certified, "gains": len(self.gains)},
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [
            ("box", self.span),
            ("continuous time", self.continuous),
            ("sampled rate", self.sampled),
        ]
        rows += [(g.name, f"{g.status}: inner {text(g.inner)}") for g in self.gains]
        rows += [("WARNING", w) for w in self.warnings]
        return html_card(
            "Robust gain envelope" + ("" if self.certified else " (NOT certified)"),
            rows,
            note="Inner sets rounded inward; undecided is never passive.",
        )


def design_box(design: Design) -> UncertainBox:
    """The design's box, checked; a `ParameterError` without ``[uncertainty]``."""
    if not design.uncertainty:
        raise ParameterError(
            f"design {design.name!r} has no [uncertainty] table: add one (e.g. m = [0.9, 1.1]) "
            "or give a fitted rig's box, to bake a robust gain envelope into the guards"
        )
    return uncertain_box(design.sea(), dict(design.uncertainty))


def check_envelope_options(budget: Any, fallback: Any) -> None:
    """A `ParameterError` for a bad ``robust_budget`` or ``robust_fallback`` (before any work)."""
    from ..robust.sampled_intervals import check_budget

    try:
        check_budget(budget)
    except ParameterError as exc:
        raise ParameterError(str(exc).replace("budget", "robust_budget", 1)) from None
    if fallback is not None and fallback not in FALLBACKS:
        raise ParameterError(f"robust_fallback must be None, 'pin' or 'nominal', got {fallback!r}")


def robust_envelopes(
    design: Design,
    envelopes: Sequence[GainEnvelope],
    *,
    budget: int = DEFAULT_ENVELOPE_BUDGET,
    fallback: str | None = None,
    progress: ProgressLike = None,
) -> tuple[tuple[GainEnvelope, ...], RobustEnvelope]:
    """``envelopes`` narrowed to the certified robust sampled set of each tunable gain.

    Parameters
    ----------
    design : Design
        With a ``[control]`` loop and an ``uncertainty`` box of plant parameters.
    envelopes : sequence of GainEnvelope
        The nominal envelopes ([`certify_gains`][seapass.export.envelope.certify_gains]).
    budget : int, default 16
        Sub-intervals of each tunable gain (and sub-boxes of the design's own check),
        in ``[1, 10000]``; what is left is undecided, never allowed.
    fallback : {None, "pin", "nominal"}
        What to accept when a gain's value is not in its certified set (see the module).
    progress : Progress, optional
        One task with a step per tunable gain (and one for the design's check).

    Returns
    -------
    (tuple of GainEnvelope, RobustEnvelope)

    Raises
    ------
    ParameterError
        Without ``[uncertainty]``, a tunable gain that is also uncertain, bad options.
    NotPassiveError
        When the design is not passive for every plant of the box in continuous time, or
        its guards cannot be certified at the sampled rate and ``fallback`` does not
        accept less.

    References
    ----------
    J. E. Colgate and G. G. Schenkel, "Passivity of a class of sampled-data systems",
    J. Robotic Systems 14(1), 1997.

    Examples
    --------
    Without tunable gains the design at its gains is certified for the box:

    >>> from seapass.model.design_file import parse_design
    >>> d = parse_design({"name": "ours", "model": {"D1": "k1 + b1*s", "CA": "kd + bd*s"},
    ...     "parameters": {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 300.0, "kd": 500.0,
    ...                    "bd": 300.0},
    ...     "control": {"rate": 500.0, "delay": 1, "velocity_filter": 50.0},
    ...     "uncertainty": {"m": [0.9999, 1.0001]}})
    >>> envelopes, robust = robust_envelopes(d, (), budget=4)
    >>> robust.certified, robust.sampled.split(" (")[0]
    (True, "passive at the design's gains")
    """
    check_envelope_options(budget, fallback)
    box = design_box(design)
    sea, loop = design.sea(), design.loop
    if loop is None:
        raise ParameterError(f"design {design.name!r} has no [control] rate")
    verdict = robust_check(sea, box=box, budget=DEFAULT_BUDGET)
    if not verdict.passive:
        raise NotPassiveError(
            f"refusing a robust export of {design.name!r}: {verdict.outcome.label} for every "
            f"plant of the box ({verdict.detail}); narrow the box or lower the gains"
        )
    tunable = [e for e in envelopes if e.tunable and e.search is not None]
    shown = as_progress(progress, where="robust_envelopes")
    out: list[GainEnvelope] = []
    gains: list[RobustGain] = []
    with task(shown, "robust envelope over the box", len(tunable) + 1):
        for env in envelopes:
            if env not in tunable:
                out.append(env)
                continue
            if env.name in box.intervals:
                raise ParameterError(f"{env.name} is uncertain; it cannot also be a tunable gain")
            new, evidence = _gain(design, env, box, budget, fallback, shown)
            out.append(new)
            gains.append(evidence)
            shown.advance(1, note=f"{env.name}: {evidence.status}")
        sampled = _design_check(design, box, gains, budget, fallback)
        shown.advance(1, note="design")
    warnings = _warnings(gains, sampled)
    env_ = RobustEnvelope(
        box=box,
        certified=not warnings,
        continuous=f"{verdict.outcome.label} ({verdict.method}): {verdict.detail}",
        sampled=sampled[1],
        gains=tuple(gains),
        warnings=warnings,
        budget=budget,
        fallback=fallback,
    )
    return tuple(out), env_


def _gain(
    design: Design, env: GainEnvelope, box: UncertainBox, budget: int,
    fallback: str | None, progress: Any,
) -> tuple[GainEnvelope, RobustGain]:  # fmt: skip
    """One tunable gain: its certified robust sampled piece, or the fallback."""
    from ..robust.sampled_intervals import robust_sampled_intervals

    assert env.search is not None and design.loop is not None
    sea = design.sea()
    free = sea.with_values(**{env.name: None})
    nominal = Fraction(env.nominal)
    cont = robust_passive_intervals(free, env.name, *env.search, box=box, budget=DEFAULT_BUDGET)
    c_hit = [(Fraction(a), Fraction(b)) for a, b in cont.intervals if a <= env.nominal <= b]
    if not c_hit:  # the design is robustly passive at its value, so only rounding misses it
        c_piece = (nominal, nominal)
    else:
        c_piece = c_hit[0]
    lo, hi = max(env.exact[0], c_piece[0]), min(env.exact[1], c_piece[1])
    searched = inward_interval(lo, hi) if lo <= hi else (env.nominal, env.nominal)
    searched = (min(searched[0], env.nominal), max(searched[1], env.nominal))
    res: RobustSampledIntervals | None = None
    if searched[0] < searched[1]:
        res = robust_sampled_intervals(
            free, env.name, loop=design.loop, lo=searched[0], hi=searched[1], box=box,
            budget=budget, progress=progress,
        )  # fmt: skip
    hit = [] if res is None else [iv for iv in res.intervals if iv[0] <= env.nominal <= iv[1]]

    def evidence(status: GainStatus) -> RobustGain:
        return RobustGain(
            name=env.name,
            status=status,
            searched=searched,
            continuous=None if not c_hit else inward_interval(*c_piece),
            inner=() if res is None else res.intervals,
            outer=() if res is None else res.outer,
            undecided=() if res is None else res.undecided,
            failing=() if res is None else res.failing,
            budget_used=0 if res is None else res.budget_used,
        )

    if hit:
        a, b = Fraction(hit[0][0]), Fraction(hit[0][1])
        exact = (max(lo, a), min(hi, b))
        low, high = inward_interval(*exact)
        new = replace(env, low=min(low, env.nominal), high=max(high, env.nominal), exact=exact)
        return new, evidence(GainStatus.CERTIFIED)
    if fallback is None:
        raise NotPassiveError(_refusal(design, env, res, budget))
    if fallback == "pin":
        pinned = replace(env, low=env.nominal, high=env.nominal, exact=(nominal, nominal))
        return pinned, evidence(GainStatus.PINNED)
    exact = (lo, hi) if lo <= hi else (nominal, nominal)
    low, high = inward_interval(*exact)
    new = replace(env, low=min(low, env.nominal), high=max(high, env.nominal), exact=exact)
    return new, evidence(GainStatus.NOMINAL)


def _refusal(
    design: Design, env: GainEnvelope, res: RobustSampledIntervals | None, budget: int
) -> str:
    """Why ``env``'s value has no certified robust sampled piece, and what to do."""
    head = f"refusing a robust export of {design.name!r}: {env.name} = {env.nominal:g}"
    if res is None:
        why = (
            "leaves nothing to search: its nominal sampled interval and its continuous robust "
            "interval meet only at the value"
        )
    elif not any(a <= env.nominal <= b for a, b in res.outer):
        why = "is not sampled passive for every plant of the box (outside the certified outer set)"
    else:
        near = [iv for iv in res.undecided if iv[0] <= env.nominal <= iv[1]]
        where = f" in [{near[0][0]:.10g}, {near[0][1]:.10g}]" if near else ""
        why = (
            f"is undecided{where} for the box at the sampled rate within the budget "
            f"({res.budget_used} of {budget} sub-intervals)"
        )
    return (
        f"{head} {why}; raise robust_budget, narrow the box, or accept less with "
        "robust_fallback='pin' (the gain fixed) or robust_fallback='nominal' (not certified "
        "for the box)"
    )


def _design_check(
    design: Design, box: UncertainBox, gains: Sequence[RobustGain], budget: int,
    fallback: str | None,
) -> tuple[bool, str]:  # fmt: skip
    """The design at its gains, sampled, over the box: (certified, finding)."""
    from ..robust.sampled_verdict import MAX_SAMPLED_BUDGET, robust_sampled_check

    assert design.loop is not None
    done = [g for g in gains if g.status is GainStatus.CERTIFIED]
    if done:  # a certified gain sub-interval × box holds the design's own gains
        return True, (
            f"passive (certified) at the design's gains: {done[0].name}'s certified piece holds them"
        )
    r = robust_sampled_check(
        design.sea(), loop=design.loop, box=box, budget=min(budget, MAX_SAMPLED_BUDGET)
    )
    finding = f"{r.outcome.label} at the design's gains ({r.boxes} sub-boxes): {r.detail}"
    if r.outcome is Outcome.PASSIVE:
        return True, finding
    if fallback != "nominal":
        raise NotPassiveError(
            f"refusing a robust export of {design.name!r}: at its gains it is {finding}; raise "
            "robust_budget, narrow the box, or accept an envelope not certified for the box "
            "with robust_fallback='nominal'"
        )
    return False, finding


def _warnings(gains: Sequence[RobustGain], sampled: tuple[bool, str]) -> tuple[str, ...]:
    out = []
    if not sampled[0]:
        out.append(
            "the design at its gains is not certified at the sampled rate for every plant of "
            "the box (nominal fallback)"
        )
    for g in gains:
        if g.status is GainStatus.NOMINAL:
            out.append(
                f"the guard of {g.name} is certified at the sampled rate for the nominal plant "
                "only, not for every plant of the box (nominal fallback)"
            )
    return tuple(out)
