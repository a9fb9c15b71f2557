"""``seapass delay-margin``: the passivity delay margin τ* of a design, certified."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import ParameterError
from ..files.limits import check_rtol
from .common import (
    add_force_option,
    add_json_option,
    add_model_options,
    add_plot_option,
    plot_path,
    print_json,
    values_from_args,
    write_figure,
)

EXAMPLE = """examples:
  seapass delay-margin tau ours --set kd=500 --set bd=25 --set b1=20 --json
  seapass delay-margin tau ours --set kd=500 --set bd=25 --set b1=20 --plot margin.png
  seapass delay-margin tau --D1 "k1 + b1*s" --CA "(kd + bd*s)*exp(-tau*s)" --set m=1 \\
      --set b=10 --set k1=1000 --set b1=20 --set kd=500 --set bd=25
  seapass delay-margin tau --Z "m*s + b + K*exp(-tau*s)/s" --set m=1 --set b=2 --set K=50

  seapass delay-margin tau ours --set bd=25 --set b1=20 --range kd=100:3000 --points 9 \\
      --plot region.png     # the passive region in (kd, tau): tau*(kd), certified per gain
  seapass delay-margin tau examples/ours.toml --uncertain m=0.9:1.1 --uncertain b1=270:330 \\
      --rtol 1e-3 --json    # robust: min of tau* over every plant of the box, certified

NAME is the delay parameter (seconds); it is free here, so do not give it with --set.
Give DESIGN right after NAME.
DESIGN is LP, APD or ours (the paper's plant m = 1, b = 10, k1 = 1000; give the gains
with --set) or a design file; a design without exp(-NAME*s) gets the delay on its
controllers C_A and C_L (a loop latency).

tau_star [lo, hi]: every delay up to lo is certified passive (lo is rounded down), and at
hi (rounded up) passivity is proven lost; hi - lo <= rtol*hi.  tau_star is null when the
design is not passive without delay (passive_at_zero false) or is passive for every delay
(delay_independent true).  loss: interior (at 'frequency'), low_frequency (w -> 0) or
unbounded_band (tau* = 0: every delay > 0 fails at arbitrarily high frequencies).

With --uncertain NAME=LO:HI (repeatable): tau_star encloses the smallest tau* over the box;
lo is certified for every plant of the box, hi is the tau* upper end of the worst plant found
(in 'worst', verified by the ordinary delay margin); 'robust' is true and 'box' the intervals.

exit codes: 0 margin found (or passive for every delay), 1 not passive without delay or
undecided, 2 bad input (one 'error:' line on stderr)
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "delay-margin",
        help="certified passivity delay margin tau*: the largest delay such that the design "
        "stays passive for every delay up to it",
        description="Certified enclosure of the passivity delay margin tau* of a design with "
        "a delay exp(-NAME*s) (exact structure, exact asymptotics, arb balls; never a Pade "
        "approximation or a frequency grid), the frequency where passivity is lost and how.",
        epilog=EXAMPLE,
    )
    p.add_argument("name", metavar="NAME", help="the delay parameter, e.g. tau")
    p.add_argument("design", nargs="?", metavar="DESIGN", help="LP, APD, ours or a design file")
    add_model_options(p)
    p.add_argument("--Z", help="a raw impedance with the delay, e.g. 'm*s + b + K*exp(-tau*s)/s'")
    p.add_argument(
        "--rtol",
        type=float,
        default=1e-6,
        help="relative width of the enclosure of tau*",
    )
    p.add_argument("--range", metavar="GAIN=LO:HI",
                   help="the passive region in (GAIN, NAME): tau* at --points gains in "
                   "[LO, HI] (do not give GAIN with --set)")  # fmt: skip
    p.add_argument("--points", type=int, metavar="N",
                   help="with --range: number of gains, 2 to 200 (default: 9)")  # fmt: skip
    from .uncertain_options import add_uncertain_options

    add_uncertain_options(
        p,
        budget=20_000,
        verdict="tau* then holds for every plant in the box (certified)",
        boxes="cells (frequency x delays x sub-box) the certified branch and bound may examine",
    )
    add_plot_option(p, "the first failing delay per frequency with the enclosure of tau* "
                    "(with --range: the passive region in (GAIN, NAME))")  # fmt: skip
    add_force_option(p)
    add_json_option(p)
    p.set_defaults(func=run, allow_delay=True)


