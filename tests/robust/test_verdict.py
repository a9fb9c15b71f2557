"""The robust verdict against independent checks: dense box sampling, the plain exact test,
the exact one-parameter passive set, and an interior worst case (issue 26)."""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest
import sympy as sp

import seapass
from seapass.analysis.passivity import is_passive
from seapass.analysis.region import passive_intervals
from seapass.errors import NotPassiveError, ParameterError
from seapass.model.catalog import design
from seapass.model.expr import S, symbol
from seapass.model.sea import SEA, Impedance
from seapass.model.stiffness import load_impedance
from seapass.outcome import Outcome
from seapass.robust.verdict import robust_check

PLANT = dict(m=1.0, b=10.0, k1=1000.0)
LP = SEA(D1="k1", CL="kd", values={**PLANT, "kd": 500.0})
OURS = design("ours").sea({**PLANT, "b1": 20.0, "kd": 500.0, "bd": 25.0})
# Re Z < 0 only near m = 1: every corner of the box is passive, the centre is not
INTERIOR = Impedance(
    expr="(s**2 + (10*(m - 1)**2 - 1/100)*s + k2)/(s**2 + s + 1)", values={"m": 1.0, "k2": 1.0}
)


def _dense_sampling_violations(system: SEA | Impedance, box: dict, n: int = 10_000) -> int:
    """Plants of the box (random, corners) found non-passive by a float frequency grid and
    numpy eigenvalues: an independent method (no exact arithmetic, no Bernstein)."""
    names = sorted(box)
    fixed = {k: v for k, v in system.values.items() if k not in box and v is not None}
    free = system.with_values(**dict.fromkeys(names)) if isinstance(system, SEA) else system
    z = load_impedance(free) if isinstance(system, SEA) else system.expr
    z = z.subs({symbol(k): sp.nsimplify(v) for k, v in fixed.items()})
    num, den = sp.fraction(sp.together(z))
    syms = [symbol(k) for k in names]
    zf = sp.lambdify([S, *syms], num / den, "numpy")
    dcoef = [sp.lambdify(syms, c, "numpy") for c in sp.Poly(den, S).all_coeffs()]
    rng = np.random.default_rng(26)
    lo = np.array([box[k][0] for k in names])
    hi = np.array([box[k][1] for k in names])
    pts = lo + (hi - lo) * rng.random((n, len(names)))
    corners = np.array(list(itertools.product(*[box[k] for k in names])))
    pts = np.vstack([corners, pts])
    w = np.logspace(-3, 5, 400)[:, None]
    vals = zf(1j * w, *[pts[:, i][None, :] for i in range(len(names))])
    bad_re = (vals.real < -1e-9 * np.abs(vals)).any(axis=0)
    coeffs = np.array([np.broadcast_to(c(*pts.T), (pts.shape[0],)) for c in dcoef]).T
    assert np.all(coeffs[:, 0] != 0)  # the degree is the same at every plant
    comp = np.zeros((len(pts), coeffs.shape[1] - 1, coeffs.shape[1] - 1))
    comp[:, 0, :] = -coeffs[:, 1:] / coeffs[:, :1]  # companion matrices: all plants at once
    comp[:, 1:, :-1] += np.eye(coeffs.shape[1] - 2)
    bad_pole = (np.linalg.eigvals(comp).real > 1e-9).any(axis=1)
    return int(np.sum(bad_re | bad_pole))


@pytest.mark.parametrize(
    ("system", "box"),
    [
        (LP, {"m": (0.5, 2.0), "b": (5.0, 15.0), "k1": (800.0, 1200.0)}),
        (OURS, {"m": (0.8, 1.2), "b": (8.0, 12.0), "b1": (15.0, 25.0)}),
        (OURS, {"m": (0.8, 1.2), "kd": (400.0, 600.0)}),
        (INTERIOR, {"m": (0.5, 0.9), "k2": (0.9, 1.1)}),
    ],
)
def test_dense_sampling_never_finds_a_non_passive_plant_in_a_robustly_passive_box(
    system: SEA | Impedance, box: dict
) -> None:
    r = robust_check(system, box=box)
    assert r.outcome is Outcome.PASSIVE and r.worst is None and r.method == "certified"
    assert _dense_sampling_violations(system, box) == 0


def test_dense_sampling_finds_the_failures_of_a_box_declared_not_passive() -> None:
    # the sampling method can fail: it sees the plants the verdict rejects
    box = {"k1": (100.0, 1000.0), "m": (0.5, 2.0)}
    assert robust_check(LP, box=box).outcome is Outcome.NOT_PASSIVE
    assert _dense_sampling_violations(LP, box, n=2000) > 0


