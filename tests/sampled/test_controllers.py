"""Discrete-time controllers: discretization and difference equations."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.signal import cont2discrete, lfilter

from seapass.errors import ParameterError, UnrealizableError
from seapass.model.sea import SEA
from seapass.sampled.controllers import (
    APDController,
    DifferenceEquation,
    DiscreteController,
    DiscreteTF,
    LPController,
    OursController,
    discretize,
    filter_pole,
)


def test_backward_difference_pd_is_exact() -> None:
    k = discretize("100 + 2*s", 0.01, method="backward")
    assert k.num == (Fraction(300), Fraction(-200))
    assert k.den == (Fraction(1),)
    assert k.period == Fraction(1, 100)


def test_derivative_uses_backward_difference_for_every_method() -> None:
    for method in ("tustin", "zoh", "backward"):
        err, meas = discretize("7 + 3*s", 0.002, method=method, split=True)
        assert err.num == (Fraction(7),)
        assert meas.num == (Fraction(1500), Fraction(-1500))


@pytest.mark.parametrize("method", ["tustin", "zoh"])
def test_proper_part_matches_scipy(method: str) -> None:
    k = discretize("10/(s + 3)", 0.01, method=method)
    scipy_method = "bilinear" if method == "tustin" else "zoh"
    nd, dd, _ = cont2discrete(([10.0], [1.0, 3.0]), 0.01, method=scipy_method)
    nd = np.squeeze(nd)
    w = np.exp(1j * np.linspace(0.1, 3.0, 7))
    ours = np.array([k(z) for z in w])
    ref = np.polyval(nd, w) / np.polyval(dd, w)
    np.testing.assert_allclose(ours, ref, rtol=1e-9)


@settings(max_examples=30, deadline=None)
@given(
    a=st.floats(0.1, 100),
    g=st.floats(-50, 50).filter(lambda x: abs(x) > 1e-3),
    method=st.sampled_from(["tustin", "zoh", "backward"]),
)
def test_dc_gain_is_preserved(a: float, g: float, method: str) -> None:
    k = discretize(f"{g}/(s + {a})", 0.002, method=method)  # type: ignore[arg-type]
    assert k.dc_gain() == pytest.approx(g / a, rel=1e-9)


@settings(max_examples=30, deadline=None)
@given(
    num=st.lists(st.floats(-5, 5), min_size=1, max_size=4),
    poles=st.lists(st.floats(-0.9, 0.9), min_size=0, max_size=3),
    seed=st.integers(0, 2**16),
)
def test_difference_equation_matches_lfilter(
    num: list[float], poles: list[float], seed: int
) -> None:
    den = np.poly(poles) if poles else np.array([1.0])
    tf = DiscreteTF(tuple(Fraction(x) for x in num), tuple(Fraction(x) for x in den), Fraction(1))
    de = DifferenceEquation(tf)
    x = np.random.default_rng(seed).normal(size=40)
    y = np.array([de.step(v) for v in x])
    np.testing.assert_allclose(
        y, lfilter([float(c) for c in tf.num], [float(c) for c in tf.den], x), rtol=1e-9, atol=1e-9
    )
    de.reset()
    assert de.step(0.0) == 0.0


def test_velocity_filter_estimates_slope_of_a_ramp() -> None:
    _err, meas = discretize("s", 0.002, velocity_filter=50.0, split=True)
    de = DifferenceEquation(meas)
    v = [de.step(0.3 * 0.002 * k) for k in range(400)]
    assert v[-1] == pytest.approx(0.3, rel=1e-9)
    assert 0 < v[1] < 0.3  # filtered, not the raw difference
    assert filter_pole(50.0, 0.002) == Fraction(np.exp(-2 * np.pi * 50 * 0.002))
    assert filter_pole(None, 0.002) == 0


def test_derivative_on_measurement_has_no_reference_kick() -> None:
    c = APDController(100.0, 50.0, 0.01)
    u0 = c.step((0.0, 0.0), (0.01, 0.0))
    assert u0 == pytest.approx(100.0 * 0.01)  # no bd * dθ/dt spike
    u1 = c.step((0.001, 0.0), (0.01, 0.0))
    assert u1 == pytest.approx(100.0 * 0.009 - 50.0 * 0.001 / 0.01)


def test_named_controllers() -> None:
    lp = LPController(500.0, 0.002)
    assert lp.step((0.01, 0.02)) == pytest.approx(-500 * 0.02)  # acts on x_L only
    ours = OursController(1000.0, 25.0, 0.002)
    assert ours.step((0.01, 0.5)) == pytest.approx(-1000 * 0.01 - 25 * 0.01 / 0.002)
    ours.reset()
    assert ours.step((0.0, 0.0)) == 0.0
    ka, kl = ours.transfer_functions()
    assert kl.is_zero and not ka.is_zero


def test_from_sea_uses_model_values() -> None:
    sea = SEA(
        D1="k1", CA="kd + bd*s", CL="ki/s", values={"k1": 1.0, "kd": 2.0, "bd": 0.5, "ki": 3.0}
    )
    c = DiscreteController.from_sea(sea, 0.01, method="tustin")
    _ka, kl = c.transfer_functions()
    assert np.allclose(sorted(abs(kl.poles())), [1.0])  # integrator at z = 1


def test_errors() -> None:
    with pytest.raises(ParameterError):
        discretize("kd", 0.01)
    with pytest.raises(ParameterError):
        discretize("1 + s", -1.0)
    with pytest.raises(ParameterError):
        discretize("1 + s", 0.01, method="euler")  # type: ignore[arg-type]
    with pytest.raises(ParameterError):
        discretize("s", 0.01, velocity_filter=-5)
    with pytest.raises(UnrealizableError):
        DiscreteTF((Fraction(1),), (Fraction(0), Fraction(1)), Fraction(1))
