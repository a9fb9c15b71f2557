"""``seapass response``: frequency response of the rendered stiffness ``|F_L/X_L(jω)|``."""

from __future__ import annotations

import argparse

from ..files.limits import MAX_FREQUENCY_POINTS
from .common import (
    add_force_option,
    add_json_option,
    add_model_options,
    add_plot_option,
    deprecated_alias,
    model_from_args,
    parse_range,
    plot_path,
    print_json,
    save_plot,
    warn_unrealizable,
)

EXAMPLE = """example:
  seapass response --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 --set k1=1005 \\
      --set b1=20 --set bd=25 --set kd=1000 --plot stiffness.png
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "response",
        help="rendered stiffness |F_L/X_L(jw)| of a design, with a plot",
        description="Evaluate the first-principles F_L/X_L on the imaginary axis.",
        epilog=EXAMPLE,
    )
    add_model_options(p)
    p.add_argument(
        "--omega", default="0.1:1e4", metavar="LO:HI", help="frequency range in rad/s (log-spaced)"
    )
    p.add_argument(
        "--points",
        type=int,
        default=400,
        help=f"number of frequencies (2 to {MAX_FREQUENCY_POINTS})",
    )
    add_plot_option(p, "the magnitude plot")
    add_force_option(p)
    p.add_argument("--out", help=argparse.SUPPRESS)  # before 0.3: the figure; now --plot
    add_json_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..analysis.freqresp import log_frequencies, stiffness_response

    omega = log_frequencies(*parse_range(args.omega, "--omega"), args.points)
    figure = plot_path(deprecated_alias(args, "out", "plot"), force=args.force)
    sea = model_from_args(args)
    warn_unrealizable(sea)
    resp = stiffness_response(sea, omega)
    if figure is not None:
        from ..plot.response import plot_stiffness_response

        k1 = sea.values.get("k1")
        save_plot(
            lambda: plot_stiffness_response(resp, title="rendered stiffness", reference=k1),
            figure,
            force=args.force,
            flag="--plot",
        )
    if args.json:
        print_json(resp.to_dict())
    else:
        print(f"static stiffness F_L/X_L(0) = {resp.static:.6g} N/m")
        print(f"high-frequency stiffness    = {resp.high_frequency:.6g} N/m")
        i = int(np.argmax(resp.magnitude))
        print(f"peak |F_L/X_L| = {resp.magnitude[i]:.6g} N/m at w = {resp.omega[i]:.6g} rad/s")
    return 0
