"""Robust sampled-data passive sets: the values of one parameter certified passive for every plant.

`robust_sampled_intervals` is ``sampled bound`` over a box of plants, and over a plant
parameter.  For one parameter ``NAME`` in ``[lo, hi]`` and an optional box of plant
parameters it returns

* ``intervals``: the certified **inner** set: every value in them is sampled passive
  for every plant of the box (ends rounded inward: a printed end is itself certified);
* ``outer``: a certified **outer** set: no value outside it is passive for every plant
  (ends rounded outward);
* ``undecided``: ``outer`` minus ``intervals``, what the budget did not settle (never
  reported passive);
* ``failing``: plants (verified by the ordinary certified
  [`sampled_passivity`][seapass.sampled.passivity.sampled_passivity]) at which the
  design is not passive, with the value of ``NAME`` there.

Two cases:

* **NAME is a plant parameter** (``m``, ``b``, ``k1``, ``b1`` ...): interval branch and
  bound over ``NAME``.  Each sub-interval ``I`` is one box ``I × box`` for the robust
  kernel [`robust_sampled_check`][seapass.robust.sampled_verdict.robust_sampled_check]:
  certified passive → inner; a failing plant found → recorded in ``failing``;
  otherwise ``I`` is halved, breadth first, until ``budget`` sub-intervals are spent.
  The deployment policy of ``sampled check`` (the continuous design must be passive
  too) is applied with the exact continuous passive set of ``NAME``
  ([`passive_intervals`][seapass.analysis.region.passive_intervals]; over a box
  [`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals]):
  inner ∩ continuous inner, outer ∩ continuous outer.
* **NAME is a controller gain** (box required): the kernel holds the controller
  fixed, so a gain interval × box cannot be certified whole (passivity at two gains
  does not imply it between them).  Outer: the intersection of the certified sampled
  passive sets of the gain
  ([`sampled_passive_bound`][seapass.sampled.bound.sampled_passive_bound]) at the
  centre and the corners of the box (each plant's passive set contains the robust
  set).  Inner: exact only when the box is a point (then it is the nominal
  ``sampled bound``); otherwise empty and everything in ``outer`` is ``undecided``.
  As the nominal ``sampled bound`` of a gain, no continuous gate.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from ..errors import NotPassiveError, ParameterError, did_you_mean
from ..files.limits import MAX_SAMPLED_INTERVAL_BUDGET
from ..model.display import Shown, html_card, short_repr
from ..model.loop import SampledLoop
from ..model.sea import SEA
from ..outcome import Outcome
from ..progress import ProgressLike, as_progress, task
from .box import NONNEGATIVE, POSITIVE, UncertainBox, uncertain_box
from .pieces import Pieces, as_floats, intersect, merge, minus, text, widen
from .verdict import Method, WorstCase

__all__ = [
    "DEFAULT_INTERVAL_BUDGET",
    "MAX_INTERVAL_BUDGET",
    "RobustSampledIntervals",
    "robust_sampled_intervals",
]

DEFAULT_INTERVAL_BUDGET = 16
"""Sub-intervals (plant parameter) or plants (gain) examined by default."""

MAX_INTERVAL_BUDGET = MAX_SAMPLED_INTERVAL_BUDGET
"""Most sub-intervals or plants one call may examine (bounded work, `seapass.files.limits`)."""

RTOL = Fraction(1, 10**9)  # sub-intervals narrower than this share of the range: not split


@dataclass(frozen=True, repr=False, kw_only=True)
class RobustSampledIntervals:
    """The robust sampled passive set of one parameter (`robust_sampled_intervals`).

    Attributes
    ----------
    param : str
    kind : str
        ``"plant"`` (a plant parameter) or ``"gain"`` (a controller parameter).
    lo, hi : float
        The search range.
    box : UncertainBox or None
        The other uncertain plant parameters (None: the plant is fixed).
    loop : SampledLoop
    intervals : tuple of (float, float)
        Certified inner set (ends rounded inward).
    outer : tuple of (float, float)
        Certified outer set (ends rounded outward).
    undecided : tuple of (float, float)
        ``outer`` minus ``intervals``: not settled within the budget.
    failing : tuple of WorstCase
        Plants where the design is verified not passive; ``values`` includes ``param``
        (for a gain: the plant whose passive set cut ``outer``, ``frequency`` None).
    budget, budget_used : int
        Sub-intervals (plant parameter) or plants (gain) allowed and examined.
    method : Method
        Always ``"certified"``.
    """

    param: str
    kind: str
    lo: float
    hi: float
    box: UncertainBox | None
    loop: SampledLoop
    intervals: tuple[tuple[float, float], ...] = ()
    outer: tuple[tuple[float, float], ...] = ()
    undecided: tuple[tuple[float, float], ...] = ()
    failing: tuple[WorstCase, ...] = ()
    budget: int = DEFAULT_INTERVAL_BUDGET
    budget_used: int = 0
    method: Method = Method.CERTIFIED

    @property
    def budget_exhausted(self) -> bool:
        return self.budget_used >= self.budget and bool(self.undecided)

    def contains(self, value: float) -> bool:
        """True when ``value`` is certified passive (in the inner set)."""
        return any(a <= value <= b for a, b in self.intervals)

    def to_dict(self) -> dict[str, Any]:
        return {
            "robust": True,
            "sampled": True,
            "param": self.param,
            "kind": self.kind,
            "range": [self.lo, self.hi],
            "box": None if self.box is None else self.box.to_dict(),
            "intervals": [list(iv) for iv in self.intervals],
            "outer": [list(iv) for iv in self.outer],
            "undecided": [list(iv) for iv in self.undecided],
            "failing": [w.to_dict() for w in self.failing],
            "method": str(self.method),
            "period": self.loop.period,
            "delay": self.loop.delay,
            "velocity_filter": self.loop.velocity_filter,
            "budget": self.budget,
            "budget_used": self.budget_used,
            "budget_exhausted": self.budget_exhausted,
        }

    def plot(self, *, ax: Any = None) -> Any:
        """Inner set, undecided pieces and failing values on one axis; returns the Axes.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure if None.

        Returns
        -------
        matplotlib.axes.Axes
        """
        from ..plot.sampled import plot_robust_sampled_bound

        return plot_robust_sampled_bound(self, ax=ax)

    def __repr__(self) -> str:
        return short_repr(
            "RobustSampledIntervals",
            {
                "param": self.param,
                "intervals": Shown(text(self.intervals)),
                "outer": Shown(text(self.outer, outer=True)),
                "undecided": len(self.undecided) or None,
            },
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [("search range", f"[{self.lo:g}, {self.hi:g}]")]
        if self.box is not None:
            rows += [(k, f"[{a:g}, {b:g}]") for k, (a, b) in self.box.intervals.items()]
        rows += [
            ("loop", self.loop.summary),
            ("passive for every plant (certified)", text(self.intervals)),
            ("outer enclosure", text(self.outer, outer=True)),
            ("undecided", text(self.undecided, outer=True)),
            ("budget used", f"{self.budget_used} of {self.budget}"),
        ]
        for w in self.failing[:10]:
            rows.append(("failing plant", ", ".join(f"{k}={v:.8g}" for k, v in w.values.items())))
        return html_card(
            f"Robust sampled passive set of {self.param} at T = {self.loop.period * 1e3:g} ms",
            rows,
            note="Inner ends rounded inward, outer ends outward; undecided is never passive.",
        )


def check_budget(budget: Any) -> int:
    if (
        isinstance(budget, bool)
        or not isinstance(budget, int)
        or not 1 <= budget <= MAX_INTERVAL_BUDGET
    ):
        raise ParameterError(
            f"budget must be an integer in [1, {MAX_INTERVAL_BUDGET}], got {budget!r}",
            argument="budget",
        )
    return budget


def plant_parameters(sea: SEA) -> set[str]:
    """The parameters the plant (``m``, ``b``, ``D1``, ``D2``) uses."""
    return {str(x) for k in ("m", "b", "D1", "D2") for x in getattr(sea, k).free_symbols}


def controller_parameters(sea: SEA) -> set[str]:
    """The parameters the controllers (``CA``, ``CL``) use."""
    return {str(x) for k in ("CA", "CL") for x in getattr(sea, k).free_symbols}


def check_range(name: str, lo: float, hi: float) -> tuple[Fraction, Fraction]:
    """The exact range; finite, ``lo <= hi`` and physical for a plant parameter."""
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (lo, hi)):
        raise ParameterError(f"lo and hi must be numbers, got {lo!r}, {hi!r}")
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ParameterError(f"need a finite range for {name}, got [{lo}, {hi}]")
    if lo > hi:
        raise ParameterError(
            f"empty range [{lo:g}, {hi:g}] for {name}: the lower end must not exceed the upper"
        )
    if name in POSITIVE and lo <= 0:
        raise ParameterError(
            f"the range [{lo:g}, {hi:g}] of {name} includes non-physical values; {name} must be "
            "positive (give a range with a positive lower end)"
        )
    if name in NONNEGATIVE and lo < 0:
        raise ParameterError(
            f"the range [{lo:g}, {hi:g}] of {name} includes non-physical values; {name} must "
            "not be negative (give a range with a lower end >= 0)"
        )
    return Fraction(lo), Fraction(hi)


def robust_sampled_intervals(
    sea: SEA,
    name: str,
    *,
    loop: SampledLoop,
    lo: float,
    hi: float,
    box: Mapping[str, Any] | UncertainBox | None = None,
    budget: int = DEFAULT_INTERVAL_BUDGET,
    progress: ProgressLike = None,
    throw: bool = False,
) -> RobustSampledIntervals:
    """Values of ``name`` in ``[lo, hi]`` certified sampled passive for every plant of ``box``.

    Parameters
    ----------
    sea : SEA
        The design; every parameter but ``name`` and those of ``box`` needs a value.
    name : str
        A plant parameter (``m``, ``b``, ``k1``, ``b1`` ...) or a controller gain (then
        ``box`` is required; without a box use
        [`sampled_passive_bound`][seapass.sampled.bound.sampled_passive_bound]).
    loop : SampledLoop
        Period, delay, velocity filter and discretization of the digital controller.
    lo, hi : float
        The range of ``name`` (``lo <= hi``; physical for a plant parameter: ``m > 0``).
    box : mapping or UncertainBox, optional
        Other uncertain *plant* parameters, ``{"b": (9, 11)}``; not ``name``.
    budget : int, default 16
        Sub-intervals of ``name`` examined (plant parameter; each one certified decision
        of the robust kernel) or plants whose passive set is computed (gain), in
        ``[1, 10000]``.  What is left is ``undecided``, never passive.
    progress : Progress, optional
        One task of ``budget`` steps (default: none).
    throw : bool, default False
        Raise `NotPassiveError` when no value is certified passive.

    Returns
    -------
    RobustSampledIntervals

    Raises
    ------
    ParameterError
        An unknown name, ``lo > hi``, a non-physical range (``m <= 0``), a bad box or
        budget, missing values.

    References
    ----------
    J. E. Colgate and G. G. Schenkel, "Passivity of a class of sampled-data systems",
    J. Robotic Systems 14(1), 1997.

    Examples
    --------
    >>> ours = SEA(D1="k1 + b1*s", CA="kd + bd*s",
    ...            values=dict(b=10, k1=1000, b1=300, kd=1708, bd=300))
    >>> loop = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
    >>> r = robust_sampled_intervals(ours, "m", loop=loop, lo=1.0, hi=1.000001, budget=1)
    >>> r.intervals, r.undecided
    (((1.0, 1.000001),), ())
    """
    from .sampled_gains import gain_intervals

    budget = check_budget(budget)
    shown = as_progress(progress, where="robust_sampled_intervals")
    if name not in sea.parameters:
        raise ParameterError(
            f"parameter {name!r} does not appear in the model{did_you_mean(name, sea.parameters)}"
            f"; it uses: {', '.join(sea.parameters)}"
        )
    flo, fhi = check_range(name, lo, hi)
    raw = {} if box is None else dict(box.intervals if isinstance(box, UncertainBox) else box)
    if name in raw:
        raise ParameterError(
            f"box[{name!r}]: {name} is the bounded parameter; it cannot also be uncertain",
            argument="box",
        )
    plant, control = plant_parameters(sea), controller_parameters(sea)
    for n in raw:
        if n not in plant or n in control:
            raise ParameterError(
                f"box[{n!r}]: not a plant parameter only (m, b, D1, D2 use it and CA, CL do "
                "not); the box holds the uncertain plant, the controller is fixed",
                argument="box",
            )
    if name in plant and name in control:
        raise ParameterError(
            f"{name} is used by the plant and by a controller: the deployed controller must "
            "not depend on an uncertain plant parameter"
        )
    free = sea.with_values(**{n: None for n in (name, *raw)})
    ubox = uncertain_box(free, raw) if raw else None
    missing = [p for p in free.free_parameters if p != name and p not in raw]
    if missing:
        raise ParameterError("sampled passivity needs values for: " + ", ".join(missing))
    if name not in plant:
        if ubox is None:
            raise ParameterError(
                f"{name} is a controller parameter: give a box of plant parameters, or bound "
                "it at fixed plant values with seapass.sampled.sampled_passive_bound"
            )
        res = gain_intervals(free, name, loop, flo, fhi, ubox, budget, shown)
    else:
        res = plant_intervals(free, name, loop, flo, fhi, ubox, budget, shown)
    if throw and not res.intervals:
        raise NotPassiveError(
            f"no value of {name} in [{lo:g}, {hi:g}] is certified sampled passive for every plant"
        )
    return res


def plant_intervals(
    sea: SEA, name: str, loop: SampledLoop, lo: Fraction, hi: Fraction,
    box: UncertainBox | None, budget: int, progress: Any,
) -> RobustSampledIntervals:  # fmt: skip
    """Interval branch and bound over the plant parameter ``name`` (see the module)."""
    from .sampled_verdict import robust_sampled_check

    others = {} if box is None else dict(box.intervals)
    try:  # the range as a box checks the bounded work (ratio, magnitude) once
        uncertain_box(sea, {name: (float(lo), float(hi)), **others})
    except ParameterError as exc:
        raise ParameterError(str(exc).replace(f"box[{name!r}]", f"the range of {name}")) from None
    per_box = 1 if box is None else 4  # the kernel's own sub-boxes for each sub-interval
    inner: Pieces = []
    failing: list[WorstCase] = []
    seen: set[tuple[tuple[str, float], ...]] = set()  # failing plants already recorded
    queue: deque[tuple[Fraction, Fraction]] = deque([(lo, hi)])
    used = 0
    tiny = RTOL * max(hi - lo, abs(hi), Fraction(1, 10**300))
    with task(progress, f"robust sampled bound of {name} (at most {budget} sub-intervals)", budget):
        while queue and used < budget:
            a, b = queue.popleft()
            used += 1
            r = robust_sampled_check(
                sea, loop=loop, box={name: (float(a), float(b)), **others}, budget=per_box,
                continuous_gate=False,
            )  # fmt: skip
            progress.advance(1, note=f"{used} of {budget} sub-intervals")
            if r.outcome is Outcome.PASSIVE:
                inner.append((a, b))
                continue
            if r.worst is not None:
                key = tuple(sorted(r.worst.values.items()))
                if key not in seen:
                    seen.add(key)
                    failing.append(r.worst)
            mid = Fraction(float((a + b) / 2))
            if b - a > tiny and a < mid < b:
                queue += [(a, mid), (mid, b)]
    inner = merge(inner)
    outer: Pieces = [(lo, hi)]
    # the deployment policy: the continuous design passive too (exact, or certified on a box)
    c_inner, c_outer = continuous_sets(sea, name, lo, hi, box)
    inner, outer = intersect(inner, c_inner), intersect(outer, c_outer)
    failing.sort(key=lambda w: w.values[name])
    return RobustSampledIntervals(
        param=name, kind="plant", lo=float(lo), hi=float(hi), box=box, loop=loop,
        intervals=as_floats(inner, inward=True), outer=as_floats(outer, inward=False),
        undecided=as_floats(minus(outer, inner), inward=False), failing=tuple(failing),
        budget=budget, budget_used=used,
    )  # fmt: skip


def continuous_sets(
    sea: SEA, name: str, lo: Fraction, hi: Fraction, box: UncertainBox | None
) -> tuple[Pieces, Pieces]:
    """Inner and outer continuous passive sets of ``name`` (exact ends as doubles)."""
    if sea.discrete is not None:  # a controller in z: the gate does not apply
        return [(lo, hi)], [(lo, hi)]
    if box is None:
        from ..analysis.region import passive_intervals

        exact = passive_intervals(sea, name, float(lo), float(hi))
        c_inner = [(Fraction(a), Fraction(b)) for a, b in exact.intervals]
        c_outer = [(Fraction(e[0][0]), Fraction(e[1][1])) for e in exact.edges]
        return c_inner, widen(c_outer, lo, hi)
    from .intervals import robust_passive_intervals

    cert = robust_passive_intervals(sea, name, float(lo), float(hi), box=box)
    c_inner = [(Fraction(a), Fraction(b)) for a, b in cert.intervals]
    return c_inner, widen([(Fraction(a), Fraction(b)) for a, b in cert.outer], lo, hi)


def corners(box: UncertainBox) -> list[dict[str, float]]:
    """The centre of the box, then its corners."""
    out = [box.center(), *box.corners()]
    seen: list[dict[str, float]] = []
    for p in out:
        if p not in seen:
            seen.append(p)
    return seen
