"""Robust sampled-data passivity: certified for every plant in a box of plant parameters.

`robust_sampled_check` decides whether the sampled-data design (continuous SEA, digital
controller at period ``T``, ZOH) is passive for *every* plant of a box of plant
parameters (``m``, ``b``, ``k1``, ``b1`` ...) and controller gains (``kd``, ``bd`` ...).

Gains: the discrete controller is an exact affine map of gains that enter the controllers'
numerators affinely ([`seapass.robust.sampled_control`][seapass.robust.sampled_control],
checked exactly, else `ParameterError`); the gains are extra dual-number variables, so
every quantity that depends on a gain (the controller family in ``P̃``, ``n_A`` in
``M̃``) carries its derivative; the controller's denominators do not depend on the gains,
so neither do its own modes nor the leading coefficient of ``χ`` (the stability argument
below holds over gains too); the continuous gate ``robust_check`` runs over the same box,
gains included.

Method: branch and bound over the parameter box.  In each sub-box the alias sums of every
plant are enclosed at once ([`seapass.robust.sampled_plant`][seapass.robust.sampled_plant]:
the parameters enter as arb balls through the exact poles, ``e^{pT}`` and the residues)
in mean-value form, and the weighted power polynomial ``P̃(x)`` (``x = cos ωT``) is
decided piece by piece on ``[−1, 1]``
([`seapass.robust.sampled_local`][seapass.robust.sampled_local]); stability with the port
held: the centre is stable and no root of the characteristic polynomial reaches the unit
circle anywhere in the sub-box.  A sub-box that is not decided is split in two along its
relatively widest side, breadth first.  Sub-boxes are counted (``budget``).

* ``passive``: every sub-box certified (and, by the deployment policy of
  [`sampled_passivity`][seapass.sampled.passivity.sampled_passivity], the continuous
  design is robustly passive on the box, [`robust_check`][seapass.robust.verdict.robust_check]);
* ``not_passive``: a *worst-case plant*, a point of the box where the ordinary certified
  sampled verdict (``sampled_passivity``) is ``not_passive`` (the vertices and the centre
  are tried first, then the centres of the sub-boxes proven or suspected to fail);
* ``undecided`` otherwise (never reported as passive).
"""

from __future__ import annotations

import itertools
from collections import deque
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from types import MappingProxyType
from typing import Any

from flint import arb

from ..errors import NotPassiveError, ParameterError
from ..exact.poly import as_poly
from ..model.display import html_card, short_repr
from ..model.loop import SampledLoop
from ..model.sea import SEA
from ..outcome import Outcome
from ..sampled.certified import precision, schur_stable_exact
from ..sampled.controllers import DiscreteController, controller_parts
from ..sampled.passivity import check_values, sampled_passivity
from ..sampled.power import family_degree
from ..sampled.verdict import MAX_POWER_DEGREE, needed_sums, point_family
from .box import UncertainBox, uncertain_box
from .sampled_control import GainModel, GainPower
from .sampled_local import Dual, local_outcome
from .sampled_plant import ParametricPlant, ball_of
from .sampled_state import StateData, StatePower
from .verdict import WorstCase

__all__ = [
    "DEFAULT_SAMPLED_BUDGET",
    "RobustSampledResult",
    "box_outcome",
    "robust_sampled_check",
]

DEFAULT_SAMPLED_BUDGET = 4
"""Sub-boxes the branch and bound may examine (each one certified decision on balls)."""

MAX_SAMPLED_BUDGET = 100_000
BOX_PRECISION = 128
PIECES = 1500  # pieces of [-1, 1] in cos(wT) (times parts) per sub-box before it is split
METHOD = (
    "branch and bound over the box: second-order Taylor ball enclosures of state-space alias "
    "sums, "
    "piecewise interpolation "
    "and Descartes on cos(wT), no characteristic root crossing the unit circle"
)

Box = tuple[tuple[Fraction, Fraction], ...]


