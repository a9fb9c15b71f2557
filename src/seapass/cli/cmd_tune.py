"""``seapass tune``: the best passive gains of any design (a design file, a model, or LP/APD/ours)."""

from __future__ import annotations

import argparse
import contextlib
import re
import sys
import warnings
from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ..errors import ParameterError, TuningWarning
from .common import (
    add_json_option,
    add_model_options,
    check_period,
    check_step,
    cli_words,
    model_from_args,
    print_json,
    values_from_args,
    warn,
)
from .design_options import add_unit_option, units_from_args
from .loop_options import add_loop_options
from .tune_objectives import add_objective_options, run_objective
from .uncertain_options import add_uncertain_options, requested_box

if TYPE_CHECKING:  # the CLI starts fast: heavy modules load when a command runs
    from ..model.design_file import Design
    from ..model.loop import SampledLoop
    from ..tuning.optimize import TuningResult
    from ..tuning.problem import DesignLike, TuningOptions

EXAMPLE = """examples:
  seapass tune examples/ours.toml --json
  seapass tune examples/ours.toml --tune kd=0:5000 --tune b1 --objective itae
  seapass tune --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 --set k1=1000 \\
      --set b1=30 --tune kd=0:5000 --tune bd=0:300 --period 0.002 --max-overshoot 5
  seapass tune ours --load-mass 10 --quick
  seapass tune examples/ours.toml --continuous --mass-policy tune --json
  seapass tune examples/cascaded_impedance.toml --objective rendering \\
      --target "kv + bv*s" --band 1:100 --quick
  seapass tune APD --objective force-bandwidth --quick --json
  seapass tune examples/ours.toml --objective zwidth --tune bd --max-boxes 500 --quick
  seapass tune --D1 "k1 + b1*s" --CA "(kd + bd*s)*exp(-tau*s)" --set m=1 --set b=10 \\
      --set k1=1000 --set b1=30 --set tau=0.001 --tune kd=0:5000 --tune bd=0:300
  seapass tune ours --uncertain m=0.8:1.2 --uncertain k1=900:1100 --json

DESIGN is a design file (TOML, see 'seapass analyze --help') or one of the paper's
designs LP, APD, ours (m = 1 kg, b = 10 N*s/m, k1 = 1000 N/m); or give the model
with --D1/--D2/--CA/--CL/--set.  Gains to tune: --tune NAME=LO:HI, or --tune NAME
for the design's box (the file's [ranges], else [0, max(10*value, 1000)]);
default: the controller gains (the parameters of CA and CL that are not plant
parameters; LP/APD/ours: the catalog's gains).  Every other parameter stays at
its value.  Plant parameters (m, b, k1, k2, b1, b2, those of D1/D2, [plant] or
--plant) are the hardware: --tune names one only with a [ranges] entry in the
design file, or with --allow-plant.  Every candidate that could become the best
is checked with the exact passivity test (and the sampled-data test with
--period).  A delay factor exp(-NAME*s) in the model (NAME given a value in
seconds; or --delay-time, [control] delay_time) makes the constraint passivity at
that delay, certified, and the step response that of the delayed loop; --uncertain NAME=LO:HI makes it passivity
for every plant in the box, certified (the nominal tune runs too and the
robustness cost is printed).  Undecided counts as not passive.  The printed
gains are the verified ones.  Exit code 0 when the result is feasible, 1 when
no passive gains within the limits were found, 2 on bad input.
"""


