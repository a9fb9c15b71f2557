"""The exact positive-real test before python-flint (benchmark reference only).

A frozen copy of ``positive_real_test`` and the imaginary-axis helpers it used
(``seapass.analysis.passivity`` and ``seapass.exact.axis`` as they were before
the kernel moved onto python-flint), running on `legacy_exactpoly` (tuples of
Fractions).  ``bench_exact.py`` times it against the current
``positive_real_test`` on the same exact ``(N, D)`` and checks that every
verdict and reason is identical.  Not part of the package.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

import numpy as np

import legacy_exactpoly as ep
from seapass.analysis.passivity import MARGINAL_RTOL, PassivityResult, Reason
from seapass.errors import ParameterError
from seapass.outcome import Outcome

# ---------------------------------------------------------------- imaginary axis


def at_j_omega(p: ep.Poly) -> tuple[ep.Poly, ep.Poly]:
    """Real and imaginary parts of ``p(jω)`` as real polynomials in ``ω``."""
    re = [Fraction(0)] * len(p)
    im = [Fraction(0)] * len(p)
    for k, c in enumerate(p):
        sign = -1 if (k // 2) % 2 else 1
        if k % 2 == 0:
            re[k] = sign * c
        else:
            im[k] = sign * c
    return ep.normalize(re), ep.normalize(im)


def axis_factor(g: ep.Poly) -> ep.Poly:
    """``∏(s − jω_i)`` over the roots ``ω_i`` of ``g`` (all real, conjugate-symmetric)."""
    n = ep.degree(g)
    lead = g[-1]
    out = []
    for k, c in enumerate(g):
        if (n + k) % 2:
            if c != 0:
                raise ArithmeticError("imaginary-axis factor is not conjugate-symmetric")
            out.append(Fraction(0))
            continue
        sign = (-1) ** k * (-1) ** ((n + k) // 2)
        out.append(sign * c / lead)
    return ep.normalize(out)


def is_hurwitz(p: ep.Poly) -> bool:
    """Exact Routh test: all roots of ``p`` in the open left half-plane."""
    if ep.degree(p) <= 0:
        return bool(p)
    desc = list(reversed(p))
    if desc[0] < 0:
        desc = [-c for c in desc]
    rows = [desc[0::2], desc[1::2]]
    n = len(desc) - 1
    for _ in range(n - 1):
        a, b = rows[-2], rows[-1]
        if not b or b[0] <= 0:
            return False
        new = []
        for i in range(len(a) - 1):
            bi1 = b[i + 1] if i + 1 < len(b) else Fraction(0)
            new.append((b[0] * a[i + 1] - a[0] * bi1) / b[0])
        rows.append(new)
    return all(r and r[0] > 0 for r in rows[: n + 1])


def even_to_x(p: ep.Poly) -> ep.Poly:
    if any(p[k] != 0 for k in range(1, len(p), 2)):
        raise ArithmeticError("Re(N(jw)D(-jw)) is not even in w")
    return ep.normalize(list(p[0::2]))


def log2(q: Fraction) -> float:
    return math.log2(q.numerator) - math.log2(q.denominator)


def safe_float(q: Fraction) -> float:
    """``float(q)``, saturating to ``±inf`` beyond the double range."""
    try:
        return float(q)
    except OverflowError:
        return math.inf if q > 0 else -math.inf


def all_real_roots(g: ep.Poly) -> bool:
    sf = ep.squarefree_part(g)
    lo = -ep.cauchy_bound(sf)
    return ep.count_real_roots(sf, lo, None) == ep.degree(sf)


def negative_point(px: ep.Poly) -> float:
    """A frequency where ``P(ω²) < 0`` (exactly checked), preferring the most negative one."""
    sf = ep.squarefree_part(px)
    # refine until every isolating interval starts strictly after the previous
    # root's interval (and after 0), however close the roots are
    tight: list[tuple[Fraction, Fraction]] = []
    prev = Fraction(0)
    for a, b in ep.isolate_real_roots(px, Fraction(0), None):
        while a <= prev:
            a, b = ep.refine(sf, a, b, (b - a) / 2)
        tight.append((a, b))
        prev = b
    points: list[Fraction] = []
    lo = Fraction(0)
    for a, b in tight:
        points.append((lo + a) / 2)
        lo = b
    points.append(lo * 2 + 1)
    neg = [x for x in points if x > 0 and ep.evaluate(px, x) < 0]
    if not neg:
        raise ArithmeticError("no witness found although P changes sign")  # pragma: no cover
    # relative depth |P|/Σ|c_i|x^i lies in [0, 1], so it converts to float safely
    depth = [abs(ep.evaluate(px, x)) / sum(abs(c) * x**i for i, c in enumerate(px)) for x in neg]
    best = neg[int(np.argmax([float(d) for d in depth]))]
    return sqrt_float(best)


def sqrt_float(q: Fraction) -> float:
    """``sqrt(q)`` as a float without overflow for rationals beyond the float range."""
    half_log = 0.5 * (math.log(q.numerator) - math.log(q.denominator))
    return math.exp(half_log) if half_log < 709.0 else math.inf


# ---------------------------------------------------------------- the test


def _margin(px: ep.Poly, pabs: ep.Poly) -> float:
    """Scale-invariant margin ``min_{x>=0} P(x)/A(x)`` in [-1, 1] (floating point).

    ``A`` is ``P`` computed with every product taken in absolute value, so the
    ratio measures how much of ``P`` survives cancellation: a design at relative
    distance ``ε`` from a boundary has a margin of order ``ε``.  The ratio is
    invariant to scaling ``x`` and the coefficients, so both are balanced
    exactly (powers of two) before converting to floats.
    """
    if not px:
        return 0.0
    n = max(len(px), len(pabs))
    c = [px[i] if i < len(px) else Fraction(0) for i in range(n)]
    a = [pabs[i] if i < len(pabs) else Fraction(0) for i in range(n)]
    nz = [i for i, v in enumerate(a) if v]
    lo, hi = nz[0], nz[-1]
    k = round((log2(a[lo]) - log2(a[hi])) / (hi - lo)) if hi > lo else 0
    xs = Fraction(2) ** k
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


def _abs_poly(p: ep.Poly) -> ep.Poly:
    return tuple(abs(c) for c in p)


def _margin_of(num: ep.Poly, den: ep.Poly, support: Sequence[bool] | None) -> float:
    """`_margin` of ``num/den`` as given, with ``A`` restricted to ``support``."""
    if not num:
        return 0.0
    nr, ni = at_j_omega(num)
    dr, di = at_j_omega(den)
    px = even_to_x(ep.add(ep.mul(nr, dr), ep.mul(ni, di)))
    pabs = even_to_x(
        ep.add(ep.mul(_abs_poly(nr), _abs_poly(dr)), ep.mul(_abs_poly(ni), _abs_poly(di)))
    )
    if support is not None:
        pabs = ep.normalize(
            [c if i < len(support) and support[i] else Fraction(0) for i, c in enumerate(pabs)]
        )
        if not pabs:
            return 0.0
    return _margin(px, pabs)


def _fail(reason: Reason, detail: str, **kw: Any) -> PassivityResult:
    return PassivityResult(
        outcome=Outcome.NOT_PASSIVE, reason=reason, detail=detail or reason.description, **kw
    )


def _to_floats(p: ep.Poly, descending: bool) -> tuple[float, ...]:
    vals = tuple(safe_float(c) for c in p)
    return tuple(reversed(vals)) if descending else vals


# ---------------------------------------------------------------- core test


def positive_real_test(
    num: ep.Poly,
    den: ep.Poly,
    *,
    hidden: ep.Poly = (),
    support: Sequence[bool] | None = None,
) -> PassivityResult:
    """Exact positive-real test of ``Z = num/den`` (ascending Fraction coefficients).

    ``hidden`` is an optional polynomial of modes known to cancel (e.g. from
    a model's internal structure); a root of it in the closed right
    half-plane makes the system not passive.  A common factor of ``num`` and
    ``den`` is such a mode too.

    ``support`` (from `structural_support`) marks the powers of ``x`` that
    ``P`` has for generic parameter values; the margin is computed from
    ``num/den`` as given and ignores cancellations outside the support.
    """
    num, den = ep.normalize(num), ep.normalize(den)
    if not den:
        raise ParameterError("the denominator is identically zero")
    margin = _margin_of(num, den, support)
    g = ep.pgcd(num, den) if num else ep.monic(den)
    if ep.degree(g) > 0:
        hidden = ep.mul(hidden, g) if hidden else g
        num, den = ep.pdivmod(num, g)[0], ep.pdivmod(den, g)[0]
    if den[-1] < 0:
        num, den = ep.scale(num, Fraction(-1)), ep.scale(den, Fraction(-1))
    base: dict[str, Any] = {
        "num": _to_floats(num, True),
        "den": _to_floats(den, True),
        "margin": margin,
    }
    if not num:
        return PassivityResult(
            outcome=Outcome.PASSIVE,
            detail="Z is identically zero",
            marginal=True,
            lossless=True,
            **base,
        )
    if hidden and _pole_defect(hidden)[0]:
        return _fail(Reason.HIDDEN_UNSTABLE_MODE, "", **base)

    # 4 (computed first, so the margin and witness are always reported)
    nr, ni = at_j_omega(num)
    dr, di = at_j_omega(den)
    p_w = ep.add(ep.mul(nr, dr), ep.mul(ni, di))
    px = even_to_x(p_w)
    base["real_part"] = _to_floats(px, False)
    base["lossless"] = not px

    # 1. relative degree and the pole at infinity
    rel = ep.degree(den) - ep.degree(num)
    if rel not in (-1, 0, 1):
        return _fail(
            Reason.RELATIVE_DEGREE, f"relative degree is {rel}; it must be -1, 0 or 1", **base
        )
    if rel == -1 and num[-1] / den[-1] <= 0:
        return _fail(Reason.INFINITY_RESIDUE, "Z ~ c*s at high frequency with c <= 0", **base)

    # 2./3. poles: imaginary-axis part and the rest
    defect, g_ax = _pole_defect(den)
    if defect:
        return _fail(defect, "", **base)
    axis: list[tuple[Fraction, Fraction]] = []
    if ep.degree(g_ax) > 0:
        axis = ep.isolate_real_roots(g_ax, Fraction(0), None)
        if ep.evaluate(g_ax, Fraction(0)) == 0:
            axis = [(Fraction(0), Fraction(0)), *axis]
    base["axis_poles"] = tuple(ep.root_value(g_ax, a, b) if a != b else float(a) for a, b in axis)
    dd = ep.derivative(den)
    ddr, ddi = at_j_omega(dd)
    # residue at jω0 ∝ N(jω0)·conj(D'(jω0)): imaginary part must vanish, real part > 0
    res_re = ep.add(ep.mul(nr, ddr), ep.mul(ni, ddi))
    res_im = ep.sub(ep.mul(ni, ddr), ep.mul(nr, ddi))
    gsf = ep.squarefree_part(g_ax) if axis else ()
    for a, b in axis:
        if ep.sign_at_root(res_im, gsf, a, b) != 0 or ep.sign_at_root(res_re, gsf, a, b) <= 0:
            w0 = float(a) if a == b else ep.root_value(gsf, a, b)
            return _fail(
                Reason.AXIS_RESIDUE,
                f"the pole at s = j*{w0:.6g} has a residue that is not real and positive",
                **base,
            )

    # 4. Re Z(jω) >= 0 for all ω
    marginal = abs(margin) <= MARGINAL_RTOL
    if not px:
        return PassivityResult(
            outcome=Outcome.PASSIVE,
            detail="lossless: Re Z(jw) = 0 for all w",
            marginal=True,
            **base,
        )
    odd = ep.positive_roots_odd_multiplicity(px)
    if ep.count_real_roots(odd, Fraction(0), None) == 0 and px[-1] > 0:
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


def _pole_defect(den: ep.Poly) -> tuple[Reason, ep.Poly]:
    """Why the roots of ``den`` are not admissible poles (`Reason.NONE` if they are).

    Admissible: open left half-plane, or simple on the imaginary axis.  Also
    returns ``gcd(Re den(jω), Im den(jω))``, whose real roots are the axis poles.
    """
    dr, di = at_j_omega(den)
    g_ax = ep.pgcd(dr, di)
    rest = den
    if ep.degree(g_ax) > 0:
        # a non-real root of g_ax is a pair of roots mirrored about the axis
        if not all_real_roots(g_ax):
            return Reason.RHP_POLE, g_ax
        if ep.degree(ep.squarefree_part(g_ax)) != ep.degree(g_ax):
            return Reason.REPEATED_AXIS_POLE, g_ax
        rest, rem = ep.pdivmod(den, axis_factor(g_ax))
        if rem:
            raise ArithmeticError("axis factor does not divide the denominator")  # pragma: no cover
    if not is_hurwitz(rest):
        return Reason.RHP_POLE, g_ax
    return Reason.NONE, g_ax
