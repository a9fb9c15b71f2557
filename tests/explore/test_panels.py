"""The explorer's two-port panel against seapass.ports and an independent numeric two-port.

The independent two-port solves the SEA's free-body equations numerically at each
``s = jω`` (a 4×4 complex linear system per frequency, numpy only), so the η the
panel draws and its certified infimum are checked against a derivation that
shares nothing with `seapass.ports.derive`.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from seapass.explore.panels import KINDS, compute
from seapass.explore.pool import AFFINITY
from seapass.explore.validation import check_state
from seapass.model.sea import SEA
from seapass.ports.stability import absolute_stability

COUPLING = {"D1": "k1 + b1*s", "CA": "kd + bd*s", "CL": "kl"}
VALUES = {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 20.0, "kd": 500.0, "bd": 25.0}


def _state(model: dict[str, str], values: dict[str, float]):
    s = check_state({"model": model, "values": values}).state
    assert s is not None
    return s


def physical_z(par: dict[str, float], w: np.ndarray) -> np.ndarray:
    """``Z(jω)`` of the coupling design from its free-body equations, solved numerically.

    Unknowns ``u = (X_A, F_A, F_L, F_2)``, given the port velocities ``v = (s X_L, s Θ)``:
    ``(m s² + b s) X_A = F_A + D1 (X_L − X_A)``, ``F_L = D1 (X_L − X_A)``,
    ``F_A = C_A (Θ − X_A) + C_L (Θ − X_L)``, ``F_2 = F_A``.
    """
    out = np.empty((w.size, 2, 2), dtype=complex)
    for i, s in enumerate(1j * w):
        d1 = par["k1"] + par["b1"] * s
        ca, cl = par["kd"] + par["bd"] * s, par["kl"]
        alpha = par["m"] * s * s + par["b"] * s
        a = np.array(
            [[alpha + d1, -1, 0, 0], [d1, 0, 1, 0], [ca, 1, 0, 0], [0, -1, 0, 1]], dtype=complex
        )
        for j, (xl, th) in enumerate(((1 / s, 0), (0, 1 / s))):  # unit velocity on port j
            rhs = np.array([d1 * xl, d1 * xl, (ca + cl) * th - cl * xl, 0], dtype=complex)
            u = np.linalg.solve(a, rhs)
            out[i, :, j] = (u[2], u[3])
    return out


def eta_of(z: np.ndarray) -> np.ndarray:
    q = z[:, 0, 1] * z[:, 1, 0]
    return (2 * z[:, 0, 0].real * z[:, 1, 1].real - q.real) / np.abs(q)


@pytest.mark.parametrize(("kl", "stable"), [(300.0, True), (1500.0, True), (5000.0, False)])
def test_twoport_panel_against_the_library_and_the_physics(kl: float, stable: bool) -> None:
    par = {**VALUES, "kl": kl}
    d = compute("twoport", _state(COUPLING, par))
    lib = absolute_stability(SEA(**COUPLING, values=par), witness=False)
    assert d["absolutely_stable"] is stable is lib.absolutely_stable
    assert d["outcome"] == lib.outcome.value
    assert d["eta_min"] == pytest.approx(lib.eta.value, rel=1e-15)
    w = np.array(d["omega"])
    eta = eta_of(physical_z(par, w))
    drawn = np.array([np.nan if v is None else v for v in d["eta"]])
    assert np.allclose(drawn, eta, rtol=1e-7, atol=1e-9)
    # the certified infimum is below every sampled value, and near the least of a dense grid
    dense = np.geomspace(w[0], w[-1], 20_000)
    least = float(np.min(eta_of(physical_z(par, dense))))
    assert d["eta_min"] <= least + 1e-9 * max(1.0, abs(least))
    assert (d["eta_min"] >= 1.0) is stable
    if d["eta_kind"] == "attained":
        assert least - d["eta_min"] < 1e-3 * max(1.0, abs(least))
    if not stable:
        assert any(c["name"] == "llewellyn" and c["bands"] for c in d["failing"])
        # a failing band holds frequencies where the physical η < 1
        lo, hi = next(c["bands"][0] for c in d["failing"] if c["name"] == "llewellyn")
        mid = math.sqrt(lo * hi) if lo > 0 and hi is not None else (hi or lo * 10) / 2
        assert eta_of(physical_z(par, np.array([mid])))[0] < 1


def test_twoport_panel_without_coupling_and_its_slot() -> None:
    """No controller: ``p12 p21 = 0``, η does not exist, absolutely stable (a passive spring)."""
    d = compute("twoport", _state({"D1": "k1"}, {"m": 1.0, "b": 10.0, "k1": 1000.0}))
    assert d["absolutely_stable"] is True and d["eta_kind"] == "undefined"
    assert d["eta_min"] is None and all(v is None for v in d["eta"])
    assert d["failing"] == [] and d["reciprocal"] is True
    assert "twoport" in KINDS and AFFINITY["twoport"] == AFFINITY["verdict"]
