"""The paper's hardware experiment (Section VI), run on the digital twin.

Two protocols:

* `run_rig_sweep` / `run_experiment` — settling experiment: the load
  starts at rest at ``experiment.initial_position`` (20 mm) and is driven to 0
  by LP (load-side P, ``C_L = kd``) or Ours (actuator-side PD,
  ``C_A = kd + bd s``, ``bd = 25``) for ``kd`` in ``[0, kd_max]`` and each
  load mass; settling time (2 % band, capped at 2 s) and steady-state error
  are measured on the encoder signals, and the gain beyond which LP becomes
  unstable is located in the twin and predicted from the continuous-time and
  the sampled (ZOH, delay, filtered finite differences) linear loops.
* `run_impacts` — perceived stiffness ``k_out = F_L/X_L`` under steps in
  load force (the paper's approximation of an impact), its dependence on the
  damper ``b1`` and on the impact time scale, and the stiffness frequency
  response of Eq. (10) from [`seapass.model.stiffness.derive_stiffness`][seapass.model.stiffness.derive_stiffness].

On the paper's own bench (the packaged rig's hardware) the findings are
compared with the paper's qualitative claims in `ExperimentFinding` objects
(match or mismatch, with the reason from the model); a user's rig gets its
measurements only, with no comparison to the paper.

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Section VI and Fig. 3.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ParameterError
from ..files.csvtext import rows_csv
from ..files.limits import MAX_KD_GAINS
from ..model.display import html_card, short_repr
from ..progress import ProgressLike, as_progress, task
from ..sim.metrics import Settling
from .findings import ExperimentFinding, sweep_findings
from .predictions import RIG_DESIGNS, controller_gains, critical_gain, rig_design
from .rigfile import Rig
from .twin import simulate_loop

__all__ = [
    "ExperimentResult",
    "RigSweepResult",
    "run_experiment",
    "run_rig_sweep",
    "run_rig_sweeps",
    "settling_metrics",
    "sweep_result",
]

FINAL_WINDOW = 0.25  # s at the end of the horizon that decide the final value
FloatArray = NDArray[np.float64]


# ----------------------------------------------------------------------------- metrics


def settling_metrics(
    t: FloatArray,
    x: FloatArray,
    *,
    x0: float,
    reference: float = 0.0,
    band: float,
    cap: float,
    final_window: float = FINAL_WINDOW,
    diverged: bool = False,
) -> tuple[Settling, float | None, float | None, float | None]:
    """Classify one response and measure it.

    Returns ``(status, settling_time, final_value, steady_state_error)``.
    ``status`` is ``settled`` (within ``band`` of its final value for good
    before ``cap``), ``slow`` (converged, but later than ``cap``), ``stuck``
    (never left the band around its start: no motion), ``oscillating``
    (bounded, not converged) or ``unstable`` (left the travel, or a sustained
    oscillation larger than 10 % of the initial offset).  The error is
    ``|final − reference|`` for converged runs, else None.
    """
    offset = abs(x0 - reference)
    n_final = max(2, round(final_window / (t[1] - t[0])))
    tail = x[-n_final:]
    if diverged or not np.all(np.isfinite(x)):
        return Settling.UNSTABLE, None, None, None
    spread = float(np.ptp(tail))
    if spread > band:
        status = Settling.UNSTABLE if spread >= 0.1 * offset else Settling.OSCILLATING
        return status, None, None, None
    final = float(np.mean(tail))
    err = abs(final - reference)
    if abs(final - x0) <= band and np.all(np.abs(x - x0) <= band):
        return Settling.STUCK, None, final, err
    outside = np.nonzero(np.abs(x - final) > band)[0]
    ts = float(t[outside[-1] + 1]) if outside.size else 0.0
    if ts <= cap:
        return Settling.SETTLED, ts, final, err
    return Settling.SLOW, None, final, err


# ----------------------------------------------------------------------------- linear predictions


# ----------------------------------------------------------------------------- sweep


@dataclass(frozen=True, repr=False, kw_only=True)
class RigSweepResult:
    """Settling experiment for one design and one load mass.

    Arrays are indexed by gain (axis 0, same order as ``kd``); traces are
    ``(gain, sample)``.  ``NaN`` in ``settling_time`` means "did not settle
    within the cap"; ``NaN`` in ``steady_state_error`` means "did not converge".
    """

    design: str
    load_mass: float
    bd: float
    kd: FloatArray
    settling_time: FloatArray
    steady_state_error: FloatArray
    final_value: FloatArray
    status: tuple[Settling, ...]
    unstable_gain_twin: float | None
    unstable_gain_continuous: float | None
    unstable_gain_sampled: float | None
    t: FloatArray = field(repr=False)
    x_L: FloatArray = field(repr=False)
    gain: str = "kd"
    """The swept gain (``kd`` for LP and Ours; any gain of a design file), its values in ``kd``."""

    def __repr__(self) -> str:
        settled = int(np.sum(~np.isnan(self.settling_time)))
        return short_repr(
            "RigSweepResult",
            {
                "design": self.design,
                "load_mass": self.load_mass,
                "gains": self.kd.size,
                "settled": settled,
                "unstable_from": self.unstable_gain_twin,
            },
        )

    def rows(self) -> list[dict[str, Any]]:
        """One dict per gain (for CSV)."""
        out = []
        for i, kd in enumerate(self.kd):
            ts, err = self.settling_time[i], self.steady_state_error[i]
            out.append(
                {
                    "design": self.design,
                    "load_mass": self.load_mass,
                    self.gain: float(kd),
                    "bd": self.bd if self.design == "ours" else 0.0,
                    "status": self.status[i],
                    "settling_time": None if math.isnan(ts) else float(ts),
                    "steady_state_error": None if math.isnan(err) else float(err),
                }
            )
        return out

    def to_dict(self) -> dict[str, Any]:
        extra = {} if self.gain == "kd" else {"gain": self.gain}
        return {
            "design": self.design,
            **extra,
            "load_mass": self.load_mass,
            "bd": self.bd if self.design == "ours" else 0.0,
            "unstable_gain_twin": self.unstable_gain_twin,
            "unstable_gain_continuous": self.unstable_gain_continuous,
            "unstable_gain_sampled": self.unstable_gain_sampled,
            "runs": self.rows(),
        }


def _kd_grid(
    rig: Rig, kd: ArrayLike | None, kd_max: float | None, kd_step: float | None
) -> FloatArray:
    if kd is not None:
        arr = np.atleast_1d(np.asarray(kd, dtype=float))
        if arr.ndim != 1 or arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr < 0):
            raise ParameterError(
                f"kd must be a non-empty 1-D array of gains >= 0, got shape {arr.shape}"
            )
        if arr.size > MAX_KD_GAINS:
            raise ParameterError(f"kd: {arr.size:,} gains; the limit is {MAX_KD_GAINS:,}")
        return arr
    top = rig.experiment.kd_max if kd_max is None else float(kd_max)
    step = rig.experiment.kd_step if kd_step is None else float(kd_step)
    if not (top > 0 and step > 0 and math.isfinite(top) and math.isfinite(step)):
        raise ParameterError("kd_max and kd_step must be positive")
    if top / step > MAX_KD_GAINS:
        raise ParameterError(f"kd grid too fine: {top / step:.0f} gains; raise kd_step")
    return np.arange(0.0, top + 0.5 * step, step)


def run_rig_sweep(
    rig: Rig,
    *,
    design: str,
    load_mass: float,
    kd: ArrayLike | None = None,
    kd_max: float | None = None,
    kd_step: float | None = None,
    bd: float | None = None,
    predictions: bool = True,
    seed: int | None = None,
) -> RigSweepResult:
    """Run the settling experiment for one design and one load mass.

    Parameters
    ----------
    rig : Rig
    design : {"LP", "ours"}
    load_mass : float
        Mass added to the output (kg).
    kd : array_like, optional
        Gains to test (default ``0, kd_step, ..., kd_max`` from the rig file).
    bd : float, optional
        Actuator-side damping of Ours (default ``experiment.bd_ours``).
    predictions : bool
        Also compute the continuous and sampled linear instability gains.
    """
    (out,) = run_rig_sweeps(
        rig, designs=(design,), load_masses=(load_mass,), kd=kd, kd_max=kd_max,
        kd_step=kd_step, bd=bd, predictions=predictions, seed=seed,
    )  # fmt: skip
    return out


def run_rig_sweeps(
    rig: Rig,
    *,
    designs: Sequence[str],
    load_masses: Sequence[float],
    kd: ArrayLike | None = None,
    kd_max: float | None = None,
    kd_step: float | None = None,
    bd: float | None = None,
    predictions: bool = True,
    seed: int | None = None,
) -> tuple[RigSweepResult, ...]:
    """`run_rig_sweep` for every design × load mass, simulated as one batch.

    The twin's runs are independent element by element, so one batch gives
    the same results as separate sweeps at the cost of about one.  Returns
    the sweeps in the order ``designs`` × ``load_masses`` (mass varying fastest).
    """
    ds = [rig_design(d) for d in designs]
    masses = [float(m) for m in load_masses]
    if not ds or not masses:
        raise ParameterError("give at least one design and one load mass")
    for m in masses:
        if not (math.isfinite(m) and m >= 0):
            raise ParameterError(f"load_mass must be >= 0, got {m!r}")
    ex = rig.experiment
    gains = _kd_grid(rig, kd, kd_max, kd_step)
    bdv = ex.bd_ours if bd is None else float(bd)
    combos = [(d, m) for d in ds for m in masses]
    per = [controller_gains(d, gains, bdv) for d, _m in combos]
    keys = sorted({k for g in per for k in g})
    batch: dict[str, Any] = {
        k: np.concatenate(
            [np.broadcast_to(np.asarray(g.get(k, 0.0), dtype=float), gains.shape) for g in per]
        )
        for k in keys
    }
    res = simulate_loop(
        rig,
        load_mass=np.repeat([m for _d, m in combos], gains.size),
        duration=ex.horizon,
        x0=ex.initial_position,
        deflection0=ex.initial_deflection,
        seed=seed,
        **batch,
    )  # fmt: skip
    out = []
    for j, (d, m) in enumerate(combos):
        rows = slice(j * gains.size, (j + 1) * gains.size)
        out.append(
            _sweep_result(rig, d, m, gains, bdv, res.t, res.x_L_measured[rows],
                          res.diverged[rows], predictions)
        )  # fmt: skip
    return tuple(out)


def _sweep_result(
    rig: Rig, d: str, load_mass: float, gains: FloatArray, bdv: float, t: FloatArray,
    x_L: FloatArray, diverged: NDArray[np.bool_], predictions: bool,
) -> RigSweepResult:  # fmt: skip
    """Settling metrics of one sweep's runs and, optionally, the linear instability gains."""
    search = max(10.0 * float(gains.max()), 1e4)

    def limit(sampled: bool) -> float | None:
        if not predictions:
            return None
        return critical_gain(
            rig, design=d, load_mass=load_mass, sampled=sampled, bd=bdv, kd_search=search
        )

    return sweep_result(rig, d, load_mass, gains, t, x_L, diverged, limit=limit, bd=bdv)


