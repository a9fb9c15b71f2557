"""The controller ``K(s) = [C_A  C_L]`` realized once and minimally (issue 22, item 1).

Cross-checks written apart from ``seapass.model.minimal``: the McMillan degree of the
row from sympy's lcm of the reduced denominators, the transfer matrix back from the
realization compared with sympy's cancelled ``C_A``, ``C_L``, and the closed-loop poles
against the roots of the characteristic polynomial derived by hand from the free-body
equations (sympy).
"""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from seapass.errors import UnrealizableError
from seapass.model.catalog import CATALOG
from seapass.model.minimal import controller_realization
from seapass.model.realization import closed_loop, closed_loop_factory
from seapass.model.sea import SEA

S = sp.Symbol("s")

CASCADE = SEA(
    D1="k1 + b1*s",
    CA="(kf + ki/s)*k1 + ba*s",
    CL="(1 + kf + ki/s)*(kv + bv*s) - (kf + ki/s)*k1",
    values=dict(m=0.4, b=3, k1=2500, b1=2, kf=0.5, ki=10, kv=1000, bv=5, ba=5),
    name="cascade",
)


def _mcmillan_degree(ca: sp.Expr, cl: sp.Expr) -> int:
    """Degree of the lcm of the reduced denominators of the strictly proper parts (sympy)."""
    dens = []
    for e in (ca, cl):
        num, den = sp.fraction(sp.cancel(sp.together(e)))
        _q, r = sp.div(sp.Poly(num, S), sp.Poly(den, S))
        rn, rd = sp.fraction(sp.cancel(r.as_expr() / den))
        dens.append(sp.Poly(rd, S) if rn != 0 else sp.Poly(1, S))
    return int(sp.lcm(dens[0], dens[1]).degree())


def _same_rational(got: tuple, expr: sp.Expr) -> bool:
    num, den = got
    g = sum(sp.Rational(int(c.p), int(c.q)) * S**i for i, c in enumerate(num.coeffs()))
    d = sum(sp.Rational(int(c.p), int(c.q)) * S**i for i, c in enumerate(den.coeffs()))
    return sp.cancel(g / d - expr) == 0


def _random_row(rng: random.Random) -> tuple[sp.Expr, sp.Expr]:
    """Two controllers sharing some poles (integrators, filters, complex pairs) at random."""
    pool = [
        S,
        S + rng.randint(1, 50),
        S**2 + rng.randint(1, 9) * S + rng.randint(10, 90),
        S + sp.Rational(rng.randint(1, 99), rng.randint(1, 9)),
    ]
    shared = sp.Mul(*rng.sample(pool, rng.randint(0, 2)))
    own = [sp.Mul(*rng.sample(pool, rng.randint(0, 2))) for _ in range(2)]
    out = []
    for own_den in own:
        den = sp.expand(shared * own_den)
        deg = sp.Poly(den, S).degree()
        top = deg + rng.choice([0, 1])  # proper, or one derivative
        num = sum(rng.randint(-20, 20) * S**i for i in range(top + 1))
        out.append(num / den if num != 0 else sp.Integer(rng.randint(1, 9)))
    return out[0], out[1]


def test_the_cascade_has_one_integrator() -> None:
    k = controller_realization(CASCADE)
    assert k.order == 1 and k.is_minimal()
    assert k.denominator == (0, 1)  # D = s
    for i, attr in enumerate(("CA", "CL")):
        assert _same_rational(k.entry(i), CASCADE.numeric(getattr(CASCADE, attr)))


def test_random_rows_are_realized_minimally_and_exactly() -> None:
    rng = random.Random(2201)
    for _ in range(60):
        ca, cl = _random_row(rng)
        k = controller_realization(SEA(D1="k1", CA=ca, CL=cl, values=dict(m=1, b=1, k1=1)))
        assert k.order == _mcmillan_degree(ca, cl), (ca, cl)
        assert k.is_minimal(), (ca, cl)
        assert _same_rational(k.entry(0), ca) and _same_rational(k.entry(1), cl)


