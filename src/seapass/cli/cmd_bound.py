"""``seapass bound``: exact passive range of one parameter."""

from __future__ import annotations

import argparse

from .common import add_json_option, add_model_options, print_json, warn_unrealizable
from .design_options import (
    add_design_argument,
    add_range_options,
    design_from_args,
    ranges_from_args,
    unit_suffix,
    units_json,
)
from .uncertain_options import add_uncertain_options, run_robust_bound, wants_box

EXAMPLE = """examples:
  seapass bound kd examples/lp.toml --json
  seapass bound kd --D1 "k1 + b1*s" --CL kd --set m=1 --set b=10 --set k1=1000 \\
      --set b1=20 --range kd=0:1e5 --json
  seapass bound kd --D1 k1 --CL kd --set m=1 --set b=10 --range kd=0:2000 \
      --uncertain k1=800:1200 --json     # passive for every plant in the box

PARAM is the free parameter: give every other parameter with --set (or in the
design file), and not PARAM itself with --set (a value is never ignored; the
file's value of PARAM only sets its default range).
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "bound",
        help="exact set of values of one parameter for which the design is passive",
        description="Exact passive intervals of PARAM within its range, all other parameters "
        "fixed by the design file and --set (PARAM itself must not be given with --set).",
        epilog=EXAMPLE,
    )
    p.add_argument("param", metavar="PARAM", help="the free parameter, e.g. kd")
    add_design_argument(p)
    add_model_options(p)
    add_range_options(p)
    add_uncertain_options(p)
    add_json_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..analysis.region import passive_intervals
    from ..exact.rounding import inward_text

    if wants_box(args) and (code := run_robust_bound(args)) is not None:
        return code  # a box: --uncertain, --robust, the file's [uncertainty]
    resolved = design_from_args(args, {args.param: f"bound {args.param}"})
    lo, hi = resolved.range_of(
        args.param, ranges_from_args(args, [args.param], strict=False)[args.param]
    )
    sea = resolved.sea
    warn_unrealizable(sea)
    result = passive_intervals(sea, args.param, lo, hi)
    unit = unit_suffix(args, resolved, args.param)
    if args.json:
        print_json({**result.to_dict(), **units_json(args, resolved)})
    else:
        if not result.intervals:
            print(f"not passive for any {args.param} in [{lo:g}, {hi:g}]{unit}")
        for a, b in result.intervals:  # rounded inward: the printed ends are passive
            a_text, b_text = inward_text(a, b, 10)
            print(f"passive for {a_text} <= {args.param} <= {b_text}{unit}")
    return 0