def sweep_result(
    rig: Rig, design: str, load_mass: float, gains: FloatArray, t: FloatArray,
    x_L: FloatArray, diverged: NDArray[np.bool_], *, limit: Callable[[bool], float | None],
    bd: float = 0.0, gain: str = "kd",
) -> RigSweepResult:  # fmt: skip
    """Settling metrics of one sweep's runs (axis 0 of ``x_L``: the gains) as a `RigSweepResult`.

    ``limit(sampled)`` gives the linear instability gain (continuous and sampled), or None.
    """
    ex = rig.experiment
    band = ex.settle_band * abs(ex.initial_position)
    ts = np.full(gains.size, np.nan)
    err = np.full(gains.size, np.nan)
    fin = np.full(gains.size, np.nan)
    status = []
    for i in range(gains.size):
        st, t_s, f, e = settling_metrics(
            t, x_L[i], x0=ex.initial_position, band=band, cap=ex.settle_cap,
            diverged=bool(diverged[i]),
        )  # fmt: skip
        status.append(st)
        ts[i] = np.nan if t_s is None else t_s
        fin[i] = np.nan if f is None else f
        err[i] = np.nan if e is None else e
    unstable = [float(g) for g, s in zip(gains, status, strict=True) if s == Settling.UNSTABLE]
    return RigSweepResult(
        design=design,
        load_mass=float(load_mass),
        bd=bd,
        kd=gains,
        settling_time=ts,
        steady_state_error=err,
        final_value=fin,
        status=tuple(status),
        unstable_gain_twin=min(unstable) if unstable else None,
        unstable_gain_continuous=limit(False),
        unstable_gain_sampled=limit(True),
        t=t,
        x_L=x_L,
        gain=gain,
    )


