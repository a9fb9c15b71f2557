"""The friction certificate: the two-port around the friction, and what passes or not."""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
import pytest
import sympy as sp

from seapass.errors import ParameterError
from seapass.model.expr import S, symbol
from seapass.model.sea import SEA
from seapass.model.stiffness import load_impedance
from seapass.outcome import Outcome
from seapass.ports.friction import friction_certificate, friction_two_port

RIG = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


@pytest.mark.parametrize("at", ["actuator", "transmission"])
def test_no_friction_gives_back_the_one_port(at: str) -> None:
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": 300.0})
    z11, z12, z21, z22 = friction_two_port(sea, at).entries
    # a free port 2 (zero friction force) leaves the SEA as it is
    assert sp.cancel(z11 - z12 * z21 / z22 - load_impedance(sea)) == 0


@pytest.mark.parametrize("at", ["actuator", "transmission"])
def test_certified_for_a_mechanical_coupling_and_not_for_load_feedback(at: str) -> None:
    good = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG)
    assert friction_certificate(good, at=at).certified
    bad = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": 300.0})
    cert = friction_certificate(bad, at=at)
    assert not cert.certified and "no proof" in cert.detail
    assert cert.to_dict()["certified"] is False


def test_viscous_friction_keeps_a_certified_design_passive() -> None:
    """Close the friction port with dampers (a passive friction law): the SEA stays passive."""
    from seapass.analysis.passivity import is_passive

    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG)
    assert friction_certificate(sea).certified
    for c in np.geomspace(0.1, 1e4, 7):
        # viscous friction c on the actuator: the same as raising b by c
        assert is_passive(sea.with_values(b=RIG["b"] + float(c))).passive


def test_bad_site() -> None:
    with pytest.raises(ParameterError, match="at"):
        friction_certificate(SEA(D1="k1", values={"m": 1, "b": 1, "k1": 1}), at="gearbox")


# --- independent cross-checks -------------------------------------------------------------
# The two-port around the friction is rebuilt below from the free-body equations written out
# by hand (numpy only, at each s = jω), and the certificate is compared with a dense grid of
# the least eigenvalue of Z + Z^H with local refinement, with the residue at s = 0 evaluated
# numerically, and with the exact one-port test of the SEA closed by passive elements at the
# friction site (a different decision procedure: seapass.analysis.passivity).

VALS = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0, kl=300.0, k2=200.0, ki=40.0)
DESIGNS = {
    "ours": dict(D1="k1 + b1*s", CA="kd + bd*s"),
    "spring-PD": dict(D1="k1", CA="kd + bd*s"),
    "with-D2": dict(D1="k1 + b1*s", D2="k2", CA="kd + bd*s"),
    "load-P": dict(D1="k1", CL="kd"),
    "load-feedback": dict(D1="k1 + b1*s", CA="kd + bd*s", CL="kl"),
    "act-PID": dict(D1="k1 + b1*s", CA="kd + bd*s + ki/s"),
}


def _design(key: str) -> tuple[SEA, dict[str, float]]:
    model = DESIGNS[key]
    names = {str(x) for e in model.values() for x in sp.sympify(e).free_symbols} - {"s"}
    vals = {k: VALS[k] for k in names | {"m", "b"}}
    return SEA(**model, values=vals), vals


@functools.cache
def _elements(key: str) -> dict[str, Any]:
    model, vals = DESIGNS[key], _design(key)[1]
    s_ = sp.Symbol("s")
    return {
        k: sp.lambdify(s_, sp.sympify(model.get(k, "0")).subs(vals), "numpy")
        for k in ("D1", "D2", "CA", "CL")
    }


def physical_friction_z(key: str, at: str, w: np.ndarray) -> np.ndarray:
    """``Z(jω)`` of the two-port around the friction, from the free-body equations by hand.

    Reference at zero, massless load, port 1 the person (``F_L``, ``s X_L``).  At the
    actuator, port 2 is ``s X_A`` and the force ``F_2`` the friction puts on the actuator:
    ``(m s² + b s) X_A = F_A + D1 (X_L − X_A) + F_2``.  In the transmission (an element in
    parallel with D1), port 2 is the stretch rate ``s (X_L − X_A)`` and ``F_2`` minus the
    element's tension ``g``: the element pulls the load by ``−g = F_2`` and the actuator by
    ``g = −F_2``.  Always ``F_L = D1 (X_L − X_A) + D2 X_L − (F_2 at the transmission)`` and
    ``F_A = −C_A X_A − C_L X_L``.
    """
    vals, fn = _design(key)[1], _elements(key)
    s = 1j * np.atleast_1d(np.asarray(w, dtype=float))
    d1, d2, ca, cl = (np.broadcast_to(fn[k](s), s.shape) for k in ("D1", "D2", "CA", "CL"))
    alpha = vals["m"] * s * s + vals["b"] * s
    out = np.empty((s.size, 2, 2), dtype=complex)
    zero = np.zeros_like(s)
    for j in range(2):  # unit velocity on port j, zero on the other
        if at == "actuator":
            xl, xa = (1 / s, zero) if j == 0 else (zero, 1 / s)
            fa = -ca * xa - cl * xl
            f2 = alpha * xa - fa - d1 * (xl - xa)
            fl = d1 * (xl - xa) + d2 * xl
        else:
            xl, x2 = (1 / s, zero) if j == 0 else (zero, 1 / s)  # x2 = X_L − X_A
            xa = xl - x2
            fa = -ca * xa - cl * xl
            f2 = fa + d1 * (xl - xa) - alpha * xa  # actuator: α X_A = F_A + D1 (X_L−X_A) − F_2
            fl = d1 * (xl - xa) + d2 * xl - f2
        out[:, 0, j], out[:, 1, j] = fl, f2
    return out


