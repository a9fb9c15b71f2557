"""``seapass simulate``: time-domain response of a design driving a load mass."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from .common import (
    add_force_option,
    add_json_option,
    add_model_options,
    add_plot_option,
    check_step,
    cli_words,
    model_from_args,
    plot_path,
    print_json,
    save_plot,
)

if TYPE_CHECKING:  # the CLI starts fast: heavy modules load when a command runs
    from ..sim.simulate import Scenario

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
        "--step",
        type=float,
        metavar="M",
        help="reference step size [m] (the default: the paper's 0.5)",
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
    p.add_argument(
        "--horizon", type=float, help="simulated time [s] (default: the paper's experiment, 10)"
    )
    p.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    p.add_argument(
        "--tolerance", type=float, default=0.02, help="settling band (fraction of the step)"
    )
    add_json_option(p, "the metrics")
    add_plot_option(p, "the response")
    add_force_option(p)
    p.set_defaults(func=run)


def scenario_from_args(args: argparse.Namespace) -> Scenario:
    from ..sim.scenarios import ForceImpulse, ForceStep, LoadDisplaced, Step, read_trajectory

    if args.load_displaced is not None:
        return LoadDisplaced(args.load_displaced)
    if args.force_step is not None:
        return ForceStep(args.force_step)
    if args.impulse is not None:
        return ForceImpulse(args.impulse)
    if args.trajectory is not None:
        return read_trajectory(args.trajectory, interpolation=args.interp, apply_to=args.reference)
    return Step(args.step, apply_to=args.reference)


def run(args: argparse.Namespace) -> int:
    from ..sim.summary import simulation_summary

    figure = plot_path(args.plot, force=args.force)
    check_step(args.step)
    sea = model_from_args(args)
    summary = simulation_summary(
        sea,
        load_mass=args.load_mass,
        scenario=scenario_from_args(args),
        horizon=args.horizon,
        dt=args.dt,
        tolerance=args.tolerance,
    )
    error = None if summary.passive_error is None else cli_words(summary.passive_error)
    if figure is not None:
        save_plot(summary.plot, figure, force=args.force, flag="--plot")
    if args.json:
        out = summary.to_dict()
        if error is not None:
            out["passive_error"] = error
        print_json(out)
    else:
        met, result = summary.metrics, summary.result
        ts = met.settling_time
        passive = {True: "passive", False: "not passive", None: "passivity not decided"}
        print(f"status: {met.status} (closed loop {result.status}; {passive[summary.passive]})")
        if error is not None:
            print(f"passivity: {error}")
        print(f"settling time: {'-' if ts is None else f'{ts:.6g} s'}")
        print(f"final error: {met.final_error:.3e} m")
        if met.overshoot is not None:  # the same unit as in --json: a fraction of the step
            print(f"overshoot: {met.overshoot:.4g} of the step")
        print(f"peak actuator force: {met.peak_force:.6g} N, energy: {met.energy:.6g} J")
    return 0
