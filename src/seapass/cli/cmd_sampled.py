"""``seapass sampled``: passivity of the design under sampled-data (digital) control."""

from __future__ import annotations

import argparse
import io
import math
from typing import Any

from ..errors import ParameterError
from ..files.limits import MAX_DELAY_SAMPLES, MAX_SAMPLED_SCAN, MIN_RTOL
from ..model.expr import parse_value
from .common import (
    add_model_options,
    check_out_dir,
    check_period,
    json_text,
    model_from_args,
    print_json,
    save_plot,
    warn_unrealizable,
    write_text,
)

EXAMPLE = """examples:
  seapass sampled bound kd --period 0.002 --D1 "k1 + b1*s" --CL "kd" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --range 0:5000 --json
  seapass sampled bound kd --period 0.002 --D1 "k1 + b1*s" --CA "kd + bd*s" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --set bd=25 --range 0:1e5 \\
      --delay 1 --velocity-filter 50 --out results/
  seapass sampled check --period 0.002 --D1 "k1 + b1*s" --CA "kd + bd*s" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --set bd=25 --set kd=2000 --json
"""


def _loop_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("sampled loop")
    g.add_argument("--period", type=float, default=0.002, help="control period T in s")
    g.add_argument("--delay", type=int, default=0, help="computational delay in samples")
    g.add_argument(
        "--velocity-filter",
        type=float,
        default=None,
        metavar="HZ",
        help="first-order low-pass on the finite-difference velocity, cutoff in Hz",
    )
    g.add_argument(
        "--method",
        choices=("tustin", "zoh", "backward"),
        default="tustin",
        help="discretization of strictly proper controller parts (derivatives always use "
        "backward differences)",
    )
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.add_argument("--out", metavar="DIR", help="write a figure and a CSV into DIR (atomically)")


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "sampled",
        help="passivity under sampled-data control (ZOH, delay, velocity filter)",
        description="Exact passivity of the load port when the controller runs at a fixed "
        "period (Colgate-Schenkel alias condition generalised to the SEA; decided by Sturm "
        "sequences on a polynomial in cos(wT)).",
        epilog=EXAMPLE,
    )
    ss = p.add_subparsers(dest="sampled_command", metavar="{bound,check}")
    ss.required = True
    b = ss.add_parser(
        "bound",
        help="passive values of one parameter (e.g. the largest passive kd)",
        epilog=EXAMPLE,
    )
    b.add_argument("param", help="free parameter to bound, e.g. kd")
    b.add_argument("--range", required=True, metavar="LO:HI", help="search range, e.g. 0:5000")
    b.add_argument("--samples", type=int, default=17, help="scan points before bisection")
    b.add_argument("--rtol", type=float, default=1e-6, help="edge tolerance relative to range")
    add_model_options(b)
    _loop_options(b)
    b.set_defaults(func=run_bound)
    c = ss.add_parser(
        "check",
        help="decide passivity of one fully specified design (exit 0 passive, 1 not, 2 bad input)",
        epilog=EXAMPLE,
    )
    add_model_options(c)
    _loop_options(c)
    c.set_defaults(func=run_check)


def _range(text: str) -> tuple[float, float]:
    parts = text.split(":")
    if len(parts) != 2:
        raise ParameterError(f"--range must look like LO:HI (e.g. 0:5000), got {text!r}")
    lo, hi = (parse_value(x, "--range") for x in parts)
    if not lo < hi:
        raise ParameterError(f"--range needs LO < HI, got {text!r}")
    return lo, hi


def _loop_kw(args: argparse.Namespace) -> dict[str, Any]:
    if not (math.isfinite(args.period) and args.period > 0):
        raise ParameterError(f"--period must be a positive number of seconds, got {args.period}")
    if not 0 <= args.delay <= MAX_DELAY_SAMPLES:
        raise ParameterError(
            f"--delay {args.delay}: give 0 to {MAX_DELAY_SAMPLES} samples of computational delay"
        )
    vf = args.velocity_filter
    if vf is not None and not (math.isfinite(vf) and vf > 0):
        raise ParameterError(f"--velocity-filter must be a positive cut-off in Hz, got {vf}")
    check_period(args.period)
    return {
        "period": args.period,
        "delay": args.delay,
        "velocity_filter": args.velocity_filter,
        "method": args.method,
    }


