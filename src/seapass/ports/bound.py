"""Exact sets of one gain (and 2-D maps) for which a two-port is absolutely stable, or an n-port passive.

Every critical value of the parameter in the range comes from resultants and
discriminants ([`seapass.ports.criticals`][seapass.ports.criticals]); between
consecutive critical values the verdict is constant, so it is decided exactly
once per cell, at a rational point, and at every rational critical value.  The
intervals are reported as floats rounded *inward*: each printed end point is a
float that itself satisfies the criterion (a rational end point that passes is
printed when it is a float, else the next float inside).  Irrational critical
values are never floats, so a passing interval is not split at one whose two
sides pass.  A cell the exact test cannot decide is reported as undecided,
never as passing.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from fractions import Fraction
from typing import Any

import numpy as np
from flint import fmpq, fmpz

from ..errors import ParameterError
from ..exact import poly as ep
from ..files.limits import MAX_REGION_COLUMNS
from ..model.display import Shown, html_card, short_repr
from ..model.expr import to_fraction
from ..outcome import Outcome
from .bands import combine
from .criticals import critical_polynomials, univariate
from .llewellyn import llewellyn_conditions
from .matrix import from_polynomials
from .passivity import matrix_passivity
from .ratfunc import frac_of, to_fmpq_poly

__all__ = [
    "CRITERIA",
    "Criterion",
    "PortIntervals",
    "PortRegion",
    "criterion_of",
    "port_critical_values",
    "port_intervals",
    "port_region",
]


class Criterion(StrEnum):
    """What a gain interval guarantees (the JSON value ``criterion`` is the string)."""

    ABSOLUTE = "absolute"
    """Llewellyn's absolute stability (two-ports only)."""
    PASSIVE = "passive"
    """Passivity (positive-realness) of the immittance matrix."""

    @property
    def label(self) -> str:
        """Words for people: ``"absolutely stable"`` or ``"passive"``."""
        return "absolutely stable" if self is Criterion.ABSOLUTE else "passive"


CRITERIA = tuple(c.value for c in Criterion)
"""``absolute``: Llewellyn's absolute stability (two-ports); ``passive``: positive-realness."""


def criterion_of(criterion: Criterion | str) -> Criterion:
    """``criterion`` as a `Criterion` (`ParameterError` naming the choices otherwise)."""
    try:
        return Criterion(criterion)
    except ValueError:
        raise ParameterError(
            f"criterion: {criterion!r} is not one of {', '.join(CRITERIA)}", argument="criterion"
        ) from None


#: Relative width of the isolating intervals of irrational critical values.
CRITICAL_RTOL = fmpq(1, 2**64)


@dataclass(frozen=True, kw_only=True, repr=False)
class PortIntervals:
    """The exact set of values of one parameter for which the criterion holds.

    Attributes
    ----------
    param : str
    criterion : Criterion
        Absolute stability or passivity.
    lo, hi : float
        The search range.
    intervals : tuple of (float, float)
        Disjoint closed intervals, ends rounded inward (every printed end point
        satisfies the criterion); a single value appears as ``(v, v)``.
    undecided : tuple of (float, float)
        Cells the exact test could not decide (never counted as passing).
    critical_values : tuple of float
        Every value in the range where the verdict may change.
    """

    param: str
    criterion: Criterion
    lo: float
    hi: float
    intervals: tuple[tuple[float, float], ...] = ()
    undecided: tuple[tuple[float, float], ...] = ()
    critical_values: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "criterion", criterion_of(self.criterion))

    def contains(self, value: float) -> bool:
        return any(a <= value <= b for a, b in self.intervals)

    def to_dict(self) -> dict[str, Any]:
        return {
            "param": self.param,
            "criterion": self.criterion.value,
            "range": [self.lo, self.hi],
            "intervals": [list(iv) for iv in self.intervals],
            "undecided": [list(iv) for iv in self.undecided],
            "critical_values": list(self.critical_values),
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """The set as a bar over the search range; returns the Axes."""
        from ..plot.region import plot_passive_intervals

        return plot_passive_intervals(self, ax=ax, **kwargs)  # type: ignore[arg-type]

    def __repr__(self) -> str:
        text = ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in self.intervals[:4]) or "[] (nowhere)"
        return short_repr(
            "PortIntervals",
            {"param": self.param, "criterion": self.criterion.value, "intervals": Shown(text)},
        )

    def _repr_html_(self) -> str:
        text = ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in self.intervals) or "nowhere"
        what = self.criterion.label
        return html_card(
            f"Exact set of {self.param} ({what})",
            [("search range", f"[{self.lo:g}, {self.hi:g}]"), (what + " for", text)],
        )


