"""Passive set of one controller parameter under sampled-data control, certified.

`sampled_passive_bound` partitions a range of one controller parameter (a gain, a
time constant: anything that appears only in ``CA``/``CL``) into proven passive intervals,
proven non-passive intervals and edge enclosures of relative width at most ``rtol`` (see
[`seapass.sampled.boxes`][seapass.sampled.boxes] for the branch and bound).  No value is sampled, so an island
wider than the tolerance cannot be missed; values where the deployed controller changes
structure (``tp = 0``, ``tz = tp``, a gain of 0) are decided one by one.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from fractions import Fraction
from typing import Any

from ..errors import ParameterError, SeapassError, UnrealizableError
from ..exact.rounding import (
    decimal_down,
    enclosure_text,
    exact_text,
    float_down,
    float_up,
    interval_text,
)
from ..files.limits import check_rtol
from ..model.display import Shown, html_card, short_repr
from ..model.loop import LoopAttributes, SampledLoop, loop_argument
from ..model.sea import SEA
from ..outcome import Outcome
from ..progress import ProgressLike, as_progress, task
from .boxes import MAX_BOXES, BoxVerdict, DecidedShare, bound_boxes
from .controllers import DiscreteController, controller_parts
from .family import controller_family
from .lowfreq import low_frequency_limit
from .passivity import check_precision, check_values, sampled_passivity
from .plant import plant_key, plant_of
from .verdict import PRECISIONS, SampledReason, decide

__all__ = ["Edge", "EdgeKind", "SampledBoundResult", "intervals_text", "sampled_passive_bound"]


class EdgeKind(StrEnum):
    """What changes across an edge of a sampled passive set (the JSON value is the string)."""

    LOW_FREQUENCY = "low_frequency"
    """``N(ω) < 0`` as ``ω → 0`` on the non-passive side."""
    STABILITY = "stability"
    """The loop with the port held becomes unstable."""
    INTERIOR = "interior"
    """``N(ω) < 0`` at a frequency inside ``(0, π/T]`` (or the side is not deployable)."""
    SPECIAL = "special"
    """A single value where the deployed controller changes structure."""


@dataclass(frozen=True, kw_only=True)
class Edge:
    """Enclosure ``[lo, hi]`` of one boundary of the passive set and what changes there."""

    lo: float
    hi: float
    kind: EdgeKind

    def to_dict(self) -> dict[str, Any]:
        return {"lo": self.lo, "hi": self.hi, "kind": self.kind}


@dataclass(frozen=True, repr=False, kw_only=True)
class SampledBoundResult(LoopAttributes):
    """Certified passive values of one parameter (`sampled_passive_bound`).

    Attributes
    ----------
    intervals : tuple of (float, float)
        Proven passive intervals of doubles (closed; a degenerate ``(v, v)`` is an
        isolated value): every double in them is proven passive.  Their ends are the
        inner ends of the edge enclosures, rounded inward to doubles.
    edges : tuple of Edge
        Every boundary of the passive set, enclosed to ``rtol`` relative width (the
        enclosure rounded outward to doubles).
    undecided : tuple of (float, float)
        Sub-intervals the certification could not settle away from the edges (rounded
        outward): narrower than the tolerance, or left when the budget of boxes ran out
        (``budget_exhausted``).  Never reported passive.
    max_passive : float or None
        Largest proven passive value.
    partition : tuple of (float, float, Outcome)
        The whole range as proven boxes and leaves: ``(lo, hi, outcome)`` (proven boxes
        rounded inward, undecided ones outward).
    loop : SampledLoop
        The sampled loop (``period``, ``delay`` and ``velocity_filter`` are its).
    design_passive : bool or None
        The design value lies in a proven passive interval (None: no design value);
        `design_outcome` tells not passive from undecided.
    budget_exhausted : bool
        The branch and bound stopped at ``max_boxes`` boxes; what it had not settled is
        in ``undecided`` (never reported passive).
    """

    param: str
    loop: SampledLoop
    lo: float
    hi: float
    intervals: tuple[tuple[float, float], ...]
    max_passive: float | None
    edges: tuple[Edge, ...] = ()
    undecided: tuple[tuple[float, float], ...] = ()
    partition: tuple[tuple[float, float, Outcome], ...] = ()
    rtol: float = 1e-9
    design_value: float | None = None
    design_passive: bool | None = None
    low_frequency: str | None = None
    budget_exhausted: bool = False

    @property
    def period(self) -> float:
        return self.loop.period

    @property
    def design_outcome(self) -> Outcome | None:
        """The certified outcome at ``design_value`` (None without one).

        ``PASSIVE`` inside a proven passive interval, ``UNDECIDED`` inside an edge
        enclosure or an undecided sliver, else ``NOT_PASSIVE``.
        """
        v = self.design_value
        if v is None:
            return None
        if self.design_passive:
            return Outcome.PASSIVE
        unsure = [(e.lo, e.hi) for e in self.edges] + list(self.undecided)
        return Outcome.UNDECIDED if any(a <= v <= b for a, b in unsure) else Outcome.NOT_PASSIVE

    def to_dict(self) -> dict[str, Any]:
        return {
            "param": self.param,
            "period": self.period,
            "range": [self.lo, self.hi],
            "delay": self.delay,
            "velocity_filter": self.velocity_filter,
            "intervals": [list(iv) for iv in self.intervals],
            "max_passive": self.max_passive,
            "edges": [e.to_dict() for e in self.edges],
            "undecided": [list(iv) for iv in self.undecided],
            "rtol": self.rtol,
            "design_value": self.design_value,
            "design_passive": self.design_passive,
            "low_frequency": self.low_frequency,
            "budget_exhausted": self.budget_exhausted,
        }

    def to_csv(self) -> str:
        """The whole range as proven boxes and leaves, one per line: ``lo, hi, status``.

        The header names the parameter (``kd_lo,kd_hi,status``); numbers are
        written exactly (``repr``).
        """
        rows = "".join(f"{a!r},{b!r},{status}\n" for a, b, status in self.partition)
        return f"{self.param}_lo,{self.param}_hi,status\n{rows}"

    def plot(self, *, ax: Any = None) -> Any:
        """The certified passive intervals, edge enclosures and design value on one axis.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure if None.

        Returns
        -------
        matplotlib.axes.Axes
        """
        from ..plot.sampled import plot_bound

        return plot_bound(self, ax=ax)

    def __repr__(self) -> str:
        top = None if self.max_passive is None else Shown(decimal_down(self.max_passive, 6))
        return short_repr(
            "SampledBoundResult",
            {
                "param": self.param,
                "period": self.period,
                "delay": self.delay,
                "passive": Shown(intervals_text(self.intervals, most=2)),
                "max_passive": top,
                "undecided": len(self.undecided) or None,
                "design_passive": self.design_passive,
            },
        )

    def _repr_html_(self) -> str:
        top = "none" if self.max_passive is None else decimal_down(self.max_passive, 10)
        rows: list[tuple[str, Any]] = [
            ("range searched", f"[{self.lo:.6g}, {self.hi:.6g}]"),
            ("loop", self.loop.summary),
            ("passive (certified)", intervals_text(self.intervals, most=20)),
            ("largest passive value", top),
        ]
        rows += [
            (f"edge ({e.kind.value.replace('_', ' ')})", enclosure_text(e.lo, e.hi, digits=10))
            for e in self.edges[:20]
        ]
        if self.undecided:
            rows.append(("undecided", intervals_text(self.undecided, most=20)))
        if self.design_value is not None:
            outcome = self.design_outcome
            rows.append(
                (
                    f"design {self.param} = {exact_text(self.design_value)}",
                    "not decided" if outcome is None else outcome.label,
                )
            )
        if self.low_frequency:
            rows.append(("low frequency", self.low_frequency))
        return html_card(
            f"Sampled passive set of {self.param} at T = {self.period * 1e3:g} ms",
            rows,
            note=f"Edges enclosed to a relative width of {self.rtol:g}; no value is sampled.",
        )


def intervals_text(intervals: Sequence[tuple[float, float]], *, most: int) -> str:
    """``[a, b] ∪ [c, d]`` (6 significant digits, rounded inward), the first ``most`` and a
    count of the rest."""
    if not intervals:
        return "none"
    text = " ∪ ".join(interval_text(a, b) for a, b in intervals[:most])
    rest = len(intervals) - most
    return text + (f" ∪ {rest} more" if rest > 0 else "")


def _merge_status(
    boxes: list[BoxVerdict],
) -> list[tuple[Fraction, Fraction, Outcome, SampledReason]]:
    out: list[tuple[Fraction, Fraction, Outcome, SampledReason]] = []
    for b in boxes:
        same = out and out[-1][2] is b.outcome and out[-1][1] == b.lo
        if same and b.outcome is not Outcome.UNDECIDED:
            out[-1] = (out[-1][0], b.hi, b.outcome, out[-1][3])
        else:
            out.append((b.lo, b.hi, b.outcome, b.reason))
    return out


def _edge_kind(sea: SEA, param: str, left: float, right: float, loop: SampledLoop) -> EdgeKind:
    """Which condition flips across an edge (from certified verdicts just outside it)."""
    reasons = set()
    for v in (left, right):
        try:
            r = sampled_passivity(sea, loop=loop, values={param: v}, continuous_gate=False)
        except SeapassError:  # no deployable controller just outside the edge
            return EdgeKind.INTERIOR
        reasons.add(r.reason)
    if SampledReason.UNSTABLE in reasons:
        return EdgeKind.STABILITY
    if SampledReason.LOW_FREQUENCY in reasons:
        return EdgeKind.LOW_FREQUENCY
    return EdgeKind.INTERIOR


def sampled_passive_bound(
    sea: SEA,
    param: str,
    *,
    loop: SampledLoop | None = None,
    lo: float,
    hi: float,
    values: Mapping[str, float] | None = None,
    rtol: float = 1e-9,
    design_value: float | None = None,
    max_precision: int = PRECISIONS[-1],
    max_boxes: int = MAX_BOXES,
    progress: ProgressLike = None,
    box: Any = None,
    **old: Any,
) -> SampledBoundResult:
    """Certified passive values of the controller parameter ``param`` in ``[lo, hi]``.

    Parameters
    ----------
    sea : SEA
        The design; ``param`` must appear in ``CA`` or ``CL`` only, every other
        parameter needs a value.
    param : str
    loop : SampledLoop
        The sampled loop (period, delay, velocity filter, discretization), as in
        [`sampled_passivity`][seapass.sampled.passivity.sampled_passivity].
    lo, hi : float
        Range to partition (``lo < hi``; ``lo = 0`` is fine).
    values : mapping, optional
        Parameter values overriding those in ``sea``.
    rtol : float, default 1e-9
        Relative width of every edge enclosure, in ``[MIN_RTOL, MAX_RTOL]`` =
        ``[1e-12, 1e-2]`` ([`seapass.files.limits.check_rtol`][seapass.files.limits.check_rtol]).
    design_value : float, optional
        The design's own value: the range is widened to include it and its verdict is
        reported (it always agrees with the intervals).
    max_precision : int
        Precision cap (bits) of the balls.
    max_boxes : int, default 20000
        Budget of the branch and bound, in boxes examined (counted, not timed).  When it
        runs out, what is not settled is reported ``undecided`` (never passive) and
        ``budget_exhausted`` is set.
    progress : Progress, optional
        Where the branch and bound reports: one task of 100 steps, the percent of the
        range decided (default: none; ``True``/``False`` still work for one release).
    box : mapping, optional
        Refused: the bound over a box of plants is
        [`robust_sampled_intervals`][seapass.robust.sampled_intervals.robust_sampled_intervals].
    **old
        ``period=, delay=, velocity_filter=, method=``: the loop's old spelling, still
        accepted for one release with a
        [`SeapassDeprecationWarning`][seapass.errors.SeapassDeprecationWarning].

    Returns
    -------
    SampledBoundResult

    Examples
    --------
    >>> ours = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1005, b1=30, bd=0))
    >>> r = sampled_passive_bound(ours, "kd", loop=SampledLoop(period=0.002), lo=0, hi=2e4)
    >>> [round(x) for x in r.intervals[0]]
    [0, 10033]
    """
    if box is not None:  # robust sampled passivity lives a layer up (issue 26)
        raise ParameterError(
            "sampled_passive_bound bounds at fixed plant values; for every plant in a box use "
            "seapass.robust.robust_sampled_intervals(sea, param, box=...)",
            argument="box",
        )
    loop = loop_argument(loop, old, where="sampled_passive_bound")
    shown = as_progress(progress, where="sampled_passive_bound")
    max_precision = check_precision(max_precision)
    if isinstance(max_boxes, bool) or not isinstance(max_boxes, int) or max_boxes < 1:
        raise ParameterError(
            f"max_boxes must be a positive whole number, got {max_boxes!r}", argument="max_boxes"
        )
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ParameterError(f"need a finite range lo < hi, got [{lo}, {hi}]")
    check_rtol(rtol)
    base = sea.with_values(**(values or {}))
    if param not in base.parameters:
        raise ParameterError(
            f"parameter {param!r} does not appear in the model; it uses: "
            + ", ".join(base.parameters)
        )
    plant_params = {str(x) for k in ("m", "b", "D1", "D2") for x in getattr(base, k).free_symbols}
    if param in plant_params:
        raise ParameterError(
            f"{param} is a plant parameter; sampled_passive_bound bounds controller parameters "
            "(those in CA/CL only): use seapass.robust.robust_sampled_intervals"
        )
    if design_value is not None:
        lo, hi = min(lo, design_value), max(hi, design_value)
    base = base.with_values(**{param: None})
    if base.free_parameters != (param,):
        others = [p for p in base.free_parameters if p != param]
        raise ParameterError("sampled bound needs values for: " + ", ".join(others))
    check_values(probe := base.with_values(**{param: hi}))
    T = loop.exact_period
    plant_of(probe)
    key = plant_key(probe)
    fam = controller_family(base, param, loop)
    # the precision the point verdicts need at a few values starts the boxes
    start = PRECISIONS[0]
    for v in {lo, hi, (lo + hi) / 2, *(() if design_value is None else (design_value,))}:
        ctrl = DiscreteController.for_loop(base.with_values(**{param: v}), loop)
        ka, kl, hidden = controller_parts(ctrl, loop.delay)
        d = decide(key, ka, kl, T, max_precision=max_precision, hidden=hidden)
        start = max(start, d.precision)
    flo, fhi = Fraction(lo), Fraction(hi)
    label = f"sampled bound of {param} in [{lo:g}, {hi:g}] (at most {max_boxes} boxes)"
    with task(shown, label, 100):
        percent = DecidedShare(shown)
        boxes = bound_boxes(
            key, T, fam, flo, fhi,
            rtol=Fraction(rtol), atol=Fraction(rtol) * (fhi - flo) / 10**6,
            start_precision=start, max_precision=max_precision, max_boxes=max_boxes,
            advance=percent,
        )  # fmt: skip
        percent.finish()
    # values where the deployed controller differs from the family: decided alone
    points = {}
    for v in fam.special:
        if flo <= v <= fhi and float(v) == v:
            try:
                r = sampled_passivity(
                    base, loop=loop, values={param: float(v)}, continuous_gate=False
                )
            except UnrealizableError:  # the discretization is undefined there: not deployable
                points[v] = False
                continue
            points[v] = r.passive
    return _assemble(base, param, boxes, points, float(lo), float(hi), loop, rtol, design_value)


def _inward(a: Fraction, b: Fraction, a_closed: bool, b_closed: bool) -> tuple[float, float]:
    """The doubles of an exact interval: ends rounded inward, open ends excluded."""
    lo = float_up(a)
    if not a_closed and Fraction(lo) == a:
        lo = math.nextafter(lo, math.inf)
    hi = float_down(b)
    if not b_closed and Fraction(hi) == b:
        hi = math.nextafter(hi, -math.inf)
    return lo, hi


def _assemble(
    sea: SEA,
    param: str,
    boxes: list[BoxVerdict],
    points: dict[Fraction, bool],
    lo: float,
    hi: float,
    loop: SampledLoop,
    rtol: float,
    design_value: float | None,
) -> SampledBoundResult:
    merged = _merge_status(boxes)
    # passive pieces as exact ends (closed: proven over the closed box), then the special
    # points overriding: a passive one is added, a non-passive one opens the pieces at it
    pieces: list[tuple[Fraction, Fraction, bool, bool]] = [
        (a, b, True, True) for a, b, outcome, _r in merged if outcome is Outcome.PASSIVE
    ]
    for v, ok in points.items():
        if ok and not any(a <= v <= b for a, b, _ac, _bc in pieces):
            pieces.append((v, v, True, True))
        if not ok:
            cut = []
            for a, b, ac, bc in pieces:
                if a < v < b:
                    cut += [(a, v, ac, False), (v, b, False, bc)]
                elif a == v == b:
                    continue
                else:
                    cut.append((a, b, ac and a != v, bc and b != v))
            pieces = cut
    pieces.sort()
    joined: list[tuple[Fraction, Fraction, bool, bool]] = []
    for a, b, ac, bc in pieces:
        if joined and joined[-1][1] == a and (joined[-1][3] or ac):
            joined[-1] = (joined[-1][0], b, joined[-1][2], bc)
        else:
            joined.append((a, b, ac, bc))
    edges: list[Edge] = []
    undecided: list[tuple[float, float]] = []
    for a, b, outcome, reason in merged:
        if outcome is not Outcome.UNDECIDED:
            continue
        if reason is SampledReason.EDGE:
            kind = _edge_kind(
                sea, param, float(a) - (float(b - a) or 1e-300), float(b) + float(b - a), loop
            )
            edges.append(Edge(lo=float_down(a), hi=float_up(b), kind=kind))  # rounded outward
        else:
            undecided.append((float_down(a), float_up(b)))
    for v, ok in points.items():
        inside = any(a < v < b for a, b, _ac, _bc in joined)
        if not inside and any(a <= v <= b for a, b, _ac, _bc in joined) != ok:
            edges.append(Edge(lo=float(v), hi=float(v), kind=EdgeKind.SPECIAL))
    edges.sort(key=lambda e: e.lo)
    # every double in a reported interval is passive: ends rounded inward
    intervals = [iv for iv in (_inward(*piece) for piece in joined) if iv[0] <= iv[1]]
    design_passive = None
    if design_value is not None:
        design_passive = any(a <= design_value <= b for a, b in intervals)
    low = None
    closed = loop.method != "zoh" and sea.discrete is None  # R_lf in closed form: C(s) only
    if any(e.kind is EdgeKind.LOW_FREQUENCY for e in edges) and closed:
        low = low_frequency_limit(sea, param, delay=loop.delay, period=loop.period, lo=lo, hi=hi)
    partition: list[tuple[float, float, Outcome]] = []
    for a, b, outcome, _r in merged:  # proven boxes rounded inward, undecided ones outward
        proven = outcome is not Outcome.UNDECIDED
        x, y = _inward(a, b, True, True) if proven else (float_down(a), float_up(b))
        partition.append((x, y, outcome))
    return SampledBoundResult(
        param=param,
        loop=loop,
        lo=lo,
        hi=hi,
        intervals=tuple(intervals),
        max_passive=intervals[-1][1] if intervals else None,
        edges=tuple(edges),
        undecided=tuple(undecided),
        partition=tuple(partition),
        rtol=rtol,
        design_value=design_value,
        design_passive=design_passive,
        low_frequency=low,
        budget_exhausted=any(r is SampledReason.BUDGET for _a, _b, _s, r in merged),
    )
