"""The exact set of passive values of one free parameter, and 2-D passive maps.

With every parameter but one (``p``) fixed to exact rationals, each condition
of the positive-real test can change its truth value only at a *critical
value* of ``p``: a real root of one of

* the leading coefficients of ``N`` and ``D`` in ``s`` (relative degree, poles at ∞);
* ``Res_s(N, D)`` (a pole-zero cancellation);
* ``Res_ω(Re D(jω), Im D(jω))`` after removing their generic common factor
  (a pole crossing the imaginary axis), and the discriminant, leading and
  constant coefficients of that factor together with its resultants with the
  residue polynomials (imaginary-axis poles and their residues);
* the discriminant, leading and lowest coefficients of ``P(x) = Re N(jω) D(−jω)``
  in ``x = ω²`` after removing generic factors (a root of ``P`` entering
  ``x > 0``).

Between consecutive critical values the verdict is constant, so one exact
test at a rational point inside each gap, plus exact tests at the rational
critical values, gives the exact passive set.

End points are algebraic numbers, isolated exactly.  They are reported as
doubles rounded **inward** (a lower end up, an upper end down), each decided
exactly against the isolating interval of the end point (`seapass.exact.rounding`):
every double in a reported interval is passive, and so is every number printed
for an end ([`seapass.exact.rounding.interval_text`][seapass.exact.rounding.interval_text]).  ``edges`` gives
the certified enclosure of each true end point beside it.  An end that is a
passive rational number is reported exactly when it is a double.  Two passive
gaps on both sides of an irrational critical value are reported as one interval:
no rational number, hence no double, lies on that value.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ParameterError
from ..exact.rounding import (
    float_above_root,
    float_below_root,
    float_down,
    float_up,
    interval_text,
)
from ..model.display import Shown, html_card, short_repr
from ..model.expr import to_fraction
from ..model.sea import SEA, Impedance, exact_values
from .critical import CriticalValue, critical_polynomials_in, critical_values_in, exact_with
from .passivity import positive_real_test

if TYPE_CHECKING:
    import sympy as sp

__all__ = [
    "PassiveIntervals",
    "PassiveMap",
    "critical_polynomials",
    "passive_intervals",
    "passive_map",
]


def _symbols() -> tuple[sp.Symbol, sp.Symbol]:
    """``x = ω²`` and ``ω`` of the symbolic critical polynomials."""
    import sympy as sp

    return sp.Symbol("x"), sp.Symbol("omega")


@dataclass(frozen=True, repr=False, kw_only=True)
class PassiveIntervals:
    """Exact passive set of one parameter within ``[lo, hi]``.

    Attributes
    ----------
    param : str
    lo, hi : float
        The search range.
    intervals : tuple of (float, float)
        Disjoint closed intervals of doubles, sorted: every double in them is
        passive, and every passive double is in them (a single passive point
        appears as ``(v, v)``).  The ends are the true end points rounded
        inward to doubles.
    critical_values : tuple of float
        Every value in the range where the verdict may change (nearest doubles,
        for information).
    edges : tuple of ((float, float), (float, float))
        For each interval, certified enclosures ``(lo, hi)`` of its true lower and
        upper end points (rounded outward; ``(v, v)`` for an end that is the
        double ``v`` exactly).
    """

    param: str
    lo: float
    hi: float
    intervals: tuple[tuple[float, float], ...] = ()
    critical_values: tuple[float, ...] = ()
    edges: tuple[tuple[tuple[float, float], tuple[float, float]], ...] = ()

    def contains(self, value: float) -> bool:
        return any(a <= value <= b for a, b in self.intervals)

    @property
    def passive_everywhere(self) -> bool:
        return len(self.intervals) == 1 and self.intervals[0] == (self.lo, self.hi)

    def to_dict(self) -> dict[str, Any]:
        return {
            "param": self.param,
            "range": [self.lo, self.hi],
            "intervals": [list(iv) for iv in self.intervals],
            "edges": [[list(lo), list(hi)] for lo, hi in self.edges],
            "critical_values": list(self.critical_values),
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """The passive set as a bar over the search range; returns the Axes."""
        from ..plot.region import plot_passive_intervals

        return plot_passive_intervals(self, ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "PassiveIntervals",
            {
                "param": self.param,
                "range": Shown(f"[{self.lo:g}, {self.hi:g}]"),
                "intervals": Shown(_intervals_text(self.intervals)),
            },
        )

    def _repr_html_(self) -> str:
        return html_card(
            f"Exact passive set of {self.param}",
            [
                ("search range", f"[{self.lo:g}, {self.hi:g}]"),
                ("passive for", _intervals_text(self.intervals)),
            ],
        )


def _intervals_text(intervals: Sequence[tuple[float, float]], limit: int = 4) -> str:
    if not intervals:
        return "[] (nowhere)"
    text = ", ".join(interval_text(a, b) for a, b in intervals[:limit])
    more = len(intervals) - limit
    return text + (f" and {more} more" if more > 0 else "")


@dataclass(frozen=True, kw_only=True)
class _Piece:
    """A cell of ``[lo, hi]``: an open gap between two critical values (or the range
    ends, which belong to it when they are not critical) or one rational critical value."""

    left: CriticalValue
    right: CriticalValue
    left_closed: bool
    right_closed: bool
    passive: bool


def _inward(
    piece_run: list[_Piece],
) -> tuple[tuple[float, float], tuple[tuple[float, float], tuple[float, float]]] | None:
    """A run of passive pieces as an interval of doubles rounded inward, and the
    enclosures of its true ends; ``None`` when no double lies in it."""
    left, right = piece_run[0], piece_run[-1]
    a, b = left.left, right.right
    if a.poly is not None:
        lo_f = float_above_root(a.poly, (a.lo, a.hi))
    else:
        lo_f = float_up(a.lo)
        if not left.left_closed and Fraction(lo_f) == a.lo:
            lo_f = float(np.nextafter(lo_f, np.inf))
    if b.poly is not None:
        hi_f = float_below_root(b.poly, (b.lo, b.hi))
    else:
        hi_f = float_down(b.hi)
        if not right.right_closed and Fraction(hi_f) == b.hi:
            hi_f = float(np.nextafter(hi_f, -np.inf))
    if lo_f > hi_f:
        return None
    edges = ((float_down(a.lo), float_up(a.hi)), (float_down(b.lo), float_up(b.hi)))
    return (lo_f, hi_f), edges


def _re_im_at_jw(expr: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """Real and imaginary parts of ``expr(jω)`` for a polynomial in ``s`` with real coefficients."""
    import sympy as sp

    from ..model.expr import S

    _X, _OM = _symbols()
    coeffs = sp.Poly(expr, S).all_coeffs()[::-1]
    re = sum((c * (-1) ** (k // 2) * _OM**k for k, c in enumerate(coeffs) if k % 2 == 0), sp.S.Zero)
    im = sum((c * (-1) ** (k // 2) * _OM**k for k, c in enumerate(coeffs) if k % 2 == 1), sp.S.Zero)
    return sp.expand(re), sp.expand(im)


def _critical_polys(z: sp.Expr, p: sp.Symbol) -> list[sp.Expr]:
    import sympy as sp

    from ..model.expr import S

    _X, _OM = _symbols()
    num, den = sp.fraction(sp.cancel(sp.together(z)))
    # clear denominators in p so both are polynomials in (s, p)
    num, den = sp.expand(num), sp.expand(den)
    out: list[sp.Expr] = []
    pn, pd = sp.Poly(num, S), sp.Poly(den, S)
    out += [pn.LC(), pd.LC()]
    if pn.degree() > 0 and pd.degree() > 0:
        out.append(sp.resultant(num, den, S))
    else:
        out += [pn.as_expr(), pd.as_expr()] if pn.degree() <= 0 else [pd.as_expr()]
    re_d, im_d = _re_im_at_jw(den)
    re_n, im_n = _re_im_at_jw(num)
    g = sp.gcd(re_d, im_d) if im_d != 0 else re_d
    g = sp.expand(g)
    if im_d != 0:
        r1, r2 = sp.cancel(re_d / g), sp.cancel(im_d / g)
        if sp.Poly(r1, _OM).degree() > 0 and sp.Poly(r2, _OM).degree() > 0:
            out.append(sp.resultant(r1, r2, _OM))
        else:
            out += [sp.Poly(r1, _OM).LC(), sp.Poly(r2, _OM).LC()]
    if g.has(_OM):
        gp = sp.Poly(g, _OM)
        out += [gp.LC(), g.subs(_OM, 0)]
        if gp.degree() > 1:
            out.append(sp.discriminant(g, _OM))
        ddr, ddi = _re_im_at_jw(sp.diff(den, S))
        for res in (sp.expand(re_n * ddr + im_n * ddi), sp.expand(im_n * ddr - re_n * ddi)):
            if res != 0:
                out.append(sp.resultant(g, res, _OM) if gp.degree() > 0 else res)
    # real part polynomial in x = ω²
    pw = sp.expand(re_n * re_d + im_n * im_d)
    if pw != 0:
        px = sp.expand(pw.subs(_OM, sp.sqrt(_X)))
        poly = sp.Poly(px, _X)
        # remove the generic power of x and generic repeated factors
        k = min(m[0] for m in poly.monoms())
        q = sp.Poly(sp.cancel(px / _X**k), _X)
        q = sp.Poly(sp.sqf_part(q.as_expr()), _X) if q.degree() > 0 else q
        out += [poly.LC(), q.as_expr().subs(_X, 0)]
        if q.degree() > 1:
            out.append(sp.discriminant(q.as_expr(), _X))
        # each coefficient of P matters where P may vanish identically
        out += [c for c in poly.all_coeffs() if c.has(p)]
    return [sp.expand(e) for e in out if sp.expand(e) != 0]


def critical_polynomials(
    system: SEA | Impedance,
    params: Sequence[str],
    *,
    values: Mapping[str, float | None] | None = None,
) -> list[sp.Expr]:
    """Polynomials in ``params`` on whose real zero set the verdict of ``system`` may change.

    Every parameter of ``system`` not in ``params`` must have a value (in
    ``system`` or ``values``); the result holds the critical polynomials
    described in the module docstring, with all of ``params`` symbolic (used
    for 2-D regions by [`seapass.analysis.boundary`][seapass.analysis.boundary]).
    """
    from ..model.expr import symbol
    from ..model.stiffness import load_impedance

    base = _with(system, {**(values or {}), **dict.fromkeys(params)})
    free = [n for n in base.parameters if n not in params and base.values.get(n) is None]
    if free:
        raise ParameterError(f"no value for parameter(s) {', '.join(free)}")
    z = load_impedance(base) if isinstance(base, SEA) else base.expr
    z = z.xreplace(base.substitutions())
    out: dict[sp.Expr, None] = {}
    for name in params:
        out.update(dict.fromkeys(_critical_polys(z, symbol(name))))
    return list(out)


def passive_intervals(
    system: SEA | Impedance,
    param: str,
    lo: float,
    hi: float,
    *,
    values: Mapping[str, float] | None = None,
) -> PassiveIntervals:
    """Exact set of values of ``param`` in ``[lo, hi]`` for which ``system`` is passive.

    Parameters
    ----------
    system : SEA or Impedance
        Model with values for every parameter except ``param``.
    param : str
        The free parameter, e.g. ``"kd"``.
    lo, hi : float
        Search range, ``lo <= hi``.
    values : mapping, optional
        Extra or overriding parameter values.

    Returns
    -------
    PassiveIntervals
    """
    lo_q, hi_q = to_fraction(lo, "lo"), to_fraction(hi, "hi")
    if lo_q > hi_q:
        raise ParameterError(f"empty range {lo}:{hi}: the lower bound must not exceed the upper")
    merged = {k: v for k, v in system.values.items() if k != param}
    merged.update({k: v for k, v in (values or {}).items() if k != param})
    if param not in system.parameters:
        raise ParameterError(
            f"parameter {param!r} does not appear in the model (its parameters: "
            f"{', '.join(system.parameters) or 'none'})"
        )
    free = [n for n in system.parameters if n != param and merged.get(n) is None]
    if free:
        raise ParameterError(
            f"no value for parameter(s) {', '.join(free)}: give them, "
            f"e.g. values={{{free[0]!r}: 1.0}}"
        )
    fixed = {k: v for k, v in merged.items() if v is not None}
    polys = critical_polynomials_in(system, param, exact_values(fixed))
    crit = critical_values_in(polys, lo_q, hi_q)

    def verdict(x: Fraction) -> bool:
        num, den, support = exact_with(system, fixed, param, x)
        if den.is_zero():
            raise ParameterError("the impedance has a zero denominator for these values")
        return positive_real_test(num, den, support=support).passive

    # one exact test per open gap and at each rational critical value
    pieces: list[_Piece] = []
    cursor, closed = CriticalValue(lo=lo_q, hi=lo_q), True  # the range end belongs to its gap
    for c in crit:
        if c.lo > cursor.hi:
            gap = verdict((cursor.hi + c.lo) / 2)
            pieces.append(
                _Piece(left=cursor, right=c, left_closed=closed, right_closed=False, passive=gap)
            )
        if c.poly is None:
            point = verdict(c.lo)
            pieces.append(
                _Piece(left=c, right=c, left_closed=True, right_closed=True, passive=point)
            )
        cursor, closed = c, False
    if hi_q > cursor.hi or not pieces:
        end, gap = CriticalValue(lo=hi_q, hi=hi_q), verdict((cursor.hi + hi_q) / 2)
        pieces.append(
            _Piece(left=cursor, right=end, left_closed=closed, right_closed=True, passive=gap)
        )
    # consecutive passive pieces share their critical value: one interval
    runs: list[list[_Piece]] = []
    previous_passive = False
    for piece in pieces:
        if piece.passive:
            if previous_passive:
                runs[-1].append(piece)
            else:
                runs.append([piece])
        previous_passive = piece.passive
    result: list[tuple[float, float]] = []
    edges: list[tuple[tuple[float, float], tuple[float, float]]] = []
    for run in runs:
        shown = _inward(run)
        if shown is not None:
            result.append(shown[0])
            edges.append(shown[1])
    crit_f = [float((c.lo + c.hi) / 2) for c in crit]
    return PassiveIntervals(
        param=param,
        lo=float(lo_q),
        hi=float(hi_q),
        intervals=tuple(result),
        critical_values=tuple(crit_f),
        edges=tuple(edges),
    )


def _with(system: SEA | Impedance, values: Mapping[str, Any]) -> SEA | Impedance:
    import sympy as sp

    from ..model.expr import symbol
    from ..model.stiffness import load_impedance

    vals = {k: (float(v) if isinstance(v, Fraction) else v) for k, v in values.items()}
    exact = {k: v for k, v in values.items() if isinstance(v, Fraction)}
    if exact and any(Fraction(float(v)) != v for v in exact.values()):
        # a rational test point that is not a float: substitute it exactly
        subs = {symbol(k): sp.Rational(v.numerator, v.denominator) for k, v in exact.items()}
        expr = load_impedance(system) if isinstance(system, SEA) else system.expr
        rest = {k: v for k, v in vals.items() if k not in exact}
        z = expr.xreplace(subs)
        left = {str(x) for x in z.free_symbols}  # the substituted names are gone from z
        merged = {**system.values, **rest}
        return Impedance(expr=z, values={k: v for k, v in merged.items() if k in left})
    if isinstance(system, SEA):
        return system.with_values(**vals)
    return Impedance(expr=system.expr, values={**system.values, **vals})


@dataclass(frozen=True, repr=False, kw_only=True)
class PassiveMap:
    """Passive region over two parameters.

    ``intervals[i]`` is the exact passive set of ``param_y`` at ``x[i]``;
    ``mask`` has axes ``(len(y), len(x))`` and marks grid points inside it.
    """

    param_x: str
    param_y: str
    x: np.ndarray
    y: np.ndarray
    intervals: tuple[tuple[tuple[float, float], ...], ...]
    mask: np.ndarray

    def to_dict(self) -> dict[str, Any]:
        return {
            "param_x": self.param_x,
            "param_y": self.param_y,
            "x": self.x.tolist(),
            "intervals": [[list(iv) for iv in ivs] for ivs in self.intervals],
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """The passive region as a filled map; returns the Axes."""
        from ..plot.region import plot_passive_map

        return plot_passive_map(self, ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "PassiveMap",
            {
                "x": Shown(f"{self.param_x} in [{self.x[0]:g}, {self.x[-1]:g}] ({self.x.size})"),
                "y": Shown(f"{self.param_y} in [{self.y[0]:g}, {self.y[-1]:g}]"),
                "passive_fraction": float(self.mask.mean()) if self.mask.size else None,
            },
        )

    def _repr_html_(self) -> str:
        return html_card(
            f"Passive region over {self.param_x} and {self.param_y}",
            [
                (self.param_x, f"{self.x.size} values in [{self.x[0]:g}, {self.x[-1]:g}]"),
                (self.param_y, f"exact along [{self.y[0]:g}, {self.y[-1]:g}]"),
                ("passive share of the grid", f"{self.mask.mean():.1%}" if self.mask.size else "-"),
            ],
        )


def passive_map(
    system: SEA | Impedance,
    param_x: str,
    x_values: Sequence[float] | np.ndarray,
    param_y: str,
    y_range: tuple[float, float],
    *,
    y_points: int = 200,
    values: Mapping[str, float] | None = None,
) -> PassiveMap:
    """Exact passive set of ``param_y`` along each value in ``x_values`` of ``param_x``.

    The boundary along ``param_y`` is exact at every ``x``; ``mask`` samples it
    on a ``y_points`` grid only for drawing.
    """
    xs = np.asarray(x_values, dtype=float)
    if xs.ndim != 1 or xs.size == 0:
        raise ParameterError(f"x_values must be a non-empty 1-D sequence, got shape {xs.shape}")
    ys = np.linspace(float(y_range[0]), float(y_range[1]), y_points)
    ivs: list[tuple[tuple[float, float], ...]] = []
    mask = np.zeros((ys.size, xs.size), dtype=bool)
    for i, xv in enumerate(xs):
        res = passive_intervals(
            system, param_y, y_range[0], y_range[1], values={**(values or {}), param_x: float(xv)}
        )
        ivs.append(res.intervals)
        for a, b in res.intervals:
            mask[:, i] |= (ys >= a) & (ys <= b)
    return PassiveMap(param_x=param_x, param_y=param_y, x=xs, y=ys, intervals=tuple(ivs), mask=mask)
