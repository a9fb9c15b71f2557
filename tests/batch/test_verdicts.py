"""Batch passivity verdicts must equal the exact scalar verdicts, design by design."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.analysis.passivity import is_passive
from seapass.analysis.region import passive_intervals
from seapass.batch.verdicts import _exact_one, batch_is_passive, compile_passivity
from seapass.errors import ParameterError
from seapass.model.catalog import PAPER_VALUES, design
from seapass.model.sea import SEA

PHYS = PAPER_VALUES

CONFIGS = {
    # the paper's baselines and proposed design (Sec. V)
    "load_side_P": design("LP").sea(PHYS),
    "actuator_PD": design("APD").sea(PHYS),
    "proposed": design("ours").sea(PHYS),
    # configurations with nontrivial passivity boundaries
    "load_side_P_damped": SEA(D1="k1 + b1*s", CL="kd", values={**PHYS, "b1": 20.0, "kd": None}),
    "load_side_PD": SEA(D1="k1", CL="kd + bd*s", values={**PHYS, "kd": None, "bd": None}),
    "mixed": SEA(
        D1="k1 + b1*s",
        D2="k2",
        CA="kd + bd*s",
        CL="ki",
        values={**PHYS, "b1": 20.0, "k2": 50.0, "kd": None, "bd": 30.0, "ki": None},
    ),
}


def _exact(sea: SEA, point: dict[str, float]):
    return is_passive(sea.with_values(**point))


def _check_against_exact(sea: SEA, vals: dict[str, np.ndarray], margins: bool = True) -> None:
    res = batch_is_passive(sea, vals)
    shape = res.passive.shape
    flat = {p: np.broadcast_to(np.asarray(v, dtype=float), shape).ravel() for p, v in vals.items()}
    for i in range(res.passive.size):
        point = {p: float(v[i]) for p, v in flat.items()}
        ex = _exact(sea, point)
        assert bool(res.passive.ravel()[i]) == ex.passive, point
        if margins and np.isfinite(ex.margin):
            assert res.margin.ravel()[i] == pytest.approx(ex.margin, rel=1e-6, abs=1e-9), point


@pytest.mark.parametrize("name", sorted(CONFIGS))
def test_random_designs_match_exact(name: str) -> None:
    sea = CONFIGS[name]
    rng = np.random.default_rng(abs(hash(name)) % 2**32)
    vals = {p: rng.uniform(-500.0, 3000.0, 40) for p in sea.free_parameters}
    _check_against_exact(sea, vals)


# load-side PD is never passive for bd > 0 (paper, Table II), so it has no boundary in kd
@pytest.mark.parametrize("name", sorted(set(CONFIGS) - {"load_side_PD"}))
def test_near_boundary_designs_match_exact(name: str) -> None:
    sea = CONFIGS[name]
    fixed = {p: 7.0 for p in sea.free_parameters if p != "kd"}
    sea1 = sea.with_values(**fixed)
    ends = [e for iv in passive_intervals(sea1, "kd", -1e4, 1e4).intervals for e in iv]
    ends = [e for e in ends if abs(e) < 1e4]
    assert ends, "expected a finite passivity boundary"
    pts = []
    for e in ends:
        pts.append(e)
        up = dn = e
        for _ in range(4):
            up, dn = np.nextafter(up, np.inf), np.nextafter(dn, -np.inf)
            pts += [up, dn]
        pts += [e * (1 + 1e-12), e * (1 - 1e-12), e * (1 + 1e-9), e * (1 - 1e-9)]
    vals = {"kd": np.array(pts), **{p: np.array([v]) for p, v in fixed.items()}}
    res = batch_is_passive(sea, vals)
    assert res.n_exact > 0  # the boundary really is exercised
    _check_against_exact(sea, vals, margins=False)


def test_paper_configurations_at_paper_values() -> None:
    # load-side P (stable below kd = k1), actuator-side PD, and Ours (Sec. V, Fig. 3)
    lp = batch_is_passive(CONFIGS["load_side_P"], {"kd": np.array([500.0, 1000.0, 1500.0])})
    assert lp.passive.tolist() == [True, True, False]
    prop = batch_is_passive(
        CONFIGS["proposed"], {"b1": 20.0, "kd": np.array([[5000.0], [1e5]]), "bd": [25.0, 1.0]}
    )
    assert prop.passive.shape == (2, 2)
    _check_against_exact(
        CONFIGS["proposed"],
        {
            "b1": np.array([20.0] * 4),
            "kd": np.array([5000.0, 5000.0, 1e5, 1e5]),
            "bd": np.array([25.0, 1.0, 25.0, 1.0]),
        },
    )


@settings(max_examples=25, deadline=None)
@given(
    b1=st.floats(1e-3, 1e4),
    kd=st.floats(1e-3, 1e7),
    bd=st.floats(1e-3, 1e4),
)
def test_proposed_design_is_passive_for_all_positive_gains(b1: float, kd: float, bd: float) -> None:
    # D1 = k1 + b1 s with C_A = kd + bd s renders a network of physical springs,
    # dampers and a mass: passive for every positive gain (the paper's bound
    # kd <= ((b+bd)^2 + b b1 + b1 bd)/2m is sufficient, not necessary).
    res = batch_is_passive(CONFIGS["proposed"], {"b1": b1, "kd": kd, "bd": bd})
    assert bool(res.passive)
    assert bool(res.passive) == _exact(CONFIGS["proposed"], dict(b1=b1, kd=kd, bd=bd)).passive


@settings(max_examples=30, deadline=None)
@given(kd=st.floats(-3000, 3000), bd=st.floats(-50, 50))
def test_hypothesis_load_side_pd(kd: float, bd: float) -> None:
    sea = CONFIGS["load_side_PD"]
    res = batch_is_passive(sea, {"kd": kd, "bd": bd})
    assert bool(res.passive) == _exact(sea, dict(kd=kd, bd=bd)).passive


def test_exact_fallback_equals_is_passive() -> None:
    sea = CONFIGS["mixed"]
    kernel = compile_passivity(sea, ("kd", "ki"))
    rng = np.random.default_rng(5)
    for kd, ki in rng.uniform(-200, 2000, (15, 2)):
        verdict, margin = _exact_one(kernel, [kd, ki])
        ex = _exact(sea, dict(kd=kd, ki=ki))
        assert verdict == ex.passive
        assert margin == pytest.approx(ex.margin, rel=1e-9, abs=1e-12)


def test_most_random_designs_are_certified_in_float() -> None:
    sea = CONFIGS["load_side_P_damped"]
    res = batch_is_passive(sea, {"kd": np.linspace(1.0, 5000.0, 10001)})
    assert res.certified.mean() > 0.99
    assert 0 < res.passive.mean() < 1


def test_broadcasting_and_axis_order() -> None:
    sea = CONFIGS["actuator_PD"]
    kd = np.array([[100.0], [2000.0], [9000.0]])
    bd = np.array([[1.0, 10.0, 100.0, 1000.0]])
    res = batch_is_passive(sea, {"kd": kd, "bd": bd})
    assert res.passive.shape == (3, 4) and res.margin.shape == (3, 4)
    for i in range(3):
        for j in range(4):
            assert res.passive[i, j] == _exact(sea, dict(kd=kd[i, 0], bd=bd[0, j])).passive
    assert not res.passive.flags.writeable


def test_errors_name_argument_and_shape() -> None:
    sea = CONFIGS["actuator_PD"]
    with pytest.raises(ParameterError, match=r"values\['bd'\] has shape \(4,\).*kd: \(3,\)"):
        batch_is_passive(sea, {"kd": np.ones(3), "bd": np.ones(4)})
    with pytest.raises(ParameterError, match="bd"):
        batch_is_passive(sea, {"kd": np.ones(3)})
    with pytest.raises(ParameterError, match="zz"):
        batch_is_passive(sea, {"kd": 1.0, "bd": 1.0, "zz": 1.0})
    with pytest.raises(ParameterError, match=r"values\['kd'\].*non-finite"):
        batch_is_passive(sea, {"kd": [1.0, np.nan], "bd": 1.0})


def test_fixed_parameter_can_be_swept() -> None:
    sea = CONFIGS["load_side_P_damped"]
    k1 = np.array([10.0, 100.0, 1000.0, 1e8])
    res = batch_is_passive(sea, {"kd": 400.0, "k1": k1})
    for i, v in enumerate(k1):
        assert res.passive[i] == _exact(sea, dict(kd=400.0, k1=v)).passive


def test_chunking_does_not_change_results() -> None:
    sea = CONFIGS["load_side_P_damped"]
    kd = np.linspace(0.0, 3000.0, 301)
    a = batch_is_passive(sea, {"kd": kd})
    b = batch_is_passive(sea, {"kd": kd}, chunk_size=7)
    np.testing.assert_array_equal(a.passive, b.passive)
    np.testing.assert_allclose(a.margin, b.margin, rtol=1e-12, atol=1e-15)
    c = batch_is_passive(sea, {"kd": kd}, margin=False)
    np.testing.assert_array_equal(a.passive, c.passive)
    assert np.isnan(c.margin).all()


def test_undefined_impedance_is_reported_not_raised() -> None:
    sea = SEA(
        D1="k1 + b1*s",
        CA="kd + bd*s",
        values=dict(m=None, b=None, k1=1000.0, b1=None, kd=None, bd=None),
    )
    bad = dict(m=0.0, b=0.0, b1=0.0, bd=0.0, kd=np.array([-1000.0, 5.0]))
    res = batch_is_passive(sea, bad)
    assert res.undefined.tolist() == [True, False]
    assert not res.passive[0] and np.isnan(res.margin[0])
    with pytest.raises(ParameterError, match=r"zero denominator.*kd=-1000"):
        batch_is_passive(sea, bad, throw=True)
