"""Simulation check of the sampled-data bound: the digital loop coupled to passive environments.

The sampled SEA loop (ZOH force, sampled encoders, the deployed discrete
controller) is coupled to a mass-spring(-damper) environment at the port and
discretized exactly; a spectral radius above one is a destabilizing passive
environment.  This is the empirical counterpart of [`seapass.sampled.passivity.sampled_passivity`][seapass.sampled.passivity.sampled_passivity].
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from ..errors import ModelError, ParameterError
from ..model.expr import S
from ..model.loop import SampledLoop
from ..model.sea import SEA
from .controllers import DiscreteController

__all__ = [
    "CoupledCheck",
    "coupled_check",
    "coupled_closed_loop",
    "coupled_plant",
    "worst_sampled_environment",
]


@dataclass(frozen=True, kw_only=True)
class CoupledCheck:
    """Sampled closed loop coupled to a mass–spring–damper environment at the port.

    Attributes
    ----------
    env_mass, env_stiffness, env_damping : float
        The passive environment (kg, N/m, N s/m).
    spectral_radius : float
        Of the exact discrete-time closed loop (states at the sampling instants,
        ZOH discretized by the matrix exponential); ``< 1`` means stable.
    """

    env_mass: float
    env_stiffness: float
    env_damping: float
    spectral_radius: float

    @property
    def stable(self) -> bool:
        return self.spectral_radius < 1.0

    def to_dict(self) -> dict[str, Any]:
        return {
            "env_mass": self.env_mass,
            "env_stiffness": self.env_stiffness,
            "env_damping": self.env_damping,
            "spectral_radius": self.spectral_radius,
            "stable": self.stable,
        }


def _kb(expr: sp.Expr, what: str) -> tuple[float, float]:
    if sp.denom(sp.together(expr)).free_symbols or sp.Poly(sp.expand(expr), S).degree() > 1:
        raise ModelError(f"coupled simulation supports {what} = k + b*s only, got {expr}")
    poly = sp.Poly(sp.expand(expr), S)
    c = [*poly.all_coeffs()[::-1], 0, 0]
    return float(c[0]), float(c[1])


def coupled_plant(sea: SEA) -> tuple[float, ...]:
    """``(m, b, k1, b1, k2, b2)`` of ``D1 = k1 + b1 s``, ``D2 = k2 + b2 s`` (else `ModelError`)."""
    e = {k: sea.numeric(v) for k, v in sea.elements().items()}
    return (float(e["m"]), float(e["b"]), *_kb(e["D1"], "D1"), *_kb(e["D2"], "D2"))


def coupled_closed_loop(
    sea: SEA,
    *,
    loop: SampledLoop,
    env_mass: float,
    env_stiffness: float = 0.0,
    env_damping: float = 0.0,
    controller: DiscreteController | None = None,
    _plant: tuple[float, ...] | None = None,
) -> np.ndarray:
    """Closed-loop transition matrix over one period (plant states first: x_A, v_A, x_L, v_L,
    then the states of ``D1`` and ``D2``, then the controller's).

    Any rational ``D1``, ``D2`` with at most one derivative
    ([`discrete_plant`][seapass.sampled.plantloop.discrete_plant]).  The controller is its
    one minimal realization
    ([`controller_state_space`][seapass.sampled.controllers.controller_state_space]) followed by
    the loop's delay; ``controller`` (a `DiscreteController`) skips re-discretizing it.
    ``_plant`` is ignored (kept for callers of the former ``k + b s`` plant).
    """
    from .plantloop import discrete_plant, loop_matrix

    if not env_mass > 0:
        raise ParameterError(f"env_mass must be positive, got {env_mass!r}")
    plant = discrete_plant(sea, loop.period, load_mass=float(env_mass),
                           env_stiffness=float(env_stiffness), env_damping=float(env_damping))  # fmt: skip
    ctrl = controller or DiscreteController.for_loop(sea, loop)
    return loop_matrix(plant, ctrl, loop.delay)


def coupled_check(
    sea: SEA,
    *,
    loop: SampledLoop,
    env_mass: float,
    env_stiffness: float = 0.0,
    env_damping: float = 0.0,
    **kw: Any,
) -> CoupledCheck:
    """Stability of the sampled loop coupled to one passive environment."""
    acl = coupled_closed_loop(
        sea,
        loop=loop,
        env_mass=env_mass,
        env_stiffness=env_stiffness,
        env_damping=env_damping,
        **kw,
    )
    rho = float(np.max(np.abs(np.linalg.eigvals(acl))))
    return CoupledCheck(
        env_mass=float(env_mass),
        env_stiffness=float(env_stiffness),
        env_damping=float(env_damping),
        spectral_radius=rho,
    )


def worst_sampled_environment(
    sea: SEA,
    *,
    loop: SampledLoop,
    masses: Any = None,
    stiffnesses: Any = None,
    damping: float = 0.0,
) -> CoupledCheck:
    """The environment of a grid (masses × stiffnesses, kg × N/m) with the largest spectral radius.

    Defaults: 13 masses in ``[1e-3, 10]`` kg and 0 plus 13 stiffnesses in
    ``[10, 1e5]`` N/m.  A returned check with ``stable == False`` is a concrete
    passive environment that the sampled loop destabilizes.
    """
    ms = np.logspace(-3, 1, 13) if masses is None else np.atleast_1d(masses)
    ks = np.r_[0.0, np.logspace(1, 5, 13)] if stiffnesses is None else np.atleast_1d(stiffnesses)
    ctrl = DiscreteController.for_loop(sea, loop)
    best: CoupledCheck | None = None
    for me in ms:
        for ke in ks:
            c = coupled_check(
                sea,
                loop=loop,
                env_mass=float(me),
                env_stiffness=float(ke),
                env_damping=damping,
                controller=ctrl,
            )
            if best is None or c.spectral_radius > best.spectral_radius:
                best = c
    assert best is not None
    return best
