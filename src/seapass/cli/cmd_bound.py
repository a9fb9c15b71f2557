"""``seapass bound``: exact passive range of one parameter."""

from __future__ import annotations

import argparse

from .common import (
    add_json_option,
    add_model_options,
    model_from_args,
    parse_range,
    print_json,
    warn_unrealizable,
)

EXAMPLE = """example:
  seapass bound kd --D1 "k1 + b1*s" --CL kd --set m=1 --set b=10 --set k1=1000 \\
      --set b1=20 --range 0:1e5 --json

PARAM is the free parameter: give every other parameter with --set, and not
PARAM itself (giving it both ways is an error, so a value is never ignored).
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "bound",
        help="exact set of values of one parameter for which the design is passive",
        description="Exact passive intervals of PARAM within --range, all other parameters "
        "fixed with --set (PARAM itself must not be given with --set).",
        epilog=EXAMPLE,
    )
    p.add_argument("param", metavar="PARAM", help="the free parameter, e.g. kd")
    add_model_options(p)
    p.add_argument("--range", default="0:1e5", metavar="LO:HI", help="search range of PARAM")
    add_json_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..analysis.region import passive_intervals
    from ..exact.rounding import inward_text

    lo, hi = parse_range(args.range)
    sea = model_from_args(args, extra_free={args.param: f"bound {args.param}"})
    warn_unrealizable(sea)
    result = passive_intervals(sea, args.param, lo, hi)
    if args.json:
        print_json(result.to_dict())
    else:
        if not result.intervals:
            print(f"not passive for any {args.param} in [{lo:g}, {hi:g}]")
        for a, b in result.intervals:  # rounded inward: the printed ends are passive
            a_text, b_text = inward_text(a, b, 10)
            print(f"passive for {a_text} <= {args.param} <= {b_text}")
    return 0
