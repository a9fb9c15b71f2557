"""The exact passive region over two parameters, with its boundary curves.

With every parameter but ``x`` and ``y`` fixed, the verdict can change only on
the real zero set of finitely many polynomials ``f_k(x, y)``: the critical
polynomials of [`seapass.analysis.region`][seapass.analysis.region] computed with both parameters
symbolic (leading coefficients, resultants and discriminants of the
positive-real conditions).  Their zero sets are the only place the boundary
can run, so the boundary is drawn on these curves, not on a raster.

`passive_region` builds a cylindrical decomposition of the box
``[x0, x1] × [y0, y1]``: the *x-critical values* are the real roots of the
leading coefficients and discriminants in ``y`` of every ``f_k``, of the
resultants in ``y`` of every pair, of ``f_k(x, y0)`` and ``f_k(x, y1)``, and
of the factors in ``x`` alone.  Between two consecutive x-critical values the
``y``-roots of the ``f_k`` in ``(y0, y1)`` are continuous branches that never
meet, so the verdict is constant between two consecutive branches.  One exact
test ([`seapass.analysis.passivity.is_passive`][seapass.analysis.passivity.is_passive] at a rational point) per
gap at the middle of the x-interval labels every cell.

What is exact: the curves, the x-critical values (isolated over QQ), the
number and order of the branches, and the label of every cell.  What is
floating point, for drawing only (no number here is reported as a passive value;
`seapass region` prints the certified intervals of
[`passive_map`][seapass.analysis.region.passive_map]): the points on the curves drawn between (roots of
``f_k(x_i, y)`` in double precision at about ``points`` values of ``x``; where
double precision does not find the exact number of roots, they are isolated
exactly).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from ..errors import ParameterError
from ..model.expr import symbol
from ..model.sea import SEA, Impedance
from .passivity import is_passive
from .region import critical_polynomials

__all__ = ["PassiveRegion", "RegionCell", "passive_region"]


@dataclass(frozen=True, kw_only=True)
class RegionCell:
    """One x-interval of the decomposition.

    Attributes
    ----------
    x_range : (float, float)
        The open interval between two consecutive x-critical values.
    x : ndarray, shape (n,)
        Values of ``x`` inside it where the branches were evaluated.
    branches : ndarray, shape (k, n)
        ``y`` of the ``k`` branches at each ``x``, bottom to top.
    passive : tuple of bool, length k + 1
        Verdict of each gap: below the first branch, between branches, above the last.
    """

    x_range: tuple[float, float]
    x: np.ndarray
    branches: np.ndarray
    passive: tuple[bool, ...]

    def passive_sets(self, y_range: tuple[float, float]) -> list[list[tuple[float, float]]]:
        """The passive set of ``y`` at each ``x`` of the cell, as intervals, **for drawing**.

        Its ends are the floating-point branch values: not a certificate.  The certified
        passive set of ``y`` at one ``x``, with its ends rounded inward, is
        [`passive_intervals`][seapass.analysis.region.passive_intervals].
        """
        out = []
        for col in range(self.x.size):
            edges = [y_range[0], *self.branches[:, col].tolist(), y_range[1]]
            ivs: list[tuple[float, float]] = []
            for j, ok in enumerate(self.passive):
                if not ok:
                    continue
                if ivs and ivs[-1][1] == edges[j]:
                    ivs[-1] = (ivs[-1][0], edges[j + 1])
                else:
                    ivs.append((edges[j], edges[j + 1]))
            out.append(ivs)
        return out

    @property
    def boundary(self) -> list[int]:
        """Indices of the branches that separate a passive gap from a non-passive one."""
        return [j for j in range(self.branches.shape[0]) if self.passive[j] != self.passive[j + 1]]


@dataclass(frozen=True, kw_only=True)
class PassiveRegion:
    """The exact passive region over ``param_x × param_y`` in a box.

    Attributes
    ----------
    param_x, param_y : str
    x_range, y_range : (float, float)
    curves : tuple of str
        The polynomials ``f_k(x, y)`` whose zero sets carry the boundary (as text).
    x_critical : tuple of float
        The x-critical values inside the box, sorted.
    cells : tuple of RegionCell
        One per open interval between them (intervals too narrow to sample are left out).
    """

    param_x: str
    param_y: str
    x_range: tuple[float, float]
    y_range: tuple[float, float]
    curves: tuple[str, ...]
    x_critical: tuple[float, ...]
    cells: tuple[RegionCell, ...]

    def to_dict(self) -> dict[str, Any]:
        return {
            "param_x": self.param_x,
            "param_y": self.param_y,
            "x_range": list(self.x_range),
            "y_range": list(self.y_range),
            "curves": list(self.curves),
            "x_critical": list(self.x_critical),
            "cells": [
                {"x_range": list(c.x_range), "branches": int(c.branches.shape[0]),
                 "passive": list(c.passive)}
                for c in self.cells
            ],
        }  # fmt: skip


def _factors(polys: Sequence[sp.Expr], gens: Sequence[sp.Symbol]) -> list[sp.Expr]:
    """Distinct irreducible factors over QQ (up to a constant) that involve any of ``gens``."""
    seen: dict[sp.Expr, None] = {}
    for e in polys:
        if not e.has(*gens):
            continue
        for f, _mult in sp.factor_list(sp.Poly(e, *gens, domain="QQ"))[1]:
            f = f.monic() if f.LC() != 0 else f
            seen.setdefault(f.as_expr(), None)
    return sorted(seen, key=sp.default_sort_key)


def _real_roots(poly: sp.Poly, lo: sp.Rational, hi: sp.Rational) -> list[float]:
    """Distinct real roots of a univariate rational polynomial in the open ``(lo, hi)``."""
    if poly.degree() <= 0:
        return []
    out = []
    for (a, b), _mult in poly.intervals(inf=lo, sup=hi, eps=sp.Rational(1, 2**60) * (hi - lo)):
        if b <= lo or a >= hi:
            continue
        mid = (a + b) / 2
        if mid <= lo or mid >= hi:
            continue
        out.append(float(mid))
    return sorted(out)


def _x_critical(
    fy: Sequence[sp.Expr], fx: Sequence[sp.Expr], x: sp.Symbol, y: sp.Symbol,
    x_box: tuple[sp.Rational, sp.Rational], y_box: tuple[sp.Rational, sp.Rational],
) -> list[float]:  # fmt: skip
    """The x-critical values in the open x-box (see the module docstring)."""
    polys: list[sp.Expr] = list(fx)
    for f in fy:
        p = sp.Poly(f, y)
        polys += [p.LC(), f.subs(y, y_box[0]), f.subs(y, y_box[1])]
        if p.degree() > 1:
            polys.append(sp.discriminant(f, y))
    for i, f in enumerate(fy):
        for g in fy[i + 1 :]:
            polys.append(sp.resultant(f, g, y))
    values: set[float] = set()
    for q in _factors([sp.expand(p) for p in polys], [x]):
        values.update(_real_roots(sp.Poly(q, x, domain="QQ"), *x_box))
    return sorted(values)


def _coefficient_table(f: sp.Expr, x: sp.Symbol, y: sp.Symbol) -> list[np.ndarray]:
    """Descending coefficients in ``y`` of ``f``, each a descending float polynomial in ``x``."""
    py = sp.Poly(f, y)
    return [
        np.array([float(c) for c in sp.Poly(cy, x).all_coeffs()], dtype=float)
        for cy in py.all_coeffs()
    ]


def _numeric_roots(
    table: list[np.ndarray], xs: np.ndarray, y_lo: float, y_hi: float, count: int
) -> np.ndarray:
    """``count`` real roots in ``(y_lo, y_hi)`` at each x (NaN column where not found exactly)."""
    out = np.full((count, xs.size), np.nan)
    coeffs = np.array([np.polyval(c, xs) for c in table])  # (degree + 1, n)
    span = y_hi - y_lo
    for i in range(xs.size):
        c = coeffs[:, i]
        nz = np.flatnonzero(c)
        c = c[nz[0] :] if nz.size else c
        roots = np.roots(c) if c.size > 1 else np.array([])
        real = roots[np.abs(roots.imag) <= 1e-9 * np.maximum(1.0, np.abs(roots.real))].real
        inside = np.sort(real[(real > y_lo + 1e-12 * span) & (real < y_hi - 1e-12 * span)])
        if inside.size == count:
            out[:, i] = inside
    return out


def passive_region(
    system: SEA | Impedance,
    param_x: str,
    x_range: tuple[float, float],
    param_y: str,
    y_range: tuple[float, float],
    *,
    values: Mapping[str, float] | None = None,
    points: int = 400,
) -> PassiveRegion:
    """The exact passive region of ``system`` over ``param_x × param_y`` in a box.

    Parameters
    ----------
    system : SEA or Impedance
        Model with values for every parameter except ``param_x`` and ``param_y``.
    param_x, param_y : str
        The two free parameters (horizontal and vertical).
    x_range, y_range : (float, float)
        The box, ``lo < hi`` each.
    values : mapping, optional
        Extra or overriding values of the other parameters.
    points : int
        About how many values of ``x`` the branches are evaluated at, in total.

    Returns
    -------
    PassiveRegion

    Raises
    ------
    ParameterError
        If a parameter is missing from the model, has no value, or a range is empty.
    """
    if param_x == param_y:
        raise ParameterError("param_x and param_y must be different parameters")
    for name, (lo, hi) in ((param_x, x_range), (param_y, y_range)):
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise ParameterError(f"range of {name}: need finite lo < hi, got {lo}:{hi}")
        if name not in system.parameters:
            raise ParameterError(
                f"parameter {name!r} does not appear in the model (its parameters: "
                f"{', '.join(system.parameters) or 'none'})"
            )
    fixed = {k: v for k, v in {**system.values, **(values or {})}.items()
             if k not in (param_x, param_y)}  # fmt: skip
    free = [n for n in system.parameters if n not in (param_x, param_y) and fixed.get(n) is None]
    if free:
        raise ParameterError(f"no value for parameter(s) {', '.join(free)}")
    x, y = symbol(param_x), symbol(param_y)
    polys = critical_polynomials(system, (param_x, param_y), values=fixed)
    factors = _factors(polys, [x, y])
    fy = [f for f in factors if f.has(y)]
    fx = [f for f in factors if not f.has(y)]
    xq = (sp.Rational(float(x_range[0])), sp.Rational(float(x_range[1])))
    yq = (sp.Rational(float(y_range[0])), sp.Rational(float(y_range[1])))
    crit = _x_critical(fy, fx, x, y, xq, yq)
    edges = [float(x_range[0]), *crit, float(x_range[1])]
    tables = [_coefficient_table(f, x, y) for f in fy]
    width = edges[-1] - edges[0]
    cells = []
    for a, b in itertools.pairwise(edges):
        if b - a <= 1e-12 * width:
            continue
        cells.append(_cell(system, fixed, param_x, param_y, fy, tables, (a, b), y_range,
                           max(12, int(points * (b - a) / width))))  # fmt: skip
    return PassiveRegion(
        param_x=param_x,
        param_y=param_y,
        x_range=(float(x_range[0]), float(x_range[1])),
        y_range=(float(y_range[0]), float(y_range[1])),
        curves=tuple(str(f) for f in fy),
        x_critical=tuple(crit),
        cells=tuple(cells),
    )


def _cell(
    system: SEA | Impedance, fixed: dict[str, Any], px: str, py: str, fy: Sequence[sp.Expr],
    tables: Sequence[list[np.ndarray]], x_iv: tuple[float, float], y_range: tuple[float, float],
    n: int,
) -> RegionCell:  # fmt: skip
    """Count the branches and label the gaps exactly at the middle; evaluate the branches."""
    x, y = symbol(px), symbol(py)
    xm = (x_iv[0] + x_iv[1]) / 2
    yq = (sp.Rational(float(y_range[0])), sp.Rational(float(y_range[1])))
    mids: list[float] = []
    counts = []
    for f in fy:
        roots = _real_roots(sp.Poly(f.subs(x, sp.Rational(xm)), y, domain="QQ"), *yq)
        counts.append(len(roots))
        mids += roots
    mids.sort()
    edges = [float(y_range[0]), *mids, float(y_range[1])]
    labels = tuple(
        is_passive(system, values={**fixed, px: xm, py: (lo + hi) / 2}).passive
        for lo, hi in itertools.pairwise(edges)
    )
    # cosine spacing: dense near the ends, where branches may turn or meet
    t = (1 - np.cos(np.pi * np.linspace(1e-6, 1 - 1e-6, n))) / 2
    xs = x_iv[0] + (x_iv[1] - x_iv[0]) * t
    parts = []
    for f, tab, c in zip(fy, tables, counts, strict=True):
        if not c:
            continue
        ys = _numeric_roots(tab, xs, y_range[0], y_range[1], c)
        # where double precision misses a root (close roots near a critical x): exactly
        for i in np.flatnonzero(np.isnan(ys).any(axis=0)):
            exact = _real_roots(sp.Poly(f.subs(x, sp.Rational(xs[i])), y, domain="QQ"), *yq)
            if len(exact) == c:
                ys[:, i] = exact
        parts.append(ys)
    branches = np.vstack(parts) if parts else np.zeros((0, xs.size))
    keep = ~np.isnan(branches).any(axis=0)
    branches = np.sort(branches[:, keep], axis=0)
    return RegionCell(x_range=x_iv, x=xs[keep], branches=branches, passive=labels)
