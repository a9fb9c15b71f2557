"""``seapass twoport``: the SEA (or any 2×2 immittance) as a two-port, decided exactly."""

from __future__ import annotations

import argparse
from typing import Any

from ..errors import ParameterError, SeapassError
from ..files.limits import MAX_REGION_COLUMNS
from ..outcome import Outcome
from .common import (
    add_force_option,
    add_json_option,
    add_model_options,
    add_plot_option,
    model_from_args,
    parse_range,
    plot_path,
    print_json,
    save_plot,
    values_from_args,
    warn,
    warn_unrealizable,
)
from .design_options import (
    add_range_options,
    design_file_from_args,
    points_from_args,
    ranges_from_args,
)
from .uncertain_options import add_uncertain_options, box_text, wants_box

EXAMPLE = """examples:
  seapass twoport check --D1 "k1 + b1*s" --CA "kd + bd*s" --CL kl --set m=1 --set b=10 \\
      --set k1=1000 --set b1=20 --set kd=500 --set bd=25 --set kl=300 --json
  seapass twoport check examples/ours.toml --plot eta.png
  seapass twoport check --Z11 "mm*s + bm" --Z12 1 --Z21 -1 --Z22 "1/(ms*s + bs + kc/s)" \\
      --form h --set mm=0.5 --set bm=2 --set ms=1 --set bs=5 --set kc=400
  seapass twoport bound kl --D1 "k1 + b1*s" --CA "kd + bd*s" --CL kl --set m=1 --set b=10 \\
      --set k1=1000 --set b1=20 --set kd=500 --set bd=25 --range 0:1e4 --json
  seapass twoport check examples/ours.toml --uncertain m=0.9:1.1 --uncertain b=8:12 --json
  seapass twoport bound kl --D1 "k1 + b1*s" --CA "kd + bd*s" --CL kl --set b=10 \\
      --set k1=1000 --set b1=20 --set kd=500 --set bd=25 --uncertain m=0.9:1.1 --range 0:3000
  seapass twoport region kd kl --D1 "k1 + b1*s" --CA "kd + bd*s" --CL kl --set m=1 \\
      --set b=10 --set k1=1000 --set b1=20 --set bd=25 --range kd=0:5000 --range kl=0:5000 \\
      --points 11
  seapass twoport friction --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 \\
      --set k1=1000 --set b1=20 --set kd=500 --set bd=25 --at actuator

Port 1 is the person (F_L, v_L = s x_L); port 2 the virtual environment: the
controllers act on the error to its position theta, f_A = C_A (theta - x_A) +
C_L (theta - x_L), and F_2 = f_A, v_2 = s theta. A passive termination obeys
F = -Z v. Absolutely stable: stable with every pair of passive terminations
(Llewellyn); passive: the immittance matrix is positive real (Raisbeck).

With --uncertain NAME=LO:HI (or --robust, or a design file's [uncertainty]) check
and bound hold for every plant in the box (check: exact for one uncertain
parameter, certified by exact Bernstein branch and bound for several; bound:
certified inner and outer sets); what cannot be certified is 'undecided', never
absolutely stable or passive.  region: --range/--range2/--nx
are the old spellings of --range X=..., --range Y=... and --points.

exit codes (check): 0 absolutely stable (for every plant of a box), 1 not (or
undecided), 2 bad input;
(friction): 0 certified, 1 not certified, 2 bad input.
"""

_ENTRIES = ("Z11", "Z12", "Z21", "Z22")
REGION_POINTS = 21
DEFAULT_RANGE = (0.0, 1e5)


