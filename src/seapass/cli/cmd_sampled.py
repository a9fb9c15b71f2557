"""``seapass sampled``: passivity of the design under sampled-data (digital) control."""

from __future__ import annotations

import argparse
import math
from typing import Any

from ..errors import ParameterError
from ..files.limits import MAX_RTOL, MIN_RTOL, check_rtol
from .common import (
    add_json_option,
    add_model_options,
    add_out_dir_option,
    check_out_dir,
    json_text,
    model_from_args,
    parse_range,
    print_json,
    save_plot,
    warn_unrealizable,
    write_text,
)
from .loop_options import add_loop_options, loop_from_args

EXAMPLE = """examples:
  seapass sampled check --period 0.002 --D1 "k1 + b1*s" --CA "kd + bd*s" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --set bd=25 --set kd=2000 --json
  seapass sampled bound kd --period 0.002 --D1 "k1 + b1*s" --CL "kd" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --range 0:5000 --json
  seapass sampled bound kd --period 0.002 --D1 "k1 + b1*s" --CA "kd + bd*s" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --set bd=25 --range 0:1e5 \\
      --delay 1 --velocity-filter 50 --out results/
  seapass sampled region kd bd --period 0.002 --D1 "k1 + b1*s" --CA "kd + bd*s" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --range 0:1e5 --range2 0:100 \\
      --delay 1 --velocity-filter 50 --out results/
"""

_FORMATTER = argparse.RawDescriptionHelpFormatter  # the CLI shows every default


def _loop_options(
    p: argparse.ArgumentParser, *, delay: int = 0, velocity_filter: float | None = None
) -> None:
    g = add_loop_options(p, period=0.002, delay=delay, velocity_filter=velocity_filter)
    g.add_argument(
        "--max-precision",
        type=int,
        default=4096,
        metavar="BITS",
        help="cap of the ball arithmetic's working precision; beyond it the answer is 'undecided'",
    )
    add_json_option(p)
    add_out_dir_option(p, "figures, CSV and JSON")


def _budget_options(p: argparse.ArgumentParser, what: str) -> None:
    p.add_argument(
        "--max-boxes",
        type=int,
        default=None,
        metavar="N",
        help=f"work budget of {what} in boxes (counted, never timed; default 20000): what "
        "is not settled then is reported undecided, never passive",
    )
    p.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress on stderr (else a live bar on a terminal, one line per task otherwise)",
    )


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "sampled",
        help="passivity under sampled-data control (ZOH, delay, velocity filter)",
        description="Certified passivity of the load port when the controller runs at a fixed "
        "period (Colgate-Schenkel alias condition generalised to the SEA; the sign of the "
        "power polynomial in cos(wT) is decided with certified ball arithmetic, w -> 0 "
        "included).",
        epilog=EXAMPLE,
        formatter_class=_FORMATTER,
    )
    ss = p.add_subparsers(dest="sampled_command", metavar="{check,bound,region}")
    ss.required = True
    c = ss.add_parser(
        "check",
        help="decide passivity of one fully specified design (exit 0 passive, 1 not, 2 bad input)",
        epilog=EXAMPLE,
        formatter_class=_FORMATTER,
    )
    add_model_options(c)
    _loop_options(c)
    c.set_defaults(func=run_check)
    b = ss.add_parser(
        "bound",
        help="certified passive set of one controller parameter (e.g. the largest passive kd)",
        epilog=EXAMPLE,
        formatter_class=_FORMATTER,
    )
    b.add_argument("param", help="free controller parameter to bound, e.g. kd")
    b.add_argument(
        "--range", required=True, metavar="LO:HI", help="range to partition, e.g. 0:5000"
    )
    b.add_argument(
        "--rtol",
        type=float,
        default=1e-9,
        help=f"relative width of every edge enclosure, in [{MIN_RTOL:g}, {MAX_RTOL:g}]",
    )
    _budget_options(b, "the branch and bound")
    add_model_options(b)
    _loop_options(b)
    b.set_defaults(func=run_bound)
    r = ss.add_parser(
        "region",
        help="Z-width map: passive region of two controller parameters, three loop setups",
        description="For each of --rows values of P2 the passive set of P1 is certified (as "
        "by 'sampled bound'), for the ideal zero-order hold, DELAY samples of delay, and the "
        "delay plus the velocity filter (Colgate & Brown's Z-width).",
        epilog=EXAMPLE,
        formatter_class=_FORMATTER,
    )
    r.add_argument("p1", help="parameter bounded on each row, e.g. kd (stiffness)")
    r.add_argument("p2", help="parameter of the rows, e.g. bd (damping)")
    r.add_argument("--range", required=True, metavar="LO:HI", help="range of P1, e.g. 0:1e5")
    r.add_argument("--range2", required=True, metavar="LO:HI", help="range of P2, e.g. 0:100")
    r.add_argument("--rows", type=int, default=25, help="number of P2 rows, 2..200")
    r.add_argument("--log", action="store_true", help="space the P2 rows logarithmically")
    r.add_argument(
        "--rtol",
        type=float,
        default=1e-6,
        help=f"relative width of edge enclosures, in [{MIN_RTOL:g}, {MAX_RTOL:g}]",
    )
    _budget_options(r, "each row's branch and bound")
    add_model_options(r)
    _loop_options(r, delay=1, velocity_filter=50.0)
    r.set_defaults(func=run_region)


