"""``--uncertain NAME=LO:HI`` and ``--robust [RIGFILE]``: robust verdicts over a box of plants.

`add_uncertain_options` registers ``--uncertain`` (repeatable), ``--budget`` and
`add_robust_options` (``--robust [RIGFILE]``, ``--confidence LEVEL``); `box_from_args`
is the box of a command line, resolved by the library's
[`robust_box`][seapass.rig.robustbox.robust_box] (the design file's ``[uncertainty]``,
a fitted rig's ``[intervals]``, the flags over both).
`run_robust_check`, `run_robust_bound` and `run_robust_region` are the robust forms
of ``check``, ``bound`` and ``region`` (`run_robust_sampled_check` that of ``sampled
check``, with `add_sampled_uncertain_options`): they parse, call one library function
([`robust_check`][seapass.robust.verdict.robust_check],
[`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals],
[`robust_passive_map`][seapass.robust.region.robust_passive_map] or
[`robust_sampled_check`][seapass.robust.sampled_verdict.robust_sampled_check]) and
print.  A name given with ``--uncertain`` is a free parameter: giving it also
with ``--set`` is an error, as is every bad box (one ``error:`` line, exit 2).
"""

from __future__ import annotations

import argparse
import re
from collections.abc import Sequence
from typing import Any

from ..errors import ParameterError
from .common import print_json, values_from_args, warn_unrealizable

__all__ = [
    "CLI_BUDGET",
    "add_robust_options",
    "add_sampled_uncertain_options",
    "add_uncertain_options",
    "box_from_args",
    "box_text",
    "cli_text",
    "requested_box",
    "robust_design",
    "run_robust_bound",
    "run_robust_check",
    "run_robust_region",
    "run_robust_sampled_check",
    "wants_box",
]

CLI_BUDGET = 5000  # seapass.robust.verdict.DEFAULT_BUDGET (a test keeps them equal)


def add_uncertain_options(
    p: argparse.ArgumentParser,
    *,
    budget: int | None = CLI_BUDGET,
    verdict: str = "the verdict then holds for every value in the box (exact for one, "
    "certified for several)",
    boxes: str = "boxes the certified branch and bound may examine (several --uncertain)",
) -> None:
    """``--uncertain NAME=LO:HI`` (repeatable), ``--budget N``, ``--robust``, ``--confidence``."""
    g = p.add_argument_group("robust (every plant in a box)")
    g.add_argument(
        "--uncertain",
        action="append",
        default=[],
        metavar="NAME=LO:HI",
        help=f"an uncertain parameter, repeatable, e.g. --uncertain m=0.9:1.1: {verdict}",
    )
    g.add_argument(
        "--budget",
        type=int,
        default=budget,
        metavar="N",
        help=f"{boxes}; when they run out the verdict is undecided, never passive",
    )
    add_robust_options(g)


def add_robust_options(p: Any) -> None:
    """``--robust [RIGFILE]`` and ``--confidence LEVEL`` (once: a second call adds nothing)."""
    if any("--robust" in a.option_strings for a in p._actions):
        return  # a command registers --uncertain (which brings them) and --robust itself
    p.add_argument(
        "--robust",
        nargs="?",
        const="",
        default=None,
        metavar="RIGFILE",
        help="robust over a box of plants: the 95 %% intervals a fit stored in RIGFILE "
        "('rig fit --rig-out'), or with no RIGFILE the design file's [uncertainty] "
        "(give DESIGN.toml before --robust)",
    )
    p.add_argument(
        "--confidence",
        type=float,
        metavar="LEVEL",
        help="level of RIGFILE's intervals in (0, 1), recomputed from the fit's standard "
        "errors (default: the stored level)",
    )