def _system_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("design", nargs="?", metavar="DESIGN", help="a design file (TOML)")
    add_model_options(p)
    g = p.add_argument_group("a 2x2 immittance instead of an SEA")
    for e in _ENTRIES:
        g.add_argument(f"--{e}", metavar="EXPR", help=f"entry {e[1:]} of the matrix")
    g.add_argument(
        "--form", choices=("z", "y", "h", "g"), default=None,
        help="form of --Z11..--Z22: z [F1,F2]=Z[v1,v2], y [v1,v2]=Y[F1,F2], h [F1,v2]=H[v1,F2], "
        "g [v1,F2]=G[F1,v2] (default: z)",
    )  # fmt: skip


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "twoport",
        help="absolute stability and passivity of the SEA as a two-port (person, environment)",
        description="The SEA between the person and the virtual environment it renders, or any "
        "2x2 immittance, decided exactly: Llewellyn's absolute stability with the exact failing "
        "bands and eta, two-port passivity, reciprocity, a destabilizing pair of passive "
        "terminations, exact gain intervals and the friction certificate.",
        epilog=EXAMPLE,
    )
    ss = p.add_subparsers(dest="twoport_command", metavar="{check,bound,region,friction,convert}")
    ss.required = True
    c = ss.add_parser(
        "check",
        help="every two-port verdict (exit 0 absolutely stable, 1 not, 2 bad input)",
        epilog=EXAMPLE,
    )
    _system_options(c)
    c.add_argument(
        "--no-witness",
        action="store_true",
        help="do not search a destabilizing pair of terminations",
    )
    add_plot_option(c, "eta(w) with the failing bands")
    add_uncertain_options(c, verdict="both verdicts then hold for every value in the box")
    add_force_option(c)
    add_json_option(c)
    c.set_defaults(func=run_check)
    b = ss.add_parser(
        "bound", help="exact set of one parameter for which the criterion holds", epilog=EXAMPLE
    )
    b.add_argument("param", metavar="NAME", help="the free parameter (not given with --set)")
    _system_options(b)
    b.add_argument("--range", default="0:1e5", metavar="LO:HI", help="search range of NAME")
    b.add_argument(
        "--criterion",
        choices=("absolute", "passive"),
        default="absolute",
        help="absolute stability or passivity",
    )
    add_uncertain_options(
        b, verdict="the set then holds for every plant in the box (certified inner and outer sets)"
    )
    b.add_argument(
        "--rtol",
        type=float,
        default=1e-3,
        help="relative width where the robust inner set stops bisecting (with a box)",
    )
    add_json_option(b)
    b.set_defaults(func=run_bound)
    r = ss.add_parser(
        "region", help="exact set of Y at each of --points values of X", epilog=EXAMPLE
    )
    r.add_argument("param_x", metavar="X", help="parameter of the columns")
    r.add_argument("param_y", metavar="Y", help="parameter bounded exactly in each column")
    _system_options(r)
    add_range_options(
        r, points=REGION_POINTS, points_help=f"number of X values, 1 to {MAX_REGION_COLUMNS}"
    )
    r.add_argument("--range2", help=argparse.SUPPRESS)  # before 0.5: --range Y=LO:HI
    r.add_argument("--nx", type=int, help=argparse.SUPPRESS)  # before 0.5: --points
    r.add_argument(
        "--criterion",
        choices=("absolute", "passive"),
        default="absolute",
        help="absolute stability or passivity",
    )
    add_plot_option(r, "the map")
    add_force_option(r)
    add_json_option(r)
    r.set_defaults(func=run_region)
    f = ss.add_parser(
        "friction",
        help="certify that every passive friction law keeps the SEA passive",
        epilog=EXAMPLE,
    )
    f.add_argument("design", nargs="?", metavar="DESIGN", help="a design file (TOML)")
    add_model_options(f)
    f.add_argument(
        "--at",
        choices=("actuator", "transmission"),
        default="actuator",
        help="where the friction acts",
    )
    add_json_option(f)
    f.set_defaults(func=run_friction)
    v = ss.add_parser(
        "convert",
        help="the two-port in another form (refused where it does not exist)",
        epilog=EXAMPLE,
    )
    _system_options(v)
    v.add_argument("--to", required=True, choices=("z", "y", "h", "g"), help="the target form")
    add_json_option(v)
    v.set_defaults(func=run_convert)