def _system(args: argparse.Namespace) -> object:
    """The design named on the command line, with the delay on its controllers if needed."""
    from ..model.catalog import CATALOG
    from ..model.design_file import load_design
    from ..model.expr import check_name
    from ..model.sea import Impedance
    from .common import model_from_args

    try:
        check_name(args.name)
    except ValueError as exc:
        raise ParameterError(f"NAME: {exc}") from None
    model_given = any(getattr(args, e) not in (None, "0") for e in ("D1", "D2", "CA", "CL"))
    given = [w for w, on in (("DESIGN", args.design), ("the model --D1 ...", model_given),
                             ("--Z", args.Z is not None)) if on]  # fmt: skip
    if len(given) > 1:
        raise ParameterError(f"give one of DESIGN, the model --D1/--D2/--CA/--CL or --Z, not {' and '.join(given)}")  # fmt: skip
    if not given:
        raise ParameterError("nothing to analyse: give DESIGN (LP, APD, ours or a design file), the model --D1 ... --set, or --Z")  # fmt: skip
    values = values_from_args(args)
    if args.name in values:
        raise ParameterError(f"--set {args.name}: {args.name} is the delay whose margin is computed; do not give it a value")  # fmt: skip
    if args.Z is not None:
        if "exp" not in args.Z:
            raise ParameterError(f"--Z has no delay: write it as exp(-{args.name}*s), e.g. 'm*s + b + K*exp(-{args.name}*s)/s'")  # fmt: skip
        return Impedance(expr=args.Z, values={**values, args.name: None})
    if model_given:
        from ..delay.structure import controller_delay

        try:
            sea = model_from_args(args, extra_free={args.name: f"NAME {args.name}"})
        except ParameterError as exc:
            if f"NAME {args.name}" not in str(exc):
                raise
            sea = model_from_args(args)  # NAME unused: the delay goes on the controllers
        return controller_delay(sea, args.name)
    from ..delay.structure import controller_delay

    name = args.design
    if name.lower() in {k.lower() for k in CATALOG} and not Path(name).is_file():
        return controller_delay(name, args.name, values)
    path = Path(name)
    if path.suffix != ".toml" and not path.exists():
        raise ParameterError(f"DESIGN {name!r} is neither a design file nor one of LP, APD, ours")
    return controller_delay(load_design(path), args.name, values)


def _run_region(args: argparse.Namespace, figure: Path | None) -> int:
    """``--range GAIN=LO:HI``: tau* per gain, certified (`seapass.delay.gain.delay_region`)."""
    from ..delay.gain import delay_region
    from ..model.sea import SEA
    from .common import parse_named, parse_range

    ((gain, parts),) = parse_named([args.range], "--range", 2, "GAIN=LO:HI, e.g. kd=100:3000")
    lo, hi = parse_range(":".join(parts), "--range", strict=True)
    if gain in values_from_args(args):
        raise ParameterError(f"--set {gain}: {gain} is the --range gain; do not give it a value")
    args.set = [*args.set, f"{gain}={lo!r}"]  # a value to build the design; the range sets it
    try:
        system = _system(args)
    except ParameterError as exc:
        if getattr(exc, "argument", None) != f"values[{gain!r}]" and f"--set {gain}" not in str(
            exc
        ):
            raise
        raise ParameterError(f"--range {gain}: not a parameter of the design") from None
    if not isinstance(system, SEA):
        raise ParameterError("--range needs a design (DESIGN or the model --D1 ...), not --Z")
    region = delay_region(system, gain, lo, hi, delay=args.name, points=args.points or 9,
                          rtol=args.rtol)  # fmt: skip
    if figure is not None:
        write_figure(lambda: region.plot(), figure, force=args.force)
    if args.json:
        print_json(region.to_dict())
        return 0
    from ..exact.rounding import enclosure_text

    for k, r in zip(region.gains, region.results, strict=True):
        star = (f"tau* in {enclosure_text(*r.tau_star, digits=6)} s" if r.tau_star is not None
                else "passive for every delay" if r.delay_independent else r.outcome.label)  # fmt: skip
        print(f"{gain} = {k:.8g}: {star}")
    return 0