@pytest.mark.parametrize(
    ("system", "box"),
    [
        (LP, {"k1": (100.0, 1000.0), "m": (0.5, 2.0)}),
        (LP, {"k1": (400.0, 600.0), "b": (0.5, 20.0)}),
        (INTERIOR, {"m": (0.9, 1.1), "k2": (0.9, 1.1)}),
        (OURS, {"kd": (400.0, 600.0), "b1": (5.0, 30.0), "m": (0.5, 1.0)}),
        (OURS, {"kd": (400.0, 6000.0), "bd": (5.0, 30.0), "b": (5.0, 30.0)}),
    ],
)
def test_the_worst_case_of_a_negative_verdict_is_not_passive_by_the_plain_exact_test(
    system: SEA | Impedance, box: dict
) -> None:
    r = robust_check(system, box=box)
    if r.outcome is Outcome.PASSIVE:  # a box that is passive must also survive sampling
        assert _dense_sampling_violations(system, box, n=2000) == 0
        return
    assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None
    for name, value in r.worst.values.items():
        assert box[name][0] <= value <= box[name][1]
    assert not is_passive(system, values=dict(r.worst.values)).passive
    if r.worst.frequency is not None:
        w = r.worst.frequency
        num, den = r.worst.result.num, r.worst.result.den
        assert (np.polyval(num, 1j * w) / np.polyval(den, 1j * w)).real < 0


def test_an_interior_worst_case_is_found_where_every_vertex_is_passive() -> None:
    box = {"m": (0.9, 1.1), "k2": (0.9, 1.1)}
    corners = [dict(zip(box, c, strict=True)) for c in itertools.product(*box.values())]
    assert all(is_passive(INTERIOR, values=c).passive for c in corners)  # vertices: all passive
    r = robust_check(INTERIOR, box=box)
    assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None
    m = r.worst.values["m"]
    assert 0.9 < m < 1.1  # strictly inside
    assert not is_passive(INTERIOR, values=dict(r.worst.values)).passive
    one = robust_check(INTERIOR, box={"m": (0.9, 1.1)})  # exact one-parameter path
    assert one.outcome is Outcome.NOT_PASSIVE and 0.9 < one.worst.values["m"] < 1.1


@pytest.mark.parametrize(
    ("name", "interval"),
    [("k1", (800.0, 1200.0)), ("k1", (400.0, 1200.0)), ("k1", (500.0, 600.0)),
     ("k1", (100.0, 499.0)), ("kd", (0.0, 1000.0)), ("kd", (100.0, 999.0)), ("m", (0.1, 10.0))],
)  # fmt: skip
def test_one_parameter_verdicts_equal_the_exact_passive_set_from_bound(
    name: str, interval: tuple[float, float]
) -> None:
    lo, hi = interval
    r = robust_check(LP, box={name: interval})
    exact = passive_intervals(LP, name, lo, hi)
    assert r.method == "exact"
    assert r.passive == (exact.intervals == ((lo, hi),))
    if not r.passive:
        assert r.worst is not None and not exact.contains(r.worst.values[name])


@pytest.mark.parametrize("interval", [(800.0, 1200.0), (100.0, 499.0), (300.0, 700.0)])
def test_the_certified_path_agrees_with_the_exact_one_on_a_flat_second_axis(
    interval: tuple[float, float],
) -> None:
    exact = robust_check(LP, box={"k1": interval})
    certified = robust_check(LP, box={"k1": interval, "m": (1.0, 1.0)})
    assert certified.method == "certified"
    assert certified.outcome is exact.outcome


def test_an_exhausted_budget_is_undecided_never_passive() -> None:
    r = robust_check(OURS, box={"m": (0.8, 1.2), "b": (8.0, 12.0), "b1": (15.0, 25.0)}, budget=1)
    assert r.outcome is Outcome.UNDECIDED and not r.passive
    assert r.to_dict()["status"] == "undecided" and r.to_dict()["passive"] is False


def test_the_result_is_a_kw_only_frozen_dataclass_with_the_issue_json_keys() -> None:
    r = robust_check(LP, box={"k1": (100.0, 1000.0), "m": (0.5, 2.0)})
    d = json.loads(json.dumps(r.to_dict()))
    assert {"robust", "box", "worst", "status", "passive"} <= set(d)
    assert d["robust"] is True and d["status"] == "not_passive" and d["passive"] is False
    assert set(d["worst"]) >= {"values", "frequency"}
    assert d["box"] == {"k1": [100.0, 1000.0], "m": [0.5, 2.0]}
    assert "RobustResult(" in repr(r) and "<table" in r._repr_html_()
    with pytest.raises(AttributeError):
        r.outcome = Outcome.PASSIVE  # type: ignore[misc]
    with pytest.raises(TypeError):
        type(r)(Outcome.PASSIVE, r.box)  # type: ignore[misc]


