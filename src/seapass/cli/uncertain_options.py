"""``--uncertain NAME=LO:HI`` on ``check`` and ``bound``: robust verdicts over a box of plants.

`add_uncertain_options` registers ``--uncertain`` (repeatable) and ``--budget``;
`run_robust_check` and `run_robust_bound` are the robust forms of ``check`` and
``bound``: they parse, call one library function
([`robust_check`][seapass.robust.verdict.robust_check] or
[`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals])
and print.  A name given with ``--uncertain`` is a free parameter: giving it also
with ``--set`` is an error, as is every bad box (one ``error:`` line, exit 2).
"""

from __future__ import annotations

import argparse
import re
from typing import Any

from ..errors import ParameterError
from .common import print_json, values_from_args, warn_unrealizable

__all__ = ["CLI_BUDGET", "add_uncertain_options", "run_robust_bound", "run_robust_check"]

CLI_BUDGET = 5000  # seapass.robust.verdict.DEFAULT_BUDGET (a test keeps them equal)


def add_uncertain_options(p: argparse.ArgumentParser) -> None:
    """``--uncertain NAME=LO:HI`` (repeatable) and ``--budget N``."""
    g = p.add_argument_group("robust (every plant in a box)")
    g.add_argument(
        "--uncertain",
        action="append",
        default=[],
        metavar="NAME=LO:HI",
        help="an uncertain parameter, repeatable, e.g. --uncertain m=0.9:1.1: the verdict "
        "then holds for every value in the box (exact for one, certified for several)",
    )
    g.add_argument(
        "--budget",
        type=int,
        default=CLI_BUDGET,
        metavar="N",
        help="boxes the certified branch and bound may examine (several --uncertain); "
        "when they run out the verdict is undecided, never passive",
    )


def _cli_text(exc: ParameterError) -> ParameterError:
    """The library's ``box['m']`` / ``budget`` in the words of the command line."""
    msg = re.sub(r"box\['(\w+)'\]", r"--uncertain \1", str(exc))
    msg = re.sub(r"e\.g\. box=\{'(\w+)': \([^)]*\)\}", r"e.g. --uncertain \1=LO:HI", msg)
    msg = re.sub(r"^budget ", "--budget ", msg)
    return ParameterError(msg)


def _box_and_model(args: argparse.Namespace, extra_free: dict[str, str]) -> tuple[Any, Any]:
    from ..model.sea import Impedance
    from ..robust.box import parse_uncertain, uncertain_box

    try:
        raw = parse_uncertain(args.uncertain)
    except ParameterError as exc:
        raise _cli_text(exc) from None
    if args.budget < 1:
        raise ParameterError(f"--budget must be a positive integer, got {args.budget}")
    labels = {name: f"--uncertain {name}" for name in raw}
    clash = set(labels) & set(extra_free)
    if clash:
        name = sorted(clash)[0]
        raise ParameterError(
            f"--uncertain {name}: {name} is the bounded parameter; it cannot also be uncertain"
        )
    if getattr(args, "Z", None) is not None:
        if getattr(args, "design", None) is not None or any(
            getattr(args, e) is not None for e in ("D1", "D2", "CA", "CL")
        ):
            raise ParameterError(
                "give either --Z or a design (DESIGN.toml, --D1/--D2/--CA/--CL), not both"
            )
        values = values_from_args(args)
        for name in raw:
            if name in values:
                raise ParameterError(
                    f"--set {name}: {name} is a free parameter here (--uncertain {name}); do not "
                    "also give it a value"
                )
        system: Any = Impedance(expr=args.Z, values=values)
    else:
        from .design_options import design_from_args

        system = design_from_args(args, {**extra_free, **labels}).sea
        warn_unrealizable(system)
    try:
        box = uncertain_box(system, raw)
    except ParameterError as exc:
        raise _cli_text(exc) from None
    return system, box


def run_robust_check(args: argparse.Namespace) -> int:
    """``check --uncertain ...``: exit 0 passive for every plant, 1 not passive or undecided."""
    from ..robust.verdict import robust_check

    system, box = _box_and_model(args, {})
    try:
        result = robust_check(system, box=box, budget=args.budget)
    except ParameterError as exc:
        raise _cli_text(exc) from None
    if args.json:
        print_json(result.to_dict())
    else:
        span = ", ".join(f"{k} in [{lo:g}, {hi:g}]" for k, (lo, hi) in box.intervals.items())
        print(
            f"{result.outcome.label} for every plant with {span} ({result.method}): {result.detail}"
        )
        if result.worst is not None:
            at = ", ".join(f"{k}={v:.10g}" for k, v in result.worst.values.items())
            w = result.worst.frequency
            print(f"worst case: {at}" + (f", Re Z(jw) < 0 at w = {w:.6g} rad/s" if w else ""))
    return 0 if result.passive else 1


def run_robust_bound(args: argparse.Namespace) -> int:
    """``bound PARAM --uncertain ...``: the robust passive set of PARAM (inner and outer)."""
    from ..exact.rounding import enclosure_text, interval_text
    from ..robust.intervals import robust_passive_intervals
    from ..robust.verdict import Method
    from .design_options import design_from_args, ranges_from_args

    given = ranges_from_args(args, [args.param], strict=False)[args.param]
    lo, hi = design_from_args(args, {args.param: f"bound {args.param}"}).range_of(args.param, given)
    system, box = _box_and_model(args, {args.param: f"bound {args.param}"})
    try:
        result = robust_passive_intervals(system, args.param, lo, hi, box=box, budget=args.budget)
    except ParameterError as exc:
        raise _cli_text(exc) from None
    if args.json:
        print_json(result.to_dict())
        return 0
    span = ", ".join(f"{k} in [{a:g}, {b:g}]" for k, (a, b) in box.intervals.items())
    if not result.intervals:
        print(f"not passive for every plant ({span}) for any {args.param} in [{lo:g}, {hi:g}]")
    for a, b in result.intervals:  # rounded inward: the printed ends are robustly passive
        print(
            f"passive for every plant ({span}) for {args.param} in {interval_text(a, b, digits=10)}"
        )
    if result.method is not Method.EXACT:
        outer = ", ".join(enclosure_text(a, b, digits=10) for a, b in result.outer) or "empty"
        print(f"certified: inner set above; no value outside {outer} is robustly passive")
    return 0