def _check_scan(args: argparse.Namespace, lo: float, hi: float) -> None:
    """Bound the work of the scan and of the bisection before it starts."""
    if not 2 <= args.samples <= MAX_SAMPLED_SCAN:
        raise ParameterError(f"--samples {args.samples}: give 2 to {MAX_SAMPLED_SCAN} scan points")
    rtol = args.rtol
    # the bisection stops at rtol*(hi - lo): below the float spacing it could never get there
    spacing = 4 * math.ulp(max(abs(lo), abs(hi), 1e-300))
    if not (math.isfinite(rtol) and MIN_RTOL <= rtol <= 0.5) or rtol * (hi - lo) < spacing:
        raise ParameterError(
            f"--rtol {rtol:g}: give a tolerance from {MIN_RTOL:g} to 0.5 that is above the "
            f"floating-point spacing of --range (here at least {spacing / (hi - lo):.3g})"
        )


def run_bound(args: argparse.Namespace) -> int:
    from ..sampled.bound import sampled_passive_bound

    kw = _loop_kw(args)
    lo, hi = _range(args.range)
    _check_scan(args, lo, hi)
    out = check_out_dir(args.out)
    sea = model_from_args(args, extra_free={args.param: f"sampled bound {args.param}"})
    warn_unrealizable(sea)
    res = sampled_passive_bound(
        sea,
        args.param,
        lo=lo,
        hi=hi,
        samples=args.samples,
        rtol=args.rtol,
        progress=True,
        **kw,
    )
    data = res.to_dict()
    if out is not None:
        from ..plot.sampled import plot_bound_scan

        buf = io.StringIO()
        buf.write(f"{args.param},passive\n")
        for x, v in res.samples:
            buf.write(f"{x!r},{int(v)}\n")
        write_text(out / f"sampled_bound_{args.param}.csv", buf.getvalue())
        write_text(out / f"sampled_bound_{args.param}.json", json_text(data))
        save_plot(lambda: plot_bound_scan(res), out / f"sampled_bound_{args.param}.png")
    if args.json:
        print_json(data)
    else:
        ivs = ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in res.intervals)
        print(f"passive {args.param} at T = {args.period:g} s: {ivs or 'none in the range'}")
        if res.max_passive is not None:
            print(f"largest passive {args.param}: {res.max_passive:.6g}")
    return 0


def run_check(args: argparse.Namespace) -> int:
    from ..sampled.passivity import sampled_passivity, sampled_power_curve

    kw = _loop_kw(args)
    d = check_out_dir(args.out)
    sea = model_from_args(args)
    warn_unrealizable(sea)
    res = sampled_passivity(sea, **kw)
    if d is not None:
        from ..plot.sampled import plot_power_curve

        write_text(d / "sampled_check.json", json_text(res.to_dict()))
        if res.reason in ("", "negative_power"):
            w, n = sampled_power_curve(sea, **kw)
            rows = "".join(f"{a!r},{b!r}\n" for a, b in zip(w, n, strict=True))
            write_text(d / "sampled_power.csv", "omega_rad_s,N\n" + rows)
            save_plot(lambda: plot_power_curve(w, n, period=args.period), d / "sampled_power.png")
    if args.json:
        print_json(res.to_dict())
    else:
        status = "passive" if res.passive else "not passive"
        print(f"{status} at T = {args.period:g} s (delay {args.delay}): {res.detail}")
        if res.omega is not None:
            print(f"witness: w = {res.omega:.6g} rad/s")
    return 0 if res.passive else 1  # a check, like cmp: 1 = not passive