def _system(system: Any, values: Mapping[str, float | None] | None) -> tuple[Any, int, str]:
    """``(object with entries and values, number of ports, form letter)``."""
    from ..model.sea import SEA
    from .axes import CoupledAxes
    from .mimo import NPort
    from .stability import as_two_port
    from .twoport import TwoPort

    if isinstance(system, SEA | TwoPort):
        tp = as_two_port(system)
        return tp, 2, tp.form.value
    if isinstance(system, CoupledAxes):
        system = system.n_port()
    if isinstance(system, NPort):
        return system, system.n, "z"
    raise ParameterError(
        f"system: expected an SEA, TwoPort, NPort or CoupledAxes, got {type(system).__name__}",
        argument="system",
    )


def _critical_values(polys: Sequence[Any], lo: Fraction, hi: Fraction) -> list[tuple[fmpq, fmpq]]:
    """Sorted critical values in ``[lo, hi]``: ``(r, r)`` exact, else tight ``(a, b]``."""
    lo_q, hi_q = ep.rational(lo), ep.rational(hi)
    found: set[tuple[fmpq, fmpq]] = set()
    factors = {}
    for p in polys:
        _c, fs = univariate(p).factor()
        for f, _e in fs:
            factors[str(f)] = f
    for f in factors.values():
        fq = ep.as_poly(f)
        if fq.degree() == 1:
            r = -fq[0] / fq[1]
            if lo_q <= r <= hi_q:
                found.add((r, r))
            continue
        for a, b in ep.isolate_real_roots(fq, lo_q, hi_q):
            width = max(abs(a), abs(b), fmpq(1, 2**64)) * CRITICAL_RTOL
            found.add(ep.refine(fq, (a, b), width))
    return sorted(found)


def _float_up(q: fmpq, strict: bool) -> float:
    """The least float ``>= q`` (``> q`` if ``strict``)."""
    f = float(q)
    while Fraction(f) < ep.to_fraction(q) or (strict and Fraction(f) == ep.to_fraction(q)):
        f = math.nextafter(f, math.inf)
    return f


def _float_down(q: fmpq, strict: bool) -> float:
    """The largest float ``<= q`` (``< q`` if ``strict``)."""
    f = float(q)
    while Fraction(f) > ep.to_fraction(q) or (strict and Fraction(f) == ep.to_fraction(q)):
        f = math.nextafter(f, -math.inf)
    return f


def _pieces(
    crit: list[tuple[fmpq, fmpq]], lo: fmpq, hi: fmpq, decide: Callable[[fmpq], Outcome]
) -> list[tuple[fmpq, bool, fmpq, bool, Outcome]]:
    """``(start, start_closed, end, end_closed, outcome)`` of every cell and rational critical value.

    A cell between critical values is decided at a rational point inside it; an
    irrational critical value in ``(a, b]`` ends the cell before it at ``a`` and
    starts the next one after ``b`` (open ends: rounding moves inward past them).
    """
    out: list[tuple[fmpq, bool, fmpq, bool, Outcome]] = []
    cursor, closed = lo, True
    for a, b in crit:
        if a > cursor:
            out.append((cursor, closed, a, False, decide((cursor + a) / 2)))
        if a == b:
            out.append((a, True, a, True, decide(a)))
        if b >= cursor:
            cursor, closed = b, False
    if hi > cursor:
        out.append((cursor, closed, hi, True, decide((cursor + hi) / 2)))
    elif hi == cursor and closed:
        out.append((hi, True, hi, True, decide(hi)))
    return out


def _merge(
    pieces: list[tuple[fmpq, bool, fmpq, bool, Outcome]], want: Outcome
) -> tuple[tuple[float, float], ...]:
    """Maximal runs of pieces with outcome ``want``, as floats rounded inward."""
    runs: list[list[tuple[fmpq, bool, fmpq, bool, Outcome]]] = []
    for p in pieces:
        if p[4] is not want:
            runs.append([])
            continue
        if runs and runs[-1]:
            runs[-1].append(p)
        else:
            runs.append([p])
    out = []
    for run in (r for r in runs if r):
        start, s_closed = run[0][0], run[0][1]
        end, e_closed = run[-1][2], run[-1][3]
        a = _float_up(start, strict=not s_closed)
        b = _float_down(end, strict=not e_closed)
        if a <= b:
            out.append((a, b))
    return tuple(out)


