"""The paper's simulation study (Sec. V): tune LP, APD and Ours at one load mass, test at three.

Setup: ``m = 1 kg``, ``b = 10 N·s/m``, ``k1 = 1000 N/m``, ``D2 = 0``; gains
tuned by [`seapass.tuning.tune`][seapass.tuning.optimize.tune] at ``m_L = 10 kg`` for a 0.5 m step
(exact passivity constraint, force limit), then each design is simulated
at ``m_L ∈ {1, 10, 25} kg`` and its 2 % settling time and final error are
tabulated.  `run_simulation_study` returns the data; figures live in
[`seapass.plot.sim`][seapass.plot.sim].

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Sec. V and Fig. 4.
"""

from __future__ import annotations

import csv
import io
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import Any

import numpy as np

from ..errors import ParameterError, TuningWarning
from ..files.jsontext import json_text
from ..model.catalog import design as catalog_design
from ..model.experiment import PAPER_EXPERIMENT
from ..progress import Progress, ProgressLike, as_progress, task
from ..sim.metrics import TrackingMetrics, tracking_metrics
from ..sim.simulate import SimulationResult, Step, simulate
from ..tuning.optimize import TuningResult, tune
from ..tuning.problem import QUICK_OPTIONS, TuningOptions

__all__ = ["QUICK_OPTIONS", "SimulationStudy", "StudyRow", "run_simulation_study"]


@dataclass(frozen=True, kw_only=True)
class StudyRow:
    """One design at one load mass."""

    design: str
    load_mass: float
    metrics: TrackingMetrics

    def to_dict(self) -> dict[str, Any]:
        return {"design": self.design, "load_mass": self.load_mass, **self.metrics.to_dict()}


@dataclass(frozen=True, kw_only=True)
class SimulationStudy:
    """Result of `run_simulation_study`.

    Attributes
    ----------
    designs : tuple of str
        Design keys in plotting order.
    masses : tuple of float
        Evaluation load masses (kg).
    tuning : mapping of str to TuningResult
    runs : mapping of (design, mass) to SimulationResult
    rows : tuple of StudyRow
        Ordered design-major, then mass.
    step, horizon, dt : float
    """

    designs: tuple[str, ...]
    masses: tuple[float, ...]
    tuning: Mapping[str, TuningResult]
    runs: Mapping[tuple[str, float], SimulationResult]
    rows: tuple[StudyRow, ...]
    step: float
    horizon: float
    dt: float

    def row(self, design: str, mass: float) -> StudyRow:
        for r in self.rows:
            if r.design == design and r.load_mass == mass:
                return r
        raise KeyError((design, mass))

    def ours_fastest(self) -> dict[float, bool]:
        """Per mass: does Ours settle strictly faster than every other design?"""
        out: dict[float, bool] = {}
        for mass in self.masses:
            ours = self.row("ours", mass).metrics.settling_time
            others = [self.row(d, mass).metrics.settling_time for d in self.designs if d != "ours"]
            out[mass] = ours is not None and all(o is None or ours < o for o in others)
        return out

    def summary(self) -> str:
        """Plain-text table and the honest comparison."""
        lines = [f"{'design':<6} {'m_L/kg':>7} {'settling/s':>11} {'final err/m':>12}  gains"]
        for r in self.rows:
            ts = r.metrics.settling_time
            gains = ", ".join(f"{k}={v:.4g}" for k, v in self.tuning[r.design].gains.items())
            lines.append(
                f"{r.design:<6} {r.load_mass:>7g} "
                f"{(f'{ts:.4f}' if ts is not None else r.metrics.status):>11} "
                f"{r.metrics.final_error:>12.3e}  {gains}"
            )
        fastest = self.ours_fastest()
        if "ours" in self.designs:
            for mass, ok in fastest.items():
                lines.append(
                    f"m_L = {mass:g} kg: Ours is {'' if ok else 'NOT '}the fastest to settle"
                )
        return "\n".join(lines)

    def table_dicts(self) -> list[dict[str, Any]]:
        out = []
        for r in self.rows:
            d = r.to_dict()
            d["gains"] = dict(self.tuning[r.design].gains)
            out.append(d)
        return out

    def table_csv(self) -> str:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        gnames = sorted({g for t in self.tuning.values() for g in t.gains})
        w.writerow(
            ["design", "load_mass_kg", "status", "settling_time_s", "final_error_m", "overshoot",
             "peak_force_N", "energy_J", *gnames]
        )  # fmt: skip
        for r in self.rows:
            m = r.metrics
            gains = self.tuning[r.design].gains
            w.writerow(
                [
                    r.design,
                    repr(r.load_mass),
                    m.status,
                    "" if m.settling_time is None else repr(m.settling_time),
                    repr(m.final_error),
                    "" if m.overshoot is None else repr(m.overshoot),
                    repr(m.peak_force),
                    repr(m.energy),
                    *[repr(gains[g]) if g in gains else "" for g in gnames],
                ]
            )
        return buf.getvalue()

    def table_json(self) -> str:
        doc = {
            "step_m": self.step,
            "horizon_s": self.horizon,
            "dt_s": self.dt,
            "tuning": {k: v.to_dict() for k, v in self.tuning.items()},
            "rows": self.table_dicts(),
            "ours_fastest": {repr(k): v for k, v in self.ours_fastest().items()},
        }
        return json_text(doc)

    def timeseries_csv(self) -> str:
        """Long format: design, load mass, time, x_A, x_L, f_A (all runs share one grid)."""
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(["design", "load_mass_kg", "time_s", "x_A_m", "x_L_m", "f_A_N"])
        for (design, mass), res in self.runs.items():
            for row in zip(res.time, res.x_A, res.x_L, res.f_A, strict=True):
                w.writerow([design, f"{mass:g}", *(f"{v:.9g}" for v in row)])
        return buf.getvalue()


