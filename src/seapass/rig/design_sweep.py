"""Any design's controller on the digital twin: the settling experiment swept over any gain.

The paper's experiment (`seapass.rig.experiment`) runs LP and Ours, whose PD controllers
the twin knows by their gains.  `run_design_sweeps` runs the realized controller ``K`` of
any design file instead: for every value of one gain the design's controller is
discretized at the rig's rate, with the rig's delay and velocity filter, and run on the
twin (friction, encoder quantization, saturation) as one difference equation per run
([`seapass.sampled.controllers.DiscreteController`][seapass.sampled.controllers.DiscreteController]).
The controller's own parameters, plant values inside a controller expression (``k1`` of a
force loop) included, are the design file's; the physical plant is the rig's.

The linear predictions of the gain where the loop turns unstable use the twin's
friction-free linear plant (`linear_matrices`, load mass and rail damping included) with
the design's minimal controller realization: continuous (eigenvalues) and sampled (ZOH,
the loop's delay; spectral radius), located on a grid and refined by bisection.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import expm

from ..errors import ParameterError
from ..files.limits import MAX_KD_GAINS
from ..model.design_file import Design
from ..model.loop import SampledLoop
from ..model.minimal import controller_realization
from ..sampled.controllers import DiscreteController, controller_state_space
from .experiment import RigSweepResult, sweep_result
from .rigfile import Rig
from .twin import linear_matrices, simulate_loop

FloatArray = NDArray[np.float64]

__all__ = ["DEFAULT_POINTS", "design_gain", "design_loop", "run_design_sweeps", "unstable"]

DEFAULT_POINTS = 21
"""Gains swept when no step is given: the range in 20 equal steps."""


def design_gain(design: Design, gain: str | None = None) -> str:
    """The gain a sweep varies: ``gain``, else the first in the file's ``[ranges]``, else the
    first controller gain.

    Raises
    ------
    ParameterError
        For a name that is not a controller gain of the design (or a design without one).
    """
    gains = design.gains
    if gain is None:
        gain = next((g for g in design.ranges if g in gains), gains[0] if gains else None)
    if gain is None:
        raise ParameterError(f"design {design.name!r} has no controller gain to sweep")
    if gain not in gains:
        raise ParameterError(
            f"gain: {gain!r} is not a controller gain of {design.name!r} "
            f"(its gains: {', '.join(gains) or 'none'})",
            argument="gain",
        )
    return gain


def design_loop(design: Design, rig: Rig) -> SampledLoop:
    """The loop the design's controller runs in on the twin: the rig's rate, delay and
    velocity filter, the design's discretization method."""
    loop = rig.loop
    return loop if design.loop is None else loop.replace(method=design.loop.method)


def _grid(design: Design, gain: str, gain_max: float | None, gain_step: float | None) -> FloatArray:
    lo, hi = design.analysis_ranges()[gain]
    hi = hi if gain_max is None else float(gain_max)
    if not (math.isfinite(hi) and hi > lo):
        raise ParameterError(f"the largest {gain} must exceed {lo:g}, got {hi!r}")
    step = (hi - lo) / (DEFAULT_POINTS - 1) if gain_step is None else float(gain_step)
    if not (math.isfinite(step) and step > 0):
        raise ParameterError(f"the {gain} step must be positive, got {gain_step!r}")
    if (hi - lo) / step > MAX_KD_GAINS:
        raise ParameterError(f"{gain} grid too fine: {(hi - lo) / step:.0f} gains; raise the step")
    return np.arange(lo, hi + 0.5 * step, step)


def unstable(
    rig: Rig, design: Design, load_mass: float, values: dict[str, float], *, sampled: bool
) -> bool:
    """Is the friction-free linear twin unstable under the design's controller at ``values``?"""
    sea = design.sea().with_values(**values)
    a, b = linear_matrices(rig, load_mass=load_mass)
    c = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])
    if not sampled:
        k = controller_realization(sea)
        A, B, C = k.arrays()
        n = A.shape[0]
        # f_A = −p0·y − p1·ẏ + C ξ, ξ̇ = A ξ − B y (zero references)
        p0 = np.array([float(x) for x in k.proportional])
        p1 = np.array([float(x) for x in k.derivative])
        m = np.zeros((4 + n, 4 + n))
        vel = np.array([[0, 1.0, 0, 0], [0, 0, 0, 1.0]])
        m[:4, :4] = a - b @ (p0 @ c + p1 @ vel)[None, :]
        m[:4, 4:] = b @ C[None, :]
        m[4:, :4] = -B @ c
        m[4:, 4:] = A
        return bool(np.max(np.linalg.eigvals(m).real) > 1e-9) if m.size else False
    loop = design_loop(design, rig)
    ctrl = DiscreteController.for_loop(sea, loop)
    Ak, Bk, Ck, Dk = controller_state_space(ctrl, loop.delay)
    blk = np.zeros((5, 5))
    blk[:4, :4], blk[:4, 4:] = a, b
    e = expm(blk * loop.period)
    ad, bd = e[:4, :4], e[:4, 4:]
    nk = Ak.shape[0]
    m = np.zeros((4 + nk, 4 + nk))
    m[:4, :4] = ad - bd @ Dk.reshape(1, 2) @ c
    m[:4, 4:] = -bd @ Ck.reshape(1, nk)
    m[4:, :4] = Bk @ c
    m[4:, 4:] = Ak
    return bool(np.max(np.abs(np.linalg.eigvals(m))) > 1.0 + 1e-12)