def _prepared(
    system: Any,
    param: str,
    lo: float,
    hi: float,
    criterion: Criterion,
    values: Mapping[str, float] | None,
) -> tuple[list[list[Any]], list[list[Any]], str, list[tuple[fmpq, fmpq]], Fraction, Fraction]:
    """``(nums, dens, form, critical values, lo, hi)`` of `port_intervals` (arguments checked)."""
    obj, n, form = _system(system, None)
    if criterion is Criterion.ABSOLUTE and n != 2:
        raise ParameterError(
            "criterion 'absolute' (Llewellyn) is for two-ports; use 'passive'", argument="criterion"
        )
    lo_f, hi_f = to_fraction(lo, "lo"), to_fraction(hi, "hi")
    if lo_f > hi_f:
        raise ParameterError(f"empty range {lo}:{hi}: the lower bound must not exceed the upper")
    if param not in obj.parameters:
        raise ParameterError(
            f"parameter {param!r} does not appear in the model (its parameters: "
            f"{', '.join(obj.parameters) or 'none'})"
        )
    merged = {k: v for k, v in obj.values.items() if k != param and v is not None}
    merged.update({k: v for k, v in (values or {}).items() if k != param})
    free = [p for p in obj.parameters if p != param and merged.get(p) is None]
    if free:
        raise ParameterError(
            f"no value for parameter(s) {', '.join(free)}: give them, e.g. values={{{free[0]!r}: 1.0}}"
        )
    exact = {k: ep.rational(to_fraction(v, k)) for k, v in merged.items()}
    polys = [frac_of(e).substitute(exact, (param,)) for e in obj.entries]
    nums = [[polys[i * n + j][0] for j in range(n)] for i in range(n)]
    dens = [[polys[i * n + j][1] for j in range(n)] for i in range(n)]
    crit = _critical_values(critical_polynomials(nums, dens, criterion), lo_f, hi_f)
    return nums, dens, form, crit, lo_f, hi_f


def port_critical_values(
    system: Any,
    param: str,
    lo: float,
    hi: float,
    *,
    criterion: Criterion | str = Criterion.ABSOLUTE,
    values: Mapping[str, float] | None = None,
) -> tuple[tuple[Fraction, Fraction], ...]:
    """The exact critical values of ``param`` in ``[lo, hi]`` that `port_intervals` uses.

    Each is ``(r, r)`` for a rational ``r`` (decided as a point) or a tight
    isolating interval ``(a, b]`` of an irrational one (never decided as a point:
    a caller that needs every real value, such as a robust verdict, must treat it
    separately).

    Examples
    --------
    >>> from seapass import SEA
    >>> sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl",
    ...           values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25, kl=None))
    >>> crit = port_critical_values(sea, "kl", 0, 10000)
    >>> [float(a) for a, b in crit if a == b]  # the rational ones
    [1600.0, 3250.0]
    """
    _n, _d, _f, crit, _lo, _hi = _prepared(system, param, lo, hi, criterion_of(criterion), values)
    return tuple((ep.to_fraction(a), ep.to_fraction(b)) for a, b in crit)


