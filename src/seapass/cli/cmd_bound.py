"""``seapass bound``: exact passive range of one parameter."""

from __future__ import annotations

import argparse

from .common import add_json_option, add_model_options, print_json, warn_unrealizable
from .design_options import (
    add_design_argument,
    add_range_options,
    design_file_from_args,
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
  seapass bound kd --D1 k1 --CL kd --set m=1 --set b=10 --range kd=0:2000 \\
      --uncertain k1=800:1200 --json     # passive for every plant in the box

  seapass bound kd --D1 "k1 + b1*s" --CA "(kd + bd*s)*exp(-tau*s)" --set m=1 \\
      --set b=10 --set k1=1000 --set b1=20 --set bd=25 --set tau=0.01 --range kd=0:1e4

A design with a delay exp(-NAME*s) (NAME given with --set, in seconds) is decided at
that delay: the intervals are certified whole (every gain in them), their printed ends
are passive, 'edges' enclose the true ends, and a gap that cannot be certified is
reported 'undecided' (never widened).  --points sets the gains decided first.  With a
box too (--uncertain, or a design file's [uncertainty] and [control] delay_time) the
robust set at the delay is certified: an inner set and an outer set ('no value outside');
--budget counts the cells of one gain segment's certificate (default 8000 at a delay);
--rtol sets where the inner set stops bisecting (default 1e-3):

  seapass bound kd --D1 k1 --CA "kd*exp(-tau*s)" --set m=1 --set k1=1000 \\
      --set tau=0.002 --range kd=0:8000 --uncertain b=9:11 --rtol 1e-2 --json

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
    p.add_argument("--points", type=int, default=None,
                   help="with a delay only: gains decided first, evenly spaced (default 17)")  # fmt: skip
    p.add_argument("--rtol", type=float, default=None,
                   help="with a box only: relative width where the certified robust inner set "
                   "stops bisecting (default 1e-3; analyze's robust stage uses 1e-2 at a "
                   "latency)")  # fmt: skip
    add_json_option(p)
    p.set_defaults(func=run, allow_delay=True)


def run(args: argparse.Namespace) -> int:
    from ..analysis.region import passive_intervals
    from ..exact.rounding import inward_text

    file = design_file_from_args(args)  # read once, passed along
    if wants_box(args, file) and (code := run_robust_bound(args, file)) is not None:
        return code  # a box: --uncertain, --robust, the file's [uncertainty]
    if args.rtol is not None:
        from ..errors import ParameterError

        raise ParameterError(
            "--rtol applies with a box only (--uncertain, --robust or the design file's "
            "[uncertainty]); the bound without one is exact"
        )
    resolved = design_from_args(args, {args.param: f"bound {args.param}"}, file=file)
    lo, hi = resolved.range_of(
        args.param, ranges_from_args(args, [args.param], strict=False)[args.param]
    )
    sea = resolved.sea
    from ..delay.structure import has_model_delay

    if has_model_delay(sea):  # certified at the delay's value: seapass.delay.gainbound
        from ..delay.gainbound import passive_gain_intervals

        res = passive_gain_intervals(sea, args.param, lo, hi, points=args.points or 17)
        if args.json:
            print_json({**res.to_dict(), **units_json(args, resolved)})
        else:
            print("\n".join(res.lines()))
        return 0
    if args.points is not None:
        from ..errors import ParameterError

        raise ParameterError("--points applies to a design with a delay exp(-NAME*s) only")
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
