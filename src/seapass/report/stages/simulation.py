"""Paper stages: the simulation study (Sec. V) and the design-space trade-off.

Each ``stage_*`` returns a [`Section`][seapass.report.document.Section], split as
python-control splits ``*_response`` from ``*_plot``: ``*_data`` computes,
``*_figures`` draws, ``*_section`` writes the section.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...batch.step_metrics import batch_step_metrics
from ...batch.verdicts import batch_is_passive
from ...model.catalog import PAPER_VALUES
from ...model.catalog import design as catalog_design
from ...model.experiment import PAPER_EXPERIMENT
from ...paper.simstudy import SimulationStudy, run_simulation_study
from ...plot.sim import plot_simulation_study, plot_tradeoff
from ...progress import Progress, ProgressLike, as_progress, task
from ...sim.metrics import overshoot_percent
from ..document import FigureData, Finding, Section, Table, Verdict
from ..pipeline import StageContext

__all__ = [
    "TradeoffData",
    "simulation_data",
    "simulation_figures",
    "simulation_section",
    "stage_simulation",
    "stage_tradeoff",
    "tradeoff_data",
    "tradeoff_figures",
    "tradeoff_section",
]


def simulation_data(quick: bool, *, progress: ProgressLike = None) -> SimulationStudy:
    """The paper's simulation study (Sec. V, Fig. 4): tuned LP, APD and Ours at three masses."""
    return run_simulation_study(quick=quick, progress=progress)


def simulation_figures(study: SimulationStudy) -> tuple[FigureData, ...]:
    return (
        FigureData.of(
            "sims",
            "Load position after a 0.5 m step for each design and load mass.",
            plot_simulation_study(study),
        ),
    )


def simulation_section(
    study: SimulationStudy, figures: Sequence[FigureData], *, quick: bool
) -> Section:
    """The section of `simulation_data` with the figures of `simulation_figures`."""
    gnames = sorted({g for t in study.tuning.values() for g in t.gains})
    rows = []
    for r in study.rows:
        m = r.metrics
        gains = study.tuning[r.design].gains
        rows.append(
            (r.design, r.load_mass, m.status, m.settling_time, m.final_error, overshoot_percent(m.overshoot),
             m.peak_force, *[gains.get(g) for g in gnames])
        )  # fmt: skip
    table = Table(
        name="sims_table",
        title="Simulation study: settling time (2 % band) and final error",
        columns=(
            "design",
            "load mass [kg]",
            "status",
            "settling time [s]",
            "final error [m]",
            "overshoot [%]",
            "peak force [N]",
            *[f"{g} [SI]" for g in gnames],
        ),
        rows=tuple(rows),
    )
    fastest = study.ours_fastest()
    findings = [
        Finding(
            f"Ours converges faster than LP and APD at m_L = {mass:g} kg (Sec. V)",
            Verdict.AGREES if ok else Verdict.DIFFERS,
            ", ".join(
                f"{d}: "
                + (
                    f"{study.row(d, mass).metrics.settling_time:.3f} s"
                    if study.row(d, mass).metrics.settling_time is not None
                    else study.row(d, mass).metrics.status
                )
                for d in study.designs
            ),
        )
        for mass, ok in fastest.items()
    ]
    budget = "a reduced optimiser budget (--quick)" if quick else "the full optimiser budget"
    return Section(
        key="simulation",
        title="Simulation study (paper Sec. V, Fig. 4)",
        text=(
            "LP, APD and Ours are tuned at `m_L = 10 kg` for the fastest 2 % settling of a "
            "0.5 m step under the exact passivity constraint and an actuator force limit "
            f"(differential evolution, fixed seed, {budget}), then simulated exactly "
            "(matrix-exponential discretization) at `m_L = 1, 10, 25 kg`."
        ),
        tables=(table,),
        figures=tuple(figures),
        findings=tuple(findings),
        files={
            "sims_table.json": study.table_json(),
            "sims_timeseries.csv": study.timeseries_csv(),
        },
    )


def stage_simulation(context: StageContext) -> Section:
    """The paper's simulation study (Sec. V, Fig. 4): tuned LP, APD and Ours at three masses."""
    study = simulation_data(context.quick, progress=context.progress)
    return simulation_section(study, simulation_figures(study), quick=context.quick)


_LOAD_MASS, _STEP, _HORIZON = (
    PAPER_EXPERIMENT.load_mass,
    PAPER_EXPERIMENT.step,
    PAPER_EXPERIMENT.horizon,
)


def _tuned_lp(quick: bool) -> tuple[float, float | None]:
    """The simulation study's tuned LP (same tuner, options and seed): ``kd`` and its settling time."""
    study = run_simulation_study(designs=("LP",), masses=(_LOAD_MASS,), quick=quick)
    return float(study.tuning["LP"].gains["kd"]), study.rows[0].metrics.settling_time