def box_from_args(
    args: argparse.Namespace, system: Any, design: Any = None, *, free: Any = ()
) -> Any:
    """The checked box of the command line (None: no source gives one), via `robust_box`.

    ``free``: names that are not plant values here (the bounded parameter).
    """
    from ..rig.robustbox import robust_box

    raw = _raw(args)
    robust = getattr(args, "robust", None)
    confidence = getattr(args, "confidence", None)
    if confidence is not None and not robust:
        raise ParameterError("--confidence LEVEL applies to --robust RIGFILE; give the rig file")
    fixed = (set(values_from_args(args)) if hasattr(args, "set") else set()) - set(raw)
    try:
        box = robust_box(
            system, design=design, rig=robust or None, confidence=confidence, uncertain=raw,
            fixed=fixed, required=robust is not None,
        )  # fmt: skip
    except ParameterError as exc:
        raise cli_text(exc) from None
    clash = sorted(set(free) & set(box.names if box is not None else ()))
    if clash:
        raise ParameterError(
            f"{clash[0]} is uncertain (the design file's [uncertainty] or the rig's "
            "[intervals]); it cannot also be the free parameter"
        )
    return box


def requested_box(
    args: argparse.Namespace, system: Any, design: Any = None, *, free: Any = ()
) -> Any:
    """The box when the command line asks for one (``--robust``, ``--uncertain``), else None.

    For commands whose robust verdict is opt-in (``sampled``, ``tune``): the design
    file's ``[uncertainty]`` applies only with ``--robust``.
    """
    if getattr(args, "robust", None) is None and not getattr(args, "uncertain", None):
        if getattr(args, "confidence", None) is not None:
            raise ParameterError(
                "--confidence LEVEL applies to --robust RIGFILE; give the rig file"
            )
        return None
    return box_from_args(args, system, design, free=free)


def robust_design(args: argparse.Namespace, design: Any) -> Any:
    """``analyze``'s design with the box of ``--robust`` as its ``uncertainty`` (unchanged
    without ``--robust``: the robust stage reads the file's ``[uncertainty]``)."""
    import dataclasses

    box = requested_box(args, design.sea(), design)
    return design if box is None else dataclasses.replace(design, uncertainty=box.intervals)


def wants_box(args: argparse.Namespace, file: Any = None) -> bool:
    """True when a box may apply: ``--uncertain``, ``--robust`` or a design file with
    ``[uncertainty]`` (``file``: the design file the command read, or None for none)."""
    if getattr(args, "uncertain", None) or getattr(args, "robust", None) is not None:
        return True
    if getattr(args, "confidence", None) is not None:
        raise ParameterError("--confidence LEVEL applies to --robust RIGFILE; give the rig file")
    return file is not None and bool(file.uncertainty)


def _raw(args: argparse.Namespace) -> dict[str, tuple[float, float]]:
    from ..robust.box import parse_uncertain

    try:
        return parse_uncertain(getattr(args, "uncertain", []) or [])
    except ParameterError as exc:
        raise cli_text(exc) from None


def cli_text(exc: ParameterError) -> ParameterError:
    """The library's ``box['m']`` / ``budget`` in the words of the command line."""
    msg = re.sub(r"box\['(\w+)'\]", r"--uncertain \1", str(exc))
    msg = re.sub(r"e\.g\. box=\{'(\w+)': \([^)]*\)\}", r"e.g. --uncertain \1=LO:HI", msg)
    msg = re.sub(r"^budget ", "--budget ", msg)
    msg = re.sub(r"^confidence ", "--confidence ", msg)
    msg = re.sub(r"^rtol must", "--rtol must", msg).replace("; got rtol=", "; got --rtol ")
    return ParameterError(msg.replace("drop the confidence", "drop --confidence"))