def _max_boxes(args: argparse.Namespace) -> dict[str, Any]:
    return {} if args.max_boxes is None else {"max_boxes": args.max_boxes}


def _range(text: str, flag: str = "--range") -> tuple[float, float]:
    return parse_range(text, flag, strict=True)


def run_check(args: argparse.Namespace) -> int:
    from ..sampled.passivity import (
        SampledReason,
        power_curve_csv,
        sampled_passivity,
        sampled_power_curve,
    )

    loop = loop_from_args(args)
    d = check_out_dir(args.out)
    sea = model_from_args(args)
    warn_unrealizable(sea)
    res = sampled_passivity(sea, loop=loop, max_precision=args.max_precision)
    if d is not None:
        from ..plot.sampled import plot_power_curve

        write_text(d / "sampled_check.json", json_text(res.to_dict()))
        curved = (
            SampledReason.NONE,
            SampledReason.NEGATIVE_POWER,
            SampledReason.LOW_FREQUENCY,
            SampledReason.UNDECIDED,
        )
        if res.reason in curved:
            w, n = sampled_power_curve(sea, loop=loop)
            write_text(d / "sampled_power.csv", power_curve_csv(w, n))
            save_plot(lambda: plot_power_curve(w, n, period=loop.period), d / "sampled_power.png")
    if args.json:
        print_json(res.to_dict())
    else:
        print(f"{res.outcome.label} at T = {loop.period:g} s (delay {loop.delay}): {res.detail}")
        if res.omega is not None:
            print(f"witness: w = {res.omega:.6g} rad/s")
    return 0 if res.passive else 1


def run_bound(args: argparse.Namespace) -> int:
    from ..sampled.bound import sampled_passive_bound
    from .progress import choose_progress

    lo, hi = _range(args.range)
    loop = loop_from_args(args)
    check_rtol(args.rtol)
    d = check_out_dir(args.out)
    sea = model_from_args(args, extra_free={args.param: f"sampled bound {args.param}"})
    warn_unrealizable(sea)
    with choose_progress(not args.no_progress) as progress:
        res = sampled_passive_bound(
            sea, args.param, loop=loop, lo=lo, hi=hi, rtol=args.rtol,
            max_precision=args.max_precision, progress=progress, **_max_boxes(args),
        )  # fmt: skip
    out = res.to_dict()
    if d is not None:
        from ..plot.sampled import plot_bound

        write_text(d / f"sampled_bound_{args.param}.csv", res.to_csv())
        write_text(d / f"sampled_bound_{args.param}.json", json_text(out))
        save_plot(lambda: plot_bound(res), d / f"sampled_bound_{args.param}.png")
    if args.json:
        print_json(out)
        return 0
    ivs = ", ".join(f"[{a:.10g}, {b:.10g}]" for a, b in res.intervals) or "none"
    print(f"passive {args.param} at T = {loop.period:g} s (delay {loop.delay}): {ivs}")
    for e in res.edges:
        print(f"  edge in [{e.lo:.12g}, {e.hi:.12g}] ({e.kind.replace('_', ' ')})")
    if res.budget_exhausted:
        print(
            f"  stopped at the box budget: {len(res.undecided)} undecided piece(s) "
            "(never passive; raise --max-boxes)"
        )
    elif res.undecided:
        print(f"  undecided slivers: {len(res.undecided)} (each narrower than rtol)")
    if res.low_frequency is not None:
        print(f"  low-frequency condition: {res.low_frequency}")
    return 0


def run_region(args: argparse.Namespace) -> int:
    from ..sampled.region import sampled_region
    from .progress import choose_progress

    lo1, hi1 = _range(args.range)
    lo2, hi2 = _range(args.range2, "--range2")
    loop = loop_from_args(args)
    check_rtol(args.rtol)
    out = check_out_dir(args.out)
    if args.p1 == args.p2:
        raise ParameterError(f"sampled region: give two different parameters, got {args.p1} twice")
    sea = model_from_args(
        args,
        extra_free={args.p1: f"sampled region {args.p1}", args.p2: f"sampled region {args.p2}"},
    )
    warn_unrealizable(sea)
    with choose_progress(not args.no_progress) as progress:
        zmap = sampled_region(
            sea, args.p1, args.p2, loop=loop, p1_range=(lo1, hi1), p2_range=(lo2, hi2),
            n=args.rows, rtol=args.rtol, log_p2=args.log, max_precision=args.max_precision,
            progress=progress, **_max_boxes(args),
        )  # fmt: skip
    if out is not None:
        from ..plot.sampled import plot_zwidth

        stem = f"sampled_region_{args.p1}_{args.p2}"
        write_text(out / f"{stem}.csv", zmap.to_csv())
        write_text(out / f"{stem}.json", json_text(zmap.to_dict()))
        save_plot(lambda: plot_zwidth(zmap), out / f"{stem}.png")
    if args.json:
        print_json(zmap.to_dict())
        return 0
    print(f"largest passive {args.p1} per {args.p2} at T = {loop.period:g} s (certified per row):")
    header = f"{args.p2:>12}  " + "  ".join(f"{s.label:>28}" for s in zmap.setups)
    print(header)
    bounds = [zmap.upper_boundary(s.label) for s in zmap.setups]
    for i, v in enumerate(zmap.p2_values):
        cells = "  ".join(f"{'none' if math.isnan(b[i]) else f'{b[i]:.6g}':>28}" for b in bounds)
        print(f"{v:>12.6g}  {cells}")
    return 0
