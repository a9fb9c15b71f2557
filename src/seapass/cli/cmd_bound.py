"""``seapass bound``: exact passive range of one parameter."""

from __future__ import annotations

import argparse

from ..analysis.region import passive_intervals
from ..errors import ParameterError
from ..model.expr import parse_value
from .common import add_model_options, model_from_args, print_json

EXAMPLE = """example:
  seapass bound kd --D1 "k1 + b1*s" --CL kd --set m=1 --set b=10 --set k1=1000 \\
      --set b1=20 --range 0:1e5 --json
"""


def parse_range(text: str) -> tuple[float, float]:
    parts = text.split(":")
    if len(parts) != 2:
        raise ParameterError(f"--range {text!r}: expected LO:HI, e.g. --range 0:1e5")
    lo, hi = parse_value(parts[0], "range start"), parse_value(parts[1], "range end")
    if lo > hi:
        raise ParameterError(f"--range {text!r}: LO must not exceed HI")
    return lo, hi


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "bound",
        help="exact set of values of one parameter for which the design is passive",
        description="Exact passive intervals of PARAM within --range, all other parameters fixed.",
        epilog=EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("param", help="the free parameter, e.g. kd")
    add_model_options(p)
    p.add_argument("--range", default="0:1e5", help="search range LO:HI (default 0:1e5)")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    lo, hi = parse_range(args.range)
    sea = model_from_args(args, extra_free=(args.param,))
    if sea.values.get(args.param) is not None:
        raise ParameterError(f"{args.param} is the free parameter: do not also --set it")
    result = passive_intervals(sea, args.param, lo, hi)
    if args.json:
        print_json(result.to_dict())
    else:
        if not result.intervals:
            print(f"not passive for any {args.param} in [{lo:g}, {hi:g}]")
        for a, b in result.intervals:
            print(f"passive for {a:.10g} <= {args.param} <= {b:.10g}")
    return 0