@given(
    p=st.integers(1, 60),
    a=st.integers(1, 30),
    c=st.integers(-30, -2),
    shared=st.booleans(),
)
def test_a_shared_pole_is_one_state(p: int, a: int, c: int, shared: bool) -> None:
    q = p if shared else p + 1
    ca, cl = (a + 1) / (S + p), (c + 1) / (S + q)
    k = controller_realization(SEA(D1="k1", CA=ca, CL=cl, values=dict(m=1, b=1, k1=1)))
    assert k.order == (1 if shared else 2) and k.is_minimal()


@pytest.mark.parametrize("key", sorted(CATALOG))
def test_catalog_controllers_introduce_no_uncontrollable_or_unobservable_mode(key: str) -> None:
    entry = CATALOG[key]
    sea = entry.sea()
    vals = {p: 3.0 for p in sea.parameters}
    k = controller_realization(sea, values=vals)
    assert k.is_minimal()
    assert k.order == _mcmillan_degree(sea.CA.subs(vals), sea.CL.subs(vals))


def test_improper_controller_is_refused() -> None:
    with pytest.raises(UnrealizableError, match="at most one derivative"):
        controller_realization(SEA(D1="k1", CA="kd*s**2", values=dict(m=1, b=1, k1=1, kd=1)))


def _denominator(e: sp.Expr) -> sp.Poly:
    return sp.Poly(sp.fraction(sp.cancel(sp.together(e)))[1], S)


def _characteristic(sea: SEA, load_mass: float) -> sp.Poly:
    """``det`` of the free-body equations times ``d1 d2 lcm(d_A, d_L)`` (by hand, sympy).

    Not cancelled: a factor the determinant shares with the denominators is still a mode.
    """
    e = {k: sea.numeric(v) for k, v in sea.elements().items()}
    clear = (
        _denominator(e["D1"]) * _denominator(e["D2"])
        * sp.lcm(_denominator(e["CA"]), _denominator(e["CL"]))
    )  # fmt: skip
    alpha = e["m"] * S**2 + e["b"] * S
    mat = sp.Matrix(
        [
            [alpha + e["D1"] + e["CA"], -e["D1"] + e["CL"]],
            [-e["D1"], sp.Rational(load_mass) * S**2 + e["D1"] + e["D2"]],
        ]
    )
    char = sp.cancel(sp.together(mat.det() * clear.as_expr()))
    assert sp.fraction(char)[1].free_symbols == set()  # a polynomial
    return sp.Poly(char, S)


def _monic(c: np.ndarray) -> np.ndarray:
    return np.asarray(c, dtype=float) / float(c[0])


@pytest.mark.parametrize(
    "sea",
    [
        CASCADE,
        SEA(D1="k1 + b1*s", CA="kd + bd*s/(1 + s/300)", CL="ki/s",
            values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=20, ki=50)),
        SEA(D1="k1", CA="(kf + ki/s + kdf*s/(1 + s/200))*k1", CL="-(kf + ki/s + kdf*s/(1 + s/200))*k1 + kv",
            values=dict(m=0.5, b=4, k1=2000, kf=0.4, ki=8, kdf=0.01, kv=800)),
    ],
)  # fmt: skip
def test_closed_loop_poles_are_the_roots_of_the_exact_characteristic_polynomial(sea: SEA) -> None:
    sys = closed_loop(sea, load_mass=2.0)
    char = _characteristic(sea, 2.0)
    assert len(sys.states) == char.degree()  # no extra (cancelled) state
    want = _monic(np.array([float(c) for c in char.all_coeffs()]))
    got = _monic(np.poly(sys.A))
    np.testing.assert_allclose(got, want, rtol=1e-7, atol=1e-7 * np.abs(want).max())


def test_the_tuning_factory_builds_the_same_minimal_loop() -> None:
    gains = ("kf", "ki", "kv")
    build = closed_loop_factory(CASCADE, gains, load_mass=2.0)
    sys = build([CASCADE.values[g] for g in gains])
    ref = closed_loop(CASCADE, load_mass=2.0)
    assert sys.states == ref.states
    np.testing.assert_allclose(np.sort_complex(sys.poles), np.sort_complex(ref.poles), rtol=1e-9)
