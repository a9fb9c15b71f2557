"""``seapass sampled``: passivity of the design under sampled-data (digital) control."""

from __future__ import annotations

import argparse
import math
import re
from typing import Any

from ..errors import ParameterError
from ..files.limits import MAX_RTOL, MAX_SAMPLED_INTERVAL_BUDGET, MIN_RTOL, check_rtol
from .common import (
    add_force_option,
    add_json_option,
    add_model_options,
    add_out_dir_option,
    check_out_dir,
    json_text,
    print_json,
    save_plot,
    warn_unrealizable,
    write_text,
)
from .design_options import (
    add_design_argument,
    add_range_options,
    design_from_args,
    points_from_args,
    ranges_from_args,
    unit_suffix,
    units_json,
)
from .loop_options import add_loop_options
from .uncertain_options import (
    add_sampled_uncertain_options,
    add_uncertain_options,
    requested_box,
    run_robust_sampled_check,
)

ROWS = 25
DEFAULT_ROBUST_BUDGET = 16  # seapass.robust.sampled_intervals.DEFAULT_INTERVAL_BUDGET (tested)

EXAMPLE = """examples:
  seapass sampled check examples/ours.toml          # at the file's [control] rate
  seapass sampled bound kd examples/ours.toml --range kd=0:5000
  seapass sampled region kd bd examples/ours.toml --range kd=0:1e5 --points 5
  seapass sampled bound m examples/ours.toml --range m=1:1.000004 --budget 8
  seapass sampled bound kd examples/ours.toml --range kd=0:5000 --uncertain m=0.95:1.05
  seapass sampled check --period 0.002 --D1 "k1 + b1*s" --CA "kd + bd*s" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --set bd=25 --set kd=2000 --json
  seapass sampled bound kd --period 0.002 --D1 "k1 + b1*s" --CL "kd" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --range kd=0:5000 --json
  seapass sampled bound kd --period 0.002 --D1 "k1 + b1*s" --CA "kd + bd*s" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --set bd=25 --range kd=0:1e5 \\
      --delay 1 --velocity-filter 50 --out results/
  seapass sampled region kd bd --period 0.002 --D1 "k1 + b1*s" --CA "kd + bd*s" \\
      --set m=1.02 --set b=10 --set k1=1005 --set b1=30 --range kd=0:1e5 --range bd=0:100 \\
      --delay 1 --velocity-filter 50 --out results/

The loop: the flags, else the design file's [control], else T = 0.002 s (500 Hz)
with no delay and no filter ('region': 1 sample of delay and a 50 Hz filter).
Ranges: --range NAME=LO:HI, else the file's [ranges], else [0, max(10*value,
1000)] around the file's value, else 0:1e5 (the rule of 'seapass bound'); the old
spellings --range LO:HI, --range2 and --rows still work for one release.  A plant
parameter (m, b, k1, b1, ...) needs --range or [ranges].

'sampled bound' of a plant parameter, or with --uncertain: 'intervals' is the set
certified passive for every plant of the box (ends rounded inward), 'outer' a
certified superset (ends rounded outward), 'undecided' the rest (never passive).
For a gain with a box only the outer set is certified (the inner set needs a
point box); see docs/sampled.md.
"""

_FORMATTER = argparse.RawDescriptionHelpFormatter  # the CLI shows every default