_OBJECTIVES = ("settling", "itae", "rendering", "force-bandwidth", "zwidth")


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "tune",
        help="tune the gains of any design for the best passive step response",
        description="Differential evolution (seeded, reproducible) on the simulated step "
        "response, under exact passivity (always), sampled-data passivity (--period), a "
        "force limit and an overshoot limit. Progress goes to stderr (a live bar on a terminal, "
        "one line otherwise; --no-progress: none); Ctrl-C stops cleanly (exit 130).",
        epilog=EXAMPLE,
    )
    p.add_argument("design", nargs="?", metavar="DESIGN", help="design file or LP, APD, ours")
    p.add_argument("--design", dest="design_option", help=argparse.SUPPRESS)  # old spelling
    add_model_options(p)
    g = p.add_argument_group("what to tune")
    g.add_argument("--tune", action="append", default=[], metavar="NAME=LO:HI",
                   help="a gain and its box, repeatable; NAME alone: the design's box")  # fmt: skip
    g.add_argument("--allow-plant", action="store_true",
                   help="allow --tune to name plant parameters (k1, b1, --plant/[plant] values) "
                   "that the design file gives no [ranges] entry: redesign the hardware")  # fmt: skip
    g.add_argument("--bound", action="append", default=[], help=argparse.SUPPRESS)  # old name
    g.add_argument("--objective", default="settling", choices=_OBJECTIVES,
                   help="settling: 2%% settling time; itae: integral of t*|error|; rendering: "
                   "worst relative error of F_L/X_L to --target over --band; force-bandwidth: "
                   "-3 dB force bandwidth with the load clamped; zwidth: largest passive "
                   "virtual stiffness at the loop rate (default: settling)")  # fmt: skip
    add_objective_options(g)
    g.add_argument("--max-overshoot", type=float, metavar="PCT",
                   help="overshoot limit in percent of the step (default: none)")  # fmt: skip
    g.add_argument("--force-limit", type=float, metavar="N",
                   help="peak actuator force |f_A| [N] (default: the paper's experiment, 1000)")  # fmt: skip
    g.add_argument("--no-force-limit", action="store_true", help="no force limit")
    lg = add_loop_options(p, method=False, what="the sampled loop (--period, else the design file's [control])",
                          period_help="also require passivity under sampled-data control with period T [s] (default: the design file's [control], else none)")  # fmt: skip
    lg.add_argument("--continuous", action="store_true",
                    help="ignore the design file's [control]: continuous passivity only")  # fmt: skip
    lg.add_argument("--delay-time", type=float, metavar="SECONDS",
                    help="loop latency replacing the design file's [control] delay_time; a "
                    "controller in z: a whole number of periods, each one more sample of "
                    "delay in the certified sampled loop (default: the file's, else none)")  # fmt: skip
    add_unit_option(p)
    add_uncertain_options(
        p, budget=None, boxes="boxes of the certified test per candidate (default 5000; a "
        "controller in z: sub-boxes of the robust sampled verdict, default 4)",
    )  # fmt: skip
    s = p.add_argument_group("the step response (default: the file's [simulation], else the paper's experiment: 10 kg, 0.5 m, 10 s)")  # fmt: skip
    s.add_argument("--load-mass", type=float, metavar="KG", help="tuning load mass m_L [kg]")
    s.add_argument("--mass-policy", choices=("worst", "tune"),
                   help="settling/itae: worst = the worst objective over the file's load_masses; "
                   "tune = the tuning mass only (default: worst when the design file lists "
                   "several load masses and --load-mass is not given, else tune)")  # fmt: skip
    s.add_argument("--step", type=float, metavar="M", help="reference step [m]")
    s.add_argument("--horizon", type=float, metavar="S", help="simulated time [s]")
    b = p.add_argument_group("the search")
    b.add_argument("--maxiter", type=int, help="generations (default: 60; --quick: 12)")
    b.add_argument("--popsize", type=int, help="population per gain (default: 12; --quick: 6)")
    b.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    b.add_argument("--quick", action="store_true", help="small budget (for previews and tests)")
    b.add_argument("--no-progress", action="store_true", help="no progress on stderr")
    add_json_option(p)
    p.set_defaults(func=run, allow_delay=True)


# ----------------------------------------------------------------- arguments


