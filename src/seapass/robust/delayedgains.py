"""Robust gain sets of a delayed design: the values of a gain passive at a fixed delay for
every plant of a box.

`robust_delayed_gain_set` is the delayed form of the robust gain set of
[`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals]: a design
with one delay ``exp(-NAME*s)`` at its value ``τ``, a box of plant parameters and a gain
``g`` searched in ``[lo, hi]``.  The robust set ``G = {g : passive at τ for every plant}``
is enclosed by two certified sets:

* **inner** (``intervals``): segments ``[a, b]`` of ``g`` on which the delayed box
  certificate of [`seapass.robust.delayed`][seapass.robust.delayed] (uniform structure,
  no loop root reaching the axis, ``|D|² Re Z(jω) > 0`` on frequency × box by mean-value
  balls and branch and bound) holds with ``g`` as one more box dimension, found by
  bisection of the outer set down to ``rtol`` ([`bisect_inner`][seapass.robust.pieces.bisect_inner]);
* **outer** (``outer``): ``[lo, hi]`` minus gain segments proven **not** robustly
  passive.  Each excluded segment carries a plant of the box and a frequency ``ω`` with
  ``|D(jω)|² Re Z(jω) < 0`` proven for every gain of the segment by one ball enclosure
  (so ``D(jω) ≠ 0`` and ``Re Z(jω) < 0``: not positive real at that plant).  The
  segments grow around the gains that the certified delayed gain set
  ([`passive_gain_intervals`][seapass.delay.gainbound.passive_gain_intervals]) proves not
  passive at the corners and the centre of the box, and around every failing point the
  inner certificate finds; a gain proven not passive only through an unstable loop (no
  frequency) excludes nothing.

A box of one point is the nominal delayed gain set (its certified intervals are the
inner set).  Work is bounded by counts: ``budget`` cells per segment certificate,
`MAX_DELAYED_SEGMENTS` segments, `MAX_SEEDS` excluded segments.

References
----------
.. [1] W. Michiels and S.-I. Niculescu, *Stability and Stabilization of Time-Delay
   Systems*, SIAM, 2007, ch. 1.
.. [2] R. E. Moore, R. B. Kearfott and M. J. Cloud, *Introduction to Interval Analysis*,
   SIAM, 2009, ch. 6 (mean-value form).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from fractions import Fraction
from types import MappingProxyType
from typing import Any

import numpy as np
from flint import fmpq

from ..delay.balls import ball
from ..delay.gainbound import passive_gain_intervals
from ..delay.passivity import delayed_passivity
from ..exact import poly as ep
from ..model.sea import SEA, Impedance
from ..outcome import Outcome
from . import pieces
from .box import UncertainBox
from .delayed import certify_delays, crossing_free, point_values, unstable_at
from .delayform import DelayedFamily, high_cutoff, negative_on, value_at

__all__ = ["MAX_DELAYED_SEGMENTS", "MAX_SEEDS", "SEGMENT_BUDGET", "robust_delayed_gain_set"]

SEGMENT_BUDGET = 8000
"""Default cells of one segment's certificate (a segment that needs more is halved)."""

MAX_DELAYED_SEGMENTS = 64
"""Gain segments the inner set's bisection may certify (each a branch and bound)."""

MAX_SEEDS = 24
"""Failing (plant, gain) points from which excluded segments are grown."""

GRID = 200
"""Frequencies searched (floats, a heuristic) for a failing frequency at a seed."""

GROW_STEPS = 48
"""Ball enclosures spent growing one end of an excluded segment."""

UNSTABLE_STEPS = 12
"""Crossing-free certificates spent growing one end of an unstable segment."""

CROSSING_BUDGET = 400
"""Cells of one crossing-free certificate (at most ``budget``)."""


def _q(x: Fraction | float) -> fmpq:
    return ep.rational(Fraction(x))


