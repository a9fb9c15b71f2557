"""A gain against the delay: the certified delay margin ``τ*(k)`` at chosen gains, the
(gain, delay) picture, and certified edges of the gains that tolerate a given delay.

What is certified, and what is not: every column ``k_i`` carries the certified enclosure
of ``τ*(k_i)`` from [`delay_margin`][seapass.delay.margin.delay_margin], so a cell
``(k_i, τ_j)`` is *passive for every delay up to* ``τ_j`` when ``τ_j ≤ lo_i`` and not
when ``τ_j ≥ hi_i`` (a proof at that gain).  An edge of `delay_gain_edges` is a pair of
gains, one proven to tolerate every delay up to ``τ`` and one proven not to, at most
``rtol`` apart: a boundary lies between them.  Nothing is claimed *between* the gains that
were computed (a family certificate in the gain is not part of this module), so no
"passive interval" of gains is reported.

Examples
--------
>>> from seapass.model.sea import SEA
>>> wall = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=10, k1=1000, kd=None, tau=None))
>>> r = delay_gain_edges(wall, "kd", 1000, 7000, tau=0.002, points=3, rtol=1e-3)
>>> [round(a, -1) for a in r.edges[0]]       # τ*(kd) = b/kd: kd = 5000 at 2 ms
[5000.0, 5000.0]
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..files.limits import MAX_DELAY_GAINS
from ..model.display import html_card, short_repr
from ..model.sea import SEA
from ..outcome import Outcome
from .margin import DelayMarginResult, delay_margin

__all__ = ["DelayGainEdges", "DelayRegion", "delay_gain_edges", "delay_region"]

MAX_GAIN_POINTS = MAX_DELAY_GAINS
"""`seapass.files.limits.MAX_DELAY_GAINS`: gains of one region or edge search."""


def _check(sea: SEA, gain: str, lo: float, hi: float, points: int) -> None:
    if not isinstance(sea, SEA):
        raise ParameterError(f"sea: expected an SEA, got {type(sea).__name__}")
    if gain not in sea.parameters:
        raise ParameterError(f"gain: {gain!r} is not a parameter of the design ({', '.join(sea.parameters)})")  # fmt: skip
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ParameterError(f"the gain range must be finite with lo < hi, got [{lo:g}, {hi:g}]")
    if not (isinstance(points, int) and 2 <= points <= MAX_GAIN_POINTS):
        raise ParameterError(f"points must be a whole number in [2, {MAX_GAIN_POINTS}], got {points!r}")  # fmt: skip


def _margin(sea: SEA, gain: str, k: float, delay: str, rtol: float) -> DelayMarginResult:
    return delay_margin(sea.with_values(**{gain: k}), delay, rtol=rtol)


def _tolerates(r: DelayMarginResult, tau: float) -> Outcome:
    """Passive for every delay up to ``tau``: proven, disproven, or undecided."""
    if not r.passive_at_zero:
        return Outcome.NOT_PASSIVE
    if r.delay_independent:
        return Outcome.PASSIVE
    if r.tau_star is None:
        return Outcome.UNDECIDED
    lo, hi = r.tau_star
    if r.outcome is Outcome.PASSIVE and tau <= lo:
        return Outcome.PASSIVE
    if tau >= hi and (r.certified or r.outcome is not Outcome.PASSIVE):
        return Outcome.NOT_PASSIVE
    return Outcome.UNDECIDED


@dataclass(frozen=True, kw_only=True, repr=False)
class DelayRegion:
    """``τ*(k)`` at the gains ``gains`` and the certified (gain, delay) cells.

    ``codes[i][j]`` is 1 (passive for every delay up to ``taus[j]`` at ``gains[i]``,
    proven), 0 (proven not) or 0.5 (undecided, or inside ``τ*``'s enclosure).
    ``margins[i]`` is the certified lower end of ``τ*(gains[i])`` (``inf``: every delay;
    None: not passive without delay).
    """

    gain: str
    delay: str
    gains: tuple[float, ...]
    taus: tuple[float, ...]
    codes: tuple[tuple[float, ...], ...]
    margins: tuple[float | None, ...] | None
    results: tuple[DelayMarginResult, ...] = field(default=(), compare=False)

    def to_dict(self) -> dict[str, Any]:
        return {
            "gain": self.gain,
            "delay": self.delay,
            "gains": list(self.gains),
            "taus": list(self.taus),
            "codes": [list(c) for c in self.codes],
            "margins": [
                None if m is None or not math.isfinite(m) else m for m in self.margins or ()
            ],
            "margins_note": "certified lower ends of tau*; null: not passive without delay "
            "or passive for every delay (see 'results')",
            "results": [r.to_dict() for r in self.results],
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        from ..plot.delay import plot_delay_region

        return plot_delay_region(self, ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr("DelayRegion", {"gain": self.gain, "delay": self.delay,
                                          "gains": len(self.gains), "taus": len(self.taus)})  # fmt: skip

    def _repr_html_(self) -> str:
        rows = [("gain", f"{self.gain}: {self.gains[0]:g} to {self.gains[-1]:g} ({len(self.gains)})"),
                ("delay", f"{self.delay}: {self.taus[0]:g} to {self.taus[-1]:g} s")]  # fmt: skip
        return html_card("Passive region in (gain, delay)", rows, note="Certified per column.")


def delay_region(
    sea: SEA,
    gain: str,
    lo: float,
    hi: float,
    *,
    delay: str = "tau",
    points: int = 25,
    taus: Sequence[float] | None = None,
    rtol: float = 1e-4,
) -> DelayRegion:
    """The passive region in (gain, delay): ``τ*`` at ``points`` gains in ``[lo, hi]``.

    ``taus`` (seconds, default 60 values up to twice the largest margin) are the rows of
    the picture.  A design without the delay gets it on its controllers.
    """
    _check(sea, gain, lo, hi, points)
    gains = tuple(float(k) for k in np.linspace(lo, hi, points))
    results = tuple(_margin(sea, gain, k, delay, rtol) for k in gains)
    margins: list[float | None] = []
    for r in results:
        if r.delay_independent:
            margins.append(math.inf)
        elif r.tau_star is None or r.outcome is not Outcome.PASSIVE:
            margins.append(None)
        else:
            margins.append(r.tau_star[0])
    if taus is None:
        finite = [r.tau_star[1] for r in results if r.tau_star is not None and r.tau_star[1] > 0]
        top = 2 * max(finite) if finite else 1.0
        taus = tuple(float(t) for t in np.linspace(top / 60, top, 60))
    taus = tuple(float(t) for t in taus)
    if not taus or any(not (math.isfinite(t) and t >= 0) for t in taus):
        raise ParameterError("taus: give finite delays >= 0 s")
    codes = tuple(
        tuple({Outcome.PASSIVE: 1.0, Outcome.NOT_PASSIVE: 0.0}.get(_tolerates(r, t), 0.5) for t in taus)
        for r in results
    )  # fmt: skip
    return DelayRegion(gain=gain, delay=delay, gains=gains, taus=taus, codes=codes,
                       margins=tuple(margins), results=results)  # fmt: skip


@dataclass(frozen=True, kw_only=True, repr=False)
class DelayGainEdges:
    """Certified edges of the gains that stay passive for every delay up to ``tau``.

    ``edges``: pairs ``(k_pass, k_fail)`` (in the order of the scan) with ``k_pass`` proven
    to tolerate every delay up to ``tau`` and ``k_fail`` proven not to; ``|k_fail - k_pass|
    <= rtol·max(|k|)``.  ``tested``: every gain computed and its outcome.
    """

    gain: str
    delay: str
    tau: float
    edges: tuple[tuple[float, float], ...]
    tested: tuple[tuple[float, str], ...]
    rtol: float
    undecided: tuple[float, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {
            "gain": self.gain,
            "delay": {"name": self.delay, "tau": self.tau},
            "edges": [list(e) for e in self.edges],
            "tested": [{"gain": k, "outcome": o} for k, o in self.tested],
            "undecided": list(self.undecided),
            "rtol": self.rtol,
        }

    def __repr__(self) -> str:
        return short_repr("DelayGainEdges", {"gain": self.gain, "tau": self.tau,
                                             "edges": [list(e) for e in self.edges]})  # fmt: skip

    def _repr_html_(self) -> str:
        rows = [
            (f"edge {i + 1}", f"{a:.8g} passive, {b:.8g} not")
            for i, (a, b) in enumerate(self.edges)
        ]
        return html_card(f"Gains of {self.gain} passive for every delay up to {self.tau:g} s",
                         rows or [("edges", "none found")])  # fmt: skip


def delay_gain_edges(
    sea: SEA,
    gain: str,
    lo: float,
    hi: float,
    *,
    tau: float,
    delay: str = "tau",
    points: int = 17,
    rtol: float = 1e-6,
) -> DelayGainEdges:
    """Edges, in the gain, of "passive for every delay up to ``tau``", each certified.

    ``points`` gains in ``[lo, hi]`` are decided; between neighbours with opposite proven
    outcomes the gain is bisected (each step a certified margin) until the pair is
    ``rtol`` apart.  An edge narrower than the grid can be missed (nothing is claimed
    between the computed gains).
    """
    _check(sea, gain, lo, hi, points)
    if not (math.isfinite(tau) and tau >= 0):
        raise ParameterError(f"tau must be a finite delay >= 0 s, got {tau!r}")
    if not (math.isfinite(rtol) and 1e-12 <= rtol <= 1e-2):
        raise ParameterError(f"rtol must be in [1e-12, 1e-2], got {rtol!r}")
    budget = MAX_GAIN_POINTS
    verdict: dict[float, Outcome] = {}

    def decide(k: float) -> Outcome:
        nonlocal budget
        if k not in verdict:
            budget -= 1
            verdict[k] = _tolerates(_margin(sea, gain, k, delay, 1e-6), tau)
        return verdict[k]

    grid = [float(k) for k in np.linspace(lo, hi, points)]
    decided = [(k, o) for k in grid if (o := decide(k)) is not Outcome.UNDECIDED]
    edges: list[tuple[float, float]] = []
    for (a, oa), (b, ob) in itertools.pairwise(decided):
        if oa is ob:
            continue
        good, bad = (a, b) if oa is Outcome.PASSIVE else (b, a)
        while abs(bad - good) > rtol * max(abs(good), abs(bad)) and budget > 0:
            for mid in ((good + bad) / 2, (3 * good + bad) / 4, (good + 3 * bad) / 4):
                o = decide(mid)
                if o is not Outcome.UNDECIDED:
                    break
            if o is Outcome.PASSIVE:
                good = mid
            elif o is Outcome.NOT_PASSIVE:
                bad = mid
            else:
                break  # three undecided gains in a row: the edge stays this wide
        edges.append((good, bad))
    tested = tuple((k, str(o)) for k, o in sorted(verdict.items()))
    undecided = tuple(k for k, o in sorted(verdict.items()) if o is Outcome.UNDECIDED)
    return DelayGainEdges(gain=gain, delay=delay, tau=float(tau), edges=tuple(edges),
                          tested=tested, rtol=rtol, undecided=undecided)  # fmt: skip
