"""``seapass tune``: best-case passive gains of LP, APD or Ours (paper Sec. V)."""

from __future__ import annotations

import argparse
from dataclasses import replace

from ..errors import ParameterError
from ..model.expr import parse_value
from ..paper.simstudy import QUICK_OPTIONS
from ..sim.tuning import TuningOptions, tune
from .common import (
    add_json_option,
    check_names,
    check_step,
    parse_named,
    print_json,
    values_from_args,
)

EXAMPLE = """examples:
  seapass tune --design ours --load-mass 10 --json
  seapass tune --design LP --quick
  seapass tune --design APD --bound kd=0:2000 --bound bd=0:150 --force-limit 500

Designs: LP (D1 = k1, C_L = kd), APD (D1 = k1, C_A = kd + bd*s),
ours (D1 = k1 + b1*s, C_A = kd + bd*s). The objective is the 2 % settling time of
the load after a reference step; every candidate that could become the best is
checked with the exact passivity test, and the peak actuator force is limited.
"""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "tune",
        help="tune LP / APD / ours for the fastest passive step response",
        description="Differential evolution (fixed seed, reproducible) on the exact "
        "simulated settling time, under the exact passivity constraint and an actuator "
        "force limit. A progress bar is shown on stderr when it is a terminal.",
        epilog=EXAMPLE,
    )
    p.add_argument("--design", required=True, help="LP, APD or ours (case-insensitive)")
    p.add_argument("--load-mass", type=float, default=10.0, help="load mass m_L [kg]")
    p.add_argument("--step", type=float, metavar="M", help="reference step [m] (the default: 0.5)")
    p.add_argument("--horizon", type=float, default=10.0, help="simulated time [s]")
    p.add_argument("--force-limit", type=float, default=1000.0, help="peak |f_A| [N]")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="plant value m, b or k1 (defaults 1, 10, 1000)")  # fmt: skip
    p.add_argument(
        "--bound",
        action="append",
        default=[],
        metavar="GAIN=LO:HI",
        help="search range of a gain, e.g. --bound kd=0:2000",
    )
    p.add_argument("--maxiter", type=int, default=None, help="generations (default 60)")
    p.add_argument("--popsize", type=int, default=None, help="population per gain (default 12)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--quick", action="store_true", help="small budget (for previews and tests)")
    p.add_argument("--no-progress", action="store_true", help="never show a progress bar")
    add_json_option(p)
    p.set_defaults(func=run)


def _bounds(items: list[str]) -> dict[str, tuple[float, float]]:
    out: dict[str, tuple[float, float]] = {}
    for name, (lo, hi) in parse_named(items, "--bound", 2, "GAIN=LO:HI, e.g. kd=0:2000"):
        a, b = parse_value(lo, f"--bound {name} LO"), parse_value(hi, f"--bound {name} HI")
        if not 0 <= a < b:
            raise ParameterError(f"--bound {name}={lo}:{hi}: need 0 <= LO < HI")
        out[name] = (a, b)
    return out


def options_from_args(args: argparse.Namespace) -> TuningOptions:
    plant = values_from_args(args)
    check_names(plant, ("m", "b", "k1"), "--set", "the plant (tune takes m, b and k1)")
    base = TuningOptions(
        load_mass=args.load_mass,
        step=0.5 if args.step is None else args.step,
        horizon=args.horizon,
        force_limit=args.force_limit,
        seed=args.seed,
        bounds=_bounds(args.bound),
        m=plant.get("m", 1.0),
        b=plant.get("b", 10.0),
        k1=plant.get("k1", 1000.0),
    )
    if args.quick:
        base = replace(
            base,
            maxiter=QUICK_OPTIONS.maxiter,
            popsize=QUICK_OPTIONS.popsize,
            dt_search=QUICK_OPTIONS.dt_search,
        )
    if args.maxiter is not None:
        base = replace(base, maxiter=args.maxiter)
    if args.popsize is not None:
        base = replace(base, popsize=args.popsize)
    return base


def run(args: argparse.Namespace) -> int:
    if not args.load_mass > 0:
        raise ParameterError(f"--load-mass must be positive, got {args.load_mass:g}")
    check_step(args.step)
    opts = options_from_args(args)
    result = tune(args.design, options=opts, progress=False if args.no_progress else None)
    if args.json:
        print_json(result.to_dict())
    else:
        m = result.metrics
        gains = ", ".join(f"{k} = {v:.6g}" for k, v in result.gains.items())
        ts = "-" if m.settling_time is None else f"{m.settling_time:.4f} s"
        print(f"{result.design}: {gains}")
        print(f"passive: {result.passive}; settling time {ts} ({m.status}); "
              f"final error {m.final_error:.3e} m; peak force {m.peak_force:.4g} N")  # fmt: skip
    return 0