def _loop_options(p: argparse.ArgumentParser, *, default: str = "0.002 (500 Hz)") -> None:
    g = add_loop_options(
        p, period_help=f"control period T in s (default: the design file's, else {default})"
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
    add_design_argument(c)
    add_model_options(c)
    _loop_options(c)
    add_sampled_uncertain_options(c)
    c.set_defaults(func=run_check)
    b = ss.add_parser(
        "bound",
        help="certified passive set of one controller parameter (e.g. the largest passive kd)",
        epilog=EXAMPLE,
        formatter_class=_FORMATTER,
    )
    b.add_argument("param", help="free controller parameter to bound, e.g. kd")
    add_design_argument(b)
    add_range_options(b)
    b.add_argument(
        "--rtol",
        type=float,
        default=1e-9,
        help=f"relative width of every edge enclosure, in [{MIN_RTOL:g}, {MAX_RTOL:g}]",
    )
    _budget_options(b, "the branch and bound")
    add_model_options(b)
    _loop_options(b)
    add_uncertain_options(
        b,
        budget=DEFAULT_ROBUST_BUDGET,
        verdict="the set is then certified for every plant in the box (plant parameters)",
        boxes="with a plant parameter or --uncertain: sub-intervals of a plant parameter, or "
        f"plants of the box for a gain (default {DEFAULT_ROBUST_BUDGET}, at most "
        f"{MAX_SAMPLED_INTERVAL_BUDGET})",
    )
    b.set_defaults(func=run_bound, budget=None)
    r = ss.add_parser(
        "region",
        help="Z-width map: passive region of two controller parameters, three loop setups",
        description="For each of --points values of P2 the passive set of P1 is certified (as "
        "by 'sampled bound'), for the ideal zero-order hold, DELAY samples of delay, and the "
        "delay plus the velocity filter (Colgate & Brown's Z-width).",
        epilog=EXAMPLE,
        formatter_class=_FORMATTER,
    )
    r.add_argument("p1", help="parameter bounded on each row, e.g. kd (stiffness)")
    r.add_argument("p2", help="parameter of the rows, e.g. bd (damping)")
    add_design_argument(r)
    add_range_options(r, points=ROWS, points_help="number of P2 rows, 2..200")
    r.add_argument("--range2", help=argparse.SUPPRESS)  # before 0.4: --range P2=LO:HI
    r.add_argument("--rows", type=int, help=argparse.SUPPRESS)  # before 0.4: --points
    r.add_argument("--log", action="store_true", help="space the P2 rows logarithmically")
    r.add_argument(
        "--rtol",
        type=float,
        default=1e-6,
        help=f"relative width of edge enclosures, in [{MIN_RTOL:g}, {MAX_RTOL:g}]",
    )
    _budget_options(r, "each row's branch and bound")
    add_model_options(r)
    _loop_options(r, default="0.002 (500 Hz), 1 sample of delay, a 50 Hz filter")
    r.set_defaults(func=run_region)


def _default_loop(region: bool = False) -> Any:
    """The loop of a design without ``[control]``: 500 Hz (region: delay 1, 50 Hz filter)."""
    from ..model.loop import SampledLoop

    if region:
        return SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
    return SampledLoop(period=0.002)


def _max_boxes(args: argparse.Namespace) -> dict[str, Any]:
    return {} if args.max_boxes is None else {"max_boxes": args.max_boxes}


def run_check(args: argparse.Namespace) -> int:
    from ..sampled.passivity import (
        SampledReason,
        power_curve_csv,
        sampled_passivity,
        sampled_power_curve,
    )

    if args.uncertain or args.robust is not None:  # every plant of a box (robust.sampled_verdict)
        if args.out is not None:
            raise ParameterError("--out is not available with --uncertain or --robust; use --json")
        return run_robust_sampled_check(args, _default_loop())
    names = ("sampled_check.json", "sampled_power.csv", "sampled_power.png")
    d = check_out_dir(args.out, files=names, force=args.force)
    resolved = design_from_args(args, default_loop=_default_loop())
    sea, loop = resolved.sea, resolved.loop
    warn_unrealizable(sea)
    res = sampled_passivity(sea, loop=loop, max_precision=args.max_precision)
    if d is not None:
        from ..plot.sampled import plot_power_curve

        write_text(d / "sampled_check.json", json_text(res.to_dict()), force=args.force)
        curved = (
            SampledReason.NONE,
            SampledReason.NEGATIVE_POWER,
            SampledReason.LOW_FREQUENCY,
            SampledReason.UNDECIDED,
        )
        if res.reason in curved:
            w, n = sampled_power_curve(sea, loop=loop)
            write_text(d / "sampled_power.csv", power_curve_csv(w, n), force=args.force)
            save_plot(
                lambda: plot_power_curve(w, n, period=loop.period),
                d / "sampled_power.png",
                force=args.force,
            )
    if args.json:
        print_json({**res.to_dict(), **units_json(args, resolved)})
    else:
        print(f"{res.outcome.label} at T = {loop.period:g} s (delay {loop.delay}): {res.detail}")
        if res.omega is not None:
            print(f"witness: w = {res.omega:.6g} rad/s")
    return 0 if res.passive else 1


def run_bound(args: argparse.Namespace) -> int:
    from ..exact.rounding import enclosure_text, interval_text
    from ..robust.box import parse_uncertain
    from ..sampled.bound import sampled_passive_bound
    from .progress import choose_progress

    given = ranges_from_args(args, [args.param])[args.param]
    raw = parse_uncertain(args.uncertain)
    if args.param in raw:
        raise ParameterError(
            f"--uncertain {args.param}: {args.param} is the bounded parameter; it cannot also "
            "be uncertain"
        )
    labels = {n: f"--uncertain {n}" for n in raw}
    resolved = design_from_args(
        args, {**labels, args.param: f"sampled bound {args.param}"}, default_loop=_default_loop()
    )
    check_rtol(args.rtol)
    stem = f"sampled_bound_{args.param}"
    d = check_out_dir(
        args.out, files=[f"{stem}.{x}" for x in ("csv", "json", "png")], force=args.force
    )
    sea, loop = resolved.sea, resolved.loop
    lo, hi = resolved.range_of(args.param, given)
    warn_unrealizable(sea)
    box = requested_box(args, sea, resolved.design, free=[args.param])
    if box is not None or _plant_parameter(sea, args.param):
        return _run_robust_bound(args, resolved, box, given)
    if args.budget is not None:
        raise ParameterError(
            "--budget applies to a plant parameter or --uncertain; the branch and bound of a "
            "gain takes --max-boxes"
        )
    with choose_progress(not args.no_progress) as progress:
        res = sampled_passive_bound(
            sea, args.param, loop=loop, lo=lo, hi=hi, rtol=args.rtol,
            max_precision=args.max_precision, progress=progress, **_max_boxes(args),
        )  # fmt: skip
    out = {**res.to_dict(), **units_json(args, resolved)}
    if d is not None:
        from ..plot.sampled import plot_bound

        unit = resolved.units.get(args.param, "")
        write_text(d / f"{stem}.csv", res.to_csv(), force=args.force)
        write_text(d / f"{stem}.json", json_text(out), force=args.force)
        save_plot(lambda: plot_bound(res, unit=unit), d / f"{stem}.png", force=args.force)
    if args.json:
        print_json(out)
        return 0
    ivs = ", ".join(interval_text(a, b, digits=10) for a, b in res.intervals) or "none"
    ivs += unit_suffix(args, resolved, args.param) if res.intervals else ""
    print(f"passive {args.param} at T = {loop.period:g} s (delay {loop.delay}): {ivs}")
    for e in res.edges:
        print(f"  edge in {enclosure_text(e.lo, e.hi)} ({e.kind.value.replace('_', ' ')})")
    if res.budget_exhausted:
        print(
            f"  stopped at the budget of boxes: {len(res.undecided)} undecided sub-interval(s) "
            "(not shown as passive; raise --max-boxes): "
            + ", ".join(enclosure_text(a, b) for a, b in res.undecided[:5])
        )
    elif res.undecided:
        print(f"  undecided slivers: {len(res.undecided)} (each narrower than rtol)")
    if res.low_frequency is not None:
        print(f"  low-frequency condition: {res.low_frequency}")
    return 0


def _plant_parameter(sea: Any, name: str) -> bool:
    from ..robust.sampled_intervals import plant_parameters

    return name in plant_parameters(sea)


def _run_robust_bound(
    args: argparse.Namespace, resolved: Any, box: Any, given: tuple[float, float] | None
) -> int:
    """``sampled bound`` of a plant parameter, or over a box: `robust_sampled_intervals`."""
    from ..exact.rounding import enclosure_text, interval_text
    from ..robust.sampled_intervals import DEFAULT_INTERVAL_BUDGET, robust_sampled_intervals
    from .progress import choose_progress
    from .uncertain_options import box_text

    name = args.param
    if args.out is not None:
        raise ParameterError(
            "--out is not available for a plant parameter or with --uncertain; use --json"
        )
    if args.max_boxes is not None:
        raise ParameterError(
            "--max-boxes applies to the bound of a gain at fixed plant values; give --budget"
        )
    if given is None and name not in resolved.ranges:
        raise ParameterError(
            f"sampled bound {name}: a plant parameter needs its range; give --range "
            f"{name}=LO:HI (or [ranges] {name} in the design file)"
        )
    lo, hi = resolved.range_of(name, given)
    budget = DEFAULT_INTERVAL_BUDGET if args.budget is None else args.budget
    if not 1 <= budget <= MAX_SAMPLED_INTERVAL_BUDGET:
        raise ParameterError(
            f"--budget must be an integer in [1, {MAX_SAMPLED_INTERVAL_BUDGET}], got {budget}"
        )
    sea, loop = resolved.sea, resolved.loop
    with choose_progress(not args.no_progress) as progress:
        try:
            res = robust_sampled_intervals(
                sea, name, loop=loop, lo=lo, hi=hi, box=box, budget=budget, progress=progress
            )
        except ParameterError as exc:  # the box in the words of the command line
            raise ParameterError(re.sub(r"box\['(\w+)'\]", r"--uncertain \1", str(exc))) from None
    if args.json:
        print_json({**res.to_dict(), **units_json(args, resolved)})
        return 0
    over = f" for every plant with {box_text(box)}" if box is not None else ""
    ivs = ", ".join(interval_text(a, b, digits=10) for a, b in res.intervals) or "none"
    ivs += unit_suffix(args, resolved, name) if res.intervals else ""
    print(f"passive{over} at T = {loop.period:g} s (delay {loop.delay}): {name} in {ivs}")
    outer = ", ".join(enclosure_text(a, b, digits=10) for a, b in res.outer) or "empty"
    print(f"  outer (certified): no {name} outside {outer} is passive{over}")
    if res.undecided:
        rest = ", ".join(enclosure_text(a, b) for a, b in res.undecided[:5])
        more = f" and {len(res.undecided) - 5} more" if len(res.undecided) > 5 else ""
        if res.budget_exhausted:
            why = f"{res.budget_used} of {res.budget} used: raise --budget or narrow the range"
        elif res.kind == "gain" and not res.intervals:
            why = "a gain interval over a box is not certified, see docs/sampled.md"
        else:
            why = "edge enclosures"
        print(f"  undecided (never shown passive; {why}): {rest}{more}")
    for w in res.failing[:5]:
        at = ", ".join(f"{k}={v:.10g}" for k, v in w.values.items())
        freq = "" if w.frequency is None else f" (N(w) < 0 at w = {w.frequency:.6g} rad/s)"
        print(f"  not passive at {at}{freq}")
    return 0


def run_region(args: argparse.Namespace) -> int:
    from ..exact.rounding import decimal_down, exact_text
    from ..sampled.region import sampled_region
    from .progress import choose_progress

    if args.p1 == args.p2:
        raise ParameterError(f"sampled region: give two different parameters, got {args.p1} twice")
    rows = points_from_args(args, "rows", ROWS)
    given = ranges_from_args(args, [args.p1, args.p2], {args.p2: ("--range2", args.range2)})
    resolved = design_from_args(
        args,
        {args.p1: f"sampled region {args.p1}", args.p2: f"sampled region {args.p2}"},
        default_loop=_default_loop(region=True),
    )
    sea, loop = resolved.sea, resolved.loop
    lo1, hi1 = resolved.range_of(args.p1, given[args.p1])
    lo2, hi2 = resolved.range_of(args.p2, given[args.p2])
    check_rtol(args.rtol)
    stem = f"sampled_region_{args.p1}_{args.p2}"
    out = check_out_dir(
        args.out, files=[f"{stem}.{x}" for x in ("csv", "json", "png")], force=args.force
    )
    warn_unrealizable(sea)
    with choose_progress(not args.no_progress) as progress:
        zmap = sampled_region(
            sea, args.p1, args.p2, loop=loop, p1_range=(lo1, hi1), p2_range=(lo2, hi2),
            n=rows, rtol=args.rtol, log_p2=args.log, max_precision=args.max_precision,
            progress=progress, **_max_boxes(args),
        )  # fmt: skip
    if out is not None:
        from ..plot.sampled import plot_zwidth

        write_text(out / f"{stem}.csv", zmap.to_csv(), force=args.force)
        write_text(out / f"{stem}.json", json_text(zmap.to_dict()), force=args.force)
        units = (resolved.units.get(args.p1, ""), resolved.units.get(args.p2, ""))
        save_plot(lambda: plot_zwidth(zmap, units=units), out / f"{stem}.png", force=args.force)
    if args.json:
        print_json({**zmap.to_dict(), **units_json(args, resolved)})
        return 0
    print(f"largest passive {args.p1} per {args.p2} at T = {loop.period:g} s (certified per row):")
    header = f"{args.p2:>12}  " + "  ".join(f"{s.label:>28}" for s in zmap.setups)
    print(header)
    bounds = [zmap.upper_boundary(s.label) for s in zmap.setups]
    for i, v in enumerate(zmap.p2_values):
        # the largest passive value rounded down, at the exact row value
        cells = "  ".join(
            f"{'none' if math.isnan(b[i]) else decimal_down(b[i], 6):>28}" for b in bounds
        )
        print(f"{exact_text(v):>12}  {cells}")
    return 0
