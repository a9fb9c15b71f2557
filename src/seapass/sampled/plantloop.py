"""The sampled loop in state space: any rational plant, discretized exactly, closed by the
deployed difference equation.

The plant (actuator mass, transmission ``D1``, port element ``D2``, a load mass and an
optional spring and damper of an environment) is the realization of
[`plant_realization`][seapass.model.realization.plant_realization]: any rational ``D1``,
``D2`` with at most one derivative, not only ``k + b s``.  Over one period with the force
held (ZOH) it is exactly ``x⁺ = Φ x + Γ (f_A, f_ext)`` (``Φ``, ``Γ`` from one block matrix
exponential).  The controller is its one minimal realization with the loop's delay as a
shift register ([`controller_state_space`][seapass.sampled.controllers.controller_state_space]),
reading ``x_A`` and ``x_L`` at the instants.

References
----------
.. [1] G. F. Franklin, J. D. Powell, M. Workman, *Digital Control of Dynamic
   Systems*, 3rd ed., Addison-Wesley, 1998, §4.3 (ZOH equivalent).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..model.realization import ClosedLoop, plant_realization
from ..model.sea import SEA
from .controllers import DiscreteController, controller_state_space

__all__ = ["DiscretePlant", "discrete_plant", "loop_matrix"]


@dataclass(frozen=True, kw_only=True)
class DiscretePlant:
    """A plant with its load, continuous and over one held period.

    Attributes
    ----------
    continuous : ClosedLoop
        The plant (`plant_realization`), with the environment's spring and damper on the
        load; input slots ``(f_A, unused, f_ext)``.
    Phi, Gamma : ndarray, shapes (n, n) and (n, 2)
        ``x⁺ = Φ x + Γ (f_A, f_ext)`` over one period with both forces held.
    period : float
    """

    continuous: ClosedLoop
    Phi: np.ndarray
    Gamma: np.ndarray
    period: float

    @property
    def order(self) -> int:
        return int(self.Phi.shape[0])


def discrete_plant(
    sea: SEA,
    period: float,
    *,
    load_mass: float,
    env_stiffness: float = 0.0,
    env_damping: float = 0.0,
) -> DiscretePlant:
    """The plant of ``sea`` with a load mass (and an environment spring and damper to
    ground), exactly discretized over ``period`` with the forces held.

    Raises
    ------
    ParameterError
        For a non-positive load mass, negative environment values, missing plant values.
    UnrealizableError
        For ``D1``/``D2`` that need accelerations.
    """
    from scipy.linalg import expm

    if not env_stiffness >= 0 or not env_damping >= 0:
        raise ParameterError(
            f"the environment must be passive: env_stiffness = {env_stiffness!r}, "
            f"env_damping = {env_damping!r} must be >= 0"
        )
    plant = plant_realization(sea, load_mass=load_mass)
    A = np.array(plant.A)
    if env_stiffness or env_damping:
        A[3, 2] -= env_stiffness / plant.load_mass
        A[3, 3] -= env_damping / plant.load_mass
        plant = ClosedLoop(A=A, B=plant.B, C=plant.C, D=plant.D, states=plant.states,
                           load_mass=plant.load_mass, relaxed=plant.relaxed)  # fmt: skip
    B = np.column_stack([plant.B[:, 0], plant.B[:, 2]])
    n = A.shape[0]
    big = np.zeros((n + 2, n + 2))
    big[:n, :n], big[:n, n:] = A * period, B * period
    E = expm(big)
    return DiscretePlant(continuous=plant, Phi=E[:n, :n], Gamma=E[:n, n:], period=float(period))


def loop_matrix(plant: DiscretePlant, ctrl: DiscreteController, delay: int) -> np.ndarray:
    """The loop's transition matrix over one period, plant states first, references zero.

    ``u = −(C_k ξ + D_k y)``, ``ξ⁺ = A_k ξ + B_k y`` with ``y = (x_A, x_L)`` at the instant
    (`controller_state_space`, the delay included).
    """
    Ak, Bk, Ck, Dk = controller_state_space(ctrl, delay)
    n, nk = plant.order, Ak.shape[0]
    cy = np.zeros((2, n))
    cy[0, 0] = cy[1, 2] = 1.0
    bu = plant.Gamma[:, :1]
    out = np.zeros((n + nk, n + nk))
    out[:n, :n] = plant.Phi - bu @ Dk.reshape(1, 2) @ cy
    out[:n, n:] = -bu @ Ck.reshape(1, nk)
    out[n:, :n] = Bk @ cy
    out[n:, n:] = Ak
    return out