# ----------------------------------------------------------------------------- findings


@dataclass(frozen=True, repr=False, kw_only=True)
class ExperimentResult:
    """The full settling experiment: one `RigSweepResult` per (design, mass).

    ``findings`` are the paper's claims checked on the twin, for the paper's
    bench only (empty for any other rig).
    """

    rig_name: str
    sweeps: tuple[RigSweepResult, ...]
    findings: tuple[ExperimentFinding, ...]

    def plot(self, *, axes: Any = None) -> Any:
        """Settling time and steady-state error against ``kd``; returns the Axes."""
        from ..plot.rig import plot_rig_sweep

        return plot_rig_sweep(self, axes=axes)

    def __repr__(self) -> str:
        return short_repr(
            "ExperimentResult",
            {
                "rig": self.rig_name,
                "sweeps": len(self.sweeps),
                "findings": len(self.findings) or None,
            },
        )

    def _repr_html_(self) -> str:
        rows = [
            (
                f"{s.design}, m_L = {s.load_mass:g} kg",
                f"{int(np.sum(~np.isnan(s.settling_time)))}/{s.kd.size} gains settled; unstable "
                f"from kd = {'-' if s.unstable_gain_twin is None else f'{s.unstable_gain_twin:g}'}",
            )
            for s in self.sweeps
        ]
        return html_card(f"Rig experiment on {self.rig_name}", rows)

    def to_csv(self) -> str:
        """One line per gain of every sweep (the rows of `RigSweepResult.rows`)."""
        return rows_csv([r for s in self.sweeps for r in s.rows()])

    def to_dict(self) -> dict[str, Any]:
        return {
            "rig": self.rig_name,
            "sweeps": [s.to_dict() for s in self.sweeps],
            "findings": [f.to_dict() for f in self.findings],
        }


def run_experiment(
    rig: Rig,
    *,
    designs: Sequence[str] = RIG_DESIGNS,
    load_masses: Sequence[float] | None = None,
    kd: ArrayLike | None = None,
    kd_max: float | None = None,
    kd_step: float | None = None,
    progress: ProgressLike = None,
) -> ExperimentResult:
    """Settling experiment for every design × load mass (axis order of ``sweeps``).

    ``progress`` (a [`Progress`][seapass.progress.Progress]) gets one task of one step:
    the sweeps run as one batch.  Default: none; ``True``/``False`` still work for one
    release.
    """
    shown = as_progress(progress, where="run_experiment")
    masses = list(rig.experiment.load_masses if load_masses is None else load_masses)
    label = (
        f"kd sweeps on the twin of {rig.name}: {len(designs)} design(s) x {len(masses)} mass(es)"
    )
    with task(shown, label, 1):
        sweeps = run_rig_sweeps(
            rig, designs=designs, load_masses=masses, kd=kd, kd_max=kd_max, kd_step=kd_step
        )
        shown.advance(1)
    return ExperimentResult(
        rig_name=rig.name, sweeps=tuple(sweeps), findings=tuple(sweep_findings(sweeps))
    )


# ----------------------------------------------------------------------------- impacts
