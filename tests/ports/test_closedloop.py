"""The closed loop with two passive terminations, checked against the SEA's physical equations.

The physical model (``numeric.sea_closed_loop_poles``) is a 6-state second-order
system written out by hand; the library computes ``χ`` from the two-port matrix.
"""

from __future__ import annotations

import numpy as np
import pytest

from seapass.analysis.coupled import Environment
from seapass.model.catalog import CATALOG, REFERENCE_VALUES
from seapass.model.sea import SEA
from seapass.ports import two_port
from seapass.ports.closedloop import closed_loop
from seapass.ports.stability import absolute_stability

from .numeric import (
    batched_roots,
    exact_coefficients,
    routh_rhp_count,
    sea_characteristic,
    sea_closed_loop_poles,
)

BASE = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)
PAIRS = 10_000


def _design(kl: float, **kw: float) -> tuple[dict[str, float], object]:
    par = {**BASE, "kl": kl, **kw}
    return par, two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values=par))


def _random_terminations(rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` pairs of passive mass-spring-dampers over many decades (masses > 0)."""

    def logu(lo: float, hi: float) -> np.ndarray:
        return np.exp(rng.uniform(np.log(lo), np.log(hi), n))

    env = np.empty((n, 6))
    for port in (0, 3):
        env[:, port] = logu(1e-3, 1e2)
        env[:, port + 1] = np.where(rng.random(n) < 0.2, 0.0, logu(1e-3, 1e3))
        env[:, port + 2] = np.where(rng.random(n) < 0.2, 0.0, logu(1e-1, 1e6))
    return env


def _unstable(poles: np.ndarray) -> np.ndarray:
    scale = np.maximum(1.0, np.abs(poles))
    return np.any(poles.real > 1e-7 * scale, axis=1)


@pytest.mark.parametrize("form", ["z", "h", "g", "y"])
def test_characteristic_polynomial_matches_the_physical_closed_loop(form: str) -> None:
    par, tp = _design(300.0)
    m = tp.convert(form).exact()
    rng = np.random.default_rng(7)
    env = _random_terminations(rng, 16)
    env[:8, [2, 5]] = np.maximum(env[:8, [2, 5]], 1.0)  # springs on both: no rigid-body mode
    env[8:12, 2] = 0.0  # no spring at the person: ...
    env[12:, [2, 5]] = 0.0  # ... or at neither (the whole rig may drift: a root at s = 0)
    physical = sea_closed_loop_poles(par, env)
    for row, phys in zip(env, physical, strict=True):
        loop = closed_loop(m, form, Environment(*row[:3]), Environment(*row[3:]))
        scale = np.abs(phys).max()
        phys_nonzero = phys[np.abs(phys) > 1e-9 * scale]
        ours = loop.poles[np.abs(loop.poles) > 0]
        assert ours.size == phys_nonzero.size and loop.poles.size <= 6
        np.testing.assert_allclose(
            np.sort_complex(ours), np.sort_complex(phys_nonzero), rtol=1e-6, atol=1e-6 * scale
        )


@pytest.mark.parametrize("kl", [0.0, 300.0, -400.0])
def test_absolutely_stable_designs_survive_ten_thousand_random_terminations(kl: float) -> None:
    par, tp = _design(kl)
    assert absolute_stability(tp, witness=False).absolutely_stable
    rng = np.random.default_rng(2024)
    env = _random_terminations(rng, PAIRS)
    poles = sea_closed_loop_poles(par, env)
    assert poles.shape == (PAIRS, 6)  # the work: PAIRS eigenvalue problems
    assert not _unstable(poles).any()


def test_not_absolutely_stable_design_its_witness_is_unstable_in_the_physical_model() -> None:
    par, tp = _design(5000.0)
    r = absolute_stability(tp)
    assert not r.absolutely_stable
    w = r.witness
    assert w is not None and w.found and w.within_bounds
    env = np.array([[w.port1.mass, w.port1.damping, w.port1.stiffness,
                     w.port2.mass, w.port2.damping, w.port2.stiffness]])  # fmt: skip
    env[:, [0, 3]] = np.maximum(env[:, [0, 3]], 1e-12)  # a massless port: a tiny mass
    poles = sea_closed_loop_poles(par, env)[0]
    assert poles.real.max() > 0.1
    assert poles.real.max() == pytest.approx(w.closed_loop.max_real_part, rel=1e-3)
    # and a blind random search confirms that unstable pairs exist (the test above has teeth)
    rng = np.random.default_rng(1)
    assert _unstable(sea_closed_loop_poles(par, _random_terminations(rng, 2000))).any()


def test_witness_for_a_lightly_damped_design() -> None:
    par, tp = _design(2000.0, b1=2.0, bd=3.0)
    r = absolute_stability(tp)
    assert not r.absolutely_stable and r.witness is not None and r.witness.found
    w = r.witness
    env = np.array([[max(w.port1.mass, 1e-12), w.port1.damping, w.port1.stiffness,
                     max(w.port2.mass, 1e-12), w.port2.damping, w.port2.stiffness]])  # fmt: skip
    assert sea_closed_loop_poles(par, env)[0].real.max() > 0


def test_the_virtual_wall_of_the_docs_passes_the_one_port_test_yet_its_witness_is_unstable() -> (
    None
):
    from seapass.analysis.passivity import is_passive

    par = {**BASE, "kd": 2000.0, "bd": 40.0, "kl": 3500.0}  # kd, bd: the virtual coupling
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values=par)
    assert is_passive(sea).passive  # the environment held rigid: passive
    r = absolute_stability(sea)
    assert not r.absolutely_stable and r.witness is not None and r.witness.within_bounds
    w = r.witness
    env = np.array([[max(w.port1.mass, 1e-12), w.port1.damping, w.port1.stiffness,
                     max(w.port2.mass, 1e-12), w.port2.damping, w.port2.stiffness]])  # fmt: skip
    assert sea_closed_loop_poles(par, env)[0].real.max() > 0.1


@pytest.mark.parametrize("key", sorted(CATALOG))
def test_every_catalog_design_against_its_closed_loop_with_random_terminations(key: str) -> None:
    """Absolutely stable ⇒ no unstable pair among PAIRS random passive terminations; not
    absolutely stable ⇒ the witness pair is unstable; both in `numeric.sea_characteristic`,
    a closed loop written out by hand for any D1, D2, C_A, C_L (shares nothing with ports)."""
    design = CATALOG[key]
    sea = design.sea()
    values = {k: REFERENCE_VALUES[k] for k in sea.parameters}
    sea = sea.with_values(**values)
    model = {k: str(getattr(design, k)) for k in ("D1", "D2", "CA", "CL") if getattr(design, k)}
    coeffs, degree = sea_characteristic(model, values)
    r = absolute_stability(two_port(sea))
    if r.absolutely_stable:
        env = _random_terminations(np.random.default_rng(24), PAIRS)
        poles = batched_roots(coeffs(env))
        assert poles.shape == (PAIRS, degree)  # the work: PAIRS eigenvalue problems
        assert not _unstable(poles).any()
    else:
        w = r.witness
        assert w is not None and w.found, key
        env = np.array([w.port1.mass, w.port1.damping, w.port1.stiffness,
                        w.port2.mass, w.port2.damping, w.port2.stiffness])  # fmt: skip
        assert routh_rhp_count(exact_coefficients(model, values, env)) > 0, key  # exact
        poles = np.roots(coeffs(env)[0])
        assert poles.real.max() == pytest.approx(w.closed_loop.max_real_part, rel=1e-2, abs=1e-9)
