"""Critical values of one parameter on flint (``analysis.critical``) against the sympy version.

``seapass bound`` no longer imports sympy: the critical polynomials are formed on
bivariate flint polynomials.  The symbolic version (``critical_polynomials``, still used
for 2-D regions) is an independent implementation of the same list: for every standard
structure and every parameter both give the same critical values, and the verdict at
each value, from the exact path, equals the verdict from sympy's ``N/D``.
"""

from __future__ import annotations

import itertools
from fractions import Fraction

import pytest
import sympy as sp
from flint import fmpq, fmpq_poly

from seapass.analysis.critical import critical_polynomials_in, critical_values_in, exact_with
from seapass.analysis.passivity import positive_real_test
from seapass.analysis.region import critical_polynomials, passive_intervals
from seapass.model.catalog import REFERENCE_VALUES
from seapass.model.expr import S, symbol
from seapass.model.sea import SEA, exact_values
from seapass.model.stiffness import load_impedance

STRUCTURES = list(
    itertools.product(
        ("k1", "k1 + b1*s"),
        ("0", "k2", "b2*s"),
        ("0", "kd", "kd + bd*s", "kd + ki/s"),
        ("0", "kd", "kd + bd*s"),
    )
)


def _sympy_roots(polys: list[sp.Expr], p: sp.Symbol, lo: float, hi: float) -> list[float]:
    out: set[float] = set()
    for e in polys:
        if not e.has(p):
            continue
        for r in sp.Poly(e, p, domain="QQ").real_roots():
            v = float(r)
            if lo <= v <= hi:
                out.add(v)
    return sorted(out)


def _cases():
    for d1, d2, ca, cl in STRUCTURES:
        sea = SEA(D1=d1, D2=d2, CA=ca, CL=cl)
        for param in sea.parameters:
            if param in ("m",):
                continue
            yield pytest.param((d1, d2, ca, cl), param, id=f"{d1}/{d2}/{ca}/{cl}:{param}")


@pytest.mark.parametrize(("elements", "param"), list(_cases())[::3])
def test_the_same_critical_values_as_the_symbolic_polynomials(elements, param):
    sea = SEA(**dict(zip(("D1", "D2", "CA", "CL"), elements, strict=True)))
    fixed = {k: REFERENCE_VALUES[k] for k in sea.parameters if k != param}
    lo, hi = -1e5, 1e5
    ours = critical_values_in(
        critical_polynomials_in(sea, param, exact_values(fixed)), Fraction(lo), Fraction(hi)
    )
    theirs = _sympy_roots(critical_polynomials(sea, [param], values=fixed), symbol(param), lo, hi)
    assert len(ours) == len(theirs)
    for c, v in zip(ours, theirs, strict=True):
        a, b = c.lo, c.hi
        assert (float(a) <= v * (1 + 1e-12) + 1e-300 and v <= float(b) * (1 + 1e-12) + 1e-300) or (
            abs(float((a + b) / 2) - v) <= 1e-12 * max(1.0, abs(v))
        )


def _sympy_verdict(sea: SEA, values: dict[str, Fraction]):
    """Verdict from sympy's N/D with the values substituted, then cancelled again (as the
    symbolic path did for a rational test point)."""
    z = load_impedance(sea).xreplace({symbol(k): sp.Rational(v) for k, v in values.items()})
    n, d = sp.fraction(sp.cancel(sp.together(z)))

    def poly(e: sp.Expr) -> fmpq_poly:
        c = sp.Poly(sp.expand(e), S).all_coeffs()[::-1]
        return fmpq_poly([fmpq(int(sp.Rational(x).p), int(sp.Rational(x).q)) for x in c])

    return positive_real_test(poly(n), poly(d))


@pytest.mark.parametrize(
    "elements",
    [("k1", "0", "0", "kd"), ("k1 + b1*s", "0", "0", "kd + bd*s"), ("k1", "k2", "kd + ki/s", "kd")],
)
def test_verdicts_at_rational_points_match_sympy(elements):
    sea = SEA(**dict(zip(("D1", "D2", "CA", "CL"), elements, strict=True)))
    fixed = {k: REFERENCE_VALUES[k] for k in sea.parameters if k != "kd"}
    for x in (Fraction(1, 3), Fraction(1000), Fraction(2001, 7), Fraction(5, 2)):
        num, den, support = exact_with(sea, fixed, "kd", x)
        ours = positive_real_test(num, den, support=support)
        ref = _sympy_verdict(sea, {**{k: Fraction(v) for k, v in fixed.items()}, "kd": x})
        assert (ours.passive, ours.reason) == (ref.passive, ref.reason)


def test_the_readme_bound():
    sea = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1, b=10, k1=1000, b1=20, kd=None))
    res = passive_intervals(sea, "kd", 0, 1e5)
    assert res.critical_values == (0.0, 300.0, 849.1933384829667, 1000.0)
    assert res.intervals == ((0.0, 849.1933384829667),)
