"""Exact passivity (positive-realness) of a port impedance.

A rational impedance ``Z = N/D`` (real coefficients, reduced) is positive real,
hence passive and coupled-stable with every passive environment, if and only if

1. its relative degree ``deg D − deg N`` is −1, 0 or 1;
2. it has no pole in the open right half-plane;
3. its poles on the imaginary axis, including ``s = 0`` and ``s = ∞``, are
   simple with real positive residues;
4. ``Re Z(jω) ≥ 0`` for every ``ω`` that is not a pole.

Every condition is decided in exact rational arithmetic: each float input is
converted to the rational number it represents, so the verdict is exact for
the numbers given.  Condition 4 is the sign of the even polynomial
``P(ω) = Re(N(jω) D(−jω))``, decided on ``P`` as a polynomial in ``x = ω²``
over ``x ≥ 0`` by the exact kernel [`seapass.exact.poly`][seapass.exact.poly]
(python-flint: exact gcd and squarefree parts, certified real-root isolation,
exact sign checks).  No frequency grid is used.

References
----------
.. [1] B. D. O. Anderson and S. Vongpanitlerd, *Network Analysis and Synthesis*,
   Prentice-Hall, 1973, sec. 5.1 (positive real functions).
.. [2] J. E. Colgate and N. Hogan, "Robust control of dynamically interacting
   systems", Int. J. Control 48(1), 1988.
.. [3] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Eqs. (5)-(7).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

import numpy as np
from flint import fmpq, fmpq_poly

from ..errors import NotPassiveError, ParameterError
from ..exact import poly as ep
from ..exact.axis import (
    all_real_roots,
    at_j_omega,
    axis_factor,
    even_to_x,
    is_hurwitz,
    log2,
    negative_point,
    safe_float,
)
from ..model.display import html_card, poly_text, short_repr
from ..outcome import Outcome
from .impedance import SystemLike, evaluate_system
from .portresponse import ImpedanceResponse, response_of

__all__ = [
    "TOLERANCE_POLICY",
    "PassivityResult",
    "Reason",
    "is_passive",
    "positive_real_test",
]

MARGINAL_RTOL = 1e-9
"""Relative margin below which an exact verdict is flagged ``marginal``."""

TOLERANCE_POLICY = (
    "exact: every input float is converted to the rational it represents and all "
    "conditions are decided in exact rational arithmetic (certified real-root isolation "
    "with exact sign checks), so the "
    "verdict has no tolerance; a design whose scale-invariant margin "
    "min_{x>=0} P(x)/A(x) (A: P with every product in absolute value, on the powers "
    "of x that P has for generic parameter values) lies within "
    f"{MARGINAL_RTOL:g} of zero is additionally flagged 'marginal' (the margin itself "
    "is computed in floating point and is informative only)"
)


class Reason(StrEnum):
    """Why an impedance is not positive real (`NONE` when it is)."""

    NONE = ""
    RELATIVE_DEGREE = "relative_degree"
    RHP_POLE = "rhp_pole"
    REPEATED_AXIS_POLE = "repeated_axis_pole"
    AXIS_RESIDUE = "axis_residue"
    INFINITY_RESIDUE = "infinity_residue"
    NEGATIVE_REAL_PART = "negative_real_part"
    HIDDEN_UNSTABLE_MODE = "hidden_unstable_mode"

    @property
    def description(self) -> str:
        """One plain sentence for people (figure titles, reports)."""
        return _DESCRIPTIONS[self]


_DESCRIPTIONS = {
    Reason.NONE: "positive real",
    Reason.RELATIVE_DEGREE: "relative degree is not -1, 0 or 1",
    Reason.RHP_POLE: "pole in the open right half-plane",
    Reason.REPEATED_AXIS_POLE: "repeated pole on the imaginary axis",
    Reason.AXIS_RESIDUE: "imaginary-axis pole with a residue that is not real and positive",
    Reason.INFINITY_RESIDUE: "pole at infinity with a negative coefficient",
    Reason.NEGATIVE_REAL_PART: "Re Z(jw) < 0 at some frequency",
    Reason.HIDDEN_UNSTABLE_MODE: "cancelled (hidden) mode in the closed right half-plane",
}


@dataclass(frozen=True, repr=False, kw_only=True)
class PassivityResult:
    """Outcome of an exact positive-real test.

    Attributes
    ----------
    outcome : Outcome
        Exact verdict for the given numbers: ``PASSIVE`` or ``NOT_PASSIVE``, never
        ``UNDECIDED`` (``passive`` is ``outcome.passive``).
    reason : Reason
        `Reason.NONE` (``""``) when passive, else why not, e.g.
        `Reason.NEGATIVE_REAL_PART`.
    detail : str
        Human-readable explanation.
    omega : float or None
        A witness frequency [rad/s] with ``Re Z(jω) < 0`` when one exists.
    margin : float
        Scale-invariant margin ``min_{x>=0} P(x)/A(x)`` in [-1, 1], where ``A``
        is ``P`` with every product in absolute value, on the powers of ``x``
        that ``P`` has for generic parameter values (0 for lossless designs;
        about ``ε`` at relative distance ``ε`` from a boundary).  Informative,
        not used for the verdict.
    marginal : bool
        Decided, but ``|margin| <= MARGINAL_RTOL`` (or lossless): the one meaning
        of [`seapass.outcome`][seapass.outcome].
    lossless : bool
        ``Re Z(jω) ≡ 0``.
    num, den : tuple of float
        Reduced ``Z = N/D`` coefficients, descending powers of ``s``.
    real_part : tuple of float
        Coefficients of ``P`` in ``x = ω²``, ascending powers.
    tolerance : str
        The tolerance policy used (`TOLERANCE_POLICY`).
    exact_num, exact_den : flint.fmpq_poly or None
        The reduced ``N`` and ``D`` exactly (for
        `response` and `plot`; not part of ``to_dict``).

    Examples
    --------
    >>> r = is_passive("(s - 1)/(s + 2)")
    >>> r
    PassivityResult(passive=False, reason='negative_real_part', omega=..., margin=...)
    >>> [round(x, 6) for x in r.response().negative_bands[0]]
    [0.0, 1.414214]
    """

    outcome: Outcome
    reason: Reason = Reason.NONE
    detail: str = ""
    omega: float | None = None
    margin: float = math.nan
    marginal: bool = False
    lossless: bool = False
    num: tuple[float, ...] = ()
    den: tuple[float, ...] = ()
    real_part: tuple[float, ...] = ()
    axis_poles: tuple[float, ...] = field(default=())
    tolerance: str = TOLERANCE_POLICY
    exact_num: fmpq_poly | None = field(default=None, compare=False)
    exact_den: fmpq_poly | None = field(default=None, compare=False)

    @property
    def passive(self) -> bool:  # the exact verdict as a bool
        return self.outcome.passive

    @property
    def status(self) -> str:
        """Words for people (the JSON ``status``): ``outcome.label``, with ``" (marginal)"``."""
        return f"{self.outcome.label} (marginal)" if self.marginal else self.outcome.label

    def to_dict(self) -> dict[str, Any]:
        return {
            "passive": self.passive,
            "status": self.status,
            "reason": self.reason,
            "detail": self.detail,
            "omega": self.omega,
            "margin": self.margin,
            "marginal": self.marginal,
            "lossless": self.lossless,
            "num": list(self.num),
            "den": list(self.den),
            "real_part_x": list(self.real_part),
            "axis_poles": list(self.axis_poles),
            "tolerance": self.tolerance,
        }

    def response(self, omega: Any = None, *, label: str = "") -> ImpedanceResponse:
        """``Z(jω)`` of the tested impedance and the exact bands where ``Re Z(jω) < 0``.

        Parameters
        ----------
        omega : array_like, shape (n,), optional
            Frequencies [rad/s]; default a grid around the poles and zeros.
        label : str, optional
            Legend label.
        """
        if self.exact_num is not None and self.exact_den is not None:
            num, den = self.exact_num, self.exact_den
        else:  # built by hand from floats: the rationals those floats represent
            num = ep.as_poly(list(reversed(self.num)))
            den = ep.as_poly(list(reversed(self.den)))
        return response_of(num, den, omega, label=label)

    def plot(self, kind: str = "real", *, ax: Any = None, omega: Any = None, **kwargs: Any) -> Any:
        """``Re Z(jω)`` with the failing bands shaded (``kind="real"``) or the Nyquist plot of ``Z``.

        The bands are exact (see `response`).  Returns the matplotlib Axes.
        """
        from ..plot.passivity import plot_impedance

        return plot_impedance(self.response(omega), kind=kind, ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "PassivityResult",
            {
                "passive": self.passive,
                "reason": str(self.reason) or None,
                "omega": self.omega,
                "margin": self.margin,
                "marginal": self.marginal or None,
                "lossless": self.lossless or None,
            },
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [("verdict", self.status), ("detail", self.detail)]
        if self.omega is not None:
            rows.append(("witness", f"Re Z(jω) < 0 at ω = {self.omega:.6g} rad/s"))
        rows += [
            ("margin", f"{self.margin:.3g}"),
            ("Z(s) numerator", poly_text(self.num)),
            ("Z(s) denominator", poly_text(self.den)),
        ]
        return html_card(
            f"Passivity: {self.status}", rows, note="Exact verdict (rational arithmetic)."
        )


# ---------------------------------------------------------------- helpers


def _margin(px: fmpq_poly, pabs: fmpq_poly) -> float:
    """Scale-invariant margin ``min_{x>=0} P(x)/A(x)`` in [-1, 1] (floating point).

    ``A`` is ``P`` computed with every product taken in absolute value, so the
    ratio measures how much of ``P`` survives cancellation: a design at relative
    distance ``ε`` from a boundary has a margin of order ``ε``.  The ratio is
    invariant to scaling ``x`` and the coefficients, so both are balanced
    exactly (powers of two) before converting to floats.
    """
    if px.is_zero():
        return 0.0
    n = max(px.degree(), pabs.degree()) + 1
    c = [px[i] for i in range(n)]
    a = [pabs[i] for i in range(n)]
    nz = [i for i, v in enumerate(a) if v]
    lo, hi = nz[0], nz[-1]
    k = round((log2(a[lo]) - log2(a[hi])) / (hi - lo)) if hi > lo else 0
    xs = fmpq(2) ** k
    c = [v * xs**i for i, v in enumerate(c)]
    a = [v * xs**i for i, v in enumerate(a)]
    top = max(a)
    cs = np.array([float(v / top) for v in c])
    as_ = np.array([float(v / top) for v in a])
    cands = [float(c[lo] / a[lo]), float(c[hi] / a[hi])]
    pp, aa = np.polynomial.Polynomial(cs), np.polynomial.Polynomial(as_)
    crit: Any = (pp.deriv() * aa - pp * aa.deriv()).roots() if n > 1 else []
    for r in np.atleast_1d(crit):
        if abs(r.imag) <= 1e-9 * max(1.0, abs(r.real)) and r.real > 0 and aa(r.real) > 0:
            cands.append(float(pp(r.real) / aa(r.real)))
    return float(np.clip(min(cands), -1.0, 1.0))


def _abs_poly(p: fmpq_poly) -> fmpq_poly:
    return fmpq_poly([abs(c) for c in p.coeffs()])


def _margin_of(num: fmpq_poly, den: fmpq_poly, support: Sequence[bool] | None) -> float:
    """`_margin` of ``num/den`` as given, with ``A`` restricted to ``support``."""
    if num.is_zero():
        return 0.0
    nr, ni = at_j_omega(num)
    dr, di = at_j_omega(den)
    px = even_to_x(nr * dr + ni * di)
    pabs = even_to_x(_abs_poly(nr) * _abs_poly(dr) + _abs_poly(ni) * _abs_poly(di))
    if support is not None:
        pabs = fmpq_poly(
            [c if i < len(support) and support[i] else 0 for i, c in enumerate(pabs.coeffs())]
        )
        if pabs.is_zero():
            return 0.0
    return _margin(px, pabs)


def _fail(reason: Reason, detail: str, **kw: Any) -> PassivityResult:
    no = Outcome.NOT_PASSIVE
    return PassivityResult(outcome=no, reason=reason, detail=detail or reason.description, **kw)


def _to_floats(p: fmpq_poly, descending: bool) -> tuple[float, ...]:
    vals = tuple(safe_float(c) for c in p.coeffs())
    return tuple(reversed(vals)) if descending else vals


# ---------------------------------------------------------------- core test


def positive_real_test(
    num: ep.PolyLike,
    den: ep.PolyLike,
    *,
    hidden: ep.PolyLike | None = None,
    support: Sequence[bool] | None = None,
) -> PassivityResult:
    """Exact positive-real test of ``Z = num/den``.

    ``num`` and ``den`` are `flint.fmpq_poly` or ascending sequences of exact
    rationals (converted by [`as_poly`][seapass.exact.poly.as_poly]).

    ``hidden`` is an optional polynomial of modes known to cancel (e.g. from
    a model's internal structure); a root of it in the closed right
    half-plane makes the system not passive.  A common factor of ``num`` and
    ``den`` is such a mode too.

    ``support`` (from `structural_support`) marks the powers of ``x`` that
    ``P`` has for generic parameter values; the margin is computed from
    ``num/den`` as given and ignores cancellations outside the support.

    Examples
    --------
    >>> from fractions import Fraction
    >>> positive_real_test([1, 1], [2, 1]).passive  # (s + 1)/(s + 2)
    True
    >>> positive_real_test([Fraction(-1, 2), 1], [1, 1]).reason  # (s − 1/2)/(s + 1)
    <Reason.NEGATIVE_REAL_PART: 'negative_real_part'>
    """
    num, den = ep.as_poly(num), ep.as_poly(den)
    hid = fmpq_poly([]) if hidden is None else ep.as_poly(hidden)
    if den.is_zero():
        raise ParameterError("the denominator is identically zero")
    margin = _margin_of(num, den, support)
    g = num.gcd(den) if not num.is_zero() else ep.monic(den)
    if g.degree() > 0:
        hid = g if hid.is_zero() else hid * g
        num, den = num // g, den // g
    if den.leading_coefficient() < 0:
        num, den = -num, -den
    base: dict[str, Any] = {
        "num": _to_floats(num, True),
        "den": _to_floats(den, True),
        "margin": margin,
        "exact_num": num,
        "exact_den": den,
    }
    if num.is_zero():
        return PassivityResult(
            outcome=Outcome.PASSIVE,
            detail="Z is identically zero",
            marginal=True,
            lossless=True,
            **base,
        )
    if not hid.is_zero() and _pole_defect(hid)[0]:
        return _fail(Reason.HIDDEN_UNSTABLE_MODE, "", **base)

    # 4 (computed first, so the margin and witness are always reported)
    nr, ni = at_j_omega(num)
    dr, di = at_j_omega(den)
    px = even_to_x(nr * dr + ni * di)
    base["real_part"] = _to_floats(px, False)
    base["lossless"] = px.is_zero()

    # 1. relative degree and the pole at infinity
    rel = den.degree() - num.degree()
    if rel not in (-1, 0, 1):
        return _fail(
            Reason.RELATIVE_DEGREE, f"relative degree is {rel}; it must be -1, 0 or 1", **base
        )
    if rel == -1 and num.leading_coefficient() / den.leading_coefficient() <= 0:
        return _fail(Reason.INFINITY_RESIDUE, "Z ~ c*s at high frequency with c <= 0", **base)

    # 2./3. poles: imaginary-axis part and the rest
    defect, g_ax = _pole_defect(den)
    if defect:
        return _fail(defect, "", **base)
    axis: list[ep.Interval] = []
    if g_ax.degree() > 0:
        axis = ep.isolate_real_roots(g_ax, 0)
        if g_ax[0] == 0:
            axis = [(fmpq(0), fmpq(0)), *axis]
    base["axis_poles"] = tuple(ep.root_value(g_ax, iv) for iv in axis)
    ddr, ddi = at_j_omega(den.derivative())
    # residue at jω0 ∝ N(jω0)·conj(D'(jω0)): imaginary part must vanish, real part > 0
    res_re = nr * ddr + ni * ddi
    res_im = ni * ddr - nr * ddi
    for iv in axis:
        if ep.sign_at_root(res_im, g_ax, iv) != 0 or ep.sign_at_root(res_re, g_ax, iv) <= 0:
            w0 = ep.root_value(g_ax, iv)
            return _fail(
                Reason.AXIS_RESIDUE,
                f"the pole at s = j*{w0:.6g} has a residue that is not real and positive",
                **base,
            )

    # 4. Re Z(jω) >= 0 for all ω
    marginal = abs(margin) <= MARGINAL_RTOL
    if px.is_zero():
        lossless = "lossless: Re Z(jw) = 0 for all w"
        return PassivityResult(outcome=Outcome.PASSIVE, detail=lossless, marginal=True, **base)
    odd = ep.positive_roots_odd_multiplicity(px)
    if ep.count_real_roots(odd, 0) == 0 and px.leading_coefficient() > 0:
        return PassivityResult(
            outcome=Outcome.PASSIVE, detail=Reason.NONE.description, marginal=marginal, **base
        )
    witness = negative_point(px)
    return _fail(
        Reason.NEGATIVE_REAL_PART,
        f"Re Z(jw) < 0 at w = {witness:.6g} rad/s",
        omega=witness,
        marginal=marginal,
        **base,
    )


def _pole_defect(den: fmpq_poly) -> tuple[Reason, fmpq_poly]:
    """Why the roots of ``den`` are not admissible poles (`Reason.NONE` if they are).

    Admissible: open left half-plane, or simple on the imaginary axis.  Also
    returns ``gcd(Re den(jω), Im den(jω))``, whose real roots are the axis poles.
    """
    dr, di = at_j_omega(den)
    g_ax = dr.gcd(di)
    rest = den
    if g_ax.degree() > 0:
        # a non-real root of g_ax is a pair of roots mirrored about the axis
        if not all_real_roots(g_ax):
            return Reason.RHP_POLE, g_ax
        if ep.squarefree_part(g_ax).degree() != g_ax.degree():
            return Reason.REPEATED_AXIS_POLE, g_ax
        rest, rem = divmod(den, axis_factor(g_ax))
        if not rem.is_zero():
            raise ArithmeticError("axis factor does not divide the denominator")  # pragma: no cover
    if not is_hurwitz(rest):
        return Reason.RHP_POLE, g_ax
    return Reason.NONE, g_ax


# ---------------------------------------------------------------- entry point


def is_passive(
    system: SystemLike,
    *,
    values: Mapping[str, float] | None = None,
    throw: bool = False,
) -> PassivityResult:
    """Decide exactly whether the port impedance of ``system`` is positive real.

    Parameters
    ----------
    system : SEA, Impedance, str, sympy.Expr or (num, den)
        An SEA (its load impedance ``Z_L = F_L/(s X_L)`` is tested), a raw
        impedance, an expression in ``s`` such as ``"(s + 1)/(s + 2)"``, or a
        pair of descending coefficient sequences.
    values : mapping, optional
        Parameter values overriding those stored in ``system``.
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] instead of returning a
        non-passive result.

    Returns
    -------
    PassivityResult

    Examples
    --------
    >>> is_passive("(s + 1)/(s + 2)").passive
    True
    >>> is_passive("1/(s + 1) - 1e-9").passive
    False
    """
    num, den, support = evaluate_system(system, values)
    result = positive_real_test(num, den, support=support)
    if throw and not result.passive:
        raise NotPassiveError(f"not passive: {result.detail}")
    return result
