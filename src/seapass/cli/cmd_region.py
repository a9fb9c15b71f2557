"""``seapass region``: exact 2-D passive region over two parameters, with a figure."""

from __future__ import annotations

import argparse

import numpy as np

from ..analysis.region import passive_map
from ..errors import ParameterError
from .cmd_bound import parse_range
from .common import add_model_options, model_from_args, print_json, save_plot

EXAMPLE = """example:
  seapass region kd b1 --D1 "k1 + b1*s" --CL kd --set m=1 --set b=10 --set k1=1000 \\
      --x-range 0:1200 --y-range 0:100 --out lp_region.png
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "region",
        help="exact passive region over two parameters (a 2-D map with a figure)",
        description="For each of --nx values of X, the exact passive set of Y (boundary exact along Y).",
        epilog=EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("x", help="parameter on the horizontal axis")
    p.add_argument("y", help="parameter on the vertical axis (boundary computed exactly)")
    add_model_options(p)
    p.add_argument("--x-range", required=True, help="LO:HI")
    p.add_argument("--y-range", required=True, help="LO:HI")
    p.add_argument("--nx", type=int, default=41, help="number of X values (default 41)")
    p.add_argument("--out", help="write the figure (PNG/PDF by extension)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.x == args.y:
        raise ParameterError("x and y must be different parameters")
    if not 2 <= args.nx <= 2000:
        raise ParameterError(f"--nx {args.nx}: use between 2 and 2000 columns")
    x_lo, x_hi = parse_range(args.x_range)
    y_range = parse_range(args.y_range)
    sea = model_from_args(args, extra_free=(args.x, args.y))
    pmap = passive_map(sea, args.x, np.linspace(x_lo, x_hi, args.nx), args.y, y_range)
    if args.out:
        from ..analysis.boundary import passive_region
        from ..plot.region import plot_passive_region

        # the figure: the exact boundary curves between the columns, not a raster edge
        region = passive_region(sea, args.x, (x_lo, x_hi), args.y, y_range)
        save_plot(lambda: plot_passive_region(region, title="exact passive region"), args.out)
    if args.json:
        print_json(pmap.to_dict())
    elif not args.out:
        for xv, ivs in zip(pmap.x, pmap.intervals, strict=True):
            shown = ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in ivs) or "none"
            print(f"{args.x} = {xv:.6g}: passive {args.y} in {shown}")
    return 0
