"""Linear predictions for the rig: where LP and Ours become unstable.

The continuous-time loop (eigenvalues of ``A − B K``) and the sampled loop at
the rig's rate with its ZOH, delay and filtered finite-difference velocities
(`sampled_loop_matrix`) predict the gain at which the twin goes unstable.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import expm

from ..errors import ParameterError
from ..model.catalog import design as catalog_design
from ..model.loop import SampledLoop, loop_argument
from ..model.sea import SEA
from .rigfile import Rig
from .twin import linear_matrices

FloatArray = NDArray[np.float64]

__all__ = [
    "RIG_DESIGNS",
    "controller_gains",
    "critical_gain",
    "rig_design",
    "rig_sea",
    "sampled_loop_matrix",
    "zoh_matrices",
]


def zoh_matrices(
    rig: Rig, load_mass: float, period: float | None = None
) -> tuple[FloatArray, FloatArray]:
    """The rig's linear plant held (ZOH) over one ``period`` (default: the rig's)."""
    a, b = linear_matrices(rig, load_mass=load_mass)
    blk = np.zeros((5, 5))
    blk[:4, :4], blk[:4, 4:] = a, b
    e = expm(blk * (rig.period if period is None else period))
    return e[:4, :4], e[:4, 4:]


def sampled_loop_matrix(
    rig: Rig,
    *,
    load_mass: float,
    kp_actuator: float = 0.0,
    kv_actuator: float = 0.0,
    kp_load: float = 0.0,
    kv_load: float = 0.0,
    loop: SampledLoop | None = None,
    _zoh_cache: tuple[FloatArray, FloatArray] | None = None,
    **old: Any,
) -> FloatArray:
    """Closed-loop transition matrix of the sampled linear loop (9 states).

    State ``(x, y_{k-1}, v̂_{k-1}, u_{k-1})``: plant ``(x_A, v_A, x_L, v_L)``
    discretised with ZOH at the control period, last measured positions,
    filtered finite-difference velocities and the pending command (used with one
    sample of delay).  ``loop`` replaces the rig's (`Rig.loop`; delay 0 or 1).  The
    loop is stable iff the spectral radius < 1.
    """
    loop = loop_argument(loop, old, where="sampled_loop_matrix", base=rig.loop)
    if loop.delay not in (0, 1):
        raise ParameterError(f"loop: the rig's loop has 0 or 1 samples of delay, got {loop.delay}")
    T, delay, fc = loop.period, loop.delay, loop.velocity_filter
    alpha = math.exp(-2.0 * math.pi * fc * T) if fc else 0.0
    beta = (1.0 - alpha) / T
    ad, bd = zoh_matrices(rig, load_mass, T) if _zoh_cache is None else _zoh_cache
    c = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])
    kp = np.array([[kp_actuator, kp_load]])
    kv = np.array([[kv_actuator, kv_load]])
    gx = -kp @ c - beta * kv @ c
    gy = beta * kv
    gv = -alpha * kv
    m = np.zeros((9, 9))
    # rows: x (0:4), y (4:6), v (6:8), u (8)
    if delay:
        m[0:4, 0:4] = ad
        m[0:4, 8:9] = bd
    else:
        m[0:4, 0:4] = ad + bd @ gx
        m[0:4, 4:6] = bd @ gy
        m[0:4, 6:8] = bd @ gv
    m[4:6, 0:4] = c
    m[6:8, 0:4] = beta * c
    m[6:8, 4:6] = -beta * np.eye(2)
    m[6:8, 6:8] = alpha * np.eye(2)
    m[8:9, 0:4] = gx
    m[8:9, 4:6] = gy
    m[8:9, 6:8] = gv
    return m


def _unstable(
    rig: Rig,
    design: str,
    load_mass: float,
    kd: float,
    bd: float,
    sampled: bool,
    zoh: tuple[FloatArray, FloatArray] | None,
) -> bool:
    g = controller_gains(design, kd, bd)
    if sampled:
        mat = sampled_loop_matrix(rig, load_mass=load_mass, _zoh_cache=zoh, **g)
        return bool(np.max(np.abs(np.linalg.eigvals(mat))) > 1.0 + 1e-12)
    a, b = linear_matrices(rig, load_mass=load_mass)
    k = np.array(
        [[g.get("kp_actuator", 0.0), g.get("kv_actuator", 0.0), g.get("kp_load", 0.0), 0.0]]
    )
    return bool(np.max(np.linalg.eigvals(a - b @ k).real) > 1e-12)


def critical_gain(
    rig: Rig,
    *,
    design: str,
    load_mass: float,
    sampled: bool,
    bd: float | None = None,
    kd_search: float = 1e5,
    grid: int = 500,
) -> float | None:
    """Smallest ``kd`` at which the linear closed loop becomes unstable.

    ``sampled=False`` uses the continuous-time loop (eigenvalues of ``A − B K``);
    ``sampled=True`` the ZOH loop at the rig's rate with its delay and velocity
    filter (`sampled_loop_matrix`).  The first crossing on a grid over
    ``[0, kd_search]`` is refined by bisection; None when stable throughout.
    """
    d = rig_design(design)
    bdv = rig.experiment.bd_ours if bd is None else float(bd)
    zoh = zoh_matrices(rig, load_mass) if sampled else None
    grid_kd = np.linspace(0.0, kd_search, grid + 1)
    prev = 0.0
    for kd in grid_kd[1:]:
        if _unstable(rig, d, load_mass, float(kd), bdv, sampled, zoh):
            lo, hi = prev, float(kd)
            for _ in range(50):
                mid = 0.5 * (lo + hi)
                if _unstable(rig, d, load_mass, mid, bdv, sampled, zoh):
                    hi = mid
                else:
                    lo = mid
            return hi
        prev = float(kd)
    return None


RIG_DESIGNS: tuple[str, ...] = ("LP", "ours")
"""Catalog designs the rig experiment runs (load-side P and Ours' actuator-side PD)."""


def rig_design(design: str) -> str:
    """The catalog key of a rig design (``"LP"`` or ``"ours"``, case-insensitive)."""
    key = catalog_design(design).key if str(design).strip().lower() in ("lp", "ours") else ""
    if key not in RIG_DESIGNS:
        raise ParameterError(f"design must be 'LP' or 'ours', got {design!r}")
    return key


def rig_sea(rig: Rig, design: str, **gains: float | None) -> SEA:
    """The linear SEA model of ``design`` on ``rig``: its controller on the rig's damped spring.

    The rig's transmission is ``D1 = k1 + b1 s`` with its ``m, b, k1, b1``;
    the controller elements come from the catalog entry.  Gains not given are free.
    """
    entry = catalog_design(rig_design(design))
    vals: dict[str, float | None] = {g: None for g in entry.gains if g != "b1"}
    vals.update(rig.model_values())
    vals.update(gains)
    return SEA(D1="k1 + b1*s", CA=entry.CA, CL=entry.CL, values=vals, name=entry.key)


def controller_gains(design: str, kd: ArrayLike, bd: float) -> dict[str, Any]:
    """The twin's gain arguments ([`simulate_loop`][seapass.rig.twin.simulate_loop]) of a rig design."""
    if rig_design(design) == "LP":
        return {"kp_load": kd}
    return {"kp_actuator": kd, "kv_actuator": bd}