class _Search:
    """The state of one robust delayed gain set: the family, the outer set, the witnesses."""

    def __init__(
        self, system: SEA | Impedance, gain: str, lo: Fraction, hi: Fraction,
        box: UncertainBox, fixed: Mapping[str, Any], budget: int, max_cells: int | None = None,
    ) -> None:  # fmt: skip
        self.gain, self.lo, self.hi, self.box, self.budget = gain, lo, hi, box, budget
        self.max_cells, self.exhausted = max_cells, False
        self.system, self.fixed = system, fixed
        self.names = tuple(sorted({*box.names, gain}))
        self.fam = DelayedFamily.of(system, self.names, fixed)
        self.tau = ep.rational(Fraction(repr(float(fixed[self.fam.delay]))))
        self.form = self.fam.real_part()
        self.outer: pieces.Pieces = [(lo, hi)]
        self.excluded: list[dict[str, Any]] = []
        self.cells = 0
        self.unstable_cells = 0  # of them, spent growing unstable segments (outer set)
        self.seeds = 0

    def allowance(self, wanted: int, *, outer: bool = False) -> int:
        """Cells the next certificate may spend: ``wanted``, cut to what ``max_cells`` leaves
        (0: none left; the certificate is not tried and ``exhausted`` is set).  Growing
        unstable segments (``outer``) may spend half of ``max_cells`` only, so that the inner
        set's certificates, tried after the seeds, keep the other half."""
        if self.max_cells is None:
            return wanted
        left = max(0, self.max_cells - self.cells)
        if outer:
            left = min(left, max(0, self.max_cells // 2 - self.unstable_cells))
        if left < wanted:
            self.exhausted = True
        return min(wanted, left)

    # -- outer set: excluded segments ---------------------------------------------------
    def _cell(self, omega: fmpq, plant: Mapping[str, float], a: Fraction, b: Fraction) -> Any:
        out: list[tuple[fmpq, fmpq]] = [(omega, omega), (self.tau, self.tau)]
        for n in self.names:
            out.append((_q(a), _q(b)) if n == self.gain else (_q(plant[n]), _q(plant[n])))
        return tuple(out)

    def _negative(self, omega: fmpq, plant: Mapping[str, float], a: Fraction, b: Fraction) -> bool:
        return negative_on(self.form, self._cell(omega, plant, a, b))

    def _frequency(self, plant: Mapping[str, float], g: Fraction) -> fmpq | None:
        """A frequency where the form is negative at (plant, g) (float search, then balls)."""
        point = [_q(plant[n]) if n != self.gain else _q(g) for n in self.names]
        cut = high_cutoff(self.form, self.tau == 0, [ball(p, p) for p in point])
        top = float(cut) if cut is not None else 1e6
        n = int(min(8 * GRID, max(GRID, 4 * top * float(self.tau))))
        grid = np.unique(np.concatenate([np.geomspace(top * 1e-6, top, GRID),
                                         np.linspace(0, top, n)[1:]]))  # fmt: skip
        vals = [value_at(self.form, [_q(float(w)), self.tau, *point]) for w in grid]
        order = np.argsort(vals)[:3]
        for i in order:
            if vals[i] >= 0:
                break
            w = _q(float(grid[i]))
            if w > 0 and self._negative(w, plant, g, g):
                return w
        return None

    def _grow(
        self, omega: fmpq, plant: Mapping[str, float], g: Fraction
    ) -> tuple[Fraction, Fraction]:
        """The widest segment around ``g`` found with the form proven negative at ``ω``."""
        scale = max(abs(self.hi), abs(self.lo), Fraction(1))
        return _grow_around(
            g, self.lo, self.hi, scale * Fraction(1, 2**20), GROW_STEPS,
            lambda a, b: self._negative(omega, plant, a, b),
        )  # fmt: skip

    def _unstable(
        self, plant: Mapping[str, float], g: Fraction
    ) -> tuple[Fraction, Fraction] | None:
        """A segment around ``g`` on which the loop at ``plant`` keeps a root in ``Re s > 0``:
        unstable at ``g`` and no root on the axis over the segment (`crossing_free`)."""
        point = [_q(plant[n]) if n != self.gain else _q(g) for n in self.names]
        if not unstable_at(self.fam, point, self.tau):
            return None
        values = {**self.fixed, **plant, self.gain: float(g)}
        if delayed_passivity(self.system, values=values).outcome is not Outcome.NOT_PASSIVE:
            return None

        def free(a: Fraction, b: Fraction) -> bool:
            sides = {k: (plant[k], plant[k]) for k in self.box.names}
            seg = UncertainBox(intervals={**sides, self.gain: (float(a), float(b))})
            cells = self.allowance(min(self.budget, CROSSING_BUDGET), outer=True)
            if cells == 0:  # the total is spent: nothing proven, nothing excluded
                return False
            ok, n = crossing_free(self.fam, seg, self.tau, cells)
            self.cells += n
            self.unstable_cells += n
            return ok

        scale = max(abs(self.hi), abs(self.lo), Fraction(1))
        a, b = _grow_around(g, self.lo, self.hi, scale * Fraction(1, 2**10), UNSTABLE_STEPS, free)
        return (a, b) if a < b else None

    def seed(
        self, plant: Mapping[str, float], g: Fraction, omega: fmpq | None = None
    ) -> tuple[Fraction, Fraction] | None:
        """Grow an excluded segment around ``g`` at ``plant`` (None: nothing excluded)."""
        if not self.lo <= g <= self.hi:
            return None
        for x in self.excluded:
            a, b = x["exact"]
            if a < g < b:
                return a, b
        if self.seeds >= MAX_SEEDS:
            return None
        self.seeds += 1
        if omega is None or omega <= 0 or not self._negative(omega, plant, g, g):
            omega = self._frequency(plant, g)
        if omega is None:
            seg = self._unstable(plant, g)
            if seg is None:
                return None
            a, b = seg
        else:
            a, b = self._grow(omega, plant, g)
        self.excluded.append({
            "gains": [float(a), float(b)], "values": {k: plant[k] for k in self.box.names},
            "frequency": None if omega is None else float(ep.to_fraction(omega)),
            "reason": "unstable" if omega is None else "negative_real_part", "exact": (a, b),
        })  # fmt: skip
        self.outer = pieces.minus(self.outer, [(a, b)])
        return a, b

    def chain(self, plant: Mapping[str, float], g: Fraction, omega: fmpq | None = None) -> None:
        """`seed` at ``g``, then again just beyond each end while gains keep failing."""
        first = self.seed(plant, g, omega)
        if first is None:
            return
        for side in (1, 0):
            end = first[side]
            while self.seeds < MAX_SEEDS:
                step = max(abs(end), Fraction(1)) * Fraction(1, 10**9)
                nxt = end + step if side else end - step
                got = self.seed(plant, Fraction(float(nxt))) if self.lo <= nxt <= self.hi else None
                if got is None or abs(got[side] - end) <= 4 * step:  # no progress
                    break
                end = got[side]

    # -- inner set: certified segments ----------------------------------------------------
    def certify(self, a: Fraction, b: Fraction) -> bool:
        seg = UncertainBox(intervals={**self.box.intervals, self.gain: (float(a), float(b))})
        cells = self.allowance(self.budget)
        if cells == 0:  # the total is spent: not certified (never passive by default)
            return False
        cert = certify_delays(self.fam, seg, self.tau, self.tau, cells)
        self.cells += cert.cells
        if cert.outcome is Outcome.PASSIVE:
            return True
        if cert.cells == 0 and "not proven stable" in cert.detail:  # unstable at the centre?
            centre = seg.center()
            self.chain({k: centre[k] for k in self.box.names}, Fraction(repr(centre[self.gain])))
        if cert.point is not None:  # the form is negative at this cell centre
            at = point_values(seg, cert.point[2:])
            plant = {k: at[k] for k in self.box.names}
            self.chain(plant, Fraction(repr(at[self.gain])), cert.point[0])
        return False


def robust_delayed_gain_set(
    system: SEA | Impedance,
    gain: str,
    lo: Fraction,
    hi: Fraction,
    *,
    box: UncertainBox,
    fixed: Mapping[str, Any],
    rtol: float,
    budget: int,
    max_cells: int | None = None,
) -> dict[str, Any]:
    """Certified inner and outer sets of ``gain`` over ``box`` at the design's delay.

    ``system`` has a delay ``exp(-NAME*s)`` whose value is in ``fixed`` with every other
    parameter but ``gain`` and the box (checked by the caller,
    [`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals]).
    ``max_cells`` (None: no cap) bounds the cells of all certificates together; once spent,
    no further segment is certified or excluded, so the inner set is what was certified
    before (possibly empty) and the outer set is wider, never wrong.
    Returns ``{"intervals", "outer", "excluded", "delay", "cells", "segments",
    "exhausted"}``: inner and outer sets as float pairs (inner rounded inward, outer
    outward), the excluded segments with their failing plant and frequency, the delay
    ``{"name", "tau"}``, the counted work and whether ``max_cells`` ran out.

    Examples
    --------
    >>> from fractions import Fraction as F
    >>> from seapass.model.sea import SEA
    >>> from seapass.robust.box import UncertainBox
    >>> wall = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=None, k1=1000, kd=None, tau=0.002))
    >>> r = robust_delayed_gain_set(wall, "kd", F(0), F(8000), box=UncertainBox(intervals={"b": (9.0, 11.0)}),
    ...                             fixed={"m": 1, "k1": 1000, "tau": 0.002}, rtol=1e-2, budget=20000)
    >>> r["intervals"][-1][1] <= 4500 <= r["outer"][0][1] < 4600      # b/tau at the smallest b
    True
    """
    search = _Search(system, gain, lo, hi, box, fixed, budget, max_cells)
    tau = float(fixed[search.fam.delay])
    plants = [*box.corners(), box.center()]
    uniq = list({tuple(sorted(p.items())): p for p in plants}.values())
    point_box = all(a == b for a, b in box.intervals.values())
    nominal_inner: pieces.Pieces = []
    for plant in uniq:
        nom = passive_gain_intervals(
            system, gain, float(lo), float(hi), values={**fixed, **plant}, points=9,
            rtol=min(max(rtol, 1e-6), 1e-2),
        )  # fmt: skip
        if point_box:
            nominal_inner = [(Fraction(a), Fraction(b)) for a, b in nom.intervals]
        ends = [e for iv in nom.intervals for e in iv] or [float(hi)]
        # the failing gains, those next to the plant's passive set first
        for k in sorted(nom.not_passive, key=lambda v: min(abs(v - e) for e in ends)):
            search.chain(plant, Fraction(k))
    if point_box:
        inner, seen = nominal_inner, 0
    else:
        width = Fraction(rtol) * max(abs(lo), abs(hi), Fraction(1))
        inner, seen = pieces.bisect_inner(
            lambda: search.outer, search.certify, width=width, max_segments=MAX_DELAYED_SEGMENTS
        )
    excluded = sorted(search.excluded, key=lambda x: x["exact"])
    return {
        "intervals": pieces.as_floats(pieces.merge(inner), inward=True),
        "outer": pieces.as_floats(search.outer, inward=False),
        "excluded": tuple(MappingProxyType(_without_exact(x)) for x in excluded),
        "delay": MappingProxyType({"name": search.fam.delay, "tau": tau}),
        "cells": search.cells,
        "segments": seen,
        "exhausted": search.exhausted,
    }


def _without_exact(entry: Mapping[str, Any]) -> dict[str, Any]:
    """An excluded segment for the result: its exact end points stay internal."""
    out = dict(entry)
    out.pop("exact", None)
    return out


def _grow_around(
    g: Fraction,
    lo: Fraction,
    hi: Fraction,
    first: Fraction,
    steps: int,
    holds: Callable[[Fraction, Fraction], bool],
) -> tuple[Fraction, Fraction]:
    """The widest segment ``[a, b]`` around ``g`` within ``[lo, hi]`` on which ``holds(a, b)``
    was proven: steps growing fourfold from ``first``, then bisection of the first failure,
    at most ``steps`` tests per side (every end returned is one that was proven)."""
    ends = []
    for limit in (hi, lo):
        good, step = g, first
        bad: Fraction | None = None
        for _ in range(steps):
            if bad is None:
                trial = min(g + step, limit) if limit > g else max(g - step, limit)
            else:
                trial = Fraction(float((good + bad) / 2))
            if trial in (good, bad):
                break
            if holds(min(g, trial), max(g, trial)):
                good = trial
                if trial == limit:
                    break
                step *= 4
            else:
                bad = trial
        ends.append(good)
    return ends[1], ends[0]
