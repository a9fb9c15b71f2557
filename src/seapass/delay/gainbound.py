"""The certified passive set of one gain at a fixed delay: ``bound`` for a delayed design.

Every gain that is computed is a double ``k`` (an exact rational); its verdict is
[`decide`][seapass.delay.passivity.decide] at the delay.  Between two gains ``a < b``
with ``a`` passive, [`family_certificate`][seapass.delay.gainfamily.family_certificate]
proves passive for **every** gain in ``[a, b]`` (Bernstein coefficients in the gain,
certified signs, no root crossing the axis), so an interval is reported only when it is
proven whole; its ends are doubles that are themselves passive (rounded inward by
construction).  Each end is then pushed toward the next gain proven **not** passive by
bisection: the true end of the passive set lies between them (``edges``, a certified
enclosure).  Where no gain proven not passive is found next to an end the gap is
``undecided`` (never widened).  Between gains that are proven not passive nothing is
claimed (no family certificate of "not passive" is attempted).

Examples
--------
The rigid wall behind a spring, ``kd`` behind ``τ = 2 ms``: passive up to ``b/τ = 5000``.

>>> from seapass.model.sea import SEA
>>> wall = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=10, k1=1000, kd=None, tau=0.002))
>>> r = passive_gain_intervals(wall, "kd", 0, 8000, points=5, rtol=1e-6)
>>> r.intervals[0][0], round(r.intervals[0][1], 2), str(r.outcome)
(0.0, 5000.0, 'passive')
>>> [round(x, 2) for x in r.edges[0][1]]
[5000.0, 5000.0]
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from flint import fmpq

from ..errors import ParameterError, did_you_mean
from ..exact import poly as ep
from ..exact.rounding import enclosure_text, inward_text
from ..files.limits import MAX_DELAY_GAINS
from ..model.display import html_card, short_repr
from ..model.sea import SEA, Impedance
from ..outcome import Outcome
from .gainfamily import GainFamily, family_certificate, gain_family
from .passivity import decide
from .structure import check_tau, delay_parameter, delayed_impedance

__all__ = ["DelayGainIntervals", "passive_gain_intervals"]

MAX_STEPS = 4 * MAX_DELAY_GAINS
"""Verdicts plus family certificates of one search (a count, not a time)."""

SPLIT_DEPTH = 5
"""Halvings of a grid cell between two passive gains whose family certificate fails."""


@dataclass(frozen=True, kw_only=True, repr=False)
class DelayGainIntervals:
    """The certified passive set of ``gain`` in ``[lo, hi]`` at the delay ``tau``.

    Attributes
    ----------
    gain, delay : str
        The gain and the delay parameter.
    tau : float
        The delay [s].
    lo, hi : float
        The search range.
    intervals : tuple of (float, float)
        Closed intervals of doubles proven passive **in full** (every gain in them); the
        ends are doubles that are themselves passive.
    edges : tuple of ((float, float), (float, float))
        Per interval, certified enclosures of its true lower and upper end points:
        ``(c, a)`` with ``c`` proven not passive and ``a`` the interval's end; ``(v, v)`` at
        an end of the search range.  None for an end that is undecided.
    undecided : tuple of (float, float)
        Gaps next to an interval where no gain proven not passive was found: the end of
        the passive set lies in there or beyond, undecided.
    not_passive : tuple of float
        Gains computed and proven not passive (nothing is claimed between them).
    outcome : Outcome
        ``passive``: some gains are passive and every end is enclosed; ``undecided``: an
        end is undecided (or nothing passive was found and some gain is undecided);
        ``not_passive``: every gain computed is proven not passive.
    steps : int
        Verdicts and family certificates computed (the counted budget).
    """

    gain: str
    delay: str
    tau: float
    lo: float
    hi: float
    intervals: tuple[tuple[float, float], ...] = ()
    edges: tuple[tuple[tuple[float, float] | None, tuple[float, float] | None], ...] = ()
    undecided: tuple[tuple[float, float], ...] = ()
    not_passive: tuple[float, ...] = ()
    outcome: Outcome = Outcome.UNDECIDED
    steps: int = 0
    rtol: float = 1e-6
    certificate: str = field(
        default="every gain in an interval is certified (Bernstein coefficients in the gain, "
        "arb balls, exact asymptotics); the delay is exact",
        compare=False,
    )

    def contains(self, value: float) -> bool:
        """``value`` lies in a certified interval (proven passive)."""
        return any(a <= value <= b for a, b in self.intervals)

    def to_dict(self) -> dict[str, Any]:
        return {
            "param": self.gain,
            "range": [self.lo, self.hi],
            "intervals": [list(iv) for iv in self.intervals],
            "edges": [[None if e is None else list(e) for e in pair] for pair in self.edges],
            "critical_values": [],
            "undecided": [list(g) for g in self.undecided],
            "not_passive": list(self.not_passive),
            "outcome": str(self.outcome),
            "delay": {"name": self.delay, "tau": self.tau},
            "rtol": self.rtol,
            "steps": self.steps,
            "certificate": self.certificate,
        }

    def lines(self) -> list[str]:
        """The result as lines for people (ends rounded inward, enclosures outward)."""
        out = []
        for (a, b), (le, he) in zip(self.intervals, self.edges, strict=True):
            a_text, b_text = inward_text(a, b, 10)
            line = f"passive for {a_text} <= {self.gain} <= {b_text}"
            ends = [f"{w} end in {enclosure_text(*e, digits=10)}" for w, e in (("lower", le), ("upper", he))
                    if e is not None and e[0] != e[1]]  # fmt: skip
            out.append(line + (f" ({'; '.join(ends)})" if ends else ""))
        out += [
            f"undecided for {self.gain} in {enclosure_text(a, b, digits=10)}"
            for a, b in self.undecided
        ]
        if not self.intervals:
            out.insert(0, f"no {self.gain} in [{self.lo:g}, {self.hi:g}] certified passive "
                          f"({len(self.not_passive)} gains proven not passive)")  # fmt: skip
        return out

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """The certified set as bars over the search range; returns the Axes."""
        from ..plot.delay import plot_gain_intervals

        return plot_gain_intervals(self, ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "DelayGainIntervals",
            {"gain": self.gain, "tau": self.tau, "outcome": str(self.outcome),
             "intervals": [list(iv) for iv in self.intervals]},
        )  # fmt: skip

    def _repr_html_(self) -> str:
        rows = [("delay", f"{self.delay} = {self.tau:g} s"), ("outcome", self.outcome.label)]
        rows += [(f"line {i + 1}", t) for i, t in enumerate(self.lines())]
        return html_card(f"Certified passive set of {self.gain} at a fixed delay", rows,
                         note="Certified for every gain in an interval; undecided is never passive.")  # fmt: skip


class _Search:
    def __init__(self, system: SEA | Impedance, fam: GainFamily, values: dict[str, Any]) -> None:
        self.system, self.fam, self.values = system, fam, values
        self.verdicts: dict[fmpq, Outcome] = {}
        self.steps = 0

    def spend(self) -> bool:
        self.steps += 1
        return self.steps <= MAX_STEPS

    def verdict(self, k: fmpq) -> Outcome:
        if k not in self.verdicts:
            if not self.spend():
                return Outcome.UNDECIDED
            vals = {**self.values, self.fam.gain: Fraction(int(k.p), int(k.q))}
            z = delayed_impedance(self.system, vals)
            self.verdicts[k] = decide(z).outcome
        return self.verdicts[k]

    def whole(self, a: fmpq, b: fmpq) -> bool:
        """Every gain in ``[a, b]`` is passive (proven)."""
        if a == b:
            return self.verdict(a) is Outcome.PASSIVE
        if self.verdict(a) is not Outcome.PASSIVE or not self.spend():
            return False
        return family_certificate(self.fam, a, b).ok

    def cover(self, a: fmpq, b: fmpq, depth: int) -> list[tuple[fmpq, fmpq]]:
        """Certified sub-intervals of ``[a, b]`` (a and b passive)."""
        if self.whole(a, b):
            return [(a, b)]
        if depth == 0:
            return [(a, a), (b, b)]
        mid = _double((a + b) / 2)
        if self.verdict(mid) is not Outcome.PASSIVE or mid in (a, b):
            return [(a, a), (b, b)]
        return self.cover(a, mid, depth - 1) + self.cover(mid, b, depth - 1)

    def push(self, end: fmpq, toward: fmpq, rtol: fmpq, floor: fmpq) -> tuple[fmpq, fmpq, bool]:
        """Move a certified ``end`` toward ``toward``: ``(new end, outer point, proven)``;
        stop at ``rtol`` relative or ``floor`` absolute width."""
        outer = toward
        while abs(outer - end) > max(rtol * max(abs(end), abs(outer)), floor):
            moved = False
            for frac in (fmpq(1, 2), fmpq(1, 8), fmpq(1, 64)):
                mid = _double(end + (outer - end) * frac)
                if mid in (end, outer):
                    continue
                v = self.verdict(mid)
                if v is Outcome.NOT_PASSIVE:
                    outer, moved = mid, True
                    break
                if v is Outcome.PASSIVE and self.whole(min(end, mid), max(end, mid)):
                    end, moved = mid, True
                    break
            if not moved or self.steps > MAX_STEPS:
                break
        return end, outer, self.verdict(outer) is Outcome.NOT_PASSIVE


def _double(q: fmpq) -> fmpq:
    """The double nearest to ``q``, exactly."""
    return fmpq(*Fraction(float(Fraction(int(q.p), int(q.q)))).as_integer_ratio())


def _f(q: fmpq) -> float:
    return float(Fraction(int(q.p), int(q.q)))


def _merge(pieces: list[tuple[fmpq, fmpq]]) -> list[tuple[fmpq, fmpq]]:
    out: list[tuple[fmpq, fmpq]] = []
    for a, b in sorted(pieces):
        if out and a <= out[-1][1]:
            out[-1] = (out[-1][0], max(b, out[-1][1]))
        else:
            out.append((a, b))
    return out


Edge = tuple[float, float] | None


def _join(
    intervals: list[tuple[float, float]], edges: list[tuple[Edge, Edge]]
) -> tuple[list[tuple[float, float]], list[tuple[Edge, Edge]]]:
    """Join intervals that overlap after their ends were pushed (each is certified whole)."""
    out: list[tuple[float, float]] = []
    out_edges: list[tuple[Edge, Edge]] = []
    for (a, b), (le, he) in sorted(zip(intervals, edges, strict=True), key=lambda t: t[0]):
        if out and a <= out[-1][1]:
            if b > out[-1][1]:
                out[-1] = (out[-1][0], b)
                out_edges[-1] = (out_edges[-1][0], he)
            continue
        out.append((a, b))
        out_edges.append((le, he))
    return out, out_edges


def _outside(
    gaps: list[tuple[float, float]], intervals: list[tuple[float, float]]
) -> list[tuple[float, float]]:
    """The parts of undecided gaps outside the certified intervals."""
    out = []
    for x, y in gaps:
        for a, b in intervals:
            if a <= x <= b:
                x = max(x, b)
            if a <= y <= b:
                y = min(y, a)
        if x < y and not any(a <= x and y <= b for a, b in intervals):
            out.append((x, y))
    return out


def _check(system: Any, gain: str, lo: float, hi: float, points: int, rtol: float) -> None:
    if not isinstance(system, SEA | Impedance):
        raise ParameterError(f"system: expected an SEA or an Impedance, got {type(system).__name__}")  # fmt: skip
    if gain not in system.parameters:
        hint = did_you_mean(gain, list(system.parameters))
        raise ParameterError(
            f"gain: {gain!r} is not a parameter of the design{hint}", argument="gain"
        )
    if not all(isinstance(x, int | float) and math.isfinite(x) for x in (lo, hi)) or not lo < hi:
        raise ParameterError(f"the gain range must be finite with lo < hi, got [{lo!r}, {hi!r}]")
    if not (isinstance(points, int) and 2 <= points <= MAX_DELAY_GAINS):
        raise ParameterError(f"points must be a whole number in [2, {MAX_DELAY_GAINS}], got {points!r}")  # fmt: skip
    if not (isinstance(rtol, int | float) and math.isfinite(rtol) and 1e-12 <= rtol <= 1e-2):
        raise ParameterError(f"rtol must be in [1e-12, 1e-2], got {rtol!r}", argument="rtol")


def passive_gain_intervals(
    system: SEA | Impedance,
    gain: str,
    lo: float,
    hi: float,
    *,
    tau: float | None = None,
    delay: str | None = None,
    values: Mapping[str, float | None] | None = None,
    points: int = 17,
    rtol: float = 1e-6,
) -> DelayGainIntervals:
    """Certified set of ``gain`` in ``[lo, hi]`` for which the delayed design is passive.

    Parameters
    ----------
    system : SEA or Impedance
        A design with one delay factor ``exp(-NAME*s)``; every parameter but ``gain``
        (and the delay, when ``tau`` is given) has a value.
    gain : str
        The free gain, e.g. ``"kd"``.
    lo, hi : float
        The search range, ``lo < hi``.
    tau : float, optional
        The delay [s]; default: the design's value of the delay parameter.
    delay : str, optional
        The delay parameter (checked against the design's).
    values : mapping, optional
        Values overriding the stored ones.
    points : int, default 17
        Gains decided first, evenly spaced (2 to `MAX_DELAY_GAINS`).
    rtol : float, default 1e-6
        Relative width at which the enclosure of an end stops being refined (absolute
        ``rtol·(hi - lo)/1000`` near 0).

    Returns
    -------
    DelayGainIntervals

    Raises
    ------
    ParameterError
        A gain that is not a parameter, a missing or negative delay, a bad range.
    DelayError
        The design has no delay (or two).
    """
    _check(system, gain, lo, hi, points, rtol)
    name = delay_parameter(system)
    if delay is not None and delay != name:
        raise ParameterError(
            f"delay: {delay!r} is not the delay of the design{did_you_mean(delay, [name])}; "
            f"its delay is exp(-{name}*s)",
            argument="delay",
        )
    if gain == name:
        raise ParameterError(f"gain: {gain!r} is the delay; use delay_margin for the delay")
    merged: dict[str, Any] = dict(system.values)
    merged.update(values or {})
    given = tau if tau is not None else merged.get(name)
    if given is None:
        raise ParameterError(
            f"tau: no value for the delay {name}: give it in seconds, e.g. tau=0.001",
            argument="tau",
        )
    tau_q = check_tau(given, name)
    merged[name] = Fraction(int(tau_q.p), int(tau_q.q))
    merged.pop(gain, None)
    fam = gain_family(system, gain, tau=tau_q, values=merged)
    search = _Search(system, fam, merged)
    grid = sorted({_double(ep.rational(Fraction(float(k)))) for k in np.linspace(lo, hi, points)})
    for k in grid:
        search.verdict(k)
    pieces: list[tuple[fmpq, fmpq]] = [
        (k, k) for k in grid if search.verdicts.get(k) is Outcome.PASSIVE
    ]
    for a, b in itertools.pairwise(grid):
        if search.verdicts.get(a) is Outcome.PASSIVE and search.verdicts.get(b) is Outcome.PASSIVE:
            pieces += search.cover(a, b, SPLIT_DEPTH)
    merged_pieces = _merge(pieces)
    tol = ep.rational(rtol)
    floor = tol * (grid[-1] - grid[0]) / 1000  # an end at 0: absolute, 1e-3 rtol of the range
    intervals, edges, undecided = [], [], []
    for i, (a, b) in enumerate(merged_pieces):
        left = merged_pieces[i - 1][1] if i > 0 else grid[0]
        right = merged_pieces[i + 1][0] if i + 1 < len(merged_pieces) else grid[-1]
        pair: list[tuple[float, float] | None] = []
        new = []
        for end, toward in ((a, left), (b, right)):
            if end == toward:  # the end of the search range
                new.append(end)
                pair.append((_f(end), _f(end)))
                continue
            end, outer, proven = search.push(end, toward, tol, floor)
            new.append(end)
            lo_e, hi_e = sorted((_f(outer), _f(end)))
            pair.append((lo_e, hi_e) if proven else None)
            if not proven:
                undecided.append((lo_e, hi_e))
        intervals.append((_f(new[0]), _f(new[1])))
        edges.append((pair[0], pair[1]))
    intervals, edges = _join(intervals, edges)
    undecided = _outside(undecided, intervals)
    if not intervals:
        undecided = [(_f(k), _f(k)) for k in grid if search.verdicts.get(k) is Outcome.UNDECIDED]
    undecided = sorted(set(undecided))
    bad = tuple(sorted(_f(k) for k, v in search.verdicts.items() if v is Outcome.NOT_PASSIVE))
    if intervals and not undecided:
        outcome = Outcome.PASSIVE
    elif not intervals and not undecided:
        outcome = Outcome.NOT_PASSIVE
    else:
        outcome = Outcome.UNDECIDED
    return DelayGainIntervals(
        gain=gain, delay=name, tau=_f(tau_q), lo=float(lo), hi=float(hi),
        intervals=tuple(intervals), edges=tuple(edges), undecided=tuple(undecided),
        not_passive=bad, outcome=outcome, steps=search.steps, rtol=float(rtol),
    )  # fmt: skip