def _box_and_model(
    args: argparse.Namespace, extra_free: dict[str, str], file: Any = None
) -> tuple[Any, Any]:
    from ..model.sea import Impedance

    raw = _raw(args)
    if args.budget < 1:
        raise ParameterError(f"--budget must be a positive integer, got {args.budget}")
    labels = {name: f"--uncertain {name}" for name in raw}
    clash = set(labels) & set(extra_free)
    if clash:
        name = sorted(clash)[0]
        raise ParameterError(
            f"--uncertain {name}: {name} is already the parameter of `{extra_free[name]}`; "
            "it cannot also be uncertain"
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
        design = None
    else:
        from .design_options import design_from_args

        resolved = design_from_args(args, {**extra_free, **labels}, file=file)
        system, design = resolved.sea, resolved.design
        warn_unrealizable(system)
    return system, box_from_args(args, system, design, free=extra_free)


def box_text(box: Any) -> str:
    """``m in [0.9, 1.1], ...``: each end the shortest text that reads back as its double."""
    from ..exact.rounding import exact_text

    items = box.intervals.items()
    return ", ".join(f"{k} in [{exact_text(a)}, {exact_text(b)}]" for k, (a, b) in items)


def run_robust_check(args: argparse.Namespace, file: Any = None) -> int | None:
    """``check --uncertain ...``: exit 0 passive for every plant, 1 not passive or undecided.

    None when no source gives a box (the plain check runs).  ``file``: the design
    file the command read (`design_file_from_args`), passed along, not read again.
    """
    from ..robust.verdict import robust_check

    system, box = _box_and_model(args, {}, file)
    if box is None:
        return None
    try:
        result = robust_check(system, box=box, budget=args.budget)
    except ParameterError as exc:
        raise cli_text(exc) from None
    if args.json:
        print_json(result.to_dict())
    else:
        span = box_text(box)
        print(
            f"{result.outcome.label} for every plant with {span} ({result.method}): {result.detail}"
        )
        if result.worst is not None:
            at = ", ".join(f"{k}={v:.10g}" for k, v in result.worst.values.items())
            w = result.worst.frequency
            print(f"worst case: {at}" + (f", Re Z(jw) < 0 at w = {w:.6g} rad/s" if w else ""))
    return 0 if result.passive else 1


def run_robust_bound(args: argparse.Namespace, file: Any = None) -> int | None:
    """``bound PARAM --uncertain ...``: the robust passive set of PARAM (None: no box);
    ``file`` as in `run_robust_check`."""
    from ..exact.rounding import enclosure_text, interval_text
    from ..robust.intervals import robust_passive_intervals
    from ..robust.verdict import Method
    from .design_options import design_from_args, ranges_from_args

    given = ranges_from_args(args, [args.param], strict=False)[args.param]
    free = {args.param: f"bound {args.param}"}
    lo, hi = design_from_args(args, free, file=file).range_of(args.param, given)
    system, box = _box_and_model(args, free, file)
    if box is None:
        return None
    try:
        rtol = getattr(args, "rtol", None)
        result = robust_passive_intervals(
            system, args.param, lo, hi, box=box, budget=args.budget,
            **({} if rtol is None else {"rtol": rtol}),
        )  # fmt: skip
    except ParameterError as exc:
        raise cli_text(exc) from None
    if args.json:
        print_json(result.to_dict())
        return 0
    span = box_text(box)
    if result.delay is not None:  # the sets are at the design's delay
        span += f"; at {result.delay['name']} = {result.delay['tau']:g} s"
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


def run_robust_region(
    args: argparse.Namespace,
    x_values: Any,
    y_range: tuple[float, float],
    figure: Any,
    units: tuple[str | None, str | None],
    file: Any = None,
) -> int | None:
    """``region X Y --uncertain ...``: per column, the robust passive set of Y beside the nominal.

    None when no source gives a box (the plain region runs); ``file`` as in `run_robust_check`.
    """
    from ..exact.rounding import enclosure_text, exact_text
    from ..robust.region import robust_passive_map
    from ..robust.verdict import Method
    from .common import save_plot

    labels = {args.x: f"region X {args.x}", args.y: f"region Y {args.y}"}
    system, box = _box_and_model(args, labels, file)
    if box is None:
        return None
    try:
        result = robust_passive_map(
            system, args.x, x_values, args.y, y_range, box=box, budget=args.budget
        )
    except ParameterError as exc:
        raise cli_text(exc) from None
    if figure is not None:
        from ..plot.region import plot_robust_map

        save_plot(
            lambda: plot_robust_map(result, title="robust passive region", units=units),
            figure,
            force=args.force,
            flag="--plot",
        )
    if args.json:
        print_json(result.to_dict())
        return 0
    span = ", ".join(f"{k} in [{a:g}, {b:g}]" for k, (a, b) in box.intervals.items())
    nominal = ", ".join(f"{k}={v:g}" for k, v in result.nominal_values.items())
    at = "" if result.delay is None else f" at {result.delay['name']} = {result.delay['tau']:g} s"
    print(f"robust: passive for every plant with {span}{at} ({result.method}); nominal: {nominal}")
    for i, xv in enumerate(result.x):
        robust = _pieces_text(result.intervals[i])
        nom = _pieces_text(result.nominal[i])
        line = f"{args.x} = {exact_text(float(xv))}: robust {args.y} in {robust}; nominal {nom}"
        if result.method is not Method.EXACT:
            outer = ", ".join(enclosure_text(a, b) for a, b in result.outer[i]) or "empty"
            line += f"; outer {outer}"
        print(line)
    return 0


def _pieces_text(intervals: Sequence[tuple[float, float]], *, most: int = 6) -> str:
    """A passive set as text; a long list of pieces (e.g. values proven one by one at a
    delay) is cut to its first and last pieces and a count (--json has them all)."""
    from ..exact.rounding import interval_text

    texts = [interval_text(a, b) for a, b in intervals]
    if len(texts) > most:
        texts = [*texts[:3], f"... ({len(texts)} pieces in all; --json lists them)", texts[-1]]
    return ", ".join(texts) or "none"


def add_sampled_uncertain_options(p: argparse.ArgumentParser) -> None:
    """The options of `add_uncertain_options` on ``sampled check`` (plant parameters only)."""
    add_uncertain_options(
        p,
        budget=4,
        verdict="passive then means certified for every plant in the box (plant parameters)",
        boxes="sub-boxes the certified branch and bound may examine",
    )


def run_robust_sampled_check(args: argparse.Namespace, default_loop: Any) -> int:
    """``sampled check --uncertain ...``: exit 0 passive for every plant, 1 otherwise."""
    from ..robust.box import parse_uncertain
    from ..robust.sampled_verdict import robust_sampled_check
    from .design_options import design_from_args

    try:
        raw = parse_uncertain(args.uncertain)
        resolved = design_from_args(
            args, {n: f"--uncertain {n}" for n in raw}, default_loop=default_loop
        )
        warn_unrealizable(resolved.sea)
        # the box of the flags, the file's [uncertainty] and a fitted rig (--robust)
        box = requested_box(args, resolved.sea, resolved.design)
        assert box is not None  # --uncertain or --robust was given: robust_box requires a box
        result = robust_sampled_check(resolved.sea, loop=resolved.loop, box=box, budget=args.budget)
    except ParameterError as exc:
        raise cli_text(exc) from None
    if args.json:
        print_json(result.to_dict())
    else:
        span = ", ".join(f"{k} in [{lo:g}, {hi:g}]" for k, (lo, hi) in box.intervals.items())
        loop = resolved.loop
        print(
            f"{result.outcome.label} over the box {span} at T = {loop.period:g} s "
            f"(delay {loop.delay}): {result.detail}"
        )
        if result.worst is not None:
            at = ", ".join(f"{k}={v:.10g}" for k, v in result.worst.values.items())
            w = result.worst.frequency
            print(f"worst case: {at}" + (f", N(w) < 0 at w = {w:.6g} rad/s" if w else ""))
    return 0 if result.passive else 1