def test_top_level_is_passive_takes_a_box() -> None:
    r = seapass.is_passive(LP, box={"m": (0.9, 1.1)})
    assert r.outcome is Outcome.PASSIVE and r.to_dict()["robust"] is True
    assert seapass.is_passive(LP).passive  # without a box: the exact test, unchanged
    with pytest.raises(NotPassiveError):
        seapass.is_passive(LP, box={"k1": (100.0, 1000.0)}, throw=True)


def test_library_errors_name_python_arguments() -> None:
    with pytest.raises(ParameterError, match=r"box\['mass'\]"):
        robust_check(LP, box={"mass": (0.9, 1.1)})
    with pytest.raises(ParameterError, match="budget"):
        robust_check(LP, box={"m": (0.9, 1.1)}, budget=0)
    with pytest.raises(ParameterError, match="budget must be an integer in"):
        robust_check(LP, box={"m": (0.9, 1.1)}, budget=10**9)  # bounds time and memory
    with pytest.raises(ParameterError, match="no value"):
        robust_check(SEA(D1="k1", CL="kd", values=PLANT), box={"m": (0.9, 1.1)})


def test_a_box_touching_a_lossless_corner_is_undecided_not_passive() -> None:
    # at b = bd = 0 the design is marginal (margin ~ 0): no finite branch and bound proves it
    box = {"kd": (400.0, 6000.0), "bd": (0.0, 30.0), "b": (0.0, 30.0)}
    r = robust_check(OURS, box=box, budget=200)
    assert r.outcome is Outcome.UNDECIDED and r.boxes == 200 and "budget" in r.detail


def test_a_cancellation_that_appears_only_at_the_fixed_values_is_not_hidden() -> None:
    # (s - k2)/(s - 1) cancels at k2 = 1: an unstable hidden mode the exact test rejects
    z = Impedance(
        expr="(s - k2)*(s + m)/((s - 1)*(s**2 + b*s + 1))",
        values={"k2": 1.0, "m": 1.0, "b": 2.0},
    )
    assert not is_passive(z).passive
    r = robust_check(z, box={"m": (0.9, 1.1), "b": (1.5, 2.5)})
    assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None
    assert not is_passive(z, values=dict(r.worst.values)).passive


def test_an_irrational_critical_value_inside_the_box_is_decided_over_the_reals() -> None:
    """b has an irrational critical value (about 28.237) inside [20, 40] where the passive
    set of doubles is unbroken: a plant is a real number, so the one-parameter path must not
    conclude from the doubles; the certified branch and bound decides the real interval."""
    from fractions import Fraction

    from seapass.analysis.critical import critical_polynomials_in, critical_values_in
    from seapass.model.sea import exact_values
    from seapass.robust.verdict import Method

    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=30))
    fixed = {k: v for k, v in sea.values.items() if k != "b"}
    crit = critical_values_in(
        critical_polynomials_in(sea, "b", exact_values(fixed)), Fraction(20), Fraction(40)
    )
    assert any(c.poly is not None for c in crit)  # irrational, inside the box
    inside = robust_check(sea, box={"b": (20.0, 40.0)})
    assert inside.method is Method.CERTIFIED and inside.outcome is Outcome.PASSIVE
    away = robust_check(sea, box={"b": (30.0, 40.0)})  # no irrational critical value: exact
    assert away.method is Method.EXACT and away.outcome is Outcome.PASSIVE


def test_irrational_critical_values_are_certified_on_their_isolating_intervals() -> None:
    """Ours over b1 in [0, 300]: three irrational critical values inside, and at b1 = 0 the
    leading coefficient of the real part vanishes (a degree drop), so the Bernstein search over
    the whole interval cannot finish.  The exact cells plus a certified tiny box around each
    irrational value decide the real interval; dense sampling by the exact test agrees."""
    sea = SEA(
        D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1000, b1=300, kd=1708, bd=300)
    )  # examples/ours.toml
    r = robust_check(sea, box={"b1": (0.0, 300.0)})
    assert r.outcome is Outcome.PASSIVE, r.detail
    assert "irrational critical value" in r.detail
    for b1 in [*np.linspace(0.0, 300.0, 61), 0.1444050904017456, 3.2852724842756893]:
        assert is_passive(sea, values={"b1": float(b1)}).passive
