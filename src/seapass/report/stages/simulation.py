"""Paper stages: the simulation study (Sec. V) and the design-space trade-off.

Each ``stage_*`` returns a [`Section`][seapass.report.document.Section].
"""

from __future__ import annotations

import numpy as np

from ...batch.step_metrics import batch_step_metrics
from ...batch.verdicts import batch_is_passive
from ...model.catalog import PAPER_VALUES
from ...model.catalog import design as catalog_design
from ...paper.simstudy import run_simulation_study
from ...plot.sim import plot_simulation_study, plot_tradeoff
from ...plot.style import figure_bytes
from ..document import FigureData, Finding, Section, Table, Verdict

__all__ = [
    "stage_simulation",
    "stage_tradeoff",
]


def stage_simulation(quick: bool) -> Section:
    """The paper's simulation study (Sec. V, Fig. 4): tuned LP, APD and Ours at three masses."""
    study = run_simulation_study(quick=quick, progress=False)
    fig = plot_simulation_study(study)
    gnames = sorted({g for t in study.tuning.values() for g in t.gains})
    rows = []
    for r in study.rows:
        m = r.metrics
        gains = study.tuning[r.design].gains
        rows.append(
            (r.design, r.load_mass, m.status, m.settling_time, m.final_error, m.overshoot,
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
            "overshoot",
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
        figures=(
            FigureData(
                "sims",
                "Load position after a 0.5 m step for each design and load mass.",
                figure_bytes(fig),
            ),
        ),
        findings=tuple(findings),
        files={
            "sims_table.json": study.table_json(),
            "sims_timeseries.csv": study.timeseries_csv(),
        },
    )


def stage_tradeoff(quick: bool) -> Section:
    """Exact passivity and settling time over whole 2-D gain grids (batch engine)."""
    n = 21 if quick else 41
    load_mass, step, horizon = 10.0, 0.5, 10.0
    cases = [
        ("Ours (b1 = 100)", catalog_design("ours").sea(PAPER_VALUES, b1=100.0),
         ("kd", 0.0, 5000.0), ("bd", 0.0, 300.0)),
        # LP on the damped spring: the paper's Table I row 3
        ("LP", catalog_design("mech/parallel-spring-damper").sea(PAPER_VALUES, b1=None),
         ("kd", 0.0, 1500.0), ("b1", 0.0, 300.0)),
    ]  # fmt: skip
    rows, maps, lines = [], [], ["design,x_name,x,y_name,y,passive,settling_time_s"]
    for label, sea, (xn, x0, x1), (yn, y0, y1) in cases:
        xs, ys = np.linspace(x0, x1, n), np.linspace(y0, y1, n)
        vals = {xn: xs[None, :], yn: ys[:, None]}  # axes: (y, x)
        pas = batch_is_passive(sea, vals, margin=False).passive
        met = batch_step_metrics(sea, vals, load_mass=load_mass, step=step, horizon=horizon)
        ts = np.where(met.settled, met.settling_time, np.nan)
        good = np.where(pas, ts, np.nan)
        best = None
        if np.isfinite(good).any():
            bi, bj = (int(k) for k in np.unravel_index(int(np.nanargmin(good)), good.shape))
            best = (float(good[bi, bj]), float(xs[bj]), float(ys[bi]))
        rows.append(
            (label, f"{xn} ∈ [{x0:g}, {x1:g}], {yn} ∈ [{y0:g}, {y1:g}]", n * n,
             float(np.mean(pas)), None if best is None else best[0],
             None if best is None else f"{xn} = {best[1]:g}, {yn} = {best[2]:g}")
        )  # fmt: skip
        maps.append((label, xn, yn, xs, ys, pas, ts, best))
        for i, y in enumerate(ys.tolist()):
            for j, x in enumerate(xs.tolist()):
                t = ts[i, j]
                lines.append(
                    f"{label},{xn},{x!r},{yn},{y!r},{bool(pas[i, j])},{'' if np.isnan(t) else repr(float(t))}"
                )
    table = Table(
        name="tradeoff",
        title=f"Design space at m_L = {load_mass:g} kg: passivity and settling time ({n}×{n} grid)",
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
            "Every grid point is decided exactly (`seapass.batch.verdicts.batch_is_passive`: certified "
            "float64 with an exact rational fallback) and simulated by the vectorized modal "
            f"solution (`seapass.batch.step_metrics`): a {step:g} m step with a {load_mass:g} kg load, "
            f"{horizon:g} s horizon, 2 % settling. Grey: not passive."
        ),
        tables=(table,),
        figures=(
            FigureData(
                "tradeoff",
                "Settling time over the design space.",
                figure_bytes(plot_tradeoff(maps)),
            ),
        ),
        files={"tradeoff_grid.csv": "\n".join(lines) + "\n"},
    )