def port_intervals(
    system: Any,
    param: str,
    lo: float,
    hi: float,
    *,
    criterion: Criterion | str = Criterion.ABSOLUTE,
    values: Mapping[str, float] | None = None,
) -> PortIntervals:
    """Exact set of values of ``param`` in ``[lo, hi]`` for which the criterion holds.

    Parameters
    ----------
    system : SEA, TwoPort, NPort or CoupledAxes
        Every parameter but ``param`` must have a value.
    param : str
        The free parameter, e.g. ``"kd"``.
    lo, hi : float
        The search range, ``lo <= hi``.
    criterion : Criterion or {"absolute", "passive"}, default "absolute"
        Llewellyn's absolute stability (two-ports only) or passivity.
    values : mapping, optional
        Extra or overriding parameter values.

    Returns
    -------
    PortIntervals

    Examples
    --------
    >>> from seapass import SEA
    >>> sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl",
    ...           values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25, kl=None))
    >>> r = port_intervals(sea, "kl", 0, 10000)
    >>> [(round(a, 3), round(b, 3)) for a, b in r.intervals]
    [(0.0, 1523.919)]
    """
    criterion = criterion_of(criterion)
    nums, dens, form, crit, lo_f, hi_f = _prepared(system, param, lo, hi, criterion, values)

    def decide(x: fmpq) -> Outcome:
        at: dict[str | int, int | fmpz | fmpq] = {param: x}
        num = [[to_fmpq_poly(p.subs(at)) for p in row] for row in nums]
        den = [[to_fmpq_poly(p.subs(at)) for p in row] for row in dens]
        if any(d.is_zero() for row in den for d in row):
            return Outcome.NOT_PASSIVE  # an entry is undefined: no two-port there
        m = from_polynomials(num, den)
        if criterion is Criterion.ABSOLUTE:
            return combine([c.outcome for c in llewellyn_conditions(m, form)])
        return matrix_passivity(m, form=form).outcome

    pieces = _pieces(crit, ep.rational(lo_f), ep.rational(hi_f), decide)
    return PortIntervals(
        param=param,
        criterion=criterion,
        lo=float(lo_f),
        hi=float(hi_f),
        intervals=_merge(pieces, Outcome.PASSIVE),
        undecided=_merge(pieces, Outcome.UNDECIDED),
        critical_values=tuple(float((a + b) / 2) for a, b in crit),
    )


@dataclass(frozen=True, kw_only=True, repr=False)
class PortRegion:
    """The exact set of ``param_y`` at each value of ``param_x`` (a 2-D map, exact along y)."""

    param_x: str
    param_y: str
    criterion: Criterion
    x: np.ndarray
    y_range: tuple[float, float]
    columns: tuple[PortIntervals, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "criterion", criterion_of(self.criterion))
        object.__setattr__(self, "columns", tuple(self.columns))

    @property
    def intervals(self) -> tuple[tuple[tuple[float, float], ...], ...]:
        return tuple(c.intervals for c in self.columns)

    def to_dict(self) -> dict[str, Any]:
        return {
            "param_x": self.param_x,
            "param_y": self.param_y,
            "criterion": self.criterion.value,
            "x": self.x.tolist(),
            "y_range": list(self.y_range),
            "intervals": [[list(iv) for iv in c.intervals] for c in self.columns],
            "undecided": [[list(iv) for iv in c.undecided] for c in self.columns],
        }

    def __repr__(self) -> str:
        return short_repr(
            "PortRegion",
            {
                "x": Shown(f"{self.param_x} ({self.x.size} values)"),
                "y": self.param_y,
                "criterion": self.criterion.value,
            },
        )

    def _repr_html_(self) -> str:
        return html_card(
            f"Exact region over {self.param_x} and {self.param_y}",
            [
                (self.param_x, f"{self.x.size} values"),
                (self.param_y, f"exact in {list(self.y_range)}"),
            ],
        )


def port_region(
    system: Any,
    param_x: str,
    x_values: Sequence[float] | np.ndarray,
    param_y: str,
    y_range: tuple[float, float],
    *,
    criterion: Criterion | str = Criterion.ABSOLUTE,
    values: Mapping[str, float] | None = None,
) -> PortRegion:
    """`port_intervals` of ``param_y`` at every value of ``param_x`` in ``x_values``."""
    xs = np.asarray(x_values, dtype=float)
    if xs.ndim != 1 or not 1 <= xs.size <= MAX_REGION_COLUMNS:
        raise ParameterError(f"x_values: 1 to {MAX_REGION_COLUMNS} values, got shape {xs.shape}")
    if param_x == param_y:
        raise ParameterError("param_x and param_y must be different parameters")
    cols = tuple(
        port_intervals(
            system, param_y, y_range[0], y_range[1], criterion=criterion,
            values={**(values or {}), param_x: float(x)},
        )
        for x in xs
    )  # fmt: skip
    return PortRegion(
        param_x=param_x,
        param_y=param_y,
        criterion=criterion_of(criterion),
        x=xs,
        y_range=(float(y_range[0]), float(y_range[1])),
        columns=cols,
    )