def _run_robust(args: argparse.Namespace, figure: Path | None) -> int:
    """``--uncertain``: the delay margin of every plant of the box (`robust_delay_margin`)."""
    from ..model.sea import SEA
    from ..outcome import Outcome
    from ..robust.delayed import robust_delay_margin
    from .uncertain_options import box_from_args, box_text, cli_text

    if args.range is not None:
        raise ParameterError("give --range or --uncertain, not both")
    if args.budget < 1:
        raise ParameterError(f"--budget must be a positive integer, got {args.budget}")
    clash = sorted(
        set(values_from_args(args)) & {a.partition("=")[0].strip() for a in args.uncertain}
    )
    if clash:
        raise ParameterError(f"--set {clash[0]}: {clash[0]} is uncertain (--uncertain {clash[0]}); do not also give it a value")  # fmt: skip
    if args.name in {a.partition("=")[0].strip() for a in args.uncertain}:
        raise ParameterError(f"--uncertain {args.name}: {args.name} is the delay whose margin is computed; it cannot be uncertain")  # fmt: skip
    system = _system(args)
    if not isinstance(system, SEA):
        raise ParameterError("--uncertain needs a design (DESIGN or the model --D1 ...), not --Z")
    try:
        box = box_from_args(args, system, free=[args.name])
        result = robust_delay_margin(system, args.name, box=box, rtol=args.rtol, budget=args.budget)
    except ParameterError as exc:
        raise cli_text(exc) from None
    if figure is not None and result.worst_margin is not None:
        write_figure(lambda: result.plot(), figure, force=args.force)
    if args.json:
        print_json(result.to_dict())
    else:
        from ..exact.rounding import decimal_down, enclosure_text

        span = box_text(box)
        if result.exact is not None:
            lo, hi = result.exact
            print(f"passive for every plant with {span} and every delay {args.name} <= {decimal_down(lo, 6)} s")  # fmt: skip
            print(f"robust tau* in {enclosure_text(lo, hi)} s")
        if result.worst_values is not None:
            at = ", ".join(f"{k}={v:.10g}" for k, v in result.worst_values.items())
            wm = result.worst_margin
            star = (
                ""
                if wm is None or wm.tau_star is None
                else f": tau* in {enclosure_text(*wm.tau_star, digits=6)} s"
            )
            print(f"worst plant: {at}{star}")
        if result.outcome is not Outcome.PASSIVE or not result.certified:
            print(f"{result.outcome.label}: {result.detail}")
    return 0 if result.outcome is Outcome.PASSIVE else 1


def run(args: argparse.Namespace) -> int:
    from ..delay.margin import delay_margin
    from ..outcome import Outcome

    check_rtol(args.rtol)
    figure = plot_path(args.plot, force=args.force)  # checked before the work starts
    if args.range is not None:
        return _run_region(args, figure)
    if args.points is not None:
        raise ParameterError("--points needs --range GAIN=LO:HI (the gains of the region)")
    if args.uncertain or args.robust is not None:
        return _run_robust(args, figure)
    result = delay_margin(_system(args), args.name, rtol=args.rtol)
    if figure is not None:
        write_figure(lambda: result.plot(), figure, force=args.force)
    if args.json:
        print_json(result.to_dict())
    else:
        if result.tau_star is not None:
            from fractions import Fraction

            from ..exact.rounding import decimal_down, enclosure_text

            lo, hi = result.exact or (
                Fraction(result.tau_star[0]),
                Fraction(result.tau_star[1]),
            )
            where = {
                "interior": f"at w = {result.frequency:.6g} rad/s" if result.frequency else "",
                "low_frequency": "as w -> 0",
                "unbounded_band": "at arbitrarily high frequencies, for every delay > 0",
            }.get(str(result.loss or ""), "")
            # inward: the printed lower end is at most the certified lo (so below tau*);
            # the enclosure is printed outward, so it still holds tau*
            if result.outcome is Outcome.PASSIVE:
                print(f"passive for every delay {args.name} <= {decimal_down(lo, 6)} s")
            print(f"tau* in {enclosure_text(lo, hi)} s ({result.loss} {where})".replace(" )", ")"))
        elif result.delay_independent:
            print(f"passive for every delay {args.name} >= 0")
        else:
            print(f"tau*: none ({result.detail})")
        if result.outcome is not Outcome.PASSIVE or not result.certified:
            print(f"{result.outcome.label}: {result.detail}")
    return 0 if result.outcome is Outcome.PASSIVE else 1