@pytest.mark.parametrize("at", ["actuator", "transmission"])
@pytest.mark.parametrize("key", sorted(DESIGNS))
def test_friction_two_port_matches_the_hand_written_free_body_equations(key: str, at: str) -> None:
    sea, vals = _design(key)
    entries = friction_two_port(sea, at).entries
    w = np.geomspace(0.05, 5e3, 41)
    mine = np.empty((w.size, 2, 2), dtype=complex)
    for k, e in enumerate(entries):
        f = sp.lambdify(S, e.xreplace({symbol(n): sp.Rational(v) for n, v in vals.items()}))
        mine[:, k // 2, k % 2] = np.broadcast_to(f(1j * w), w.shape)
    theirs = physical_friction_z(key, at, w)
    assert np.allclose(mine, theirs, rtol=1e-9, atol=1e-9 * np.abs(theirs).max())


@pytest.mark.parametrize("at", ["actuator", "transmission"])
@pytest.mark.parametrize("key", sorted(DESIGNS))
def test_certificate_agrees_with_a_refined_grid_and_the_residue_at_zero(key: str, at: str) -> None:
    from .numeric import OMEGA, min_eig_hermitian, refined_minimum, vectorized

    sea, _ = _design(key)
    cert = friction_certificate(sea, at=at)
    assert cert.outcome is not Outcome.UNDECIDED
    w = OMEGA[::20]
    scale = float(np.abs(physical_friction_z(key, at, w)).max())
    low, _where = refined_minimum(
        vectorized(lambda x: min_eig_hermitian(physical_friction_z(key, at, x))), w
    )
    # the residue matrix at the pole s = 0, numerically: s Z(s) as s → 0 along the axis
    tiny = np.array([1e-7])
    r0 = (1j * tiny[0]) * physical_friction_z(key, at, tiny)[0]
    r0 = np.where(np.abs(r0) < 1e-6 * max(1.0, np.abs(r0).max()), 0, r0)
    hermitian_psd = np.allclose(r0, r0.conj().T, atol=1e-6 * max(1.0, np.abs(r0).max())) and (
        np.linalg.eigvalsh((r0 + r0.conj().T) / 2)[0] >= -1e-6 * max(1.0, np.abs(r0).max())
    )
    names = {c.name for c in cert.passivity.failing}
    if cert.certified:
        assert low >= -1e-9 * scale and hermitian_psd
    else:
        assert low < -1e-9 * scale or not hermitian_psd
        if names & {"minor_1", "minor_2", "minor_12"}:
            assert low < 0  # a frequency condition fails: the grid finds it too
        assert ("axis_poles" in names) is (not hermitian_psd)


@pytest.mark.parametrize("at", ["actuator", "transmission"])
@pytest.mark.parametrize("key", ["ours", "spring-PD", "with-D2"])
def test_certified_designs_stay_passive_with_random_passive_elements_at_the_site(
    key: str, at: str
) -> None:
    """A passive linear element at the friction site (mass, damper, spring; an inerter in the
    transmission) leaves a certified SEA passive, by the exact one-port test."""
    from seapass.analysis.passivity import is_passive

    sea, vals = _design(key)
    assert friction_certificate(sea, at=at).certified
    model = DESIGNS[key]
    rng = np.random.default_rng(24)
    for mf, cf, kf in 10.0 ** rng.uniform(-2, 3, size=(8, 3)):
        extra = {"mf": float(mf), "cf": float(cf), "kf": float(kf)}
        if at == "actuator":  # grounded on the actuator: more mass, damping, and a spring
            closed = SEA(
                D1=model["D1"],
                D2=model.get("D2", "0"),
                CA=f"{model['CA']} + kf",
                values={**vals, "m": vals["m"] + extra["mf"], "b": vals["b"] + extra["cf"],
                        "kf": extra["kf"]},
            )  # fmt: skip
        else:  # in parallel with D1: an inerter, a damper and a spring across the stretch
            closed = SEA(
                D1=f"{model['D1']} + mf*s**2 + cf*s + kf",
                D2=model.get("D2", "0"),
                CA=model["CA"],
                values={**vals, **extra},
            )
        assert is_passive(closed).passive, (key, at, extra)
