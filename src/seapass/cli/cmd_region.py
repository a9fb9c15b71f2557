"""``seapass region``: exact 2-D passive region over two parameters, with a figure."""

from __future__ import annotations

import argparse

from ..errors import ParameterError
from ..files.limits import MAX_REGION_COLUMNS
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
  seapass region kd b1 --D1 "k1 + b1*s" --CL kd --set m=1 --set b=10 --set k1=1000 \\
      --x-range 0:1200 --y-range 0:100 --plot lp_region.png
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "region",
        help="exact passive region over two parameters (a 2-D map with a figure)",
        description="For each of --nx values of X, the exact passive set of Y (boundary "
        "exact along Y). X and Y are free: do not give them with --set.",
        epilog=EXAMPLE,
    )
    p.add_argument("x", metavar="X", help="parameter on the horizontal axis")
    p.add_argument(
        "y", metavar="Y", help="parameter on the vertical axis (boundary computed exactly)"
    )
    add_model_options(p)
    p.add_argument("--x-range", required=True, metavar="LO:HI", help="range of X")
    p.add_argument("--y-range", required=True, metavar="LO:HI", help="range of Y")
    p.add_argument(
        "--nx", type=int, default=41, help=f"number of X values (2 to {MAX_REGION_COLUMNS})"
    )
    add_plot_option(p, "the map")
    add_force_option(p)
    p.add_argument("--out", help=argparse.SUPPRESS)  # before 0.3: the figure; now --plot
    add_json_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..analysis.region import passive_map
    from ..exact.rounding import exact_text, interval_text

    if args.x == args.y:
        raise ParameterError("X and Y must be different parameters")
    if not 2 <= args.nx <= MAX_REGION_COLUMNS:
        raise ParameterError(f"--nx {args.nx}: use between 2 and {MAX_REGION_COLUMNS} columns")
    x_lo, x_hi = parse_range(args.x_range, "--x-range")
    y_range = parse_range(args.y_range, "--y-range")
    figure = plot_path(deprecated_alias(args, "out", "plot"), force=args.force)
    sea = model_from_args(
        args, extra_free={args.x: f"region X {args.x}", args.y: f"region Y {args.y}"}
    )
    warn_unrealizable(sea)
    pmap = passive_map(sea, args.x, np.linspace(x_lo, x_hi, args.nx), args.y, y_range)
    if figure is not None:
        from ..analysis.boundary import passive_region
        from ..plot.region import plot_passive_region

        # the figure: the exact boundary curves between the columns, not a raster edge
        region = passive_region(sea, args.x, (x_lo, x_hi), args.y, y_range)
        save_plot(
            lambda: plot_passive_region(region, title="exact passive region"),
            figure,
            force=args.force,
            flag="--plot",
        )
    if args.json:
        print_json(pmap.to_dict())
    else:
        for xv, ivs in zip(pmap.x, pmap.intervals, strict=True):
            shown = ", ".join(interval_text(a, b) for a, b in ivs)  # rounded inward
            print(
                f"{args.x} = {exact_text(float(xv))}: "
                + (f"passive {args.y} in {shown}" if shown else f"no passive {args.y}")
            )
    return 0
