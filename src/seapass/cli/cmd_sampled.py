"""``seapass sampled``: passivity of the design under sampled-data (digital) control."""

from __future__ import annotations

import argparse
import io
import math
import sys
from typing import Any

from ..errors import ParameterError
from ..files.limits import MAX_DELAY_SAMPLES, MIN_RTOL
from .common import (
    add_force_option,
    add_json_option,
    add_model_options,
    add_out_dir_option,
    check_out_dir,
    check_period,
    check_rtol,
    json_text,
    model_from_args,
    parse_range,
    print_json,
    save_plot,
    warn_unrealizable,
    write_text,
)

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
    g = p.add_argument_group("sampled loop")
    g.add_argument("--period", type=float, default=0.002, help="control period T in s")
    g.add_argument(
        "--delay",
        type=int,
        default=delay,
        help=f"computational delay in samples, 0 to {MAX_DELAY_SAMPLES}",
    )
    g.add_argument(
        "--velocity-filter",
        type=float,
        default=velocity_filter,
        metavar="HZ",
        help="first-order low-pass on the finite-difference velocity, cutoff in Hz",
    )
    g.add_argument(
        "--method",
        choices=("tustin", "zoh", "backward"),
        default="tustin",
        help="discretization of strictly proper controller parts; derivatives always use "
        "backward differences",
    )
    g.add_argument(
        "--max-precision",
        type=int,
        default=4096,
        metavar="BITS",
        help="cap of the ball arithmetic's working precision; beyond it the answer is 'undecided'",
    )
    add_json_option(p)
    add_out_dir_option(p, "figures, CSV and JSON")
    add_force_option(p)


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
        help=f"relative width of every edge enclosure, in [{MIN_RTOL:g}, 1e-2]",
    )
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
        help=f"relative width of edge enclosures, in [{MIN_RTOL:g}, 1e-2]",
    )
    add_model_options(r)
    _loop_options(r, delay=1, velocity_filter=50.0)
    r.set_defaults(func=run_region)


def _range(text: str, flag: str = "--range") -> tuple[float, float]:
    return parse_range(text, flag, strict=True)


def _loop_kw(args: argparse.Namespace) -> dict[str, Any]:
    """The loop options, checked before any work starts."""
    if not (math.isfinite(args.period) and args.period > 0):
        raise ParameterError(f"--period must be a positive number of seconds, got {args.period}")
    check_period(args.period)
    if not 0 <= args.delay <= MAX_DELAY_SAMPLES:
        raise ParameterError(
            f"--delay {args.delay}: give 0 to {MAX_DELAY_SAMPLES} samples of computational delay"
        )
    vf = args.velocity_filter
    if vf is not None and not (math.isfinite(vf) and vf > 0):
        raise ParameterError(f"--velocity-filter must be a positive cut-off in Hz, got {vf}")
    if not 64 <= args.max_precision <= 65536:
        raise ParameterError(
            f"--max-precision must be in [64, 65536] bits, got {args.max_precision}"
        )
    return {
        "period": args.period,
        "delay": args.delay,
        "velocity_filter": args.velocity_filter,
        "method": args.method,
        "max_precision": args.max_precision,
    }


def run_check(args: argparse.Namespace) -> int:
    from ..sampled.passivity import sampled_passivity, sampled_power_curve

    kw = _loop_kw(args)
    names = ("sampled_check.json", "sampled_power.csv", "sampled_power.png")
    d = check_out_dir(args.out, files=names, force=args.force)
    sea = model_from_args(args)
    warn_unrealizable(sea)
    res = sampled_passivity(sea, **kw)
    if d is not None:
        from ..plot.sampled import plot_power_curve

        write_text(d / "sampled_check.json", json_text(res.to_dict()), force=args.force)
        if res.reason in ("", "negative_power", "low_frequency", "undecided"):
            curve = {k: v for k, v in kw.items() if k != "max_precision"}
            w, n = sampled_power_curve(sea, **curve)
            rows = "".join(f"{a!r},{b!r}\n" for a, b in zip(w, n, strict=True))
            write_text(d / "sampled_power.csv", "omega_rad_s,N\n" + rows, force=args.force)
            save_plot(
                lambda: plot_power_curve(w, n, period=args.period),
                d / "sampled_power.png",
                force=args.force,
            )
    if args.json:
        print_json(res.to_dict())
    else:
        status = {"passive": "passive", "not_passive": "not passive", "undecided": "undecided"}
        print(
            f"{status[res.status.value]} at T = {args.period:g} s (delay {args.delay}): {res.detail}"
        )
        if res.omega is not None:
            print(f"witness: w = {res.omega:.6g} rad/s")
    return 0 if res.passive else 1


def _partition_csv(param: str, res: Any) -> str:
    buf = io.StringIO()
    buf.write(f"{param}_lo,{param}_hi,status\n")
    for a, b, status in res.partition:
        buf.write(f"{a!r},{b!r},{status}\n")
    return buf.getvalue()


