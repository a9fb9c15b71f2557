"""Poles of an exact rational matrix: the right half-plane, the imaginary axis and infinity.

* `pole_defect`: whether a polynomial has a root in the open right half-plane
  or a repeated root on the imaginary axis (a `PoleDefect`) (exact Routh–Hurwitz on the part off
  the axis, certified real roots for the axis part);
* `axis_points`: the imaginary-axis poles ``jω0``, ``ω0 ≥ 0``, of the common
  denominator ``d`` as exact points (a rational or a root in an isolating
  interval), and whether they are simple;
* `residue_matrix`: at a simple pole ``jω0`` of ``d`` the residue matrix is
  ``K = N(jω0)/d'(jω0) = K̃/|d'(jω0)|²`` with ``K̃ = N(jω0)·conj(d'(jω0))``;
  `residue_signs` decides signs of polynomial expressions in ``K̃`` exactly at
  ``ω0``; `infinity_residues` gives ``K∞ = lim P(s)/s`` exactly.

References
----------
.. [1] B. D. O. Anderson and S. Vongpanitlerd, *Network Analysis and Synthesis*,
   Prentice-Hall, 1973, sec. 5.2 (residues of positive real matrices).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from flint import fmpq, fmpq_poly

from ..exact import poly as ep
from ..exact.axis import all_real_roots, at_j_omega, axis_factor, is_hurwitz
from ..exact.halfline import HalfLinePoint
from .bands import root_point
from .matrix import ExactMatrix
from .onaxis import CPoly, axis_matrix

__all__ = [
    "AxisPoles",
    "PoleDefect",
    "axis_points",
    "infinity_residues",
    "pole_defect",
    "residue_matrix",
]


class PoleDefect(StrEnum):
    """What keeps the roots of a denominator from being those of a stable immittance."""

    NONE = ""
    """Every root in the open left half-plane or simple on the imaginary axis."""
    RHP_POLE = "rhp_pole"
    """A root in the open right half-plane."""
    REPEATED_AXIS_POLE = "repeated_axis_pole"
    """A repeated root on the imaginary axis."""


def pole_defect(p: fmpq_poly) -> PoleDefect:
    """The `PoleDefect` of the roots of ``p``, decided exactly.

    >>> pole_defect(fmpq_poly([1, 0, 1])) is PoleDefect.NONE, pole_defect(fmpq_poly([-1, 1]))
    (True, <PoleDefect.RHP_POLE: 'rhp_pole'>)
    """
    if p.degree() <= 0:
        return PoleDefect.NONE
    dr, di = at_j_omega(p)
    g = dr.gcd(di)
    rest, repeated = p, False
    if g.degree() > 0:
        if not all_real_roots(g):
            return PoleDefect.RHP_POLE  # a root pair mirrored about the axis
        repeated = ep.squarefree_part(g).degree() != g.degree()
        rest = p // axis_factor(g)
    if not is_hurwitz(rest):
        return PoleDefect.RHP_POLE
    return PoleDefect.REPEATED_AXIS_POLE if repeated else PoleDefect.NONE


@dataclass(frozen=True, kw_only=True)
class AxisPoles:
    """The imaginary-axis poles ``jω0`` (``ω0 ≥ 0``) of a common denominator.

    Attributes
    ----------
    points : tuple of HalfLinePoint
        Exact ``ω0`` (in ``ω``, not ``x``), increasing.
    simple : bool
        Every one is a simple root of the denominator.
    """

    points: tuple[HalfLinePoint, ...]
    simple: bool


def axis_points(d: fmpq_poly) -> AxisPoles:
    """The poles of ``1/d`` on the imaginary axis, exactly (``d`` free of open-RHP roots)."""
    if d.degree() <= 0:
        return AxisPoles(points=(), simple=True)
    dr, di = at_j_omega(d)
    g = dr.gcd(di)
    if g.degree() <= 0:
        return AxisPoles(points=(), simple=True)
    sf = ep.squarefree_part(g)
    pts: list[HalfLinePoint] = []
    if sf(0) == 0:
        pts.append(HalfLinePoint(fmpq(0), fmpq(0)))
    for iv in ep.isolate_real_roots(sf, 0):
        pts.append(root_point(sf, iv))
    return AxisPoles(points=tuple(pts), simple=sf.degree() == g.degree())


def residue_matrix(nmat: Sequence[Sequence[Any]], d: Any) -> list[list[CPoly]]:
    """``K̃(ω) = N(jω)·conj(d'(jω))``: at a simple axis pole ``jω0`` the residue matrix is
    ``K̃(ω0)/|d'(jω0)|²`` (a positive multiple, so signs and semidefiniteness agree)."""
    deriv = d.derivative() if isinstance(d, fmpq_poly) else d.derivative("s")
    return axis_matrix(nmat, deriv)


def infinity_residues(m: ExactMatrix) -> tuple[list[list[fmpq]], bool]:
    """``K∞ = lim_{s→∞} P(s)/s`` exactly, and whether every pole at infinity is simple."""
    k: list[list[fmpq]] = []
    simple = True
    for i in range(m.n):
        row = []
        for j in range(m.n):
            num, den = m.entry(i, j)
            rel = num.degree() - den.degree() if not num.is_zero() else -(10**9)
            if rel >= 2:
                simple = False
            row.append(
                num.leading_coefficient() / den.leading_coefficient() if rel == 1 else fmpq(0)
            )
        k.append(row)
    return k, simple