def _sea(
    args: argparse.Namespace,
    free: tuple[str, ...],
    labels: dict[str, str] | None = None,
    file: Any = None,
) -> Any:
    """The SEA of DESIGN (with --set overrides) or of the model options; ``free`` left free
    (``labels``: how each was given, for messages; ``file``: DESIGN already read)."""
    labels = {n: n for n in free} | (labels or {})

    elements = any(getattr(args, e) not in (None, "0") for e in ("D1", "D2", "CA", "CL"))
    if args.design is not None:
        if elements:
            raise ParameterError(
                "give either DESIGN or the model elements --D1/--D2/--CA/--CL, not both"
            )
        sea = (file if file is not None else design_file_from_args(args)).sea()
        over = values_from_args(args)
        for name in free:
            if name in over:
                raise ParameterError(
                    f"--set {name}: {name} is a free parameter here ({labels[name]}); do not "
                    "also give it a value"
                )
            if name not in sea.parameters:
                raise ParameterError(
                    f"{labels[name]}: {name} is not a parameter of the design "
                    f"({', '.join(sea.parameters)})"
                )
        return sea.with_values(**over, **dict.fromkeys(free))
    if not elements:
        raise ParameterError(
            "nothing to check: give a design file, the model (--D1 ... --set ...) or the matrix "
            "(--Z11 --Z12 --Z21 --Z22)"
        )
    return model_from_args(args, extra_free=labels)


def two_port_from_args(
    args: argparse.Namespace,
    free: tuple[str, ...] = (),
    labels: dict[str, str] | None = None,
    file: Any = None,
) -> Any:
    """The `TwoPort` of the command line: DESIGN, the model options, or --Z11..--Z22 [--form]
    (``file``: DESIGN already read by `design_file_from_args`)."""
    labels = {n: n for n in free} | (labels or {})
    from ..ports.twoport import TwoPort, two_port

    given = [e for e in _ENTRIES if getattr(args, e, None) is not None]
    if given:
        missing = [f"--{e}" for e in _ENTRIES if e not in given]
        if missing:
            raise ParameterError(f"give all four entries: {', '.join(missing)} missing")
        if args.design is not None or any(
            getattr(args, e) not in (None, "0") for e in ("D1", "D2", "CA", "CL")
        ):
            raise ParameterError(
                "give either the matrix --Z11..--Z22 or a design (file or --D1 ...), not both"
            )
        values: dict[str, float | None] = dict(values_from_args(args))
        for name in free:
            if name in values:
                raise ParameterError(
                    f"--set {name}: {name} is a free parameter here ({labels[name]}); do not "
                    "also give it a value"
                )
            values[name] = None
        m = [[args.Z11, args.Z12], [args.Z21, args.Z22]]
        try:
            return TwoPort.from_matrix(m, form=args.form or "z", values=values)
        except SeapassError as exc:  # name the flag of the entry, not its Python label
            label = exc.argument or ""
            if len(label) == 3 and label[0] in "zyhg" and label[1:] in ("11", "12", "21", "22"):
                raise type(exc)(f"--Z{label[1:]}{str(exc)[len(label) :]}") from None
            raise
    if args.form is not None:
        raise ParameterError("--form applies to a matrix given with --Z11 --Z12 --Z21 --Z22")
    sea = _sea(args, free, labels, file)
    warn_unrealizable(sea)
    return two_port(sea)


def _robust_two_port(
    args: argparse.Namespace, free: tuple[str, ...] = (), file: Any = None
) -> tuple[Any, Any]:
    """``(TwoPort, box)`` of a command line that may give a box (box None: no source gives
    one); ``file``: DESIGN already read."""
    from ..robust.box import parse_uncertain
    from .uncertain_options import box_from_args

    if args.budget < 1:
        raise ParameterError(f"--budget must be a positive integer, got {args.budget}")
    raw = parse_uncertain(args.uncertain)
    clash = sorted(set(raw) & set(free))
    if clash:
        raise ParameterError(
            f"--uncertain {clash[0]}: {clash[0]} is the free parameter here; it cannot also be "
            "uncertain"
        )
    labels = {**{n: n for n in free}, **{n: f"--uncertain {n}" for n in raw}}
    tp = two_port_from_args(args, (*free, *raw), labels, file)
    return tp, box_from_args(args, tp, file, free=free)