@dataclass(frozen=True, repr=False, kw_only=True)
class RobustSampledResult:
    """The verdict of `robust_sampled_check`.

    Attributes
    ----------
    outcome : Outcome
        ``passive`` for every plant of the box, ``not_passive`` (with `worst`) or
        ``undecided``.
    box : UncertainBox
    worst : WorstCase or None
    loop : SampledLoop
    boxes : int
        Sub-boxes examined (the counted work).
    certified_share : float
        Share of the box's volume certified passive (1.0 when passive).
    detail : str
    """

    outcome: Outcome
    box: UncertainBox
    worst: WorstCase | None
    loop: SampledLoop
    boxes: int
    certified_share: float
    detail: str
    method: str = METHOD

    @property
    def passive(self) -> bool:
        return self.outcome.passive

    @property
    def status(self) -> Outcome:
        return self.outcome

    def to_dict(self) -> dict[str, Any]:
        return {
            "robust": True,
            "sampled": True,
            "passive": self.passive,
            "status": self.outcome.value,
            "box": self.box.to_dict(),
            "worst": None if self.worst is None else self.worst.to_dict(),
            "period": self.loop.period,
            "delay": self.loop.delay,
            "velocity_filter": self.loop.velocity_filter,
            "method": self.method,
            "boxes": self.boxes,
            "certified_share": self.certified_share,
            "detail": self.detail,
        }

    def __repr__(self) -> str:
        return short_repr(
            "RobustSampledResult",
            {"status": self.outcome.value, "box": dict(self.box.intervals), "boxes": self.boxes},
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [
            ("verdict", self.outcome.label),
            ("box", ", ".join(f"{k} ∈ [{a:g}, {b:g}]" for k, (a, b) in self.box.intervals.items())),
            ("detail", self.detail),
            ("sub-boxes examined", self.boxes),
        ]
        if self.worst is not None:
            rows.append(
                ("worst case", ", ".join(f"{k}={v:.8g}" for k, v in self.worst.values.items()))
            )
        title = f"Robust sampled passivity at T = {self.loop.period * 1e3:g} ms"
        return html_card(title, rows, note=f"Method: {self.method}.")


class Setup:
    """Everything a box decision needs that does not depend on the box.

    ``names`` are the plant parameters of the box, ``gains`` its controller gains (the
    derivative slots are ``names`` then ``gains``; `GainModel` holds the controller).
    """

    def __init__(
        self,
        sea: SEA,
        loop: SampledLoop,
        names: tuple[str, ...],
        gains: tuple[str, ...] = (),
        gain_box: Box = (),
    ) -> None:
        self.plant = ParametricPlant(sea, names)
        self.sea, self.loop = sea, loop
        self.names = (*names, *gains)
        self.offset = len(names)
        plant_values = {n: 1.0 for n in names if sea.values.get(n) is None}
        nominal = sea.with_values(
            **plant_values, **{g: float(lo) for g, (lo, _hi) in zip(gains, gain_box, strict=True)}
        )
        self.model = GainModel(sea, loop, gains, gain_box, plant_values) if gains else None
        controller = DiscreteController.for_loop(nominal, loop)
        self.ka, self.kl, hidden = controller_parts(controller, loop.delay)
        self.period = loop.exact_period
        self.family = point_family(self.ka, self.kl)
        ka_zero, kl_zero = bool(self.ka.is_zero), bool(self.kl.is_zero)
        if self.model is not None:  # zero for every gain of the box, not only at one
            ka_zero, kl_zero = self.model.zero(3), self.model.zero(2)
        self.no_control = ka_zero and kl_zero
        self.open_stable = _open_modes_stable(self.ka, self.kl, hidden)
        sums = needed_sums(ka_zero, kl_zero)
        self.sums_names = sums if "Sg" in sums else (*sums, "Sg")
        self.injection = (not kl_zero) and self.plant.alias_injection()
        self.plant.check_sums(self.sums_names)
        self.state = StateData(self.plant, self.sums_names)

    def powers(self, box: Box, mid: Sequence[Fraction], sigma: Fraction) -> tuple[Any, Any]:
        """``(centre, box)`` powers of ``box`` around its point ``mid`` (the plant and, with
        gains, the controller: exact at ``mid``, Dual over the box)."""
        point = {n: ball_of(c, c) for n, c in zip(self.names, mid, strict=True)}
        ball = {n: ball_of(lo, hi) for n, (lo, hi) in zip(self.names, box, strict=True)}
        # second order: value and gradient at the centre, Hessian over the box
        c = StatePower(self.state, point, self.period, sigma, order=1)
        b = StatePower(self.state, ball, self.period, sigma, order=2)
        if self.model is None:
            return c, b
        k = self.offset
        at = tuple((x, x) for x in mid[k:])
        return (
            GainPower(c, self.model.duals(at, k), len(box)),
            GainPower(b, self.model.duals(box[k:], k), len(box)),
        )


def _sigma(setup: Setup) -> Fraction:
    """The scale ``σ`` of ``s`` in the companion realization (any ``σ > 0`` is sound):
    ``1/T``, so that ``AT`` is of order one and the Markov parameters that vanish
    (relative degree) do not cancel far below the size of the entries."""
    return 1 / setup.period


def _open_modes_stable(ka: Any, kl: Any, hidden: Any) -> bool:
    from ..exact.poly import as_poly
    from ..sampled.verdict import joint_family

    rest = joint_family(ka, kl)[1] if not kl.is_zero else as_poly([1])
    p = rest * as_poly(list(hidden))
    coeffs = [Fraction(int(c.p), int(c.q)) for c in reversed(p.coeffs())] or [Fraction(1)]
    return schur_stable_exact(coeffs)


def box_outcome(setup: Setup, box: Box, *, prec: int = BOX_PRECISION) -> Outcome:
    """Certified outcome of every plant of ``box``: PASSIVE / NOT_PASSIVE proven for all
    of them, UNDECIDED otherwise (the continuous policy gate is not part of it).

    Mean-value enclosures and piecewise interpolation in ``cos ωT``
    ([`seapass.robust.sampled_local`][seapass.robust.sampled_local]); stability: the
    centre is stable (its ordinary certified verdict is passive) and no root of the
    characteristic polynomial reaches the unit circle on the box.
    """
    if not setup.open_stable:
        return Outcome.NOT_PASSIVE
    if setup.injection:
        return Outcome.UNDECIDED  # decided pointwise by the caller
    # a centre that is a float (the point verdict takes floats), and the radii around it
    centre = tuple(Fraction(float(c)) for c in _centre(box))
    with precision(prec):
        ball = {n: ball_of(lo, hi) for n, (lo, hi) in zip(setup.names, box, strict=True)}
        if not setup.plant.plant_ok(ball):
            return Outcome.UNDECIDED
        if setup.no_control:  # the passive physics, for every plant whose physics is proven
            return Outcome.PASSIVE
        values = {n: float(c) for n, c in zip(setup.names, centre, strict=True)}
    at_centre = sampled_passivity(setup.sea, loop=setup.loop, values=values, continuous_gate=False)
    if at_centre.outcome is not Outcome.PASSIVE:
        return Outcome.UNDECIDED  # the caller verifies the centre itself
    with precision(prec):
        sigma = _sigma(setup)
        local_c, local_b = setup.powers(box, centre, sigma)
        if not (local_c.ok and local_b.ok):
            return Outcome.UNDECIDED
        radii = [
            ball_of(r, r)
            for r in (max(c - lo, hi - c) for c, (lo, hi) in zip(centre, box, strict=True))
        ]
        fdeg = family_degree(setup.family)[0] if setup.model is None else setup.model.degree()
        degree = local_c.degree + 1 + fdeg + 2
        if degree > MAX_POWER_DEGREE:
            raise ParameterError("the power polynomial's degree exceeds the supported maximum")
        ka = (as_poly(setup.ka.num), as_poly(setup.ka.den))
        sub: dict[int, list[Any]] = {}

        def refine(level: int) -> list[Any]:
            if level not in sub:
                sub[level] = _parts(setup, box, sigma, 2**level)
            return sub[level]

        outcome, stable = local_outcome(
            local_c, local_b, radii, setup.family, ka, degree, prec, budget=PIECES,
            refine=refine, levels=_levels(len(box)),
        )  # fmt: skip
    if outcome is Outcome.PASSIVE and not stable:
        return Outcome.UNDECIDED
    return outcome


def _levels(dims: int) -> int:
    """Refinement levels of a piece: at most 64 parts per axis and 64 parts in all."""
    return max(1, 6 // dims)


def _parts(setup: Setup, box: Box, sigma: Fraction, k: int) -> list[Any]:
    """``k`` equal parts per axis of ``box``: ``(centre, box, radii)`` dual numbers each."""
    axes = []
    for lo, hi in box:
        step = (hi - lo) / k
        axes.append([(lo + i * step, lo + (i + 1) * step) for i in range(k)])
    out = []
    for cell in itertools.product(*axes):
        mid = [(lo + hi) / 2 for lo, hi in cell]
        c, b = setup.powers(tuple(cell), mid, sigma)
        if not (c.ok and b.ok):
            return [_NOWHERE]
        radii = [ball_of((hi - lo) / 2, (hi - lo) / 2) for lo, hi in cell]
        out.append((c, b, radii))
    return out


class _Nowhere:
    """A part whose enclosures are everything (a part that is not proven valid)."""

    def values(self, z: Any, family: Any, ka: Any) -> tuple[Any, Any]:
        unknown = Dual(arb(0, float("inf")), [])
        return unknown, unknown


_NOWHERE: tuple[Any, Any, list[Any]] = (_Nowhere(), _Nowhere(), [])


def split(box: Box) -> tuple[Box, Box]:
    """Halves along the relatively widest side."""

    def rel(iv: tuple[Fraction, Fraction]) -> Fraction:
        lo, hi = iv
        scale = max(abs(lo), abs(hi)) or Fraction(1)
        return (hi - lo) / scale

    k = max(range(len(box)), key=lambda i: rel(box[i]))
    lo, hi = box[k]
    mid = (lo + hi) / 2
    return (*box[:k], (lo, mid), *box[k + 1 :]), (*box[:k], (mid, hi), *box[k + 1 :])


def volume_share(box: Box, whole: Box) -> float:
    share = 1.0
    for (a, b), (lo, hi) in zip(box, whole, strict=True):
        share *= float((b - a) / (hi - lo)) if hi > lo else 1.0
    return share


def point_verdict(
    sea: SEA, loop: SampledLoop, names: tuple[str, ...], point: tuple[Fraction, ...]
) -> WorstCase | None:
    """The ordinary certified verdict at ``point``; a worst case when it is not passive."""
    values = {n: float(x) for n, x in zip(names, point, strict=True)}
    r = sampled_passivity(sea, loop=loop, values=values)
    if r.outcome is Outcome.NOT_PASSIVE:
        return WorstCase(values=MappingProxyType(values), frequency=r.omega, result=r)
    return None


def _centre(box: Box) -> tuple[Fraction, ...]:
    return tuple((lo + hi) / 2 for lo, hi in box)


def robust_sampled_check(
    sea: SEA,
    *,
    loop: SampledLoop,
    box: Mapping[str, Any] | UncertainBox,
    budget: int = DEFAULT_SAMPLED_BUDGET,
    continuous_gate: bool = True,
    throw: bool = False,
) -> RobustSampledResult:
    """Decide sampled-data passivity of ``sea`` for every plant in ``box`` (certified).

    Parameters
    ----------
    sea : SEA
        The design; every parameter but those of ``box`` needs a value.
    loop : SampledLoop
        Period, delay, velocity filter and discretization of the digital controller.
    box : mapping or UncertainBox
        Uncertain plant parameters and controller gains, ``{"m": (0.9, 1.1), "kd": (400, 500)}``.
    budget : int, default 4
        Sub-boxes the branch and bound may examine; when they run out the answer is
        ``undecided``, never passive.
    continuous_gate : bool, default True
        The deployment policy of `sampled_passivity`: also require continuous-time
        passivity for every plant of the box (``robust_check``).  A controller given in z
        has no continuous counterpart, so the gate does not apply to it.
    throw : bool, default False
        Raise `NotPassiveError` unless passive.

    Returns
    -------
    RobustSampledResult

    Examples
    --------
    >>> ours = SEA(D1="k1 + b1*s", CA="kd + bd*s",
    ...            values=dict(b=10, k1=1000, b1=300, kd=1708, bd=300))
    >>> loop = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
    >>> r = robust_sampled_check(ours, loop=loop, box={"m": (0.9, 1.1)})
    >>> r.outcome.value, dict(r.worst.values)
    ('not_passive', {'m': 0.9})
    """
    ubox = uncertain_box(sea, box)
    if (
        isinstance(budget, bool)
        or not isinstance(budget, int)
        or not 1 <= budget <= MAX_SAMPLED_BUDGET
    ):
        raise ParameterError(
            f"budget must be an integer in [1, {MAX_SAMPLED_BUDGET}], got {budget!r}",
            argument="budget",
        )
    control = {str(x) for k in ("CA", "CL") for x in getattr(sea, k).free_symbols}
    plant_names = tuple(n for n in ubox.names if n not in control)
    gains = tuple(n for n in ubox.names if n in control)
    names = (*plant_names, *gains)  # the derivative slots: plant parameters, then gains
    free = [p for p in sea.free_parameters if p not in names]
    if free:
        raise ParameterError("sampled passivity needs values for: " + ", ".join(free))
    sea = sea.with_values(**{n: None for n in names if n in sea.values})
    exact_box = dict(zip(ubox.names, ubox.exact(), strict=True))
    whole: Box = tuple(exact_box[n] for n in names)
    for (lo, hi), n in zip(whole, names, strict=True):
        check_values(sea.with_values(**{n: float(lo)}))
        check_values(sea.with_values(**{n: float(hi)}))
    setup = Setup(sea, loop, plant_names, gains, whole[len(plant_names) :])

    def result(
        outcome: Outcome, worst: WorstCase | None, n: int, share: float, detail: str
    ) -> RobustSampledResult:
        r = RobustSampledResult(
            outcome=outcome, box=ubox, worst=worst, loop=loop, boxes=n,
            certified_share=share, detail=detail,
        )  # fmt: skip
        if throw and not r.passive:
            raise NotPassiveError(f"not passive for every plant of the box: {detail}")
        return r

    # the centre and the vertices first: a failing plant there is the common case
    for point in [_centre(whole), *itertools.product(*whole)]:
        worst = point_verdict(sea, loop, names, point)
        if worst is not None:
            return result(Outcome.NOT_PASSIVE, worst, 0, 0.0, _worst_detail(worst))
    queue: deque[Box] = deque([whole])  # breadth first: the box is covered evenly
    boxes, share = 0, 0.0
    undecided = False
    while queue:
        b = queue.popleft()
        if boxes >= budget:
            undecided = True
            break
        boxes += 1
        outcome = box_outcome(setup, b)
        if outcome is Outcome.PASSIVE:
            share += volume_share(b, whole)
            continue
        if b != whole:  # an interior plant can be the worst case (the whole's centre is done)
            worst = point_verdict(sea, loop, names, _centre(b))
            if worst is not None:
                return result(Outcome.NOT_PASSIVE, worst, boxes, share, _worst_detail(worst))
        if outcome is Outcome.NOT_PASSIVE or _tiny(b):
            undecided = True  # proven to fail, or too small to split, yet its centre does not
            continue
        queue.extend(split(b))
    if undecided:
        return result(
            Outcome.UNDECIDED, None, boxes, share,
            f"certified on {share:.1%} of the box, no failing plant found; the rest is not decided "
            f"within the budget of {budget} sub-boxes (raise budget, or narrow the box: the "
            "enclosures certify boxes of about 1e-4 relative width, see docs/robust.md)",
        )  # fmt: skip
    if continuous_gate and sea.discrete is None:  # a z-controller has no continuous twin
        from .verdict import robust_check

        cont = robust_check(sea, box=ubox)
        if not cont.passive:
            detail = f"the continuous design is {cont.outcome.label} on the box ({cont.detail})"
            worst = None
            if cont.worst is not None:
                point = tuple(Fraction(cont.worst.values[n]) for n in names)
                worst = point_verdict(sea, loop, names, point)
            status = Outcome.NOT_PASSIVE if worst is not None else Outcome.UNDECIDED
            return result(status, worst, boxes, share, detail)
    return result(
        Outcome.PASSIVE, None, boxes, 1.0,
        f"certified for every plant of the box ({boxes} sub-boxes)",
    )  # fmt: skip


TINY = Fraction(1, 10**7)


def _tiny(box: Box) -> bool:
    return all(hi - lo <= TINY * max(abs(lo), abs(hi), Fraction(1)) for lo, hi in box)


def _worst_detail(worst: WorstCase) -> str:
    at = ", ".join(f"{k}={v:.10g}" for k, v in worst.values.items())
    return f"not passive at the plant {at}: {worst.result.detail}"
