"""``seapass simulate``: time-domain response of a design driving a load mass."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from ..errors import ParameterError
from .common import (
    add_force_option,
    add_json_option,
    add_model_options,
    add_plot_option,
    check_step,
    cli_words,
    plot_path,
    print_json,
    save_plot,
)
from .design_options import add_design_argument, design_from_args

if TYPE_CHECKING:  # the CLI starts fast: heavy modules load when a command runs
    from ..sim.simulate import Scenario

EXAMPLE = """examples:
  seapass simulate examples/ours.toml --json     # the file's tune_mass, step and horizon
  seapass simulate --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 --set k1=1000 \\
      --set b1=100 --set kd=2000 --set bd=60 --load-mass 10 --step 0.5 --json
  seapass simulate --D1 k1 --CL kd --set m=1 --set b=10 --set k1=1000 --set kd=500 \\
      --load-mass 10 --load-displaced 0.02 --horizon 5 --plot lp.png
  seapass simulate --D1 k1 --CA "kd + ki/s" --set m=1 --set b=10 --set k1=1000 \\
      --set kd=300 --set ki=100 --load-mass 1 --trajectory ref.csv --interp linear

A loop latency (--delay-time, [control] delay_time, or exp(-NAME*s) on the
controllers) delays the controller output: the loop is simulated by the method of
steps (a step of at most --dt that divides the delay) and passivity is certified at it.
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
    add_design_argument(p)
    add_model_options(p)
    p.add_argument(
        "--load-mass",
        type=float,
        help="load mass m_L [kg], > 0 (default: the design file's tune_mass; needed without one)",
    )
    g = p.add_mutually_exclusive_group()
    g.add_argument(
        "--step",
        type=float,
        metavar="M",
        help="reference step size [m] (default: the design file's, else the paper's 0.5)",
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
        "--horizon",
        type=float,
        help="simulated time [s] (default: the design file's, else the paper's experiment, 10)",
    )
    p.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    p.add_argument(
        "--tolerance", type=float, default=0.02, help="settling band (fraction of the step)"
    )
    add_json_option(p, "the metrics")
    add_plot_option(p, "the response")
    add_force_option(p)
    p.set_defaults(func=run, allow_delay=True)


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
    from ..sim.metrics import overshoot_text
    from ..sim.summary import simulation_summary

    figure = plot_path(args.plot, force=args.force)
    check_step(args.step)
    resolved = design_from_args(args)
    if resolved.load_mass is None:
        raise ParameterError("give the load mass with --load-mass KG (or a design file)")
    if args.step is None and resolved.step is not None:
        args.step = resolved.step
    if resolved.sea.discrete is not None:  # a controller in z: the sampled loop, as it runs
        return _run_sampled(args, resolved, figure)
    summary = simulation_summary(
        resolved.sea,
        load_mass=resolved.load_mass,
        scenario=scenario_from_args(args),
        horizon=resolved.horizon,
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
        if summary.delay_time:
            print(
                f"loop latency: {summary.delay_time:g} s (the controller output is applied "
                f"that late; method of steps at {summary.dt:.6g} s)"
            )
        if error is not None:
            print(f"passivity: {error}")
        print(f"settling time: {'-' if ts is None else f'{ts:.6g} s'}")
        print(f"final error: {met.final_error:.3e} m")
        if met.overshoot is not None:  # --json holds the fraction of the step
            print(f"overshoot: {overshoot_text(met.overshoot)} of the step")
        print(f"peak actuator force: {met.peak_force:.6g} N, energy: {met.energy:.6g} J")
    return 0


def _run_sampled(args: argparse.Namespace, resolved: Any, figure: Any) -> int:
    """``simulate`` of a controller given in z: the sampled loop at the controller's rate."""
    from ..sampled.response import sampled_response
    from ..sim.metrics import overshoot_text

    r = sampled_response(
        resolved.sea,
        loop=resolved.loop,
        load_mass=resolved.load_mass,
        scenario=scenario_from_args(args),
        horizon=resolved.horizon,
    )
    if figure is not None:
        save_plot(r.plot, figure, force=args.force, flag="--plot")
    if args.json:
        print_json(r.to_dict())
        return 0
    d = r.to_dict()
    print(
        f"sampled loop at {1 / d['period']:g} Hz (delay {d['delay']}): "
        f"{'stable' if r.stable else 'unstable'} (spectral radius {d['spectral_radius']:.6g})"
    )
    print(f"final x_L: {d['final_x_L']:.6g} m (target {d['target']:g} m), "
          f"error {d['final_error']:.3e} m")  # fmt: skip
    met = d["metrics"]
    ts = met["settling_time"]
    print(f"status: {met['status']}; settling time: {'-' if ts is None else f'{ts:.6g} s'} "
          "(on the exact motion between the samples)")  # fmt: skip
    if met["overshoot"] is not None:
        print(f"overshoot: {overshoot_text(met['overshoot'])} of the step")
    print(f"peak actuator force: {d['peak_force']:.6g} N over {d['samples']} samples, "
          f"energy: {met['energy']:.6g} J")  # fmt: skip
    return 0