def _critical(
    rig: Rig, design: Design, gain: str, load_mass: float, grid: FloatArray, sampled: bool
) -> float | None:
    """Smallest gain of ``grid`` (refined by bisection) where the linear twin is unstable."""
    prev = float(grid[0])
    if unstable(rig, design, load_mass, {gain: prev}, sampled=sampled):
        return prev
    for g in grid[1:]:
        if unstable(rig, design, load_mass, {gain: float(g)}, sampled=sampled):
            lo, hi = prev, float(g)
            for _ in range(40):
                mid = 0.5 * (lo + hi)
                if unstable(rig, design, load_mass, {gain: mid}, sampled=sampled):
                    hi = mid
                else:
                    lo = mid
            return hi
        prev = float(g)
    return None


def run_design_sweeps(
    rig: Rig,
    design: Design,
    *,
    gain: str | None = None,
    load_masses: Sequence[float] | None = None,
    gain_max: float | None = None,
    gain_step: float | None = None,
    predictions: bool = True,
    seed: int | None = None,
) -> tuple[RigSweepResult, ...]:
    """The settling experiment of the rig with ``design``'s controller, one sweep per load mass.

    Parameters
    ----------
    rig : Rig
        The twin (plant, rate, delay, velocity filter, experiment: start 20 mm from the
        reference, settling band and cap, horizon).
    design : Design
        Any design file; its controller is realized once per gain value
        ([`DiscreteController.for_loop`][seapass.sampled.controllers.DiscreteController.for_loop]
        at `design_loop`).
    gain : str, optional
        The gain to sweep (default: the first in the file's ``[ranges]``, `design_gain`).
    load_masses : sequence of float, optional
        Default: the rig file's ``experiment.load_masses``.
    gain_max, gain_step : float, optional
        Largest value and step; default the gain's range (`Design.analysis_ranges`) in
        `DEFAULT_POINTS` values.
    predictions : bool
        Also locate the linear instability gains (continuous and sampled), searched up to the
        top of the grid.
    seed : int or None
        Encoder phases (see [`simulate_loop`][seapass.rig.twin.simulate_loop]).

    Returns
    -------
    tuple of RigSweepResult
        One per load mass, ``design`` the design's name and ``gain`` the swept gain.
    """
    name = design_gain(design, gain)
    masses = [
        float(m) for m in (rig.experiment.load_masses if load_masses is None else load_masses)
    ]
    if not masses:
        raise ParameterError("give at least one load mass")
    for m in masses:
        if not (math.isfinite(m) and m >= 0):
            raise ParameterError(f"load_mass must be >= 0, got {m!r}")
    grid = _grid(design, name, gain_max, gain_step)
    loop = design_loop(design, rig)
    sea = design.sea()
    ctrls: list[Any] = [DiscreteController.for_loop(sea.with_values(**{name: float(v)}), loop)
                        for v in grid]  # fmt: skip
    ex = rig.experiment
    res = simulate_loop(
        rig,
        load_mass=np.repeat(masses, grid.size),
        duration=ex.horizon,
        x0=ex.initial_position,
        deflection0=ex.initial_deflection,
        seed=seed,
        loop=loop,
        controllers=ctrls * len(masses),
    )
    out = []
    for j, mass in enumerate(masses):
        rows = slice(j * grid.size, (j + 1) * grid.size)

        def limit(sampled: bool, mass: float = mass) -> float | None:
            if not predictions or (not sampled and design.discrete is not None):
                return None  # a controller in z has no continuous prediction
            return _critical(rig, design, name, mass, grid, sampled)

        out.append(
            sweep_result(rig, design.name, mass, grid, res.t, res.x_L_measured[rows],
                         res.diverged[rows], limit=limit, gain=name)
        )  # fmt: skip
    return tuple(out)
