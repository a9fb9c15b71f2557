"""Conditions that vanish on a face of the box (seapass.robust.faces and its use)."""

from __future__ import annotations

import itertools
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
import sympy as sp
from flint import fmpq
from hypothesis import given
from hypothesis import strategies as st

from seapass.analysis.passivity import is_passive
from seapass.model.expr import S, symbol
from seapass.model.sea import SEA, Impedance
from seapass.model.stiffness import load_impedance
from seapass.outcome import Outcome
from seapass.robust.bernstein import from_terms
from seapass.robust.faces import at_value, divide_out, split_top
from seapass.robust.verdict import robust_check


def _eval(coeffs: np.ndarray, point: tuple[fmpq, ...]) -> fmpq:
    total = fmpq(0)
    for idx in itertools.product(*(range(n) for n in coeffs.shape)):
        term = coeffs[idx]
        for v, e in zip(point, idx, strict=True):
            term = term * v**e
        total += term
    return total


_small = st.fractions(min_value=-3, max_value=3, max_denominator=7)
_coeffs = st.lists(st.integers(min_value=-5, max_value=5), min_size=9, max_size=9).map(
    lambda xs: np.array([fmpq(x) for x in xs], dtype=object).reshape(3, 3)
)


@given(_coeffs, _small, _small, _small)
def test_divide_out_and_split_top_are_exact_identities(
    g: np.ndarray, c: Fraction, t: Fraction, p: Fraction
) -> None:
    """(v - c)·g divided by (v - c) gives back g; Q = c_d t^e + (1 - t) Q_R at every point."""
    cq, tq, pq = (fmpq(x.numerator, x.denominator) for x in (c, t, p))
    lin = from_terms({(0, 1): fmpq(1), (0, 0): -cq}, 2)  # v - c along axis 1
    f = np.zeros((3, 4), dtype=object)
    f[:] = fmpq(0)
    for (i, j), a in np.ndenumerate(g):
        for (k, m), b in np.ndenumerate(lin):
            f[i + k, j + m] += a * b
    q = divide_out(f, 1, cq, upper=False)
    assert q is not None
    assert _eval(q, (tq, pq)) * (pq - cq) == _eval(f, (tq, pq))
    up = divide_out(f, 1, cq, upper=True)
    assert up is not None and _eval(up, (tq, pq)) == -_eval(q, (tq, pq))
    parts = split_top(f)
    assert parts is not None
    top, rest = parts
    e = f.shape[0] - 1
    assert _eval(top, (tq, pq)) * tq**e + (1 - tq) * _eval(rest, (tq, pq)) == _eval(f, (tq, pq))
    assert _eval(at_value(f, 1, cq), (tq, pq)) == 0


def test_divide_out_refuses_a_polynomial_that_does_not_vanish_on_the_face() -> None:
    f = from_terms({(1,): fmpq(1), (0,): fmpq(1)}, 1)  # v + 1
    assert divide_out(f, 0, fmpq(0), upper=False) is None


def test_a_damper_box_from_zero_is_decided_off_the_face_and_on_it() -> None:
    """Ours over b1 in [0, 300] and m in [0.5, 2]: at b1 = 0 the real part drops two degrees
    (its leading coefficient is b1·m²), so the plain Bernstein search stops at a corner that
    is passive.  Proven off the face b1 = 0 and decided on it; dense exact sampling agrees."""
    sea = SEA(
        D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1000, b1=300, kd=1708, bd=300)
    )
    box = {"b1": (0.0, 300.0), "m": (0.5, 2.0)}
    r = robust_check(sea, box=box)
    assert r.outcome is Outcome.PASSIVE, r.detail
    assert "face" in r.detail
    for b1, m in itertools.product(np.linspace(0, 300, 13), np.linspace(0.5, 2, 7)):
        assert is_passive(sea, values={"b1": float(b1), "m": float(m)}).passive


@pytest.mark.parametrize(
    ("expr", "passive"),
    [
        ("c*s + 1/s + a*(s + 2)/(s + 1)", True),  # lossless at a = 0, dissipative for a > 0
        ("c*s + 1/s + a*(1 - s)/(s + 1)", False),  # lossless at a = 0, active above 1 rad/s
    ],
)
def test_a_lossless_face_is_never_mistaken_for_the_box(expr: str, passive: bool) -> None:
    """Re Z is identically 0 on the face a = 0: positive off it is proven through the
    quotient by a; negative off it is found by moving the face point inwards and verified."""
    z = Impedance(expr=expr, values={"a": 0.5, "c": 1.0})
    r = robust_check(z, box={"a": (0.0, 1.0), "c": (1.0, 2.0)})
    grid = itertools.product(np.linspace(0, 1, 9), np.linspace(1, 2, 5))
    sampled = all(is_passive(z, values={"a": float(a), "c": float(c)}).passive for a, c in grid)
    assert sampled is passive
    if passive:
        assert r.outcome is Outcome.PASSIVE, r.detail
    else:
        assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None
        assert not is_passive(z, values=dict(r.worst.values)).passive


# --- corners: two faces meeting, or a face meeting t = 1 (issue 26) ---------------------