def _bands(bands: Any) -> str:
    return ", ".join(f"({b.lo:.6g}, {b.hi:.6g})" for b in bands)


def run_check(args: argparse.Namespace) -> int:
    from ..ports.check import check_two_port
    from ..ports.stability import eta_text

    file = design_file_from_args(args)  # read once, passed along
    if wants_box(args, file) and (code := _run_robust_check(args, file)) is not None:
        return code  # a box: --uncertain, --robust, the file's [uncertainty]
    figure = plot_path(args.plot, force=args.force)
    tp = two_port_from_args(args, file=file)
    result = check_two_port(tp, witness=not args.no_witness)
    stab = result.stability
    if figure is not None:
        save_plot(lambda: stab.plot(), figure, force=args.force, flag="--plot")
    if args.json:
        print_json(result.to_dict())
    else:
        if stab.absolutely_stable:
            print("absolutely stable (Llewellyn, exact)")
        else:
            word = "undecided" if stab.outcome is Outcome.UNDECIDED else "not absolutely stable"
            parts = [
                f"{c.name} fails for w in {_bands(c.bands)} rad/s"
                if c.bands
                else f"{c.name}: {c.detail or 'fails'}"
                for c in stab.conditions
                if c.holds is not True
            ]
            print(f"{word}: " + "; ".join(parts))
        pas = result.passivity
        failing = ", ".join(c.name for c in pas.conditions if c.holds is not True)
        print(
            f"two-port: {pas.outcome.label}"
            + (f" ({failing})" if failing else "")
            + f"; reciprocal: {'yes' if result.reciprocal else 'no'}"
        )
        print(f"inf eta = {eta_text(stab.eta)}")
        if stab.witness is not None:
            print(f"witness: {stab.witness.detail}")
    return 0 if result.absolutely_stable else 1


def _run_robust_check(args: argparse.Namespace, file: Any) -> int | None:
    """``twoport check --uncertain ...``: exit 0 absolutely stable for every plant, else 1."""
    from ..robust.twoport import robust_two_port_check

    figure = plot_path(args.plot, force=args.force)
    tp, box = _robust_two_port(args, file=file)
    if box is None:
        return None
    result = robust_two_port_check(tp, box=box, budget=args.budget)
    if figure is not None and result.worst is None:
        warn(f"--plot {figure}: no worst plant to draw (absolute stability over the box: "
             f"{result.stability.outcome.label}); nothing written")  # fmt: skip
    elif figure is not None:
        save_plot(lambda: result.plot(), figure, force=args.force, flag="--plot")
    if args.json:
        print_json(result.to_dict())
        return 0 if result.absolutely_stable else 1
    span = box_text(box)
    for v in (result.stability, result.passivity):
        word = "undecided" if v.outcome is Outcome.UNDECIDED else (
            v.criterion.label if v.holds else f"not {v.criterion.label}"
        )  # fmt: skip
        print(f"{word} for every plant with {span} ({v.method}): {v.detail}")
        if v.worst is not None:
            at = ", ".join(f"{k}={x:.10g}" for k, x in v.worst.values.items())
            w = v.worst.frequency
            where = f" at w = {w:.6g} rad/s" if w is not None else ""
            print(f"worst plant: {at}; {v.worst.condition} fails{where} (exact verdict there)")
    return 0 if result.absolutely_stable else 1


