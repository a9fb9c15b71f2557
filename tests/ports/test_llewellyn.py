"""Llewellyn's absolute stability and η, cross-checked against a dense grid with local refinement."""

from __future__ import annotations

import math

import numpy as np
import pytest

from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.ports import TwoPort, two_port
from seapass.ports.stability import absolute_stability

from .numeric import OMEGA, llewellyn_terms, matrix_function, refined_minimum, vectorized

RIG = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


def _sea(cl: float, **kw: float) -> TwoPort:
    return two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": cl, **kw}))


CASES = {
    "virtual coupling": two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG)),
    "load feedback 300": _sea(300.0),
    "load feedback 3000": _sea(3000.0),
    "load feedback 5000": _sea(5000.0),
    "negative load feedback": _sea(-400.0),
    "light damping": _sea(2000.0, b1=2.0, bd=3.0),
    "load PD": two_port(SEA(D1="k1", CA="kd", CL="kl + bl*s",
                            values=dict(m=1, b=10, k1=1000, kd=500, kl=200, bl=15))),
    "teleoperator h": TwoPort.from_matrix(
        [["mm*s + bm", "1"], ["-1", "1/(ms*s + bs + kc/s)"]], form="h",
        values=dict(mm=0.5, bm=2.0, ms=1.0, bs=5.0, kc=400.0)),
    "teleoperator with gain": TwoPort.from_matrix(
        [["mm*s + bm + kf", "g"], ["-1", "1/(ms*s + bs)"]], form="h",
        values=dict(mm=0.5, bm=2.0, ms=1.0, bs=5.0, kf=1.0, g=3.0)),
}  # fmt: skip


def _scale(p: np.ndarray) -> dict[str, np.ndarray]:
    """Magnitudes the terms are compared with (so the tolerances are relative)."""
    a11, a22 = np.abs(p[:, 0, 0]), np.abs(p[:, 1, 1])
    q = np.abs(p[:, 0, 1] * p[:, 1, 0])
    return {"re_p11": a11, "re_p22": a22, "llewellyn": 2 * a11 * a22 + 2 * q}


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request: pytest.FixtureRequest) -> tuple[TwoPort, object]:
    tp = CASES[request.param]
    return tp, absolute_stability(tp, witness=False)


@pytest.mark.parametrize("name", ["re_p11", "re_p22", "llewellyn"])
def test_frequency_conditions_agree_with_a_refined_grid(case, name: str) -> None:
    tp, result = case
    f = matrix_function(tp.entries, tp.values)

    def g(w: np.ndarray) -> np.ndarray:
        p = f(w)
        return llewellyn_terms(p)[name] / np.maximum(_scale(p)[name], 1e-300)

    cond = next(c for c in result.conditions if c.name == name)
    low, where = refined_minimum(vectorized(g))
    if cond.holds:
        assert low >= -1e-9, f"{name}: exact says it holds, the grid finds {low:g} at w = {where:g}"
        assert cond.bands == ()
        return
    assert cond.bands, f"{name} fails without a band"
    assert low < 0
    assert any(b.lo * (1 - 1e-6) <= where <= b.hi * (1 + 1e-6) for b in cond.bands)
    vals = g(OMEGA)
    clearly = OMEGA[vals < -1e-7]
    inside = np.zeros(clearly.size, dtype=bool)
    for b in cond.bands:
        inside |= (clearly >= b.lo * (1 - 1e-6)) & (clearly <= b.hi * (1 + 1e-6))
    assert inside.all(), f"{name}: grid points fail outside the exact bands: {clearly[~inside][:5]}"
    for b in cond.bands:  # each band really fails somewhere inside
        hi = b.hi if math.isfinite(b.hi) else b.lo * 10 + 10
        lo = b.lo if b.lo > 0 else hi * 1e-6
        mid = np.geomspace(lo, hi, 101)[1:-1]
        assert (g(mid) < 0).any()