LP_DAMPED = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500, b1=10))
_S = sp.Symbol("s")


def _coefficient_functions(
    names: tuple[str, ...], system: SEA = LP_DAMPED
) -> tuple[list[Any], list[Any]]:
    """Ascending coefficients of N and D in s of ``system`` as functions of ``names``
    (the other parameters at their values), straight from the model."""
    z = load_impedance(system.with_values(**dict.fromkeys(names)))
    num, den = sp.fraction(sp.cancel(sp.together(z)))
    fixed = {symbol(k): sp.Rational(v) for k, v in system.values.items() if k not in names}
    syms = [symbol(n) for n in names]

    def fns(p: sp.Expr) -> list[Any]:
        cs = sp.Poly(sp.expand(p.xreplace(fixed)), S).all_coeffs()[::-1]
        return [sp.lambdify(syms, c, "numpy") for c in cs]

    return fns(num), fns(den)


def _grid_passive(
    names: tuple[str, ...], plants: np.ndarray, system: SEA = LP_DAMPED
) -> np.ndarray:
    """Vectorised float check, independent of the robust kernel: Re Z(jω) ≥ 0 on a dense
    log grid of ω and no pole in the open right half-plane, for each row of ``plants``."""
    nf, df = _coefficient_functions(names, system)
    cols = [plants[:, i] for i in range(len(names))]
    ones = np.ones(len(plants))
    nc = np.stack([np.broadcast_to(f(*cols) * ones, ones.shape) for f in nf])
    dc = np.stack([np.broadcast_to(f(*cols) * ones, ones.shape) for f in df])
    jw = 1j * np.logspace(-3, 6, 1000)[np.newaxis, :]
    n_val = np.zeros((len(plants), jw.shape[1]), dtype=complex)
    d_val = np.zeros_like(n_val)
    for c in nc[::-1]:  # Horner
        n_val = n_val * jw + c[:, np.newaxis]
    for c in dc[::-1]:
        d_val = d_val * jw + c[:, np.newaxis]
    re = (n_val * np.conj(d_val)).real
    ok_re = np.all(re >= -1e-9 * np.abs(n_val) * np.abs(d_val), axis=1)
    # poles: eigenvalues of the companion matrices, all plants at once (leading coefficient ≠ 0)
    assert np.all(dc[-1] != 0)
    n = len(dc) - 1
    comp = np.zeros((len(plants), n, n))
    comp[:, 1:, :-1] = np.eye(n - 1)
    comp[:, :, -1] = -(dc[:-1] / dc[-1]).T
    stable = np.max(np.linalg.eigvals(comp).real, axis=1) <= 1e-7
    return np.asarray(ok_re & stable)


def test_lp_over_a_damper_from_zero_and_the_mass_is_passive_by_a_corner_blow_up() -> None:
    """LP with a damper b1 in [0, 50] and m in [0.5, 2] (was undecided): at b1 = 0 the real
    part drops two degrees and its next coefficient b1·(b² + b·b1 − kd·m) is negative near
    the face, so no quotient is positive on the closed box; the corner t = 1, b1 = 0 is
    blown up.  Truth, independently: P/x = b1·m²·x² + b1·c·x + b·k1·(k1 − kd) with
    c = b² + b·b1 − kd·m has no positive root iff b1·c² < 4·m²·b·k1·(k1 − kd) (sympy, on a
    grid of the box, and the limit at b1 → 0), and 2,400 plants pass a vectorised check."""
    r = robust_check(LP_DAMPED, box={"b1": (0.0, 50.0), "m": (0.5, 2.0)})
    assert r.outcome is Outcome.PASSIVE, r.detail
    assert "blowing up a corner" in r.detail and r.boxes < 200
    # sympy: P(x) from N, D, and the discriminant bound over the box
    b1, m, x, w = sp.symbols("b1 m x w", positive=True)
    nf, df = _coefficient_functions(("b1", "m"))
    n_expr = sum(f(b1, m) * _S**i for i, f in enumerate(nf))
    d_expr = sum(f(b1, m) * _S**i for i, f in enumerate(df))
    prod = sp.expand(n_expr.subs(_S, sp.I * w) * d_expr.subs(_S, -sp.I * w))
    px = sp.Poly(sp.expand(sp.re(prod)).subs(w, sp.sqrt(x)), x)
    a0, a1, a2, a3 = (px.coeff_monomial(x**i) for i in range(4))
    assert a0 == 0 and sp.expand(a3 - b1 * m**2) == 0
    assert sp.limit(a2**2 / (4 * a3 * a1), b1, 0) == 0  # the corner: the constant wins
    ratio = sp.lambdify((b1, m), a2**2 - 4 * a3 * a1)
    for bv, mv in itertools.product(np.linspace(1e-3, 50, 41), np.linspace(0.5, 2, 16)):
        assert ratio(bv, mv) < 0 or float(a2.subs({b1: bv, m: mv})) >= 0
    # dense sampling, geometric towards the face b1 = 0
    b1s = np.concatenate([[0.0], np.geomspace(1e-6, 50, 39)])
    plants = np.array(list(itertools.product(b1s, np.linspace(0.5, 2, 60))))
    assert len(plants) >= 2000 and _grid_passive(("b1", "m"), plants).all()
    for bv, mv in itertools.product(b1s[:6], (0.5, 2.0)):  # the exact verdict at the corner
        assert is_passive(LP_DAMPED, values={"b1": float(bv), "m": float(mv)}).passive


