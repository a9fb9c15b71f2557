"""Stages of :func:`seapass.reproduce.reproduce` built on the simulation, rig, sampled-data,
runtime and batch modules (each imported only when its stage runs, so a missing
module turns that stage into a *skipped* section).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..document import FigureData, Finding, Section, Table, figure_png, format_intervals, to_json

__all__ = [
    "stage_deploy",
    "stage_rig",
    "stage_sampled",
    "stage_simulation",
    "stage_tradeoff",
]


def _code(text: Any) -> str:
    return f"`{text}`"


# ----------------------------------------------------------------- simulation


def stage_simulation(quick: bool) -> Section:
    from ...plot.sim import plot_simulation_study
    from ...paper.simstudy import run_simulation_study

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
            "agrees" if ok else "differs",
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
                figure_png(fig),
            ),
        ),
        findings=tuple(findings),
        files={
            "sims_table.json": study.table_json(),
            "sims_timeseries.csv": study.timeseries_csv(),
        },
    )


# ----------------------------------------------------------------- rig


def _finding(f: Any) -> Finding:
    verdict = "info" if f.match is None else ("agrees" if f.match else "differs")
    return Finding(f.claim, verdict, f.detail)


def stage_rig(quick: bool) -> Section:
    from ...rig.experiment import run_experiment, run_impacts
    from ...plot.rig import plot_impacts, plot_sweep
    from ...rig.rigfile import paper_rig

    rig = paper_rig()
    # quick: 100 N/m steps still put two gains below 200 N/m (the low-gain finding)
    step = rig.experiment.kd_step * (4 if quick else 1)
    ex = run_experiment(rig, kd_step=step, progress=False)
    im = run_impacts(rig)
    summary = []
    for s in ex.sweeps:
        ok = np.isfinite(s.settling_time)
        best = int(np.nanargmin(s.settling_time)) if ok.any() else None
        summary.append(
            (
                "Ours" if s.design == "ours" else s.design, s.load_mass, len(s.kd),
                None if best is None else float(s.kd[best]),
                None if best is None else float(s.settling_time[best]),
                s.unstable_gain_twin, s.unstable_gain_continuous, s.unstable_gain_sampled,
            )
        )  # fmt: skip
    sweep_table = Table(
        name="rig_sweep_summary",
        title="kd sweeps on the digital twin (load from 20 mm to 0)",
        columns=(
            "design",
            "load mass [kg]",
            "gains",
            "fastest kd [N/m]",
            "its settling time [s]",
            "unstable from kd (twin) [N/m]",
            "unstable (continuous model)",
            "unstable (sampled model)",
        ),
        rows=tuple(summary),
    )
    impact_table = Table(
        name="rig_impacts",
        title="Perceived stiffness under impacts (Ours)",
        columns=("quantity", "twin", "paper"),
        rows=(
            ("k_out mean ± std [N/m]", f"{im.k_out_mean:.0f} ± {im.k_out_std:.0f}", "2292 ± 91.6"),
            ("spring k1 [N/m]", im.k1, 1005.0),
            ("static stiffness k1·kd/(k1+kd) [N/m]", im.static_stiffness, None),
            ("read-out time after onset [ms]", im.window * 1e3, None),
            ("impacts", int(im.forces.size), None),
        ),
    )
    sweep_rows = [r for s in ex.sweeps for r in s.rows()]
    cols = list(sweep_rows[0]) if sweep_rows else []
    csv_lines = [",".join(cols)] + [
        ",".join("" if r[c] is None else (repr(r[c]) if isinstance(r[c], float) else str(r[c]))
                 for c in cols)
        for r in sweep_rows
    ]  # fmt: skip
    return Section(
        key="rig",
        title="Hardware experiment on the digital twin (paper Sec. VI, Fig. 3)",
        text=(
            f"The packaged reconstruction of the paper's bench (`{rig.name}`: "
            f"m = {rig.actuator_mass:.4g} kg, b = {rig.actuator_damping:g} N·s/m, "
            f"k1 = {rig.damper.k1:g} N/m, b1 = {rig.damper.b1:g} N·s/m, "
            f"{rig.control.rate:g} Hz control, one sample of delay, "
            f"{rig.control.velocity_filter_hz:g} Hz velocity filter, Coulomb friction, encoder "
            "quantization, force saturation) runs the paper's protocol: LP and Ours, "
            f"kd from 0 to {rig.experiment.kd_max:g} N/m in steps of {step:g} N/m, load masses "
            f"{', '.join(f'{m:g}' for m in rig.experiment.load_masses)} kg. The values the paper "
            "identified are printed only in a figure, so m, b, b1 are reconstructions; compare "
            "trends, not digits."
        ),
        tables=(sweep_table, impact_table),
        figures=(
            FigureData(
                "rig_sweep",
                "Settling time and steady-state error against kd (twin).",
                figure_png(plot_sweep(ex)),
            ),
            FigureData(
                "rig_impacts",
                "Perceived stiffness of Ours under impacts (twin).",
                figure_png(plot_impacts(im)),
            ),
        ),
        findings=tuple(_finding(f) for f in (*ex.findings, *im.findings)),
        files={
            "rig_sweep.csv": "\n".join(csv_lines) + "\n",
            "rig_experiment.json": to_json(ex.to_dict()),
            "rig_impacts.json": to_json(im.to_dict()),
        },
    )


# ----------------------------------------------------------------- sampled


def stage_sampled(quick: bool) -> Section:
    from ...model.sea import SEA
    from ...analysis.region import passive_intervals
    from ...rig.rigfile import paper_rig
    from ...sampled.passivity import sampled_passive_bound

    rig = paper_rig()
    vals = rig.model_values()
    period = rig.period
    bd = rig.experiment.bd_ours
    setups = [
        ("ideal", 0, None),
        ("rig", rig.control.delay_samples, rig.control.velocity_filter_hz),
    ]
    designs = [
        ("LP", SEA(D1="k1 + b1*s", CL="kd", values={**vals, "kd": None}, name="LP"), 2000.0),
        (
            "Ours",
            SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**vals, "kd": None, "bd": bd}, name="ours"),
            1e5,
        ),
    ]
    samples, rtol = (5, 1e-2) if quick else (17, 1e-5)
    rows, results, findings = [], {}, []
    for name, sea, hi in designs:
        cont = passive_intervals(sea, "kd", 0.0, hi)
        cont_max = cont.intervals[-1][1] if cont.intervals else None
        per = []
        for label, delay, filt in setups:
            r = sampled_passive_bound(
                sea, "kd", period=period, lo=0.0, hi=hi, delay=delay, velocity_filter=filt,
                samples=samples, rtol=rtol,
            )  # fmt: skip
            results[f"{name}/{label}"] = r.to_dict()
            per.append(r.max_passive)
        rows.append((name, _code(str(sea.CA) if name == "Ours" else str(sea.CL)), hi,
                     cont_max if cont_max is None or cont_max < hi else math.inf, *per))  # fmt: skip
        findings.append(
            Finding(
                f"{name}: the continuous-time passive range of kd carries over to the 500 Hz controller",
                "differs",
                f"continuous: {format_intervals(cont.intervals, hi)}; at T = {period * 1e3:g} ms the largest "
                f"passive kd is {per[0] if per[0] is None else f'{per[0]:.5g}'} N/m (ideal) and "
                f"{per[1] if per[1] is None else f'{per[1]:.5g}'} N/m (one-sample delay, "
                f"{rig.control.velocity_filter_hz:g} Hz velocity filter)",
            )
        )
    table = Table(
        name="sampled_limits",
        title=f"Largest passive kd [N/m] at T = {period * 1e3:g} ms vs continuous time",
        columns=(
            "design",
            "controller",
            "search limit",
            "continuous",
            "500 Hz ideal",
            "500 Hz, delay + filter",
        ),
        rows=tuple(rows),
        note=(
            f"Rig values m = {vals['m']:.5g}, b = {vals['b']:g}, k1 = {vals['k1']:g}, "
            f"b1 = {vals['b1']:g}, Ours bd = {bd:g}. ∞: passive up to the search limit. Edges "
            f"refined to {rtol:g} of the search range."
        ),
    )
    fig = _plot_sampled(rows, period)
    return Section(
        key="sampled",
        title="Sampled-data passivity at the rig's 500 Hz (beyond the paper)",
        text=(
            "The paper's conditions are continuous-time; the bench runs a 500 Hz digital "
            "controller. The sampled port is decided exactly with the Colgate–Schenkel alias "
            "argument generalised to the SEA (`seapass.sampled.passivity`, see the *Sampled-data* page). "
            "Ours is passive for every kd in continuous time but has a finite kd limit once "
            "sampled; LP's limit shrinks further."
        ),
        tables=(table,),
        figures=(FigureData("sampled_limits", "Largest passive kd: continuous vs 500 Hz.", fig),),
        findings=tuple(findings),
        files={"sampled_bounds.json": to_json(results)},
    )


def _plot_sampled(rows: list[tuple[Any, ...]], period: float) -> bytes:
    import matplotlib.pyplot as plt

    labels = ("continuous", "500 Hz ideal", "500 Hz + delay + filter")
    fig, ax = plt.subplots(figsize=(7.5, 3.8), constrained_layout=True)
    width = 0.26
    for j, lab in enumerate(labels):
        xs, hs = [], []
        for i, r in enumerate(rows):
            v = r[3 + j]
            v = r[2] if v is not None and math.isinf(v) else (0.0 if v is None else v)
            xs.append(i + (j - 1) * width)
            hs.append(max(v, 1.0))
        bars = ax.bar(xs, hs, width, label=lab)
        for x, h, r in zip(xs, hs, rows, strict=True):
            v = r[3 + j]
            text = "all (≥ limit)" if v is not None and math.isinf(v) else f"{h:.0f}"
            ax.text(x, h * 1.1, text, ha="center", va="bottom", fontsize=8)
        del bars
    ax.set_yscale("log")
    ax.set_xticks(range(len(rows)), [r[0] for r in rows])
    ax.set_ylabel("largest passive kd [N/m]")
    ax.set_ylim(100, 1e6)
    ax.set_title(f"Passive kd, continuous vs sampled (T = {period * 1e3:g} ms)")
    ax.legend(fontsize=9, loc="upper left")
    ax.grid(True, axis="y", alpha=0.3)
    return figure_png(fig)


# ----------------------------------------------------------------- deploy


def stage_deploy(quick: bool) -> Section:
    from ...sampled.controllers import LPController, OursController
    from ...errors import NotPassiveError
    from ...model.sea import SEA
    from ...rig.rigfile import paper_rig
    from ...sampled.runtime import ControlLoop, SimulatedHardware
    from ...rig.twin import TwinPlant

    rig = paper_rig()
    vals = rig.model_values()
    period, delay = rig.period, rig.control.delay_samples
    filt = rig.control.velocity_filter_hz
    duration = 1.0 if quick else 2.0
    cases = [
        ("Ours, kd = 1000, bd = 25", OursController(1000.0, 25.0, period, velocity_filter=filt),
         SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**vals, "kd": 1000.0, "bd": 25.0})),
        ("LP, kd = 500", LPController(500.0, period),
         SEA(D1="k1 + b1*s", CL="kd", values={**vals, "kd": 500.0})),
        ("LP, kd = 800", LPController(800.0, period),
         SEA(D1="k1 + b1*s", CL="kd", values={**vals, "kd": 800.0})),
    ]  # fmt: skip
    rows: list[tuple[Any, ...]] = []
    runs: list[tuple[str, Any]] = []
    findings: list[Finding] = []
    for label, ctrl, sea in cases:
        plant = TwinPlant(rig, load_mass=0.1)
        plant.reset(x_A=0.02, x_L=0.02)
        hw = SimulatedHardware(plant, delay_samples=delay)
        try:
            loop = ControlLoop(
                hw, ctrl, period=period, force_limit=rig.force_limit,
                position_limits=(-0.15, 0.15), design=sea, delay=delay,
            )  # fmt: skip
        except NotPassiveError as exc:
            rows.append((label, "refused", None, None, None, str(exc)))
            findings.append(
                Finding(f"{label}: the passivity gate refuses to deploy it", "info", str(exc))
            )
            continue
        rec = loop.run(duration)
        runs.append((label, rec))
        s = rec.summary()
        rows.append(
            (label, "deployed", s["ticks"], s["saturated"], float(rec.x_L[-1]) * 1e3,
             s["stop_reason"] or "completed")
        )  # fmt: skip
    table = Table(
        name="deploy",
        title=f"Deploying controllers on the twin ({1 / period:g} Hz, {delay} sample delay)",
        columns=(
            "controller",
            "passivity gate",
            "ticks",
            "saturated commands",
            "final x_L [mm]",
            "outcome",
        ),
        rows=tuple(rows),
    )
    return Section(
        key="deploy",
        title="Deployable controllers behind a passivity gate (beyond the paper)",
        text=(
            "The same discrete controllers the analysis uses run in `seapass.sampled.runtime.ControlLoop` "
            "against the digital twin (load from 20 mm to 0, 0.1 kg). Before starting, the loop "
            "checks continuous passivity *and* sampled-data passivity of the deployed "
            "controller at its own period and delay; a design that fails either is refused. "
            "LP with kd = 800 N/m passes the continuous test (kd ≤ 849 N/m) but not the "
            "500 Hz one with the bench's delay."
        ),
        tables=(table,),
        figures=(FigureData("deploy", "Deployed loops on the twin.", _plot_deploy(runs)),),
        findings=tuple(findings),
        files={"deploy.json": to_json({label: rec.summary() for label, rec in runs})},
    )


def _plot_deploy(runs: list[tuple[str, Any]]) -> bytes:
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.6), constrained_layout=True)
    for label, rec in runs:
        a1.plot(rec.t, np.asarray(rec.x_L) * 1e3, lw=1.4, label=label)
        a2.plot(rec.t, rec.command, lw=1.0, label=label)
    a1.set_xlabel("time [s]")
    a1.set_ylabel("measured load position x_L [mm]")
    a1.set_title("Load position (reference 0)")
    a2.set_xlabel("time [s]")
    a2.set_ylabel("force command [N]")
    a2.set_title("Saturated command")
    for ax in (a1, a2):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=9)
    return figure_png(fig)


# ----------------------------------------------------------------- trade-off (batch)


def stage_tradeoff(quick: bool) -> Section:
    from ...batch.verdicts import batch_is_passive
    from ...batch.step_metrics import batch_step_metrics
    from ...model.sea import SEA

    n = 21 if quick else 41
    load_mass, step, horizon = 10.0, 0.5, 10.0
    plant = {"m": 1.0, "b": 10.0, "k1": 1000.0}
    cases = [
        ("Ours (b1 = 100)", SEA(D1="k1 + b1*s", CA="kd + bd*s",
                                values={**plant, "b1": 100.0, "kd": None, "bd": None}),
         ("kd", 0.0, 5000.0), ("bd", 0.0, 300.0)),
        ("LP", SEA(D1="k1 + b1*s", CL="kd", values={**plant, "kd": None, "b1": None}),
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
            FigureData("tradeoff", "Settling time over the design space.", _plot_tradeoff(maps)),
        ),
        files={"tradeoff_grid.csv": "\n".join(lines) + "\n"},
    )


def _plot_tradeoff(maps: list[tuple[Any, ...]]) -> bytes:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(maps), figsize=(5.6 * len(maps), 4.4), constrained_layout=True)
    units = {"kd": "N/m", "bd": "N·s/m", "b1": "N·s/m"}
    for ax, (label, xn, yn, xs, ys, pas, ts, best) in zip(np.atleast_1d(axes), maps, strict=True):
        ax.pcolormesh(xs, ys, np.where(pas, np.nan, 1.0), cmap="Greys", vmin=0, vmax=2,
                      shading="nearest")  # fmt: skip
        mesh = ax.pcolormesh(xs, ys, np.where(pas, ts, np.nan), cmap="viridis_r",
                             shading="nearest")  # fmt: skip
        fig.colorbar(mesh, ax=ax, label="2 % settling time [s]")
        if best is not None:
            ax.plot(best[1], best[2], "r*", ms=14, label=f"fastest passive: {best[0]:.3g} s")
            ax.legend(loc="upper right", fontsize=9)
        ax.set_xlabel(f"{xn} [{units.get(xn, 'SI')}]")
        ax.set_ylabel(f"{yn} [{units.get(yn, 'SI')}]")
        ax.set_title(f"{label}: grey = not passive, blank = did not settle", fontsize=10)
    return figure_png(fig)
