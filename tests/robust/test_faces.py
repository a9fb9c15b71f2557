"""Conditions that vanish on a face of the box (seapass.robust.faces and its use)."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest
from flint import fmpq
from hypothesis import given
from hypothesis import strategies as st

from seapass.analysis.passivity import is_passive
from seapass.model.sea import SEA, Impedance
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
    top, rest = split_top(f)
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