def test_lp_over_two_dampers_from_zero_is_not_passive_on_a_face_with_a_verified_plant() -> None:
    """LP over b in [0, 20] and b1 in [0, 50] (was undecided: b + b1 vanishes at the corner,
    where the plant is lossless and passive).  The faces through the corner are decided
    first: on b = 0, P/x = b1·x·(m·x − kd·m)/... is negative below x = kd/m, so the design
    is not passive there; the worst plant passes the plain exact test as not passive, and
    dense sampling finds the same failures (on and near b = 0)."""
    r = robust_check(LP_DAMPED, box={"b": (0.0, 20.0), "b1": (0.0, 50.0)})
    assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None, r.detail
    assert r.worst.values["b"] == 0 and 0 < r.worst.values["b1"] <= 50
    plain = is_passive(LP_DAMPED, values=dict(r.worst.values))
    assert not plain.passive and r.worst.frequency is not None
    assert (r.worst.frequency**2) < 500  # below sqrt(kd/m): Re Z < 0 there
    bs = np.concatenate([[0.0], np.geomspace(1e-4, 20, 44)])
    b1s = np.concatenate([[0.0], np.geomspace(1e-4, 50, 44)])
    plants = np.array(list(itertools.product(bs, b1s)))
    ok = _grid_passive(("b", "b1"), plants)
    assert len(plants) >= 2000 and not ok[plants[:, 0] == 0][1:].any()  # b = 0, b1 > 0
    assert ok[plants[:, 1] == 0].all()  # b1 = 0 (the plain LP, kd < k1): passive
    sample = plants[:: len(plants) // 40]
    for (bv, b1v), grid_ok in zip(sample, ok[:: len(plants) // 40], strict=True):
        assert is_passive(LP_DAMPED, values={"b": float(bv), "b1": float(b1v)}).passive == grid_ok


@pytest.mark.parametrize(
    "expr",
    ["1/s + (a + c)/(s + 1)", "1/s + (a*a + c - a*c)/(s + 1)", "1/s + (a + c)*(s + 2)/(s + 1)"],
)
def test_a_condition_zero_only_where_two_faces_meet_is_proven_off_the_corner(expr: str) -> None:
    """Re Z ∝ g(a, c) with g = 0 only at the corner a = c = 0 (a lossless plant): both faces
    are decided apart and g is proven off them by blowing up the corner; sampling agrees."""
    z = Impedance(expr=expr, values={"a": 0.5, "c": 1.0})
    r = robust_check(z, box={"a": (0.0, 1.0), "c": (0.0, 2.0)})
    assert r.outcome is Outcome.PASSIVE and "blowing up a corner" in r.detail, r.detail
    grid = itertools.product(np.geomspace(1e-6, 1, 6), np.geomspace(1e-6, 2, 6))
    assert all(is_passive(z, values={"a": float(a), "c": float(c)}).passive for a, c in grid)


OURS = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1000, b1=300, kd=1708, bd=300))


@pytest.mark.parametrize(
    ("system", "box", "passive"),
    [
        (LP_DAMPED, {"b1": (0.0, 50.0), "k1": (800.0, 1200.0), "m": (0.5, 2.0)}, True),
        (LP_DAMPED, {"b": (5.0, 20.0), "b1": (0.0, 50.0), "m": (0.5, 2.0)}, True),
        (OURS, {"b1": (0.0, 50.0), "bd": (0.0, 100.0)}, True),
        (LP_DAMPED, {"b1": (0.0, 50.0), "kd": (100.0, 900.0)}, False),
    ],
)
def test_more_boxes_from_a_zero_damper_are_decided_and_sampling_agrees(
    system: SEA, box: dict[str, tuple[float, float]], passive: bool
) -> None:
    """Boxes that were undecided (the real part off the face b1 = 0 failed at its corner):
    decided now, and 1,000+ plants (geometric towards the faces at 0) agree."""
    r = robust_check(system, box=box)
    names = tuple(sorted(box))
    k = int(np.ceil(1100 ** (1 / len(names))))  # points per axis: 1,100+ plants in all
    axes = [
        np.concatenate([[0.0], np.geomspace(1e-6 * hi, hi, k - 1)])
        if lo == 0
        else np.linspace(lo, hi, k)
        for lo, hi in (box[n] for n in names)
    ]
    plants = np.array(list(itertools.product(*axes)))
    ok = _grid_passive(names, plants, system)
    if passive:
        assert r.outcome is Outcome.PASSIVE and "corner" in r.detail, r.detail
        assert len(plants) >= 1000 and ok.all()
    else:
        assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None
        assert not is_passive(system, values=dict(r.worst.values)).passive and not ok.all()