def _run_robust_bound(args: argparse.Namespace, lo: float, hi: float, file: Any) -> int | None:
    from ..exact.rounding import enclosure_text, interval_text
    from ..robust.portbound import robust_port_intervals

    tp, box = _robust_two_port(args, (args.param,), file)
    if box is None:
        return None
    result = robust_port_intervals(
        tp, args.param, lo, hi, box=box, criterion=args.criterion, rtol=args.rtol,
        budget=args.budget,
    )  # fmt: skip
    if args.json:
        print_json(result.to_dict())
        return 0
    what, span = result.criterion.label, box_text(box)
    if not result.intervals:
        print(
            f"not proven {what} for every plant ({span}) for any {args.param} in [{lo:g}, {hi:g}]"
        )
    for a, b in result.intervals:  # rounded inward: the printed ends hold for every plant
        print(
            f"{what} for every plant ({span}) for {args.param} in {interval_text(a, b, digits=10)}"
        )
    outer = ", ".join(enclosure_text(a, b, digits=10) for a, b in result.outer) or "empty"
    print(f"certified: inner set above; no value outside {outer} is {what} for every plant")
    return 0


def run_bound(args: argparse.Namespace) -> int:
    from ..ports.bound import port_intervals

    lo, hi = parse_range(args.range)
    file = design_file_from_args(args)  # read once, passed along
    if wants_box(args, file) and (code := _run_robust_bound(args, lo, hi, file)) is not None:
        return code
    tp = two_port_from_args(args, free=(args.param,), file=file)
    result = port_intervals(tp, args.param, lo, hi, criterion=args.criterion)
    if args.json:
        print_json(result.to_dict())
    else:
        what = result.criterion.label
        if not result.intervals:
            print(f"not {what} for any {args.param} in [{lo:g}, {hi:g}]")
        for a, b in result.intervals:
            print(f"{what} for {a!r} <= {args.param} <= {b!r}")
        for a, b in result.undecided:
            print(f"undecided for {a!r} <= {args.param} <= {b!r}")
    return 0


def run_region(args: argparse.Namespace) -> int:
    import numpy as np

    from ..files.limits import MAX_REGION_COLUMNS
    from ..ports.bound import port_region

    if args.param_x == args.param_y:
        raise ParameterError("X and Y must be different parameters")
    nx = points_from_args(args, "nx", REGION_POINTS)
    if not 1 <= nx <= MAX_REGION_COLUMNS:
        raise ParameterError(f"--points {nx}: use between 1 and {MAX_REGION_COLUMNS} columns")
    given = ranges_from_args(
        args, [args.param_x, args.param_y], {args.param_y: ("--range2", args.range2)}, strict=False
    )
    x_lo, x_hi = given[args.param_x] or DEFAULT_RANGE
    y_range = given[args.param_y] or DEFAULT_RANGE
    figure = plot_path(args.plot, force=args.force)
    tp = two_port_from_args(args, free=(args.param_x, args.param_y))
    xs = np.linspace(x_lo, x_hi, nx)
    region = port_region(tp, args.param_x, xs, args.param_y, y_range, criterion=args.criterion)
    if figure is not None:
        from ..plot.ports import plot_port_region

        save_plot(lambda: plot_port_region(region), figure, force=args.force, flag="--plot")
    if args.json:
        print_json(region.to_dict())
    else:
        for x, col in zip(region.x, region.columns, strict=True):
            shown = ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in col.intervals) or "none"
            print(f"{args.param_x} = {x:.6g}: {args.param_y} in {shown}")
    return 0


def run_friction(args: argparse.Namespace) -> int:
    from ..ports.friction import friction_certificate

    sea = _sea(args, ())
    warn_unrealizable(sea)
    result = friction_certificate(sea, at=args.at)
    if args.json:
        print_json(result.to_dict())
    else:
        print(result.detail)
    return 0 if result.certified else 1


def run_convert(args: argparse.Namespace) -> int:
    tp = two_port_from_args(args).convert(args.to)
    if args.json:
        print_json(tp.to_dict())
    else:
        for (i, j), e in zip(((1, 1), (1, 2), (2, 1), (2, 2)), tp.entries, strict=True):
            print(f"{args.to}{i}{j} = {e}")
    return 0