def parse_tune(items: Sequence[str], flag: str = "--tune") -> dict[str, tuple[float, float] | None]:
    """``NAME=LO:HI`` or ``NAME`` items into ``{name: (lo, hi) or None}``; repeats are errors.

    The boxes themselves are checked by the library
    ([`resolve_problem`][seapass.tuning.problem.resolve_problem]).
    """
    from ..model.expr import parse_value

    out: dict[str, tuple[float, float] | None] = {}
    for item in items:
        name, sep, rng = item.partition("=")
        name = name.strip()
        if not name.isidentifier():
            raise ParameterError(f"{flag} {item!r}: expected NAME=LO:HI or NAME, e.g. kd=0:5000")
        if name in out:
            raise ParameterError(f"{flag} {name} is given twice; give each gain once")
        if not sep:
            out[name] = None
            continue
        lo, sep2, hi = rng.partition(":")
        if not sep2:
            raise ParameterError(f"{flag} {item!r}: expected NAME=LO:HI, e.g. {name}=0:5000")
        out[name] = (
            parse_value(lo.strip(), f"{flag} {name} lower bound"),
            parse_value(hi.strip(), f"{flag} {name} upper bound"),
        )
    return out


def _design(
    args: argparse.Namespace, boxes: Mapping[str, object], uncertain: Mapping[str, object]
) -> tuple[DesignLike, Design | None, dict[str, float]]:
    """The design named on the command line, its design file (if any) and the ``--set`` values.

    A model given with ``--D1 ...`` holds the ``--set`` values; a gain named only
    by ``--tune`` (and an expression) is a free parameter of it, so it needs no
    ``--set``.
    """
    from ..model.design_file import Design, load_design_or_catalog

    if args.design and args.design_option:
        raise ParameterError("give the design once (DESIGN or --design)")
    name = args.design or args.design_option
    from .controller_options import model_given as given
    from .controller_options import plant_from_args

    model_given = given(args)
    if name is not None and model_given:
        raise ParameterError(
            "give either DESIGN or the model (--D1/--D2/--CA/--CL, --controller, --plant), not both"
        )
    if name is None and not model_given:
        raise ParameterError(
            "nothing to tune: give a design file, LP/APD/ours, or the model with --D1 ... --set"
        )
    values = values_from_args(args)
    if name is None:
        known = {*values, *plant_from_args(args)}
        free = {n: f"--tune {n}" for n in boxes if n not in known}
        free.update({n: f"--uncertain {n}" for n in uncertain if n not in known})
        return model_from_args(args, extra_free=free), None, {}
    design = load_design_or_catalog(name)
    return design, design if isinstance(design, Design) else None, values


def options_from_args(args: argparse.Namespace, file: Design | None) -> TuningOptions:
    """`TuningOptions` from the command line; what it leaves out (None) the library takes
    from the design file, else from the paper's experiment."""
    from ..tuning.problem import QUICK_OPTIONS, TuningOptions

    limit = {} if args.force_limit is None else {"force_limit": args.force_limit}
    opts = TuningOptions(
        objective=args.objective if args.objective in ("settling", "itae") else "settling",
        max_overshoot=None if args.max_overshoot is None else args.max_overshoot / 100.0,
        **({"force_limit": None} if args.no_force_limit else limit),
        load_mass=args.load_mass,
        masses=args.mass_policy,
        step=args.step,
        horizon=args.horizon,
        loop=_loop(args, file),
        seed=args.seed,
    )
    if args.quick:
        opts = opts.replace(
            maxiter=QUICK_OPTIONS.maxiter,
            popsize=QUICK_OPTIONS.popsize,
            dt_search=QUICK_OPTIONS.dt_search,
        )
    if args.maxiter is not None:
        opts = opts.replace(maxiter=args.maxiter)
    if args.popsize is not None:
        opts = opts.replace(popsize=args.popsize)
    return opts


