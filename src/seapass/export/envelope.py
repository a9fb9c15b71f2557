"""The passivity envelope of a deployment: the sampled-data verdict and the certified gains.

The design must pass [`sampled_passivity`][seapass.sampled.passivity.sampled_passivity] at its period,
delay and velocity filter (which also gates on continuous-time passivity).  The
certified set of runtime gains is the union of the segments through the
certified point along each tunable gain: each gain within its sampled-data
passive interval with the others at their certified values.  That is exactly
what per-gain intervals prove; moving two gains together is not certified.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

from ..model.design_file import Design
from ..progress import Progress, ProgressLike, as_progress, task
from ..sampled.bound import sampled_passive_bound
from ..sampled.passivity import SampledPassivityResult, sampled_passivity

__all__ = ["GainEnvelope", "certify_gains", "inward_interval", "sampled_verdict"]


@dataclass(frozen=True, kw_only=True)
class GainEnvelope:
    """Certified range of one controller gain.

    Attributes
    ----------
    name : str
    nominal : float
        The certified value (from the design file).
    low, high : float
        Doubles bounding the certified interval from inside (``low == high ==
        nominal`` for a gain that is not tunable).
    exact : (Fraction, Fraction)
        The interval as seapass computed it.
    search : (float, float) or None
        The range that was searched (``[ranges]`` of the design); the interval
        never extends beyond it.
    """

    name: str
    nominal: float
    low: float
    high: float
    exact: tuple[Fraction, Fraction]
    search: tuple[float, float] | None = None

    @property
    def tunable(self) -> bool:
        return self.search is not None


def inward_interval(lo: Fraction | float, hi: Fraction | float) -> tuple[float, float]:
    """The widest pair of doubles ``[a, b]`` inside ``[lo, hi]`` (exact comparison).

    >>> inward_interval(Fraction(1, 3), Fraction(2, 3))[0] > 1 / 3
    True
    """
    lo_f, hi_f = Fraction(lo), Fraction(hi)
    a, b = float(lo_f), float(hi_f)
    if Fraction(a) < lo_f:
        a = math.nextafter(a, math.inf)
    if Fraction(b) > hi_f:
        b = math.nextafter(b, -math.inf)
    return a, b


def _certified_interval(
    design: Design, gain: str, lo: float, hi: float, *, rtol: float, progress: Progress
) -> tuple[Fraction, Fraction] | None:
    """Sampled-data passive interval of ``gain`` (others at their values) containing its value."""
    res = sampled_passive_bound(
        design.sea().with_values(**{gain: None}),
        gain,
        loop=design.loop,
        lo=lo,
        hi=hi,
        rtol=rtol,
        design_value=float(design.values[gain]),
        progress=progress,
    )
    nominal = Fraction(design.values[gain])
    for a, b in res.intervals:
        if Fraction(a) <= nominal <= Fraction(b):
            return Fraction(a), Fraction(b)
    return None


def sampled_verdict(design: Design) -> SampledPassivityResult:
    """Sampled-data passivity of ``design`` in its own loop (``[control]``)."""
    return sampled_passivity(design.sea(), loop=design.loop)


def certify_gains(
    design: Design,
    tunable: Sequence[str],
    *,
    rtol: float = 1e-6,
    progress: ProgressLike = None,
) -> tuple[tuple[GainEnvelope, ...], tuple[str, ...]]:
    """Envelope of every controller gain of ``design``; tunable ones get their interval.

    Returns the envelopes (sorted by name) and notes for gains whose certified
    value lies in no passive interval found (then only that value is allowed).
    ``progress`` gets one task with a step per tunable gain.
    """
    shown = as_progress(progress, where="certify_gains")
    if not tunable:  # nothing to certify: no task to show
        return _certify(design, tunable, rtol, shown)
    with task(shown, f"certifying {len(tunable)} gain(s) at the sampled rate", len(tunable)):
        return _certify(design, tunable, rtol, shown)


def _certify(
    design: Design, tunable: Sequence[str], rtol: float, progress: Progress
) -> tuple[tuple[GainEnvelope, ...], tuple[str, ...]]:
    notes: list[str] = []
    envelopes = []
    ranges = design.analysis_ranges()
    for g in design.gains:
        nominal = float(design.values[g])
        exact = (Fraction(nominal), Fraction(nominal))
        search = None
        if g in tunable:
            search = (float(ranges[g][0]), float(ranges[g][1]))
            iv = _certified_interval(design, g, *search, rtol=rtol, progress=progress)
            progress.advance(1, note=g)
            if iv is None:
                notes.append(
                    f"{g}: no passive interval of [{search[0]:g}, {search[1]:g}] contains the "
                    f"certified value {nominal:g}; only that value is allowed"
                )
            else:
                exact = iv
        low, high = inward_interval(*exact)
        envelopes.append(
            GainEnvelope(
                name=g,
                nominal=nominal,
                low=min(low, nominal),
                high=max(high, nominal),
                exact=exact,
                search=search,
            )
        )
    return tuple(envelopes), tuple(notes)
