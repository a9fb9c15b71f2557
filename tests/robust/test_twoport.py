"""Robust two-port verdicts and gain sets against independent checks (issue 26): dense
sampling of the box by the ordinary exact verdict, worst plants verified by it, and the
one-parameter robust set against the intersection of exact sets."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import sympy as sp

from seapass.errors import NotPassiveError, ParameterError
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.ports.bound import port_intervals
from seapass.ports.check import check_two_port
from seapass.ports.llewellyn import llewellyn_conditions
from seapass.ports.passivity import matrix_passivity
from seapass.ports.twoport import TwoPort, two_port
from seapass.robust import robust_port_intervals, robust_two_port_check
from seapass.robust.verdict import Method

BASE = dict(b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)
SEA_KL = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**BASE, "m": 1.0, "kl": 300.0})
SIMPLE = SEA(D1="k1", CA="kd", values=dict(m=1.0, b=10.0, k1=1000.0, kd=500.0))


def _exact_verdicts(tp: TwoPort, values: dict[str, float]) -> tuple[bool, bool]:
    """(absolutely stable, passive) by the ordinary exact verdict at one plant."""
    m = tp.exact(values)
    stab = all(c.outcome is Outcome.PASSIVE for c in llewellyn_conditions(m))
    return stab, matrix_passivity(m).outcome is Outcome.PASSIVE


def _float_violations(sea: SEA, box: dict, n: int = 10_000) -> tuple[int, int]:
    """(not absolutely stable, not passive) counts over the box's corners and ``n`` random
    plants, by numpy alone (no exact arithmetic, nothing of ``seapass.ports``' deciders): a
    400-point frequency grid of ``Z(jω)`` (Llewellyn's inequalities; the Hermitian part
    positive semidefinite), the poles off the origin by batched companion eigenvalues, and
    the residue matrix of the simple pole at ``s = 0`` (symmetric positive semidefinite)."""
    names = sorted(box)
    tp = two_port(sea.with_values(**dict.fromkeys(names)))
    s, syms = sp.Symbol("s"), [sp.Symbol(k) for k in names]
    fixed = {k: sp.nsimplify(v) for k, v in tp.values.items() if v is not None}
    entries = [  # plain symbols, the fixed values in exactly
        sp.cancel(e.xreplace({x: fixed.get(x.name, sp.Symbol(x.name)) for x in e.free_symbols}))
        for e in tp.entries
    ]
    zf = [sp.lambdify([s, *syms], e, "numpy") for e in entries]
    den = sp.lcm_list([sp.fraction(e)[1] for e in entries])
    den_s = sp.Poly(den, s)
    assert den_s.eval(0) == 0 and sp.Poly(sp.quo(den, s), s).eval(0) != 0  # one pole at 0
    reduced = sp.Poly(sp.quo(den, s), s).all_coeffs()
    coef = [sp.lambdify(syms, c, "numpy") for c in reduced]
    res = [sp.lambdify(syms, sp.cancel(s * e).subs(s, 0), "numpy") for e in entries]

    rng = np.random.default_rng(26)
    lo = np.array([box[k][0] for k in names])
    hi = np.array([box[k][1] for k in names])
    corners = np.array(list(itertools.product(*[box[k] for k in names])))
    pts = np.vstack([corners, lo + (hi - lo) * rng.random((n, len(names)))])
    w = np.logspace(-3, 5, 400)[:, None]
    unstable = np.zeros(len(pts), bool)
    active = np.zeros(len(pts), bool)
    for chunk in np.array_split(np.arange(len(pts)), max(1, len(pts) // 2000)):
        cols = [pts[chunk, i][None, :] for i in range(len(names))]
        z11, z12, z21, z22 = (np.broadcast_to(f(1j * w, *cols), (len(w), len(chunk))) for f in zf)
        assert all(np.isfinite(z).all() for z in (z11, z12, z21, z22))  # a NaN would pass
        r11, r22 = z11.real, z22.real
        p = z12 * z21
        herm = (z12 + np.conj(z21)) / 2
        tol = 1e-9 * (np.abs(z11) * np.abs(z22) + np.abs(p) + 1.0)
        llew = (r11 < -1e-9 * np.abs(z11)) | (r22 < -1e-9 * np.abs(z22))
        llew |= 2 * r11 * r22 - p.real - np.abs(p) < -tol
        psd = (r11 < -1e-9 * np.abs(z11)) | (r22 < -1e-9 * np.abs(z22))
        psd |= r11 * r22 - np.abs(herm) ** 2 < -tol
        c = np.array([np.broadcast_to(f(*pts[chunk].T), (len(chunk),)) for f in coef]).T
        comp = np.zeros((len(chunk), c.shape[1] - 1, c.shape[1] - 1))
        comp[:, 0, :] = -c[:, 1:] / c[:, :1]
        comp[:, 1:, :-1] += np.eye(c.shape[1] - 2)
        rhp = (np.linalg.eigvals(comp).real > -1e-9).any(axis=1)
        k = [np.broadcast_to(f(*pts[chunk].T), (len(chunk),)) for f in res]
        bad_res = (k[0] < -1e-12) | (k[3] < -1e-12) | (k[0] * k[3] - k[1] * k[2] < -1e-9)
        bad_res |= np.abs(k[1] - k[2]) > 1e-9 * (np.abs(k[1]) + np.abs(k[2]) + 1)
        unstable[chunk] = llew.any(axis=0) | rhp
        active[chunk] = psd.any(axis=0) | rhp | bad_res
    return int(unstable.sum()), int(active.sum())


def test_dense_exact_sampling_never_contradicts_a_robust_verdict() -> None:
    box = {"m": (0.9, 1.1), "b": (8.0, 12.0)}
    r = robust_two_port_check(SEA_KL, box=box)
    assert r.stability.outcome is Outcome.PASSIVE and r.passivity.outcome is Outcome.PASSIVE
    assert r.to_dict()["status"] == "passive" and r.worst is None
    # 10,004 plants (corners in) by the float method, vectorised
    assert _float_violations(SEA_KL, box) == (0, 0)
    # and 81 of them (a 9 x 9 grid, corners in) by the ordinary exact verdict, one by one
    tp = two_port(SEA_KL)
    for m, b in itertools.product(np.linspace(0.9, 1.1, 9), np.linspace(8.0, 12.0, 9)):
        assert _exact_verdicts(tp, {"m": float(m), "b": float(b)}) == (True, True), (m, b)


def test_the_float_sampling_finds_the_failures_of_a_box_declared_not_passive() -> None:
    # the float method can fail: it sees the plants the robust verdict rejects (kl = 1500)
    sea, box = SEA_KL.with_values(kl=1500.0), {"m": (0.8, 1.2), "b": (8.0, 12.0)}
    r = robust_two_port_check(sea, box=box)
    assert r.stability.outcome is Outcome.NOT_PASSIVE
    assert r.passivity.outcome is Outcome.NOT_PASSIVE
    unstable, active = _float_violations(sea, box, n=2000)
    assert unstable > 0 and active > 0


def test_worst_plant_is_verified_by_the_exact_verdict() -> None:
    sea = SEA_KL.with_values(kl=1500.0)
    box = {"m": (0.8, 1.2), "b": (8.0, 12.0)}
    r = robust_two_port_check(sea, box=box)
    for v in (r.stability, r.passivity):
        assert v.outcome is Outcome.NOT_PASSIVE and v.worst is not None
        at = v.worst.values
        assert all(box[k][0] <= x <= box[k][1] for k, x in at.items())
        check = check_two_port(sea, values=dict(at), witness=False)  # independent recomputation
        verdict = check.stability if v is r.stability else check.passivity
        assert verdict.outcome is Outcome.NOT_PASSIVE
        failing = {c.name: c for c in verdict.conditions if c.holds is False}
        assert v.worst.condition in failing
        w = v.worst.frequency
        assert w is not None and any(b.lo < w < b.hi for b in failing[v.worst.condition].bands)
    with pytest.raises(NotPassiveError):
        robust_two_port_check(sea, box=box, throw=True)


def test_certified_box_with_three_parameters_and_a_failing_box() -> None:
    r = robust_two_port_check(SIMPLE, box={"m": (0.5, 2.0), "b": (5.0, 20.0)})
    assert r.absolutely_stable and r.passive
    assert r.stability.method is Method.CERTIFIED and r.stability.boxes > 0
    d = r.to_dict()
    assert {"robust", "status", "box", "worst", "absolute_stability", "passivity"} <= set(d)
    assert d["robust"] is True and d["box"] == {"b": [5.0, 20.0], "m": [0.5, 2.0]}
    assert "RobustTwoPortResult" in repr(r) and "Robust two-port" in r._repr_html_()


def test_one_parameter_verdict_is_the_exact_set() -> None:
    tp = two_port(SEA_KL.with_values(kl=1500.0, m=None))
    exact = port_intervals(tp, "m", 0.5, 3.0, values={"m": 1.0})  # only m free
    ((lo, hi),) = exact.intervals  # absolutely stable for m in [lo, hi] (lo > 0.5)
    # a box between two critical values (no irrational one inside): decided exactly
    cuts = sorted({lo, hi, *(c for c in exact.critical_values if lo < c < hi)})
    p, q = max(itertools.pairwise(cuts), key=lambda g: g[1] - g[0])
    inside = robust_two_port_check(tp, box={"m": (p + (q - p) / 4, q - (q - p) / 4)})
    assert inside.stability.outcome is Outcome.PASSIVE
    assert inside.stability.method is Method.EXACT
    across = robust_two_port_check(tp, box={"m": (0.5, 3.0)})
    assert across.stability.outcome is Outcome.NOT_PASSIVE
    worst = across.stability.worst
    assert worst is not None and not exact.contains(worst.values["m"])
    assert not check_two_port(tp, values={"m": worst.values["m"]}, witness=False).absolutely_stable


def test_one_parameter_robust_gain_set_is_the_intersection_of_exact_sets() -> None:
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**BASE, "m": 1.0, "kl": None})
    rtol = 0.01
    r = robust_port_intervals(sea, "kl", 0, 2000, box={"m": (0.9, 1.1)}, rtol=rtol)
    # the independent answer: the intersection of the exact sets over a grid of m
    ends = [
        port_intervals(sea, "kl", 0, 2000, values={"m": float(m)}).intervals
        for m in np.linspace(0.9, 1.1, 11)
    ]
    assert all(len(e) == 1 and e[0][0] == 0.0 for e in ends)
    top = min(e[0][1] for e in ends)
    ((a, b),) = r.intervals
    ((c, d),) = r.outer
    assert a == 0.0 and c <= 0.0
    assert b <= top and d == pytest.approx(top, rel=1e-12)  # outer: the intersection, exactly
    assert top - b <= rtol * 2000  # inner: within rtol of it
    assert check_two_port(sea, values={"kl": b, "m": 1.1}, witness=False).absolutely_stable
    assert r.to_dict()["intervals"] == [[a, b]] and r.to_dict()["outer"] == [[c, d]]
    assert "RobustPortIntervals" in repr(r)


@pytest.mark.parametrize(
    ("box", "match"),
    [
        ({"m": (1.1, 0.9)}, "LO must not exceed HI"),
        ({"zz": (1.0, 2.0)}, "not a parameter"),
        ({"m": (0.0, 2.0)}, "non-physical"),
        ({"b": (-1.0, 2.0)}, "must not be negative"),
        ({}, "at least one"),
    ],
)
def test_bad_boxes_are_refused(box: dict, match: str) -> None:
    with pytest.raises(ParameterError, match=match):
        robust_two_port_check(SIMPLE, box=box)


def test_bad_arguments_are_refused() -> None:
    with pytest.raises(ParameterError, match="budget"):
        robust_two_port_check(SIMPLE, box={"m": (0.9, 1.1)}, budget=0)
    sea = SEA(D1="k1", CA="kd", values=dict(m=1.0, b=10.0, k1=1000.0, kd=None))
    with pytest.raises(ParameterError, match="no value for parameter"):
        robust_two_port_check(sea, box={"m": (0.9, 1.1)})
    with pytest.raises(ParameterError, match="bounded parameter"):
        robust_port_intervals(sea, "kd", 0, 10, box={"kd": (1.0, 2.0)})
    with pytest.raises(ParameterError, match="lower bound"):
        robust_port_intervals(sea, "kd", 10, 0, box={"m": (1.0, 2.0)})
    single = robust_two_port_check(SIMPLE, box={"m": (1.0, 1.0)})  # a one-plant box
    assert single.passive and single.passivity.method is Method.EXACT
    assert single.passivity.detail == "a single plant"


def test_an_interior_worst_plant_is_found_where_corners_and_centre_pass() -> None:
    # the quartic loses Hurwitz stability only near a = 1.2: not at a corner, not at the centre
    den = "(s**4 + 2*s**3 + (2 + 4*(a - 6/5)**2 - 1/100)*s**2 + 2*s + 1)"
    tp = TwoPort.from_matrix([[f"1 + b/{den}", "0"], ["0", "1"]], values={"a": 1.0, "b": 0.01})
    box = {"a": (0.5, 1.5), "b": (0.01, 0.02)}
    for a, b in itertools.product((0.5, 1.0, 1.5), (0.01, 0.015, 0.02)):
        assert check_two_port(tp, values={"a": a, "b": b}, witness=False).absolutely_stable
    r = robust_two_port_check(tp, box=box)
    assert r.stability.outcome is Outcome.NOT_PASSIVE and r.stability.method is Method.CERTIFIED
    assert r.worst is not None and 1.0 < r.worst.values["a"] < 1.5
    again = check_two_port(tp, values=dict(r.worst.values), witness=False)
    assert not again.absolutely_stable and r.worst.condition in {
        c.name for c in again.stability.conditions if c.holds is False
    }
    assert robust_two_port_check(tp, box={"a": (1.4, 1.5), "b": (0.01, 0.02)}).absolutely_stable
