"""Passivity of two-ports and n-ports: every principal minor, residues, and independent checks."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import sympy as sp

from seapass.model.expr import S
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.ports import TwoPort, two_port
from seapass.ports.axes import CoupledAxes
from seapass.ports.check import check_two_port, two_port_passivity
from seapass.ports.mimo import NPort, mimo_is_passive

from .numeric import OMEGA, matrix_function, min_eig_hermitian, refined_minimum, vectorized

RIG = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


def _axes(kc: float, side: str = "actuator", n: int = 2) -> NPort:
    k = [["kd" if i == j else 0 for j in range(n)] for i in range(n)]
    k[0][1], k[1][0] = "kc", "-kc"  # a curl field between axes 1 and 2
    b = [["bd" if i == j else 0 for j in range(n)] for i in range(n)]
    return CoupledAxes(
        axes=({"D1": "k1 + b1*s"},) * n, K=k, B=b, side=side, values={**RIG, "kc": kc}
    ).n_port()


CASES = {
    "sea coupling": two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG)),
    "sea load 300": two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": 300})),
    "sea load 5000": two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": 5000})),
    "curl actuator": _axes(100.0),
    "curl load": _axes(100.0, "load"),
    "no curl 3 axes": _axes(0.0, n=3),
    "curl 3 axes": _axes(40.0, n=3),
}  # fmt: skip


def _result(system):
    return two_port_passivity(system) if isinstance(system, TwoPort) else mimo_is_passive(system)


@pytest.mark.parametrize("key", sorted(CASES))
def test_verdict_agrees_with_the_least_eigenvalue_on_a_refined_grid(key: str) -> None:
    system = CASES[key]
    n = 2 if isinstance(system, TwoPort) else system.n
    f = matrix_function(system.entries, system.values, n)
    r = _result(system)

    def g(w: np.ndarray) -> np.ndarray:
        p = f(w)
        norm = np.linalg.norm(p + np.conj(np.swapaxes(p, 1, 2)), axis=(1, 2))
        return min_eig_hermitian(p) / np.maximum(norm, 1e-300)

    low, where = refined_minimum(vectorized(g))
    minors_hold = all(c.holds for c in r.conditions if c.name.startswith("minor_"))
    if minors_hold:
        assert low >= -1e-9, f"exact: P + P^H >= 0; the grid finds {low:g} at {where:g}"
    else:
        assert low < 0
        assert any(b.lo * (1 - 1e-6) <= where <= b.hi * (1 + 1e-6) for b in r.bands)
        vals = g(OMEGA)
        clearly = OMEGA[vals < -1e-7]
        inside = np.zeros(clearly.size, dtype=bool)
        for b in r.bands:
            inside |= (clearly >= b.lo * (1 - 1e-6)) & (clearly <= b.hi * (1 + 1e-6))
        assert inside.all()


def test_known_verdicts_and_the_curl_field() -> None:
    got = {k: _result(v).outcome for k, v in CASES.items()}
    assert got["sea coupling"] is Outcome.PASSIVE
    assert got["sea load 5000"] is Outcome.NOT_PASSIVE
    assert got["no curl 3 axes"] is Outcome.PASSIVE
    for key in ("curl actuator", "curl load", "curl 3 axes"):
        r = _result(CASES[key])
        assert r.outcome is Outcome.NOT_PASSIVE
        failing = {c.name for c in r.failing}
        assert "axis_poles" in failing  # the stiffness at s = 0 is not symmetric
        assert any(n.startswith("minor_") and "1" in n and "2" in n for n in failing)
        # each axis on its own is passive: only a minor that mixes axes 1 and 2 fails
        assert {"minor_1", "minor_2"}.isdisjoint(failing)


def test_every_principal_minor_is_checked_not_only_the_leading_ones() -> None:
    # leading minors 1, 0, 0 are all >= 0, yet [[1, 2], [2, 1]] on ports 1 and 3 is indefinite
    r = mimo_is_passive([[1, 0, 2], [0, 0, 0], [2, 0, 1]])
    assert not r.passive
    assert {c.name for c in r.failing} == {"minor_13"}


def test_residue_conditions() -> None:
    indefinite = TwoPort.from_matrix([["1/s", "2/s"], ["2/s", "1/s"]])
    assert {c.name for c in two_port_passivity(indefinite).failing} == {"axis_poles"}
    semidefinite = TwoPort.from_matrix([["1/s + 1", "1/s"], ["1/s", "1/s + 1"]])
    assert two_port_passivity(semidefinite).passive
    at_infinity = TwoPort.from_matrix([["s", "2*s"], ["2*s", "s"]])
    assert {c.name for c in two_port_passivity(at_infinity).failing} == {"axis_poles"}
    lossless = TwoPort.from_matrix([["s", "s"], ["s", "s"]])
    assert two_port_passivity(lossless).passive
    double = TwoPort.from_matrix([["1/s**2 + 1", 0], [0, 1]])
    assert "axis_poles" in {c.name for c in two_port_passivity(double).failing}
    unstable = TwoPort.from_matrix([["1", "1/(s - 1)"], ["1/(s - 1)", "1"]])
    assert "stable_entries" in {c.name for c in two_port_passivity(unstable).failing}


def test_passive_implies_absolutely_stable_and_reciprocity() -> None:
    for key, system in CASES.items():
        if not isinstance(system, TwoPort):
            continue
        c = check_two_port(system, witness=False)
        if c.passive:
            assert c.absolutely_stable, key
        z12, z21 = system.entries[1], system.entries[2]
        subs = {sp.Symbol(k, positive=True): sp.Rational(v) for k, v in system.values.items()}
        assert c.reciprocal == (sp.cancel((z12 - z21).xreplace(subs)) == 0)


def _random_stable_ss(rng: np.random.Generator, states: int) -> tuple[np.ndarray, ...]:
    poles = -rng.uniform(0.5, 5.0, states)
    q = np.linalg.qr(rng.normal(size=(states, states)))[0]
    a = q @ np.diag(poles) @ q.T
    b = rng.normal(size=(states, 2))
    c = rng.normal(size=(2, states))
    d = rng.normal(size=(2, 2)) + np.eye(2) * rng.uniform(0.0, 4.0)
    return a, b, c, d


def _exact_entries(a, b, c, d) -> list[sp.Expr]:
    """``C adj(sI − A) B / det(sI − A) + D`` exactly (1 or 2 states), from the float matrices."""
    from fractions import Fraction as F

    q = lambda x: F(float(x))  # noqa: E731 - the rational each float represents
    n = a.shape[0]
    if n == 1:
        det = [-q(a[0, 0]), F(1)]  # ascending coefficients of s - a11
        adj = [[[F(1)]]]
    else:
        det = [q(a[0, 0]) * q(a[1, 1]) - q(a[0, 1]) * q(a[1, 0]), -q(a[0, 0]) - q(a[1, 1]), F(1)]
        adj = [[[-q(a[1, 1]), F(1)], [q(a[0, 1])]], [[q(a[1, 0])], [-q(a[0, 0]), F(1)]]]
    out = []
    for i in range(2):
        for j in range(2):
            num = [F(0)] * (n + 1)
            for k in range(n):
                for m in range(n):
                    for p, coeff in enumerate(adj[k][m]):
                        num[p] += q(c[i, k]) * coeff * q(b[m, j])
            num = [x + q(d[i, j]) * y for x, y in zip(num, det, strict=True)]
            expr = sum(sp.Rational(x) * S**p for p, x in enumerate(num)) / sum(
                sp.Rational(x) * S**p for p, x in enumerate(det)
            )
            out.append(expr)
    return out


def test_python_control_ispassive_agrees_where_well_conditioned() -> None:
    import control

    rng = np.random.default_rng(11)
    agree = compared = 0
    for _ in range(40):
        a, b, c, d = _random_stable_ss(rng, int(rng.integers(1, 3)))
        entries = _exact_entries(a, b, c, d)
        ours = two_port_passivity(TwoPort.from_matrix([entries[:2], entries[2:]]))
        w = np.geomspace(1e-3, 1e4, 4000)
        p = (
            np.einsum(
                "ik,wkl,lj->wij", c, np.linalg.inv(1j * w[:, None, None] * np.eye(len(a)) - a), b
            )
            + d
        )
        margin = float(
            np.min(
                min_eig_hermitian(p)
                / np.linalg.norm(p + np.conj(np.swapaxes(p, 1, 2)), axis=(1, 2))
            )
        )
        if abs(margin) < 1e-2:
            continue  # the LMI is ill conditioned near the boundary
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            theirs = bool(control.ispassive(control.ss(a, b, c, d)))
        compared += 1
        agree += theirs == ours.passive
    assert compared >= 20
    assert agree == compared