def test_eta_infimum_is_certified_against_the_refined_grid(case) -> None:
    tp, result = case
    f = matrix_function(tp.entries, tp.values)
    eta = result.eta
    if eta.kind == "undefined":
        pytest.skip("p12 p21 = 0")
    low, where = refined_minimum(vectorized(lambda w: llewellyn_terms(f(w))["eta"]))
    if eta.kind == "unbounded":
        assert low < -1e3
        return
    lo, hi = float(eta.lower), float(eta.upper)
    assert hi - lo <= 1e-12 * max(1.0, abs(lo))
    assert low >= lo - 1e-9 * max(1.0, abs(lo)), "a sampled value below the certified infimum"
    if eta.kind == "attained":
        assert low == pytest.approx(lo, rel=1e-7, abs=1e-9)
        assert where == pytest.approx(eta.omega, rel=1e-3) or eta.omega == 0.0
    else:  # a limit: the grid approaches it from above
        assert low - hi < 1e-2 * max(1.0, abs(hi))


def test_eta_and_the_verdict_agree(case) -> None:
    _tp, r = case
    if r.eta.kind in ("undefined", "unbounded"):
        return
    pole_ok = all(
        c.holds
        for c in r.conditions
        if c.name in ("stable_entries", "p11_poles", "p22_poles", "re_p11")
    )
    if r.outcome is Outcome.PASSIVE:
        assert r.eta.lower >= 1
    elif pole_ok and next(c for c in r.conditions if c.name == "axis_residues").holds:
        assert r.eta.upper < 1 or not next(c for c in r.conditions if c.name == "re_p22").holds


def test_known_verdicts() -> None:
    verdicts = {k: absolute_stability(tp, witness=False).outcome for k, tp in CASES.items()}
    assert verdicts["virtual coupling"] is Outcome.PASSIVE
    assert verdicts["load feedback 300"] is Outcome.PASSIVE
    assert verdicts["load feedback 5000"] is Outcome.NOT_PASSIVE
    assert (
        verdicts["teleoperator h"] is Outcome.PASSIVE
    )  # a passive (lossless-coupled) teleoperator


def test_axis_residues_catch_what_the_frequency_conditions_miss() -> None:
    # Llewellyn's inequalities hold at every frequency, yet both ports free is unstable:
    # det z = ((1 + s)^2 - 4)/s^2 has the root s = 1
    tp = TwoPort.from_matrix([["1/s + 1", "2/s"], ["2/s", "1/s + 1"]])
    r = absolute_stability(tp, bounds=(None, None))
    failing = {c.name for c in r.conditions if c.holds is False}
    assert failing == {"axis_residues"}
    assert r.witness is not None and r.witness.found and r.witness.closed_loop.rhp
    ok = TwoPort.from_matrix([["1/s + 1", "1/(2*s)"], ["1/(2*s)", "1/s + 1"]])
    assert absolute_stability(ok).absolutely_stable


def test_the_verdict_does_not_depend_on_the_form() -> None:
    for key in ("load feedback 300", "load feedback 5000", "light damping"):
        tp = CASES[key]
        base = absolute_stability(tp, witness=False)
        for form in ("y", "h", "g"):
            other = absolute_stability(tp.convert(form), witness=False)
            assert other.outcome is base.outcome, (key, form)
            if base.eta.kind == "attained":
                assert float(other.eta.lower) == pytest.approx(float(base.eta.lower), rel=1e-12)


def test_an_unstable_entry_is_not_absolutely_stable() -> None:
    tp = TwoPort.from_matrix([["1", "1/(s - 1)"], ["0", "1"]])
    r = absolute_stability(tp, witness=False)
    assert not r.absolutely_stable
    assert next(c for c in r.conditions if c.name == "stable_entries").holds is False


def test_result_display_and_dict() -> None:
    r = absolute_stability(CASES["load feedback 5000"])
    d = r.to_dict()
    assert d["absolutely_stable"] is False and d["outcome"] == "not_passive"
    assert {c["name"] for c in d["conditions"]} == {
        "stable_entries", "p11_poles", "p22_poles", "re_p11", "re_p22", "llewellyn", "axis_residues"
    }  # fmt: skip
    assert d["witness"]["found"] is True
    assert repr(r).startswith("AbsoluteStability(outcome='not_passive'")
    assert "not absolutely stable" in r._repr_html_()