def _grid(
    sea: Any, x: tuple[str, np.ndarray], y: tuple[str, np.ndarray]
) -> tuple[np.ndarray, np.ndarray, tuple[float, float, float] | None]:
    """Exact verdicts and settling times over the grid (axes ``(y, x)``), and the best passive point."""
    (xn, xs), (yn, ys) = x, y
    vals = {xn: xs[None, :], yn: ys[:, None]}
    pas = batch_is_passive(sea, vals, margin=False).passive
    met = batch_step_metrics(sea, vals, load_mass=_LOAD_MASS, step=_STEP, horizon=_HORIZON)
    ts = np.where(met.settled, met.settling_time, np.nan)
    good = np.where(pas, ts, np.nan)
    best = None
    if np.isfinite(good).any():
        bi, bj = (int(k) for k in np.unravel_index(int(np.nanargmin(good)), good.shape))
        best = (float(good[bi, bj]), float(xs[bj]), float(ys[bi]))
    return pas, ts, best


def _best_lp_finding(
    best: tuple[float, float, float] | None, at_tuned: float, kd: float, t_study: float | None
) -> Finding:
    """Do the grid and the simulation study give the same fastest passive LP?

    ``at_tuned`` is the grid's settling time at the study's tuned gain (b1 = 0).
    """
    claim = "The trade-off grid and the simulation study give the same fastest passive LP"
    if t_study is None or best is None or not np.isfinite(at_tuned):
        return Finding(
            claim, Verdict.DIFFERS,
            f"the study's tuned LP (kd = {kd:.4g} N/m) settles in "
            f"{'no' if t_study is None else f'{t_study:.3f} s in the'} study and in "
            f"{'no' if not np.isfinite(at_tuned) else f'{at_tuned:.3f} s on the'} grid",
        )  # fmt: skip
    t, x, y = best
    tuned = (
        f"the grid includes the study's tuned LP (kd = {kd:.4g} N/m on the undamped spring, "
        f"b1 = 0): {at_tuned:.3f} s by the modal solution vs {t_study:.3f} s simulated in the study"
    )
    if abs(at_tuned - t_study) > 0.01:
        return Finding(claim, Verdict.DIFFERS, tuned)
    if t < t_study - 0.01:
        return Finding(
            claim, Verdict.INFO,
            f"{tuned}; a damped spring speeds LP up: the grid's fastest passive LP takes "
            f"{t:.3f} s at kd = {x:.4g} N/m, b1 = {y:.4g} N·s/m",
        )  # fmt: skip
    return Finding(
        claim, Verdict.AGREES,
        f"{tuned}; nothing on the grid is faster by more than 0.01 s (its fastest passive LP: "
        f"{t:.3f} s at kd = {x:.4g} N/m, b1 = {y:.4g} N·s/m)",
    )  # fmt: skip


def _grid_csv(label: str, x: tuple[str, np.ndarray], y: tuple[str, np.ndarray],
              pas: np.ndarray, ts: np.ndarray) -> list[str]:  # fmt: skip
    """One CSV line per grid point."""
    (xn, xs), (yn, ys) = x, y
    return [
        f"{label},{xn},{xv!r},{yn},{yv!r},{bool(pas[i, j])},"
        f"{'' if np.isnan(ts[i, j]) else repr(float(ts[i, j]))}"
        for i, yv in enumerate(ys.tolist())
        for j, xv in enumerate(xs.tolist())
    ]


def _tradeoff_cases(
    n: int, kd_lp: float
) -> list[tuple[str, Any, tuple[str, Any], tuple[str, Any]]]:
    """The two grids: Ours over (kd, bd) at b1 = 100, LP on the damped spring over (kd, b1)."""
    return [
        ("Ours (b1 = 100)", catalog_design("ours").sea(PAPER_VALUES, b1=100.0),
         ("kd", np.linspace(0.0, 5000.0, n)), ("bd", np.linspace(0.0, 300.0, n))),
        # LP on the damped spring (the paper's Table I row 3); b1 = 0 is the study's LP, and
        # the grid includes the study's tuned gain
        ("LP", catalog_design("mech/parallel-spring-damper").sea(PAPER_VALUES, b1=None),
         ("kd", np.union1d(np.linspace(0.0, 1500.0, n), [kd_lp])),
         ("b1", np.linspace(0.0, 300.0, n))),
    ]  # fmt: skip


#: One grid of the trade-off, as `plot_tradeoff` takes it: label, axis names, axis values,
#: verdicts, settling times, the best passive point (or None) and the marks to draw.
TradeoffGrid = tuple[Any, ...]


