"""Exact passivity: reference cases, cross-checks and invariants."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, given
from hypothesis import strategies as st

from helpers import configs
from seapass.analysis.conditions import exact_passivity_condition
from seapass.analysis.passivity import is_passive
from seapass.errors import NotPassiveError, ParameterError
from seapass.model.catalog import PAPER_VALUES
from seapass.model.expr import symbol
from seapass.model.sea import SEA, Impedance

PAPER = PAPER_VALUES


@pytest.mark.parametrize(
    ("z", "values", "passive", "reason"),
    [
        ("(s + 1)/(s + 2)", {}, True, ""),
        ("1/(s + 1) - 1e-9", {}, False, "negative_real_part"),  # python-control says passive
        ("k*s/(s**2 + k)", {"k": 1e8}, True, ""),  # lossless spring, stiff
        ("k*s/(s**2 + k)", {"k": 1.0}, True, ""),
        ("m*s + b + k/s", {"m": 1.0, "b": 10.0, "k": 1e8}, True, ""),  # improper
        ("m*s + k/s", {"m": 2.0, "k": 3.0}, True, ""),  # lossless improper
        ("5", {}, True, ""),  # static gain
        ("0.5e-12", {}, True, ""),
        ("-5", {}, False, "negative_real_part"),
        ("-s + 10", {}, False, "infinity_residue"),
        ("1/s**2", {}, False, "relative_degree"),
        ("s**2 + 1", {}, False, "relative_degree"),
        ("1/(s - 1)", {}, False, "rhp_pole"),
        ("(s + 1)/(s**2 + 1)", {}, False, "axis_residue"),
        ("(s**2 + 4)/(s*(s**2 + 1))", {}, False, "axis_residue"),
        ("(s**2 + 1)/(s*(s**2 + 4))", {}, True, ""),
        ("(s**3 + 1)/((s**2 + 1)**2)", {}, False, "repeated_axis_pole"),
        ("(s - 1)/(s + 1)", {}, False, "negative_real_part"),
        ("(s + 3)/(s**2 - s + 1)", {}, False, "rhp_pole"),
        ("(s + 2)/((s - 1)*(s + 1))", {}, False, "rhp_pole"),
        ("(s**2 + 2*s + 2)/(s**2 + s + 1)", {}, True, ""),
        ("k1*(s**2 + 10*s + 500)/(s*(s**2 + 10*s + k1))", {"k1": 1e8}, True, ""),
    ],
)
def test_reference_impedances(z, values, passive, reason):
    r = is_passive(Impedance(expr=z, values=values))
    assert r.passive is passive
    assert r.reason == reason
    if reason == "negative_real_part":
        w = r.omega
        assert w is not None and w > 0
        zz = Impedance(expr=z, values=values).expr.subs(
            {symbol(k): sp.Rational(v) for k, v in values.items()}
        )
        val = complex(sp.N(zz.subs(sp.Symbol("s"), sp.I * sp.Rational(w)), 40))
        assert val.real < 0


def test_num_den_pairs_and_hidden_modes():
    assert is_passive(((1, 1), (1, 2))).passive
    # (s - 1)/(s - 1): an unstable mode cancels; it is not hidden from the verdict
    r = is_passive(((1, -1), (1, -1)))
    assert not r.passive and r.reason == "hidden_unstable_mode"
    assert is_passive(((1, 1), (1, 1))).passive


def test_throw_option():
    with pytest.raises(NotPassiveError, match="not passive"):
        is_passive("-1", throw=True)
    assert is_passive("1", throw=True).passive


def test_missing_values_is_a_clear_error():
    with pytest.raises(ParameterError, match="kd"):
        is_passive(SEA(D1="k1", CL="kd", values=PAPER))


@pytest.mark.parametrize("k", [1e2, 1e4, 1e6, 1e8])
def test_stiff_springs(k):
    vals = {"m": 1.0, "b": 10.0, "k1": k}
    assert is_passive(SEA(D1="k1", CL="kd", values={**vals, "kd": k})).passive  # boundary, exact
    assert not is_passive(SEA(D1="k1", CL="kd", values={**vals, "kd": k * (1 + 1e-12)})).passive
    assert is_passive(
        SEA(D1="k1", CA="kd + bd*s", values={**vals, "kd": 10 * k, "bd": 25.0})
    ).passive


def test_boundary_is_exact_and_marginal():
    r = is_passive(SEA(D1="k1", CL="kd", values={**PAPER, "kd": 1000.0}))
    assert r.passive and r.marginal and r.lossless
    r = is_passive(SEA(D1="k1", CL="kd", values={**PAPER, "kd": math.nextafter(1000.0, 2000.0)}))
    assert not r.passive and r.marginal


def test_proposed_design_from_the_issue():
    vals = {"m": 1, "b": 10, "k1": 1000, "b1": 20, "bd": 25, "kd": 5000}
    r = is_passive(SEA(D1="k1 + b1*s", CA="kd + bd*s", values=vals))
    assert r.passive and not r.marginal and r.omega is None
    d = r.to_dict()
    assert {"passive", "reason", "omega", "tolerance"} <= set(d)


# ---------------------------------------------------------------- python-control


def _pc_ispassive(num, den):
    control = pytest.importorskip("control")
    pytest.importorskip("cvxopt")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return bool(control.ispassive(control.tf(num, den)))


@pytest.mark.parametrize(
    ("num", "den"),
    [
        ([1, 1], [1, 2]),
        ([1, 3], [1, 2, 1]),
        ([2, 1], [1, 1]),
        ([1, -1], [1, 1]),
        ([1, 0, 1], [1, 2, 5]),
        ([1], [1, 1]),
        ([-1], [1, 3]),
    ],
)
def test_agrees_with_python_control_when_well_conditioned(num, den):
    assert is_passive((num, den)).passive == _pc_ispassive(num, den)


# ---------------------------------------------------------------- invariants

CONFIGS = configs(
    "LP",
    "LP-damped",
    "LPD",
    "APD",
    "API",
    "ours",
    "disjoint-damper",
    "spring-spring",
)
_COND_CACHE: dict[str, object] = {}


def _condition(name):
    if name not in _COND_CACHE:
        _COND_CACHE[name] = exact_passivity_condition(SEA(**CONFIGS[name])).condition
    return _COND_CACHE[name]


positive = st.floats(min_value=-2, max_value=4).map(lambda e: float(10**e))


@given(name=st.sampled_from(sorted(CONFIGS)), data=st.data())
def test_symbolic_condition_equals_exact_numeric_verdict(name, data):
    sea = SEA(**CONFIGS[name])
    vals = {p: data.draw(positive, label=p) for p in sea.parameters}
    r = is_passive(sea.with_values(**vals))
    assume(not r.marginal and abs(r.margin) > 1e-6)
    cond = _condition(name)
    subs = {symbol(k): sp.Rational(v) for k, v in vals.items()}
    assert bool(cond.xreplace(subs)) is r.passive


@given(name=st.sampled_from(sorted(CONFIGS)), data=st.data())
def test_verdict_matches_dense_frequency_sampling_away_from_boundary(name, data):
    sea = SEA(**CONFIGS[name])
    vals = {p: data.draw(positive, label=p) for p in sea.parameters}
    r = is_passive(sea.with_values(**vals))
    assume(abs(r.margin) > 1e-3)
    num, den = np.array(r.num), np.array(r.den)
    w = np.logspace(-4, 6, 4000)
    re = (np.polyval(num, 1j * w) / np.polyval(den, 1j * w)).real
    scale = np.abs(np.polyval(num, 1j * w) / np.polyval(den, 1j * w))
    if r.passive:
        assert np.all(re >= -1e-9 * scale)
    elif r.reason == "negative_real_part":
        wz = r.omega
        z = np.polyval(num, 1j * wz) / np.polyval(den, 1j * wz)
        assert z.real < 0


@given(
    name=st.sampled_from(sorted(CONFIGS)),
    data=st.data(),
    mass_unit=st.sampled_from([1e-3, 1.0, 1e3, 2.0**-10, 2.0**10]),
    time_unit=st.sampled_from([1e-3, 1.0, 1e3, 2.0**-6, 2.0**6]),
)
def test_verdict_invariant_under_change_of_units(name, data, mass_unit, time_unit):
    """kg -> g and s -> ms rescale every parameter by M * T**-n; passivity must not change."""
    sea = SEA(**CONFIGS[name])
    vals = {p: data.draw(positive, label=p) for p in sea.parameters}
    order = {"m": 0, "b": 1, "b1": 1, "b2": 1, "bd": 1, "k1": 2, "k2": 2, "kd": 2, "ki": 3}
    scaled = {p: v * mass_unit * time_unit ** -order[p] for p, v in vals.items()}
    r1 = is_passive(sea.with_values(**vals))
    r2 = is_passive(sea.with_values(**scaled))
    assume(not r1.marginal and not r2.marginal)
    assert r1.passive is r2.passive
    assert r1.reason == r2.reason


@pytest.mark.parametrize("eps", [1e-3, 1e-6, 1e-9, 1e-12])
def test_near_boundary_of_damped_lp(eps):
    """LP with a damped spring: boundary kd* from the discriminant; test both sides."""
    from seapass.analysis.region import passive_intervals

    sea = SEA(D1="k1 + b1*s", CL="kd", values={**PAPER, "b1": 20.0})
    ((lo, hi),) = passive_intervals(sea, "kd", 0, 1e4).intervals
    assert lo == 0.0 and hi == pytest.approx(849.1933384829667, rel=1e-15)
    assert is_passive(sea.with_values(kd=hi * (1 - eps))).passive
    assert not is_passive(sea.with_values(kd=hi * (1 + eps))).passive


@pytest.mark.parametrize(
    "values",
    [
        {"m": 1.0, "b": 10.0, "k1": 1000.0, "kd": 0.0, "bd": 1.1125e-308},
        {"m": 1e-300, "b": 1e-300, "k1": 1e300, "kd": 0.0, "bd": 1e300},
        {"m": 1e300, "b": 1e300, "k1": 1e300, "kd": 1e-300, "bd": 1e-300},
    ],
)
def test_extreme_magnitudes_give_a_verdict_not_an_overflow(values):
    """Load-side PD is never passive for bd > 0, even when numbers leave the double range."""
    r = is_passive(SEA(D1="k1", CL="kd + bd*s", values=values))
    assert r.passive is False and r.reason == "negative_real_part"
    assert r.omega is not None and r.omega > 0
    assert -1.0 <= r.margin <= 0.0
    assert all(isinstance(c, float) for c in r.num + r.den)


@pytest.mark.parametrize(
    ("elements", "values", "margin"),
    [
        (dict(D1="k1", CL="kd"), {**PAPER, "kd": 500.0}, 1 / 3),  # (k1 - kd)/(k1 + kd)
        (dict(D1="k1", CA="kd + bd*s"), {**PAPER, "kd": 500.0, "bd": 25.0}, 0.5),
    ],
)
def test_structural_cancellation_is_not_marginal(elements, values, margin):
    """Terms of Re N(jw)D(-jw) that cancel for every parameter value are no boundary."""
    r = is_passive(SEA(**elements, values=values))
    assert r.passive and not r.marginal
    assert r.margin == pytest.approx(margin, rel=1e-12)


def test_batch_margin_equals_scalar_margin():
    from seapass.batch.verdicts import batch_is_passive

    sea = SEA(D1="k1", CL="kd", values=PAPER)
    kd = np.array([0.0, 250.0, 500.0, 999.0])
    res = batch_is_passive(sea, {"kd": kd})
    for i, v in enumerate(kd):
        assert res.margin[i] == pytest.approx(
            is_passive(sea.with_values(kd=float(v))).margin, rel=1e-9
        )
