"""Corners where a condition vanishes: certified by blowing the corner up into charts.

A condition ``f`` of the family ([`seapass.robust.family`][seapass.robust.family]) may be
zero at a corner of the box and positive everywhere else: two faces of the box meet where
the degree drops twice, or the real part at infinite frequency (``t = 1``) vanishes on a
face ``b1 = 0``.  Plants on such faces are decided apart (a box with one parameter fewer,
[`seapass.robust.faces`][seapass.robust.faces]); the rest of the box must have ``f > 0``,
but no Bernstein enclosure on the closed box can show it, since ``f = 0`` at the corner.

`positive_off_faces` proves ``f > 0`` at every point of the box that lies on no
*excused* face (faces decided apart) by the blow-up of the corner: with local coordinates
``y_a ≥ 0`` (``y_a = 0`` at the corner, ``a ∈ S``, ``w_a`` the widths), the chart of
``i ∈ S`` substitutes ``y_k = (w_k/w_i)·y_i·σ_k`` (``σ_k ∈ [0, 1]``, ``k ∈ S \\ {i}``);
the charts together cover the box (``y_k/w_k ≤ y_i/w_i`` in the chart of ``i``), and in
each ``f = y_i^r·g`` exactly, with ``r`` as large as division allows.  ``y_i = 0`` maps
onto the corner, which lies on an excused face, so ``g > 0`` on the closed chart box
proves ``f > 0`` off the excused faces there.  ``g`` is proven by Bernstein branch and
bound ([`positive_on_box`][seapass.robust.bernstein.positive_on_box]); a corner of a
chart where ``g`` vanishes on an excused face is blown up again (bounded depth).  This is
the point blow-up of resolution of singularities (the Newton polygon's weighted charts
arise as compositions of such blow-ups), restricted to a box.

The axes blown up together are an excused axis ``e`` through the point and the other
axes ``j`` at an end there on which ``f`` vanishes identically together with ``e``
(``f|_{y_e = 0, y_j = 0} ≡ 0``): for ``Re Z`` at ``b1 = 0`` that is ``t``, not ``m``.

References
----------
.. [1] E. Brieskorn and H. Knörrer, *Plane Algebraic Curves*, Birkhäuser, 1986, §8.3
   (blowing up points, Newton polygons).
.. [2] J. Garloff, "The Bernstein algorithm", Interval Computations 2, 1993.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass
from enum import StrEnum

import numpy as np
from flint import fmpq

from .bernstein import BoxSign, positive_on_box
from .faces import at_value, blow_axis, divide_out, evaluate, shift_axis

__all__ = ["DEFAULT_DEPTH", "CornerSearch", "CornerSign", "positive_off_faces"]

DEFAULT_DEPTH = 6
"""Most nested blow-ups along one chain of charts."""

Face = tuple[int, bool]  # (axis, upper end)
Point = tuple[fmpq, ...]


class CornerSign(StrEnum):
    """How `positive_off_faces` ended."""

    PROVEN = "proven"
    POINT = "point"
    STUCK = "stuck"
    BUDGET = "budget"


@dataclass(frozen=True, kw_only=True)
class CornerSearch:
    """Result of `positive_off_faces`.

    Attributes
    ----------
    sign : CornerSign
        ``PROVEN`` (``f > 0`` off the excused faces), ``POINT`` (``f(point) < 0`` at a
        point on no excused face, exact), ``STUCK`` (``f(point) ≤ 0`` at a point the
        blow-ups cannot resolve: on no excused face with ``f = 0``, or beyond the depth)
        or ``BUDGET``.
    point : tuple of fmpq or None
        In the coordinates of the box (``POINT``, ``STUCK``).
    boxes : int
        Boxes examined by the branch and bound, all charts together.
    charts : int
        Charts examined.
    """

    sign: CornerSign
    point: Point | None = None
    boxes: int = 0
    charts: int = 0


@dataclass(frozen=True, kw_only=True)
class _Step:
    """One blow-up: chart coordinates → coordinates of the parent box."""

    corner: Point
    axes: tuple[int, ...]
    main: int
    dirs: tuple[int, ...]
    widths: tuple[fmpq, ...]

    def apply(self, z: Point) -> Point:
        x = list(z)
        pos = self.axes.index(self.main)
        yi = z[self.main]
        x[self.main] = self.corner[self.main] + self.dirs[pos] * yi
        for k, d, w in zip(self.axes, self.dirs, self.widths, strict=True):
            if k != self.main:
                x[k] = self.corner[k] + d * (w / self.widths[pos]) * yi * z[k]
        return tuple(x)


@dataclass(frozen=True, kw_only=True)
class _Chart:
    coeffs: np.ndarray
    box: tuple[tuple[fmpq, fmpq], ...]
    excused: frozenset[Face]
    steps: tuple[_Step, ...]
    depth: int

    def back(self, z: Point) -> Point:
        for step in reversed(self.steps):
            z = step.apply(z)
        return z

    def on_excused(self, z: Point) -> bool:
        return any(z[a] == self.box[a][1 if up else 0] for a, up in self.excused)


def _is_zero(arr: np.ndarray) -> bool:
    return all(x == 0 for x in np.asarray(arr, dtype=object).flat)


def _ends(chart: _Chart, q: Point) -> dict[int, bool]:
    """The axes where ``q`` is at an end of the chart box: ``{axis: upper}``."""
    return {a: q[a] == hi for a, (lo, hi) in enumerate(chart.box) if lo < hi and q[a] in (lo, hi)}


def _centre_axes(chart: _Chart, q: Point) -> tuple[int, ...]:
    """The axes to blow up at ``q`` (module docstring), or () when none resolve it."""
    ends = _ends(chart, q)
    excused = [a for a, up in ends.items() if (a, up) in chart.excused]
    for e in excused:
        face = at_value(chart.coeffs, e, q[e])
        if _is_zero(face):  # zero on the whole face: the quotient by y_e alone
            return (e,)
        partners = tuple(j for j in ends if j != e and _is_zero(at_value(face, j, q[j])))
        if partners:
            return (e, *partners)
    return tuple(ends) if excused and len(ends) > 1 else ()


def _charts(chart: _Chart, q: Point, axes: tuple[int, ...]) -> list[_Chart]:
    ends = _ends(chart, q)
    dirs = tuple(-1 if ends[a] else 1 for a in axes)
    widths = tuple(chart.box[a][1] - chart.box[a][0] for a in axes)
    # y_main = 0 is the corner, excused when one of its faces through the corner is
    corner_excused = any((a, ends[a]) in chart.excused for a in axes)
    local = chart.coeffs
    for a, d in zip(axes, dirs, strict=True):
        local = shift_axis(local, a, q[a], d)
    out = []
    for pos, main in enumerate(axes):
        g = local
        for k, w in zip(axes, widths, strict=True):
            if k != main:
                g = blow_axis(g, main, k, w / widths[pos])
        if corner_excused:
            divided = divide_out(g, main, fmpq(0), upper=False)
            g = g if divided is None else divided
        box = list(chart.box)
        excused = {f for f in chart.excused if f[0] not in axes}
        for k, w in zip(axes, widths, strict=True):
            box[k] = (fmpq(0), w) if k == main else (fmpq(0), fmpq(1))
            if k != main and (k, ends[k]) in chart.excused:
                excused.add((k, False))  # σ_k = 0 is the parent's face y_k = 0
        if corner_excused:
            excused.add((main, False))
        if (main, not ends[main]) in chart.excused:
            excused.add((main, True))  # y_main = w_main is the parent's far face
        step = _Step(corner=q, axes=axes, main=main, dirs=dirs, widths=widths)
        out.append(
            _Chart(
                coeffs=g,
                box=tuple(box),
                excused=frozenset(excused),
                steps=(*chart.steps, step),
                depth=chart.depth + 1,
            )
        )
    return out


def _inward(chart: _Chart, q: Point) -> Point | None:
    """A chart point near ``q``, moved towards the centre of the chart box, on no
    excused face and with ``g < 0`` there (so ``f < 0`` at its image)."""
    centre = [(lo + hi) / 2 for lo, hi in chart.box]
    for k in range(1, 13):
        z = tuple(v + (c - v) / 2**k for v, c in zip(q, centre, strict=True))
        if not chart.on_excused(z) and evaluate(chart.coeffs, z) < 0:
            return z
    return None


def positive_off_faces(
    coeffs: np.ndarray,
    region: Sequence[tuple[fmpq, fmpq]],
    excused: Collection[Face],
    *,
    budget: int,
    max_depth: int = DEFAULT_DEPTH,
) -> CornerSearch:
    """Prove ``f > 0`` on ``region`` off the ``excused`` faces, by blowing up its corners.

    Parameters
    ----------
    coeffs : ndarray of fmpq
        Dense coefficients of ``f`` (`seapass.robust.bernstein.from_terms`).
    region : sequence of (fmpq, fmpq)
        The box.
    excused : collection of (int, bool)
        Faces ``(axis, upper)`` of the box on which ``f`` need not be positive (decided
        apart by the caller; a verdict that uses this result must decide them).
    budget : int
        Most boxes examined by the branch and bound, all charts together.
    max_depth : int, default DEFAULT_DEPTH
        Most nested blow-ups.

    Examples
    --------
    ``u + v`` on ``[0, 1]²`` is zero only at the corner, where both faces are excused:

    >>> from seapass.robust.bernstein import from_terms
    >>> f = from_terms({(1, 0): fmpq(1), (0, 1): fmpq(1)}, 2)
    >>> box = [(fmpq(0), fmpq(1))] * 2
    >>> positive_off_faces(f, box, {(0, False), (1, False)}, budget=50).sign
    <CornerSign.PROVEN: 'proven'>
    >>> g = from_terms({(1, 0): fmpq(1), (0, 1): fmpq(-1)}, 2)  # u − v
    >>> r = positive_off_faces(g, box, {(0, False)}, budget=50)
    >>> r.sign, g[0, 1] * r.point[1] + g[1, 0] * r.point[0] < 0
    (<CornerSign.POINT: 'point'>, True)
    """
    box = tuple((fmpq(a), fmpq(b)) for a, b in region)
    work = [_Chart(coeffs=coeffs, box=box, excused=frozenset(excused), steps=(), depth=0)]
    used = charts = 0
    while work:
        chart = work.pop()
        charts += 1
        search = positive_on_box(chart.coeffs, chart.box, budget=max(1, budget - used))
        used += search.boxes
        if search.sign is BoxSign.PROVEN:
            continue
        if search.sign is BoxSign.BUDGET or used >= budget:
            return CornerSearch(sign=CornerSign.BUDGET, boxes=used, charts=charts)
        assert search.point is not None
        q = search.point
        if evaluate(chart.coeffs, q) < 0:
            z = q if not chart.on_excused(q) else _inward(chart, q)
            if z is not None:
                return CornerSearch(
                    sign=CornerSign.POINT, point=chart.back(z), boxes=used, charts=charts
                )
        axes = () if chart.depth >= max_depth else _centre_axes(chart, q)
        if not axes or not chart.on_excused(q):
            return CornerSearch(
                sign=CornerSign.STUCK, point=chart.back(q), boxes=used, charts=charts
            )
        work.extend(_charts(chart, q, axes))
    return CornerSearch(sign=CornerSign.PROVEN, boxes=used, charts=charts)