def _loop(args: argparse.Namespace, file: Design | None) -> SampledLoop | None:
    """The sampled loop of the constraint: the flags over the file's ``[control]``."""
    from ..model.resolve import resolve_loop

    check_period(args.period)
    if args.continuous:
        if args.period is not None:
            raise ParameterError("give --period or --continuous, not both")
        return None
    changes = {k: getattr(args, k) for k in ("period", "delay", "velocity_filter")}
    return resolve_loop(None if file is None else file.loop, None, changes)


def _system(design: DesignLike) -> Any:
    """The SEA of a design, catalog design or model (a box is checked against it)."""
    from ..model.sea import SEA

    return design if isinstance(design, SEA) or isinstance(design, str) else design.sea()


def _units(args: argparse.Namespace, file: Design | None, names: Sequence[str]) -> dict[str, str]:
    """Units of ``names`` when a design file or ``--unit`` is given, else ``{}``."""
    from ..model.units import unit_map

    given = units_from_args(args)
    if file is None and not given:
        return {}
    known = set(names) | set(file.unit_map() if file is not None else ())
    for name in given:
        if name not in known:
            raise ParameterError(f"--unit {name}: not a parameter of the design")
    declared = {**(dict(file.units) if file is not None else {}), **given}
    return unit_map(declared, names)


# ----------------------------------------------------------------- run


def run(args: argparse.Namespace) -> int:
    from ..robust.box import parse_uncertain
    from ..tuning.optimize import tune
    from .progress import choose_progress

    boxes = parse_tune([*args.tune, *args.bound])
    with box_words():
        uncertain = parse_uncertain(args.uncertain)
    for name in sorted(set(uncertain) & set(values_from_args(args))):
        raise ParameterError(f"--set {name}: {name} is uncertain (--uncertain {name}); give one")
    if args.budget is not None and args.budget < 1:
        raise ParameterError(f"--budget must be a positive integer, got {args.budget}")
    design, file, values = _design(args, boxes, uncertain)
    opts = options_from_args(args, file)
    check_step(args.step)
    if args.robust is not None:  # the file's [uncertainty] or a fitted rig's, the flags over it
        box = requested_box(args, _system(design), file)
        if box is not None:
            uncertain = dict(box.intervals)
    if args.objective not in ("settling", "itae"):
        if args.mass_policy is not None:  # those objectives check every load mass already
            raise ParameterError(
                f"--mass-policy works with --objective settling or itae, not {args.objective} "
                "(its candidates must be stable with every load mass of the file already)"
            )
        if uncertain:
            raise ParameterError(
                f"--uncertain and --robust work with --objective settling or itae, "
                f"not {args.objective}"
            )
        if args.delay_time is not None:
            raise ParameterError(
                f"--delay-time works with --objective settling or itae, not {args.objective} "
                "(its objectives are those of the delay-free design)"
            )
        return run_objective(args, design, boxes, values, opts)
    with warnings.catch_warnings(), choose_progress(not args.no_progress) as progress, box_words():
        warnings.simplefilter("ignore", TuningWarning)  # printed below, once, as lines
        result = tune(
            design,
            tune=boxes or None,
            values=values or None,
            options=opts,
            progress=progress,
            allow_plant=args.allow_plant,
            uncertain=uncertain or None,
            budget=args.budget if uncertain else None,
            delay_time=args.delay_time,
        )
    for message in result.warnings:
        warn(cli_words(message))
    units = _units(args, file, list(result.gains))
    if args.json:
        print_json({**result.to_dict(), **({"units": units} if units else {})})
    else:
        _print_text(result, units)
    z_design = result.sea.discrete is not None  # its loop is its own: --continuous cannot drop it
    if (
        file is not None
        and file.loop is not None
        and opts.loop is not None
        and args.period is None
        and not z_design
    ):
        print(
            f"note: passivity also required at the design file's {file.loop.rate:g} Hz "
            "([control]); --continuous drops it",
            file=sys.stderr,
        )
    return 0 if result.feasible else 1


