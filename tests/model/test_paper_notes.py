"""Tests that back the entries of docs/notes-on-the-paper.md."""

import sympy as sp

from seapass import SEA, exact_passivity_condition, is_passive, passive_intervals
from seapass.model import load_impedance
from seapass.model.catalog import PAPER_VALUES
from seapass.model.expr import symbol
from seapass.model.stiffness import passivity_polynomial

PAPER = PAPER_VALUES


def test_eq1_with_b_xdd_has_no_dissipation():
    """Entry 1: with b*xdd_A (the printed Eq. 1) the pure spring would be lossless."""
    printed = SEA(D1="k1", CL="kd", m="m + b", b=0)
    assert sp.expand(passivity_polynomial(printed)) == 0


def test_ground_damper_only_adds_b2():
    """Entry 5: Z with a damper to ground is Z of the pure spring plus b2."""
    with_damper = load_impedance(SEA(D1="k1", D2="b2*s", CL="kd"))
    pure = load_impedance(SEA(D1="k1", CL="kd"))
    assert sp.simplify(with_damper - pure - symbol("b2")) == 0


def test_ground_damper_beats_pure_spring():
    """Entry 5: the paper's bound (k1 <= b^2/m) excludes everything; the exact set exceeds k1."""
    for b2, expected in ((20.0, 1195.0), (2.0, 1019.5)):
        res = passive_intervals(
            SEA(D1="k1", D2="b2*s", CL="kd", values={**PAPER, "b2": b2}), "kd", 0, 1e5
        )
        assert res.intervals == ((0.0, expected),)
        assert expected > PAPER["k1"]


def test_load_side_pi_has_a_double_pole_at_zero():
    """Entry 7."""
    r = is_passive(SEA(D1="k1", CL="kd + ki/s", values={**PAPER, "kd": 100.0, "ki": 1.0}))
    assert not r.passive and r.reason == "repeated_axis_pole"


def test_positive_coefficients_do_not_imply_stability():
    """Entry 8: actuator-side PI is unstable when m*ki > b*(k1 + kd)."""
    cond = exact_passivity_condition(SEA(D1="k1", CA="kd + ki/s"))
    assert str(cond.pole_conditions) == "b*k1 + b*kd - ki*m > 0"
    r = is_passive(SEA(D1="k1", CA="kd + ki/s", values={**PAPER, "kd": 100.0, "ki": 1e6}))
    assert not r.passive and r.reason == "rhp_pole"


def test_proposed_design_passive_for_all_gains_symbolically():
    """Entry 10: the exact condition is identically true."""
    assert exact_passivity_condition(SEA(D1="k1 + b1*s", CA="kd + bd*s")).condition == sp.true
    assert exact_passivity_condition(SEA(D1="k1 + b1*s", CA="kd")).condition == sp.true
