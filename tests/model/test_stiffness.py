"""First-principles derivation against the paper's Eq. (4) and physical limits."""

import pytest
import sympy as sp

from seapass.model.expr import S, symbol
from seapass.model.sea import SEA
from seapass.model.stiffness import (
    derive_stiffness,
    load_impedance,
    paper_eq4_stiffness,
    passivity_polynomial,
)

k1, k2, kd, bd, b1, b2, m, b = (symbol(n) for n in ("k1", "k2", "kd", "bd", "b1", "b2", "m", "b"))


@pytest.mark.parametrize(
    "elements",
    [
        dict(D1="k1", CL="kd"),
        dict(D1="k1 + b1*s", CA="kd + bd*s"),
        dict(D1="k1", CA="kd + ki/s"),
        dict(D1="k1", CL="kd + bd*s", CA="kd"),
        dict(D1="(k1*s + 3)/(s + 1)", CA="kd*(s + 2)/(s + 5)"),
    ],
)
def test_eq4_agrees_without_ground_element(elements):
    sea = SEA(**elements)
    assert sp.simplify(derive_stiffness(sea).stiffness - paper_eq4_stiffness(sea)) == 0


@pytest.mark.parametrize("d2", ["k2", "b2*s", "k2 + b2*s"])
def test_eq4_misses_the_d1_d2_term(d2):
    sea = SEA(D1="k1", D2=d2, CL="kd")
    derived = derive_stiffness(sea).stiffness
    eq4 = paper_eq4_stiffness(sea)
    # the ground element acts in parallel with the port: F_L/X_L = (SEA without D2) + D2
    without = derive_stiffness(SEA(D1="k1", CL="kd")).stiffness
    assert sp.simplify(derived - (without + sea.D2)) == 0
    assert sp.simplify(derived - eq4 - sea.D1 * sea.D2 / (m * S**2 + b * S + k1)) == 0


def test_physical_limits():
    sea = SEA(D1="k1 + b1*s", D2="k2", CA="kd + bd*s")
    f = derive_stiffness(sea).stiffness
    # actuator held rigidly (infinite actuator gain): the person feels D1 + D2
    assert sp.simplify(sp.limit(f, kd, sp.oo) - (k1 + b1 * S + k2)) == 0
    # a massless, undamped, uncontrolled actuator transmits nothing: only D2 remains
    free = derive_stiffness(SEA(D1="k1", D2="k2")).stiffness
    assert sp.simplify(free.subs({m: 0, b: 0}) - k2) == 0


def test_actuator_motion_and_impedance():
    sea = SEA(D1="k1", CA="kd")
    d = derive_stiffness(sea)
    assert sp.simplify(d.actuator_motion - k1 / (m * S**2 + b * S + k1 + kd)) == 0
    assert sp.simplify(load_impedance(sea) * S - d.stiffness) == 0
    assert len(d.equations) == 3


def test_paper_eq1_typo_is_not_reproduced():
    """Eq. (1) prints b*xdd_A; with viscous damping b*xd_A the pure-spring polynomial is b*k1*(k1-kd)*w^2."""
    w = sp.Symbol("w", real=True)
    p = passivity_polynomial(SEA(D1="k1", CL="kd"))
    assert sp.expand(p - b * k1 * (k1 - kd) * w**2) == 0
