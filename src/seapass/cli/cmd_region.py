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
    plot_path,
    print_json,
    save_plot,
    warn_unrealizable,
)
from .design_options import (
    add_design_argument,
    add_range_options,
    design_file_from_args,
    design_from_args,
    points_from_args,
    ranges_from_args,
    unit_suffix,
    units_json,
)
from .uncertain_options import add_uncertain_options, wants_box

POINTS = 41
ROBUST_POINTS = 11  # each robust column costs a one-parameter robust bound

EXAMPLE = """examples:
  seapass region kd bd examples/ours.toml --range kd=0:5000 --points 21
  seapass region kd b1 --D1 "k1 + b1*s" --CL kd --set m=1 --set b=10 --set k1=1000 \\
      --range kd=0:1200 --range b1=0:100 --plot lp_region.png
  seapass region bd kd --D1 "k1 + b1*s" --CL "kd + bd*s" --set m=1 --set b=10 \\
      --set b1=5 --uncertain k1=800:1200 --range bd=0:4 --range kd=0:2000 --points 5 \\
      --plot robust.png                  # robust region (every k1 in the box) over the nominal

A range not given is the design file's [ranges], else [0, max(10*value, 1000)]
around the file's value, else 0:1e5.  A design with a delay exp(-NAME*s) (NAME given
with --set) is decided at that delay: each column's set of Y is certified whole
(printed ends passive), gaps that cannot be certified are 'undecided'; with a box too
(--uncertain), each column is the certified robust set at that delay (inner, and outer
'no value outside').  (--x-range, --y-range and --nx are the old
spellings of --range X=..., --range Y=... and --points).
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "region",
        help="exact passive region over two parameters (a 2-D map with a figure)",
        description="For each of --points values of X, the exact passive set of Y (boundary "
        "exact along Y). X and Y are free: do not give them with --set.",
        epilog=EXAMPLE,
    )
    p.add_argument("x", metavar="X", help="parameter on the horizontal axis")
    p.add_argument(
        "y", metavar="Y", help="parameter on the vertical axis (boundary computed exactly)"
    )
    add_design_argument(p)
    add_model_options(p)
    add_range_options(
        p,
        points=POINTS,
        points_help=f"number of X values, 2 to {MAX_REGION_COLUMNS} ({ROBUST_POINTS} over a box)",
    )
    p.add_argument("--x-range", help=argparse.SUPPRESS)  # before 0.4: --range X=LO:HI
    p.add_argument("--y-range", help=argparse.SUPPRESS)  # before 0.4: --range Y=LO:HI
    p.add_argument("--nx", type=int, help=argparse.SUPPRESS)  # before 0.4: --points
    add_plot_option(p, "the map")
    add_uncertain_options(p)
    add_force_option(p)
    p.add_argument("--out", help=argparse.SUPPRESS)  # before 0.3: the figure; now --plot
    add_json_option(p)
    p.set_defaults(func=run, allow_delay=True)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..analysis.region import passive_map
    from ..exact.rounding import exact_text, interval_text

    if args.x == args.y:
        raise ParameterError("X and Y must be different parameters")
    file = design_file_from_args(args)  # read once, passed along
    boxed = wants_box(args, file)  # --uncertain, --robust or the file's [uncertainty]
    nx = points_from_args(args, "nx", ROBUST_POINTS if boxed else POINTS)
    if not 2 <= nx <= MAX_REGION_COLUMNS:
        raise ParameterError(f"--points {nx}: use between 2 and {MAX_REGION_COLUMNS} columns")
    given = ranges_from_args(
        args,
        [args.x, args.y],
        {args.x: ("--x-range", args.x_range), args.y: ("--y-range", args.y_range)},
        strict=False,
    )
    figure = plot_path(deprecated_alias(args, "out", "plot"), force=args.force)
    labels = {args.x: f"region X {args.x}", args.y: f"region Y {args.y}"}
    resolved = design_from_args(args, labels, file=file)
    x_lo, x_hi = resolved.range_of(args.x, given[args.x])
    y_range = resolved.range_of(args.y, given[args.y])
    if boxed:
        from .uncertain_options import run_robust_region

        units = (resolved.units.get(args.x), resolved.units.get(args.y))
        columns = np.linspace(x_lo, x_hi, nx)
        code = run_robust_region(args, columns, y_range, figure, units, file)
        if code is not None:
            return code
    sea = resolved.sea
    from ..delay.structure import has_model_delay

    if has_model_delay(sea):  # certified per column at the delay: seapass.delay.gainmap
        from ..delay.gainmap import delay_passive_map

        xs = [float(v) for v in np.linspace(x_lo, x_hi, nx)]
        dmap = delay_passive_map(sea, args.x, xs, args.y, y_range)
        if figure is not None:
            save_plot(lambda: dmap.plot(), figure, force=args.force, flag="--plot")
        if args.json:
            print_json({**dmap.to_dict(), **units_json(args, resolved)})
        else:
            for xv, col in zip(dmap.x, dmap.columns, strict=True):
                print(f"{args.x} = {exact_text(xv)}: " + "; ".join(col.lines()))
        return 0
    warn_unrealizable(sea)
    pmap = passive_map(sea, args.x, np.linspace(x_lo, x_hi, nx), args.y, y_range)
    if figure is not None:
        from ..analysis.boundary import passive_region
        from ..plot.region import plot_passive_region

        # the figure: the exact boundary curves between the columns, not a raster edge
        region = passive_region(sea, args.x, (x_lo, x_hi), args.y, y_range)
        units = (resolved.units.get(args.x), resolved.units.get(args.y))
        save_plot(
            lambda: plot_passive_region(region, title="exact passive region", units=units),
            figure,
            force=args.force,
            flag="--plot",
        )
    if args.json:
        print_json({**pmap.to_dict(), **units_json(args, resolved)})
    else:
        ux, uy = unit_suffix(args, resolved, args.x), unit_suffix(args, resolved, args.y)
        for xv, ivs in zip(pmap.x, pmap.intervals, strict=True):
            shown = ", ".join(interval_text(a, b) for a, b in ivs)  # rounded inward
            print(
                f"{args.x} = {exact_text(float(xv))}{ux}: "
                + (f"passive {args.y} in {shown}{uy}" if shown else f"no passive {args.y}")
            )
    return 0