def _print_text(result: TuningResult, units: Mapping[str, str] | None = None) -> None:
    from ..sim.metrics import overshoot_text
    from ..tuning.constraints import ConstraintKind, gain_text
    from ..tuning.problem import Objective

    m = result.metrics
    units = units or {}
    gains = ", ".join(  # the verified values, exactly (tune rounds them before verifying)
        f"{k} = {gain_text(v)}" + (f" {units[k]}" if units.get(k) else "")
        for k, v in result.gains.items()
    )
    print(f"{result.design}: {gains}")
    kind = Objective(result.options.objective)
    several = len(result.per_mass) > 1
    worst = f", worst at m_L = {result.worst_mass:g} kg" if several else ""
    print(f"{kind.label}: {result.objective:.6g} {kind.unit} ({m.status}{worst})")
    if several:
        for run in result.per_mass:
            settle = run.metrics.settling_time
            also = (
                ""
                if kind is Objective.SETTLING or settle is None
                else f", settles in {settle:.4g} s"
            )
            print(
                f"  m_L = {run.load_mass:g} kg: {kind.label} {run.objective:.6g} {kind.unit} "
                f"({run.metrics.status}{also}); overshoot {overshoot_text(run.metrics.overshoot)}; "
                f"peak force {run.metrics.peak_force:.4g} N"
            )
    c = result.constraint
    how = "" if c is None or c.kind is ConstraintKind.EXACT else f" ({c.label})"
    verdicts = f"passive{how}: {'yes' if result.passive else 'NO'}"
    if how and result.passivity is not None:
        verdicts += f" [{result.passivity.outcome}]"
    loop = result.options.loop
    if result.sea.discrete is not None and loop is not None:  # a controller in z
        over = ""
        if c is not None and c.kind is ConstraintKind.BOX and c.box is not None:
            over = ", for every plant with " + ", ".join(
                f"{k} in [{a:g}, {b:g}]" for k, (a, b) in c.box.intervals.items()
            )
        verdicts = (
            f"passive in the sampled loop at T = {loop.period:g} s (delay {loop.delay}, "
            f"controller in z, certified{over}): {'yes' if result.sampled_passive else 'NO'}"
        )
    elif result.sampled_passive is not None and loop is not None:
        verdicts += (
            f"; passive at T = {loop.period:g} s: {'yes' if result.sampled_passive else 'NO'}"
        )
    print(verdicts)
    overshoot = overshoot_text(m.overshoot)
    print(
        f"peak force {m.peak_force:.4g} N; overshoot {overshoot}; final error {m.final_error:.3e} m"
    )
    if result.on_bound:
        print(f"on the edge of the box: {', '.join(sorted(result.on_bound))}")
    if result.nominal is not None and result.robustness_cost is not None:
        print(
            f"nominal tune: {result.nominal.objective:.6g} {kind.unit}; robust: "
            f"{result.objective:.6g} {kind.unit}; robustness cost: "
            f"{result.robustness_cost:.6g} {kind.unit}"
        )


def box_text(text: str) -> str:
    """A library message about ``box`` in the words of ``--uncertain`` (and ``--continuous``).

    >>> box_text("box['m']: empty (loop=None)")
    '--uncertain m: empty (--continuous)'
    """
    text = re.sub(r"box\['(\w+)'\]", r"--uncertain \1", text)
    text = re.sub(r"e\.g\. box=\{'(\w+)': \([^)]*\)\}", r"e.g. --uncertain \1=LO:HI", text)
    return text.replace("loop=None", "--continuous")


@contextlib.contextmanager
def box_words() -> Iterator[None]:
    """Library errors about ``box`` and the loop in the words of the command line."""
    try:
        yield
    except ParameterError as exc:
        if exc.argument == "delay_time":
            from .design_options import latency_message

            text = latency_message(str(exc)).replace("CA='", "--CA '")
            raise ParameterError(
                text.replace(" with values={'tau': 0.001}", " --set tau=0.001")
            ) from None
        if "box" in str(exc) or exc.argument in ("box", "loop"):
            raise ParameterError(box_text(str(exc))) from None
        raise
