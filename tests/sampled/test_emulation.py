"""Exact emulation of numeric controllers (``sampled.emulation``) against the symbolic scheme.

The deployed difference equations and the sampled verdicts come from the exact path
(flint polynomials in ``q = z⁻¹``, no sympy).  The symbolic path of the same scheme
(``discrete_paths``, which the bound's controller families still use with a free
parameter) is an independent implementation: both must give the same ``DiscreteTF``
to the last bit, for every method and velocity filter.
"""

from __future__ import annotations

import sys
from fractions import Fraction

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.model.expr import S, parse_expression
from seapass.sampled.controllers import DiscreteTF, discrete_paths, discretize, filter_pole

Q = sp.Symbol("q")


def _symbolic(
    text: str, period: float, method: str, cutoff: float | None
) -> tuple[DiscreteTF, DiscreteTF]:
    """The scheme with sympy: split, discretize, cancel, read coefficients in q."""
    e = parse_expression(text, ())
    num, den = sp.fraction(sp.cancel(sp.together(e)))
    pn, pd = sp.Poly(num, S), sp.Poly(den, S)
    quo, rem = sp.div(pn, pd)
    coeffs = [sp.Rational(c) for c in quo.all_coeffs()[::-1]]
    proper = sp.cancel(rem.as_expr() / pd.as_expr())
    T = Fraction(repr(float(period)))
    err, meas = discrete_paths(coeffs, proper, T, method=method, velocity_filter=cutoff)

    def tf(expr: sp.Expr) -> DiscreteTF:
        n, d = sp.fraction(sp.cancel(sp.together(sp.sympify(expr))))
        asc = [
            tuple(Fraction(int(c.p), int(c.q)) for c in sp.Poly(sp.expand(x), Q).all_coeffs()[::-1])
            for x in (n, d)
        ]
        return DiscreteTF(asc[0], asc[1], T)

    return tf(err), tf(meas)


CONTROLLERS = [
    "500",
    "100 + 2*s",
    "500 + 25*s + 0.3*s**2",
    "100 + 40/s",
    "(3*s + 400)/(s/50 + 1)",
    "2 + 20/s + 0.01*s/(1 + s/300)",
    "(1 + 2 + 20/s + 0.01*s/(1 + s/300))*(1000 + 20*s) - (2 + 20/s + 0.01*s/(1 + s/300))*2500",
    "1/(s**2 + 3*s + 2)",
    "(s - 5)/(s + 5)",
]


@pytest.mark.parametrize("text", CONTROLLERS)
@pytest.mark.parametrize("method", ["tustin", "backward", "zoh"])
@pytest.mark.parametrize("cutoff", [None, 80.0])
def test_exact_emulation_equals_the_symbolic_scheme(text, method, cutoff):
    ours = discretize(text, 0.002, method=method, velocity_filter=cutoff, split=True)
    assert ours == _symbolic(text, 0.002, method, cutoff)


_coef = st.sampled_from([0, 1, 2, 0.5, 3.25, 40, 1e3, 1e-2, -7])


@settings(max_examples=40, deadline=None)
@given(
    num=st.lists(_coef, min_size=1, max_size=4),
    den=st.lists(_coef, min_size=1, max_size=3),
    method=st.sampled_from(["tustin", "backward"]),
    period=st.sampled_from([0.001, 0.002, 0.01]),
    cutoff=st.sampled_from([None, 30.0, 200.0]),
)
def test_random_controllers(num, den, method, period, cutoff):
    if all(c == 0 for c in den):
        return
    poly = lambda cs: " + ".join(f"({c!r})*s**{i}" for i, c in enumerate(cs))  # noqa: E731
    text = f"({poly(num)})/({poly(den)})"
    try:
        ours = discretize(text, period, method=method, velocity_filter=cutoff, split=True)
    except Exception as exc:  # the symbolic path must refuse the same input
        with pytest.raises(type(exc)):
            _symbolic(text, period, method, cutoff)
        return
    assert ours == _symbolic(text, period, method, cutoff)


def test_filter_pole_is_the_same_number():
    assert filter_pole(80.0, 0.002) == Fraction(
        __import__("math").exp(-2 * 3.141592653589793 * 80.0 * 0.002)
    )


def test_numeric_emulation_needs_no_sympy():
    import subprocess

    code = (
        "import sys; from seapass.sampled.controllers import discretize; "
        "discretize('2 + 20/s + 0.01*s/(1 + s/300)', 0.002, velocity_filter=50.0); "
        "print('sympy' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