def _study_design(
    key: str,
    opts: TuningOptions,
    masses: tuple[float, ...],
    horizon: float,
    dt: float,
    progress: Progress,
    tuned: dict[str, TuningResult],
    runs: dict[tuple[str, float], SimulationResult],
    rows: list[StudyRow],
    on_design: Callable[[TuningResult], None] | None,
) -> None:
    """Tune one design and simulate it at every mass (into ``tuned``, ``runs``, ``rows``)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TuningWarning)  # kept in tr.warnings and the JSON
        tr = tune(key, options=opts, progress=progress)
    tuned[key] = tr
    if on_design is not None:
        on_design(tr)
    for mass in masses:
        res = simulate(
            tr.sea, load_mass=mass, scenario=Step(tr.options.step), horizon=horizon, dt=dt
        )
        runs[(key, mass)] = res
        rows.append(
            StudyRow(
                design=key, load_mass=mass, metrics=tracking_metrics(res, tolerance=opts.tolerance)
            )
        )


def run_simulation_study(
    *,
    designs: Sequence[str] = ("LP", "APD", "ours"),
    masses: Sequence[float] = PAPER_EXPERIMENT.load_masses,
    options: TuningOptions | None = None,
    quick: bool = False,
    horizon: float = PAPER_EXPERIMENT.horizon,
    dt: float = 1e-3,
    progress: ProgressLike = None,
    on_design: Callable[[TuningResult], None] | None = None,
) -> SimulationStudy:
    """Tune each design at ``options.load_mass`` and evaluate it at every mass.

    Parameters
    ----------
    designs : sequence of str
        Subset of ``LP``, ``APD``, ``ours``.
    masses : sequence of float
        Evaluation load masses (kg), each positive; default the paper's
        ([`PAPER_EXPERIMENT`][seapass.model.experiment.PAPER_EXPERIMENT]).
    options : TuningOptions, optional
        Tuning setup (default: the paper's experiment; tuning mass 10 kg, 0.5 m step).
    quick : bool
        Use the small budget of `QUICK_OPTIONS` (for tests and previews).
    horizon, dt : float
        Evaluation horizon and time step (s).
    progress : Progress, optional
        Where the study reports: one task with a step per design, each design's tuning
        a task inside it.  Default: none; ``True``/``False`` still work for one release.
    on_design : callable, optional
        Called with each `TuningResult` as it completes.

    Returns
    -------
    SimulationStudy
    """
    shown = as_progress(progress, where="run_simulation_study")
    keys = tuple(catalog_design(d).key for d in designs)
    if not keys:
        raise ParameterError("designs is empty")
    ms = tuple(float(m) for m in masses)
    if not ms or any(not (np.isfinite(m) and m > 0) for m in ms):
        raise ParameterError(f"masses must be positive and finite, got {list(masses)}")
    opts = options or TuningOptions()
    if quick:
        opts = replace(
            opts,
            maxiter=QUICK_OPTIONS.maxiter,
            popsize=QUICK_OPTIONS.popsize,
            dt_search=QUICK_OPTIONS.dt_search,
        )
    tuned: dict[str, TuningResult] = {}
    runs: dict[tuple[str, float], SimulationResult] = {}
    rows: list[StudyRow] = []
    step = PAPER_EXPERIMENT.step
    with task(shown, f"simulation study: {len(keys)} design(s)", len(keys)):
        for key in keys:
            _study_design(key, opts, ms, horizon, dt, shown, tuned, runs, rows, on_design)
            step = tuned[key].options.step
            shown.advance(1, note=key)
    return SimulationStudy(
        designs=keys,
        masses=ms,
        tuning=MappingProxyType(tuned),
        runs=MappingProxyType(runs),
        rows=tuple(rows),
        step=step,
        horizon=horizon,
        dt=dt,
    )