def run_bound(args: argparse.Namespace) -> int:
    from ..sampled.bound import sampled_passive_bound

    lo, hi = _range(args.range)
    kw = _loop_kw(args)
    check_rtol(args.rtol)
    stem = f"sampled_bound_{args.param}"
    d = check_out_dir(
        args.out, files=[f"{stem}.{x}" for x in ("csv", "json", "png")], force=args.force
    )
    sea = model_from_args(args, extra_free={args.param: f"sampled bound {args.param}"})
    warn_unrealizable(sea)
    res = sampled_passive_bound(sea, args.param, lo=lo, hi=hi, rtol=args.rtol, progress=True, **kw)
    out = res.to_dict()
    if d is not None:
        from ..plot.sampled import plot_bound

        write_text(d / f"{stem}.csv", _partition_csv(args.param, res), force=args.force)
        write_text(d / f"{stem}.json", json_text(out), force=args.force)
        save_plot(lambda: plot_bound(res), d / f"{stem}.png", force=args.force)
    if args.json:
        print_json(out)
        return 0
    ivs = ", ".join(f"[{a:.10g}, {b:.10g}]" for a, b in res.intervals) or "none"
    print(f"passive {args.param} at T = {args.period:g} s (delay {args.delay}): {ivs}")
    for e in res.edges:
        print(f"  edge in [{e.lo:.12g}, {e.hi:.12g}] ({e.kind.replace('_', ' ')})")
    if res.undecided:
        print(f"  undecided slivers: {len(res.undecided)} (each narrower than rtol)")
    if res.low_frequency is not None:
        print(f"  low-frequency condition: {res.low_frequency}")
    return 0


def run_region(args: argparse.Namespace) -> int:
    from ..sampled.region import LoopSetup, sampled_region

    lo1, hi1 = _range(args.range)
    lo2, hi2 = _range(args.range2, "--range2")
    kw = _loop_kw(args)
    check_rtol(args.rtol)
    stem = f"sampled_region_{args.p1}_{args.p2}"
    out = check_out_dir(
        args.out, files=[f"{stem}.{x}" for x in ("csv", "json", "png")], force=args.force
    )
    if args.p1 == args.p2:
        raise ParameterError(f"sampled region: give two different parameters, got {args.p1} twice")
    sea = model_from_args(
        args,
        extra_free={args.p1: f"sampled region {args.p1}", args.p2: f"sampled region {args.p2}"},
    )
    warn_unrealizable(sea)
    d = max(int(args.delay), 1)
    setups = [LoopSetup("ideal ZOH"), LoopSetup(f"{d}-sample delay", d)]
    if args.velocity_filter is not None:
        setups.append(
            LoopSetup(
                f"{d}-sample delay + {args.velocity_filter:g} Hz filter", d, args.velocity_filter
            )
        )
    with _RowProgress(f"Z-width map {args.p1} vs {args.p2}") as progress:
        zmap = sampled_region(
            sea, args.p1, args.p2, period=kw["period"], p1_range=(lo1, hi1), p2_range=(lo2, hi2),
            n=args.rows, setups=setups, method=kw["method"], rtol=args.rtol, log_p2=args.log,
            progress=progress,
        )  # fmt: skip
    if out is not None:
        from ..plot.sampled import plot_zwidth

        write_text(out / f"{stem}.csv", zmap.to_csv(), force=args.force)
        write_text(out / f"{stem}.json", json_text(zmap.to_dict()), force=args.force)
        save_plot(lambda: plot_zwidth(zmap), out / f"{stem}.png", force=args.force)
    if args.json:
        print_json(zmap.to_dict())
        return 0
    print(f"largest passive {args.p1} per {args.p2} at T = {args.period:g} s (certified per row):")
    header = f"{args.p2:>12}  " + "  ".join(f"{s.label:>28}" for s in zmap.setups)
    print(header)
    bounds = [zmap.upper_boundary(s.label) for s in zmap.setups]
    for i, v in enumerate(zmap.p2_values):
        cells = "  ".join(f"{'none' if math.isnan(b[i]) else f'{b[i]:.6g}':>28}" for b in bounds)
        print(f"{v:>12.6g}  {cells}")
    return 0


class _RowProgress:
    """A rich progress bar over the rows when stderr is a terminal (else silent)."""

    def __init__(self, label: str) -> None:
        self.label = label
        self.bar: Any = None
        self.task: Any = None

    def __enter__(self) -> Any:
        if not sys.stderr.isatty():
            return None
        from rich.progress import Progress

        self.bar = Progress(transient=True)
        self.bar.start()
        self.task = self.bar.add_task(self.label, total=None)
        return self._advance

    def _advance(self, done: int, total: int) -> None:
        self.bar.update(self.task, completed=done, total=total)

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.stop()
