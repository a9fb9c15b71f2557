"""Exact passive intervals and maps."""

import numpy as np
import pytest
import sympy as sp

from seapass.analysis.passivity import is_passive
from seapass.analysis.region import passive_intervals, passive_map
from seapass.errors import ParameterError
from seapass.model.catalog import PAPER_VALUES
from seapass.model.sea import SEA, Impedance

PAPER = PAPER_VALUES


def closed_form_damped_lp_bound(m, b, k1, b1):
    """Largest kd with (b1 m^2) x^2 + b1 (b^2 + b b1 - m kd) x + b k1 (k1 - kd) >= 0 on x >= 0."""
    kd = sp.Symbol("kd")
    disc = 4 * b1 * m**2 * b * k1 * (k1 - kd) - (b1 * (b**2 + b * b1 - m * kd)) ** 2
    roots = [float(r) for r in sp.solve(disc, kd) if r.is_real and (b**2 + b * b1) / m < r < k1]
    return max(roots) if roots else min(k1, (b**2 + b * b1) / m)


@pytest.mark.parametrize(
    ("elements", "values", "param", "rng", "expected"),
    [
        (dict(D1="k1", CL="kd"), PAPER, "kd", (0, 1e5), [(0.0, 1000.0)]),
        (dict(D1="k1", D2="k2", CL="kd"), {**PAPER, "k2": 1000.0}, "kd", (0, 1e5), [(0.0, 1000.0)]),
        (dict(D1="k1", CA="kd + bd*s"), {**PAPER, "bd": 25.0}, "kd", (0, 1e6), [(0.0, 1e6)]),
        (
            dict(D1="k1 + b1*s", CA="kd + bd*s"),
            {**PAPER, "bd": 25.0, "b1": 20.0},
            "kd",
            (0, 1e6),
            [(0.0, 1e6)],
        ),
        (dict(D1="k1", CL="kd + bd*s"), {**PAPER, "kd": 100.0}, "bd", (0, 100), [(0.0, 0.0)]),
        (dict(D1="k1", CA="kd + ki/s"), {**PAPER, "kd": 100.0}, "ki", (0, 100), [(0.0, 0.0)]),
        (dict(D1="k1", CL="kd"), PAPER, "kd", (2000, 3000), []),
    ],
)
def test_reference_intervals(elements, values, param, rng, expected):
    res = passive_intervals(SEA(**elements, values=values), param, *rng)
    assert list(res.intervals) == expected


@pytest.mark.parametrize("b1", [2.0, 20.0, 80.0])
def test_damped_lp_bound_matches_closed_form(b1):
    res = passive_intervals(SEA(D1="k1 + b1*s", CL="kd", values={**PAPER, "b1": b1}), "kd", 0, 1e4)
    ((lo, hi),) = res.intervals
    assert lo == 0.0
    assert hi == pytest.approx(closed_form_damped_lp_bound(1.0, 10.0, 1000.0, b1), rel=1e-12)


def test_intervals_agree_with_pointwise_exact_tests():
    sea = SEA(D1="k1", D2="b2*s", CL="kd", values={**PAPER, "b2": 3.0})
    res = passive_intervals(sea, "kd", 0, 3000)
    for kd in np.linspace(0, 3000, 61):
        inside = res.contains(kd)
        near = (
            min(abs(kd - c) for c in res.critical_values) < 1e-6 if res.critical_values else False
        )
        if not near:
            assert inside is is_passive(sea.with_values(kd=float(kd))).passive


def test_lossless_impedance_parameter():
    res = passive_intervals(Impedance(expr="k*s/(s**2 + k)", values={"k": None}), "k", -10, 1e8)
    assert res.intervals == ((0.0, 1e8),)


def test_errors_name_the_problem():
    sea = SEA(D1="k1", CL="kd", values=PAPER)
    with pytest.raises(ParameterError, match="does not appear"):
        passive_intervals(sea, "bd", 0, 1)
    with pytest.raises(ParameterError, match="lower bound"):
        passive_intervals(sea, "kd", 1, 0)
    with pytest.raises(ParameterError, match="b1"):
        passive_intervals(SEA(D1="k1 + b1*s", CL="kd", values=PAPER), "kd", 0, 1)


def test_passive_map_is_exact_per_column():
    sea = SEA(D1="k1 + b1*s", CL="kd", values=PAPER)
    pm = passive_map(sea, "b1", [2.0, 20.0], "kd", (0, 1200), y_points=50)
    assert pm.mask.shape == (50, 2)
    assert pm.intervals[1][0][1] == pytest.approx(849.1933384829667, rel=1e-12)
    with pytest.raises(ParameterError, match="shape"):
        passive_map(sea, "b1", [], "kd", (0, 1))
