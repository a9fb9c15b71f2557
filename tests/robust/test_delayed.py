"""Robust verdicts of delayed designs (seapass.robust.delayed), cross-checked plant by plant
with the ordinary certified delayed verdict and the closed form tau* = b/K of a delayed
virtual wall."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.delay.margin import delay_margin
from seapass.delay.passivity import delayed_passivity
from seapass.errors import ParameterError
from seapass.model.sea import SEA, Impedance
from seapass.outcome import Outcome
from seapass.robust.delayed import robust_delay_margin, robust_delayed_check
from seapass.robust.verdict import robust_check

# Re Z(jw) = b(c) - K sin(w tau)/w: tau* = b(c)/K, lost as w -> 0; b(c) = (c - 1)^2 + 1 has its
# minimum inside [0.6, 1.8] (neither the centre 1.2 nor a vertex): tau*_robust = 1/50
WALL_C = Impedance(
    expr="m*s + (c**2 - 2*c + 2) + K*exp(-tau*s)/s", values=dict(m=1, c=None, K=50, tau=None)
)
WALL = Impedance(expr="m*s + b + K*exp(-tau*s)/s", values=dict(m=1, b=None, K=None, tau=None))
OURS = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
           values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25, tau=None))  # fmt: skip


def test_interior_worst_plant_of_the_margin_is_found() -> None:
    r = robust_delay_margin(WALL_C, "tau", box={"c": (0.6, 1.8)}, rtol=1e-3)
    assert r.outcome is Outcome.PASSIVE and r.certified
    lo, hi = r.tau_star
    assert lo <= 0.02 <= hi and hi - lo <= 1e-3 * hi
    assert r.worst_values is not None and abs(r.worst_values["c"] - 1.0) < 0.05
    # dense sampling of the box: the closed form never goes below the certified lo
    for c in np.linspace(0.6, 1.8, 400):
        assert ((c - 1) ** 2 + 1) / 50 >= lo
    # the worst plant is verified: not passive just above hi
    w = dict(r.worst_values)
    assert delayed_passivity(WALL_C, values={**w, "tau": hi * 1.001}).outcome is Outcome.NOT_PASSIVE


def test_two_parameter_margin_equals_the_closed_form() -> None:
    box = {"b": (1.8, 2.2), "K": (45.0, 55.0)}
    r = robust_delay_margin(WALL, "tau", box=box)
    lo, hi = r.tau_star
    assert lo <= 1.8 / 55 <= hi and r.worst_values == {"K": 55.0, "b": 1.8}
    d = r.to_dict()
    assert d["robust"] is True and d["box"] == {"K": [45.0, 55.0], "b": [1.8, 2.2]}
    assert d["worst"]["values"] == {"K": 55.0, "b": 1.8} and d["loss"] == "low_frequency"


def test_check_at_a_delay_never_contradicts_dense_sampling() -> None:
    box = {"b": (1.8, 2.2), "K": (45.0, 55.0)}
    sys = WALL.with_values(tau=0.03) if hasattr(WALL, "with_values") else Impedance(
        expr=WALL.expr, values={**WALL.values, "tau": 0.03})  # fmt: skip
    r = robust_check(sys, box=box)
    assert r.outcome is Outcome.PASSIVE and r.to_dict()["delay"] == {"name": "tau", "tau": 0.03}
    rng = np.random.default_rng(1)
    for b, k in zip(rng.uniform(1.8, 2.2, 200), rng.uniform(45, 55, 200), strict=True):
        res = delayed_passivity(WALL, values=dict(b=b, K=k, tau=0.03))
        assert res.outcome is not Outcome.NOT_PASSIVE
        assert b / k >= 0.03  # the closed form agrees


def test_not_passive_box_has_a_verified_worst_plant() -> None:
    sys = Impedance(expr=WALL.expr, values={**WALL.values, "tau": 0.035})
    r = robust_check(sys, box={"b": (1.8, 2.2), "K": (45.0, 55.0)})
    assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None
    w = dict(r.worst.values)
    assert delayed_passivity(WALL, values={**w, "tau": 0.035}).outcome is Outcome.NOT_PASSIVE
    assert w["b"] / w["K"] < 0.035


def test_interior_counterexample_of_the_check() -> None:
    # at tau = 0.0205 only plants with |c - 1| < 0.16 fail: not the centre, not a vertex
    sys = Impedance(expr=WALL_C.expr, values={**WALL_C.values, "tau": 0.0205})
    r = robust_check(sys, box={"c": (0.6, 1.8)})
    assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None
    assert abs(r.worst.values["c"] - 1) < 0.16


def test_a_point_box_equals_the_nominal_margin() -> None:
    nominal = delay_margin(OURS, "tau", rtol=1e-6)
    r = robust_delay_margin(OURS, "tau", box={"m": (1.0, 1.0)}, rtol=1e-4)
    assert r.tau_star[0] <= nominal.tau_star[0] and nominal.tau_star[1] <= r.tau_star[1]
    one = robust_check(OURS.with_values(tau=0.01), box={"m": (1.0, 1.0)})
    assert one.outcome is delayed_passivity(OURS, values=dict(tau=0.01)).outcome


def test_margin_of_a_box_is_below_every_sampled_plant() -> None:
    r = robust_delay_margin(OURS, "tau", box={"m": (0.9, 1.1)}, rtol=1e-2)
    assert r.outcome is Outcome.PASSIVE
    for m in (0.9, 0.95, 1.0, 1.05, 1.1):
        assert delay_margin(OURS, "tau", values=dict(m=m), rtol=1e-3).tau_star[1] >= r.tau_star[0]


@pytest.mark.parametrize(
    ("box", "match"),
    [
        ({"m": (1.1, 0.9)}, "empty interval"),
        ({"tau": (0.0, 0.1)}, "is the delay"),
        ({"m": (0.0, 1.0)}, "non-physical"),
    ],
)
def test_bad_boxes_are_clear_errors(box: dict, match: str) -> None:
    with pytest.raises(ParameterError, match=match):
        robust_delay_margin(OURS, "tau", box=box)


def test_bad_options_are_clear_errors() -> None:
    with pytest.raises(ParameterError, match="rtol"):
        robust_delay_margin(OURS, "tau", box={"m": (0.9, 1.1)}, rtol=2.0)
    with pytest.raises(ParameterError, match="budget"):
        robust_delay_margin(OURS, "tau", box={"m": (0.9, 1.1)}, budget=0)
    with pytest.raises(ParameterError, match="no value for the delay"):
        robust_delayed_check(OURS, box={"m": (0.9, 1.1)})


def test_a_small_budget_is_undecided_never_passive() -> None:
    sys = Impedance(expr=WALL.expr, values={**WALL.values, "tau": 0.0325})
    r = robust_check(sys, box={"b": (1.8, 2.2), "K": (45.0, 55.0)}, budget=3)
    assert r.outcome is Outcome.UNDECIDED


@settings(max_examples=6, deadline=None)
@given(
    b=st.floats(1.0, 3.0), db=st.floats(0.0, 0.5), k=st.floats(20.0, 80.0), dk=st.floats(0.0, 10.0)
)
def test_margin_of_the_wall_encloses_the_closed_form(
    b: float, db: float, k: float, dk: float
) -> None:
    r = robust_delay_margin(WALL, "tau", box={"b": (b, b + db), "K": (k, k + dk)}, rtol=1e-2)
    assert r.outcome is Outcome.PASSIVE
    lo, hi = r.tau_star
    assert lo <= b / (k + dk) <= hi


def test_a_zero_margin_stays_zero_over_the_box() -> None:
    # LP with a delayed controller: every delay > 0 fails at high frequency (tau* = 0)
    from seapass.delay.structure import controller_delay

    lp = controller_delay("LP", "tau", {"kd": 500.0})
    assert delay_margin(lp, "tau").tau_star == (0.0, 0.0)
    r = robust_delay_margin(lp, "tau", box={"m": (0.9, 1.1), "b": (9.0, 11.0)})
    assert r.outcome is Outcome.PASSIVE and r.tau_star == (0.0, 0.0)
    assert r.to_dict()["loss"] == "unbounded_band"


def _ours_re_z(m: np.ndarray, b1: np.ndarray, tau: float, w: np.ndarray) -> np.ndarray:
    """Re Z_L(jw) of OURS in floating point (numpy), plants by rows: an independent formula."""
    s = 1j * w[None, :]
    e = np.exp(-s * tau)
    d1 = 1000.0 + b1[:, None] * s
    ca = (500.0 + 25.0 * s) * e
    alpha = m[:, None] * s**2 + 10.0 * s
    return (d1 * (alpha + ca) / (alpha + ca + d1) / s).real


def test_margin_of_ours_against_a_dense_grid_of_400_plants() -> None:
    box = {"m": (0.9, 1.1), "b1": (18.0, 22.0)}
    r = robust_delay_margin(OURS, "tau", box=box, rtol=1e-2)
    assert r.outcome is Outcome.PASSIVE
    lo, hi = r.tau_star
    rng = np.random.default_rng(7)
    m = np.concatenate([rng.uniform(0.9, 1.1, 396), [0.9, 0.9, 1.1, 1.1]])
    b1 = np.concatenate([rng.uniform(18, 22, 396), [18.0, 22.0, 18.0, 22.0]])
    w = np.geomspace(0.1, 1e4, 6000)
    # no sampled plant has a (clearly) negative real part at the certified delay
    assert _ours_re_z(m, b1, lo, w).min() > -1e-9
    # the worst plant's real part is negative just beyond hi (the grid sees the loss too)
    wv = r.worst_values
    assert wv is not None
    worst = _ours_re_z(np.array([wv["m"]]), np.array([wv["b1"]]), hi * 1.01, w)
    assert worst.min() < 0
