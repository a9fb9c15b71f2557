"""``seapass mimo``: exact passivity of an n×n impedance matrix or of n coupled SEA axes."""

from __future__ import annotations

import argparse
from typing import Any

from ..errors import ParameterError
from .common import (
    add_force_option,
    add_json_option,
    add_plot_option,
    parse_range,
    plot_path,
    print_json,
    save_plot,
    values_from_args,
)

EXAMPLE = """examples:
  seapass mimo check --Z "[[b + k/s, c/s], [-c/s, b + k/s]]" --set b=10 --set k=100 --set c=50
  seapass mimo check --axes examples/axes/two-axis.toml --json
  seapass mimo bound c --Z "[[b + k/s, c/s], [c/s, b + k/s]]" --set b=10 --set k=100 \\
      --range -200:200 --json

--Z is the impedance matrix F = Z(s) v of expressions in s and the parameters;
--axes a TOML file of n SEA axes joined by a PD controller with gain matrices K
and B (see docs/ports.md). Passive means positive real: stable entries, simple
poles on the imaginary axis with Hermitian positive semidefinite residues, and
every principal minor of Z(jw) + Z(jw)^H >= 0.

exit codes (check): 0 passive, 1 not passive (or undecided), 2 bad input.
"""


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--Z", metavar="MATRIX", help='impedance matrix, e.g. "[[E11, E12], [E21, E22]]"'
    )
    p.add_argument("--axes", metavar="FILE", help="a TOML file of coupled SEA axes instead of --Z")
    p.add_argument(
        "--set", action="append", default=[], metavar="NAME=VALUE",
        help="parameter value, repeatable (with --axes: overrides the file)",
    )  # fmt: skip


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "mimo",
        help="passivity of an n x n impedance matrix or of coupled axes (multi-DoF)",
        description="Exact positive-realness of an n-port: every principal minor of Z + Z^H on "
        "the axis (not only the leading ones), stable entries and Hermitian positive "
        "semidefinite residues; exact intervals of one gain.",
        epilog=EXAMPLE,
    )
    ss = p.add_subparsers(dest="mimo_command", metavar="{check,bound}")
    ss.required = True
    c = ss.add_parser(
        "check", help="decide passivity (exit 0 passive, 1 not, 2 bad input)", epilog=EXAMPLE
    )
    _options(c)
    add_plot_option(c, "the principal minors with the failing bands")
    add_force_option(c)
    add_json_option(c)
    c.set_defaults(func=run_check)
    b = ss.add_parser(
        "bound", help="exact set of one parameter for which the n-port is passive", epilog=EXAMPLE
    )
    b.add_argument("param", metavar="NAME", help="the free parameter (not given with --set)")
    _options(b)
    b.add_argument("--range", default="0:1e5", metavar="LO:HI", help="search range of NAME")
    add_json_option(b)
    b.set_defaults(func=run_bound)


def n_port_from_args(args: argparse.Namespace, free: tuple[str, ...] = ()) -> Any:
    """The `NPort` of ``--Z`` or ``--axes`` with the ``--set`` values; ``free`` left free."""
    from ..ports.axes import load_axes
    from ..ports.matrixtext import parse_matrix_text
    from ..ports.mimo import NPort

    if (args.Z is None) == (args.axes is None):
        raise ParameterError(
            "give the impedance matrix with --Z or a file of coupled axes with --axes (one of them)"
        )
    values: dict[str, float | None] = dict(values_from_args(args))
    for name in free:
        if name in values:
            raise ParameterError(
                f"--set {name}: {name} is a free parameter here; do not also give it a value"
            )
    if args.Z is not None:
        rows = parse_matrix_text(args.Z, "--Z")
        return NPort.from_matrix(rows, values={**values, **dict.fromkeys(free)})
    axes = load_axes(args.axes)
    nport = axes.n_port()
    unknown = [n for n in [*values, *free] if n not in nport.parameters]
    if unknown:
        raise ParameterError(
            f"{unknown[0]}: not a parameter of the axes ({', '.join(nport.parameters)})"
        )
    return nport.with_values(**values, **dict.fromkeys(free))


def run_check(args: argparse.Namespace) -> int:
    from ..ports.mimo import mimo_is_passive

    figure = plot_path(args.plot, force=args.force)
    result = mimo_is_passive(n_port_from_args(args))
    if figure is not None:
        save_plot(lambda: result.plot(), figure, force=args.force, flag="--plot")
    if args.json:
        print_json(result.to_dict())
    else:
        print(f"{result.n}-port: {result.outcome.label}")
        for cond in result.conditions:
            if cond.holds is not True:
                bands = ", ".join(f"({b.lo:.6g}, {b.hi:.6g})" for b in cond.bands)
                print(
                    f"  {cond.name} fails"
                    + (f" for w in {bands} rad/s" if bands else f": {cond.detail}")
                )
    return 0 if result.passive else 1


def run_bound(args: argparse.Namespace) -> int:
    from ..ports.bound import port_intervals

    lo, hi = parse_range(args.range)
    nport = n_port_from_args(args, free=(args.param,))
    result = port_intervals(nport, args.param, lo, hi, criterion="passive")
    if args.json:
        print_json(result.to_dict())
    else:
        if not result.intervals:
            print(f"not passive for any {args.param} in [{lo:g}, {hi:g}]")
        for a, b in result.intervals:
            print(f"passive for {a!r} <= {args.param} <= {b!r}")
        for a, b in result.undecided:
            print(f"undecided for {a!r} <= {args.param} <= {b!r}")
    return 0
