"""``seapass simulate``: time-domain response of a design driving a load mass."""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING, Any

from ..errors import FileFormatError, SeapassError
from ..files.limits import MAX_TRAJECTORY_BYTES, MAX_TRAJECTORY_SAMPLES
from ..files.textfile import read_text_file
from .common import (
    add_force_option,
    add_json_option,
    add_model_options,
    add_plot_option,
    check_step,
    error_text,
    model_from_args,
    plot_path,
    print_json,
    save_plot,
)

if TYPE_CHECKING:  # the CLI starts fast: heavy modules load when a command runs
    from ..sim.simulate import Scenario, Trajectory

EXAMPLE = """examples:
  seapass simulate --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 --set k1=1000 \\
      --set b1=100 --set kd=2000 --set bd=60 --load-mass 10 --step 0.5 --json
  seapass simulate --D1 k1 --CL kd --set m=1 --set b=10 --set k1=1000 --set kd=500 \\
      --load-mass 10 --load-displaced 0.02 --horizon 5 --plot lp.png
  seapass simulate --D1 k1 --CA "kd + ki/s" --set m=1 --set b=10 --set k1=1000 \\
      --set kd=300 --set ki=100 --load-mass 1 --trajectory ref.csv --interp linear

Controllers act on the error, except that the derivative part (e.g. bd*s) acts on
the measured velocity only ("derivative on measurement"), so steps give no impulse.
A --trajectory file has two columns, time [s] and reference [m] (header optional).
"""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "simulate",
        help="simulate a step (or other scenario) with a load mass; report tracking metrics",
        description="Exact (matrix-exponential) simulation of the closed loop with a load "
        "mass m_L at the port, and the 2 % settling time, final error, overshoot, peak "
        "actuator force and actuator energy. An unstable closed loop is reported as a "
        "result (stable: false), not an error.",
        epilog=EXAMPLE,
    )
    add_model_options(p)
    p.add_argument("--load-mass", type=float, required=True, help="load mass m_L [kg], > 0")
    g = p.add_mutually_exclusive_group()
    g.add_argument(
        "--step", type=float, metavar="M", help="reference step size [m] (the default: 0.5)"
    )
    g.add_argument(
        "--load-displaced", type=float, metavar="X0", help="load starts at X0 [m], reference 0"
    )
    g.add_argument("--force-step", type=float, metavar="F", help="constant force on the load [N]")
    g.add_argument("--impulse", type=float, metavar="J", help="impulse on the load [N s]")
    g.add_argument("--trajectory", metavar="CSV", help="reference samples: time,value per line")
    p.add_argument(
        "--interp", choices=("zoh", "linear"), default="linear", help="trajectory interpolation"
    )
    p.add_argument(
        "--reference",
        choices=("both", "actuator", "load"),
        default="both",
        help="which references step/follow the trajectory (default both: θ_A = θ_L)",
    )
    p.add_argument("--horizon", type=float, default=10.0, help="simulated time [s]")
    p.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    p.add_argument(
        "--tolerance", type=float, default=0.02, help="settling band (fraction of the step)"
    )
    add_json_option(p, "the metrics")
    add_plot_option(p, "the response")
    add_force_option(p)
    p.set_defaults(func=run)


def _load_trajectory(path: str, interp: str, reference: str) -> Trajectory:
    import numpy as np

    from ..sim.simulate import Trajectory

    text = read_text_file(path, max_bytes=MAX_TRAJECTORY_BYTES, what="trajectory file")
    rows: list[tuple[float, float]] = []
    for n, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = [x.strip() for x in line.replace(";", ",").replace("\t", ",").split(",")]
        try:
            vals = [float(x) for x in parts if x]
        except ValueError:
            if not rows and n == 1:
                continue  # header
            raise FileFormatError(f"{path}:{n}: expected two numbers, got {line!r}") from None
        if len(vals) != 2 or not all(math.isfinite(v) for v in vals):
            raise FileFormatError(f"{path}:{n}: expected two finite numbers, got {line!r}")
        rows.append((vals[0], vals[1]))
        if len(rows) > MAX_TRAJECTORY_SAMPLES:
            raise FileFormatError(
                f"{path}: more than {MAX_TRAJECTORY_SAMPLES:,} samples; resample the trajectory"
            )
    if not rows:
        raise FileFormatError(f"{path}: no samples found")
    arr = np.array(rows)
    return Trajectory(arr[:, 0], arr[:, 1], interpolation=interp, apply_to=reference)  # type: ignore[arg-type]


def scenario_from_args(args: argparse.Namespace) -> Scenario:
    from ..sim.simulate import ForceImpulse, ForceStep, LoadDisplaced, Step

    if args.load_displaced is not None:
        return LoadDisplaced(args.load_displaced)
    if args.force_step is not None:
        return ForceStep(args.force_step)
    if args.impulse is not None:
        return ForceImpulse(args.impulse)
    if args.trajectory is not None:
        return _load_trajectory(args.trajectory, args.interp, args.reference)
    return Step(0.5 if args.step is None else args.step, apply_to=args.reference)


def run(args: argparse.Namespace) -> int:
    from ..analysis.passivity import is_passive
    from ..sim.metrics import tracking_metrics
    from ..sim.simulate import simulate

    figure = plot_path(args.plot, force=args.force)
    check_step(args.step)
    sea = model_from_args(args)
    scenario = scenario_from_args(args)
    result = simulate(
        sea, load_mass=args.load_mass, scenario=scenario, horizon=args.horizon, dt=args.dt
    )
    met = tracking_metrics(result, tolerance=args.tolerance)
    out: dict[str, Any] = {
        "settling_time": met.settling_time,
        "final_error": met.final_error,
        "overshoot": met.overshoot,
        "status": met.status,
    }
    try:
        out["passive"] = is_passive(sea).passive
    except SeapassError as exc:  # passivity is informative here; the simulation stands
        out["passive"] = None
        out["passive_error"] = error_text(exc)
    out.update(
        {
            "stable": result.stable,
            "marginal": result.marginal,
            "diverged": result.diverged,
            "peak_force": met.peak_force,
            "energy": met.energy,
            "positive_work": met.positive_work,
            "band": met.band,
            "target": met.target,
            "load_mass": args.load_mass,
            "horizon": args.horizon,
            "dt": float(result.time[1] - result.time[0]) if result.time.size > 1 else args.dt,
            "scenario": type(scenario).__name__,
            "poles": [[float(p.real), float(p.imag)] for p in result.poles],
        }
    )
    if figure is not None:
        from ..plot.sim import plot_simulation

        save_plot(lambda: plot_simulation(result, met), figure, force=args.force, flag="--plot")
    if args.json:
        print_json(out)
    else:
        ts = out["settling_time"]
        passive = {True: "passive", False: "not passive", None: "passivity not decided"}
        print(f"status: {met.status} (closed loop {result.status}; {passive[out['passive']]})")
        if out["passive"] is None:
            print(f"passivity: {out['passive_error']}")
        print(f"settling time: {'-' if ts is None else f'{ts:.6g} s'}")
        print(f"final error: {met.final_error:.3e} m")
        if met.overshoot is not None:  # the same unit as in --json: a fraction of the step
            print(f"overshoot: {met.overshoot:.4g} of the step")
        print(f"peak actuator force: {met.peak_force:.6g} N, energy: {met.energy:.6g} J")
    return 0