@dataclass(frozen=True, kw_only=True)
class TradeoffData:
    """Everything the trade-off stage computes (`tradeoff_data`)."""

    n: int
    kd_lp: float
    t_lp: float | None
    grids: tuple[TradeoffGrid, ...]
    best_lp: tuple[float, float, float] | None
    at_tuned: float


def tradeoff_data(quick: bool, *, progress: ProgressLike = None) -> TradeoffData:
    """Exact passivity and settling time over whole 2-D gain grids (batch engine)."""
    shown = as_progress(progress, where="tradeoff_data")
    with task(shown, "design-space trade-off", 3):
        return _tradeoff(quick, shown)


def _tradeoff(quick: bool, progress: Progress) -> TradeoffData:
    n = 21 if quick else 41
    kd_lp, t_lp = _tuned_lp(quick)
    progress.advance(1, note="tuned LP as in the simulation study")
    grids: list[TradeoffGrid] = []
    best_lp, at_tuned = None, float("nan")
    for label, sea, (xn, xs), (yn, ys) in _tradeoff_cases(n, kd_lp):
        pas, ts, best = _grid(sea, (xn, xs), (yn, ys))
        progress.advance(1, note=f"{label}: {xs.size * ys.size} designs")
        marks: tuple[tuple[float, float, str], ...] = ()
        if label == "LP":
            best_lp, at_tuned = best, float(ts[0, int(np.searchsorted(xs, kd_lp))])
            marks = ((kd_lp, 0.0, f"study's tuned LP: {t_lp:.3g} s" if t_lp else "study's LP"),)
        grids.append((label, xn, yn, xs, ys, pas, ts, best, marks))
    return TradeoffData(
        n=n, kd_lp=kd_lp, t_lp=t_lp, grids=tuple(grids), best_lp=best_lp, at_tuned=at_tuned
    )


def tradeoff_figures(data: TradeoffData) -> tuple[FigureData, ...]:
    return (
        FigureData.of(
            "tradeoff",
            "Settling time over the design space; the star is the fastest passive design of "
            "each grid, the circle the simulation study's tuned LP.",
            plot_tradeoff(list(data.grids), horizon=_HORIZON),
        ),
    )


def tradeoff_section(data: TradeoffData, figures: Sequence[FigureData]) -> Section:
    """The section of `tradeoff_data` with the figures of `tradeoff_figures`."""
    n, kd_lp = data.n, data.kd_lp
    rows, lines = [], ["design,x_name,x,y_name,y,passive,settling_time_s"]
    for label, xn, yn, xs, ys, pas, ts, best, _marks in data.grids:
        rows.append(
            (label, f"{xn} ∈ [{xs[0]:g}, {xs[-1]:g}], {yn} ∈ [{ys[0]:g}, {ys[-1]:g}]",
             xs.size * ys.size, float(np.mean(pas)), None if best is None else best[0],
             None if best is None else f"{xn} = {best[1]:.4g}, {yn} = {best[2]:.4g}")
        )  # fmt: skip
        lines += _grid_csv(label, (xn, xs), (yn, ys), pas, ts)
    table = Table(
        name="tradeoff",
        title=f"Design space at m_L = {_LOAD_MASS:g} kg: passivity and settling time "
        f"({n}×{n} grid; LP's kd axis also holds the simulation study's tuned kd)",
        columns=(
            "design",
            "grid",
            "designs",
            "fraction passive",
            "best passive settling [s]",
            "at",
        ),
        rows=tuple(rows),
    )
    return Section(
        key="tradeoff",
        title="Passivity–performance trade-off over the design space (beyond the paper)",
        text=(
            "Every grid point is decided exactly (`seapass.batch.verdicts.batch_is_passive`: "
            "certified float64 with an exact rational fallback) and simulated by the vectorized "
            f"modal solution (`seapass.batch.step_metrics`): a {_STEP:g} m step with a "
            f"{_LOAD_MASS:g} kg load, 2 % settling within a {_HORIZON:g} s horizon, as in the "
            "simulation study. Grey: not passive; darkest: passive but not settled within the "
            "horizon. LP on the damped spring with b1 = 0 is the simulation study's LP, and its "
            f"kd axis includes the study's tuned gain (kd = {kd_lp:.4g} N/m), so both answers "
            'to "what is the fastest passive LP" are computed on the same design.'
        ),
        tables=(table,),
        figures=tuple(figures),
        findings=(_best_lp_finding(data.best_lp, data.at_tuned, kd_lp, data.t_lp),),
        files={"tradeoff_grid.csv": "\n".join(lines) + "\n"},
    )


def stage_tradeoff(context: StageContext) -> Section:
    """Exact passivity and settling time over whole 2-D gain grids (batch engine)."""
    data = tradeoff_data(context.quick, progress=context.progress)
    return tradeoff_section(data, tradeoff_figures(data))
