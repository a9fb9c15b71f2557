"""``seapass tune --objective rendering|force-bandwidth|zwidth``: the options and the run.

Kept apart from [`cmd_tune`][seapass.cli.cmd_tune] so that the step-response tuning and
the interaction-control objectives each stay short; the library job is
[`tune_objective`][seapass.tuning.interaction.tune_objective].
"""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from ..errors import ParameterError, TuningWarning
from .common import cli_words, print_json, warn

if TYPE_CHECKING:  # the CLI starts fast
    from ..tuning.objective_result import ObjectiveTuningResult
    from ..tuning.problem import TuningOptions

__all__ = ["add_objective_options", "parse_band", "run_objective"]


def add_objective_options(g: Any) -> None:
    """``--target``, ``--band``, ``--stiffness``, ``--max-boxes`` in the group ``g``."""
    g.add_argument("--target", metavar="EXPR",
                   help="rendering: the target stiffness F_L/X_L in s and the design's "
                   "parameters, e.g. \"kv + bv*s\" or \"1000 + 5*s\"")  # fmt: skip
    g.add_argument("--band", metavar="LO:HI",
                   help="rendering: the band [rad/s] of the error (required); force-bandwidth: "
                   "the band searched for the -3 dB frequency (default: 0.01:100000)")  # fmt: skip
    g.add_argument("--stiffness", metavar="NAME",
                   help="zwidth: the virtual-stiffness gain (default: kv, else kd, else the "
                   "first controller gain)")  # fmt: skip
    g.add_argument("--max-boxes", type=int, default=2000, metavar="N",
                   help="zwidth: branch-and-bound boxes per candidate (default: 2000)")  # fmt: skip


def parse_band(text: str | None) -> tuple[float, float] | None:
    """``LO:HI`` into ``(lo, hi)`` (checked by the library: ``0 < lo < hi``)."""
    from ..model.expr import parse_value

    if text is None:
        return None
    lo, sep, hi = text.partition(":")
    if not sep:
        raise ParameterError(f"--band {text!r}: expected LO:HI in rad/s, e.g. --band 1:100")
    return parse_value(lo.strip(), "--band lower end"), parse_value(hi.strip(), "--band upper end")


def run_objective(
    args: argparse.Namespace,
    design: Any,
    boxes: Mapping[str, tuple[float, float] | None],
    values: Mapping[str, float],
    opts: TuningOptions,
) -> int:
    """Run `tune_objective` for the parsed command line and print the result."""
    from ..tuning.interaction import tune_objective
    from ..tuning.objectives import InteractionObjective
    from .progress import choose_progress

    in_z = getattr(_sea_of(design), "discrete", None) is not None  # runs at its own rate
    if args.objective == "zwidth" and opts.loop is None and not in_z:
        raise ParameterError(
            "--objective zwidth needs the loop rate: give --period T or a design file "
            "with a [control] rate"
        )
    if args.objective != "rendering" and args.target is not None:
        raise ParameterError("--target applies to --objective rendering only")
    spec = InteractionObjective(
        kind=args.objective, target=args.target, band=parse_band(args.band),
        stiffness=args.stiffness, max_boxes=args.max_boxes,
    )  # fmt: skip
    with warnings.catch_warnings(), choose_progress(not args.no_progress) as progress:
        warnings.simplefilter("ignore", TuningWarning)  # printed below, once, as lines
        result = tune_objective(
            design, spec, tune=boxes or None, values=values or None, options=opts,
            progress=progress, allow_plant=args.allow_plant,
        )  # fmt: skip
    for message in result.warnings:
        warn(cli_words(message))
    if args.json:
        print_json(result.to_dict())
    else:
        print_objective(result)
    loop = getattr(design, "loop", None)
    if loop is not None and opts.loop is not None and args.period is None and not in_z:
        print(
            f"note: passivity also required at the design file's {loop.rate:g} Hz "
            "([control]); --continuous drops it",
            file=sys.stderr,
        )
    return 0 if result.feasible else 1


def _sea_of(design: Any) -> Any:
    """The SEA of a design, catalog name or model (None for a catalog name)."""
    return design if not hasattr(design, "sea") or not callable(design.sea) else design.sea()


def print_objective(result: ObjectiveTuningResult) -> None:
    """The text output: the gains, what was achieved, what passivity cost."""
    from ..tuning.objective_result import value_text

    kind, unit = result.kind, result.unit
    c, u = result.constrained, result.unconstrained
    print(f"{result.design}: " + ", ".join(f"{k} = {v:.6g}" for k, v in c.gains.items()))
    at = f" (worst at {c.at:.4g} rad/s)" if c.at is not None else ""
    print(f"{kind.label}: {value_text(kind, c.value, unit)}{at}")
    verdict = f"passive: {'yes' if c.outcome.passive else 'NO'}"
    loop = result.options.loop
    if result.sea.discrete is not None and loop is not None:  # a controller in z
        verdict = (
            f"passive in the sampled loop at T = {loop.period:g} s (delay {loop.delay}, "
            f"controller in z, certified): {'yes' if c.outcome.passive else 'NO'}"
        )
    elif c.sampled_outcome is not None and result.options.loop is not None:
        verdict += f"; passive at T = {result.options.loop.period:g} s: "
        verdict += "yes" if c.sampled_outcome.passive else "NO"
    stable = "yes" if c.stable else "NO"
    masses = ", ".join(f"{m:g}" for m in result.load_masses)
    print(f"{verdict}; stable with m_L = {masses} kg: {stable}")
    gains = ", ".join(f"{k} = {v:.6g}" for k, v in u.gains.items())
    print(
        f"unconstrained optimum: {value_text(kind, u.value, unit)} "
        f"(passive: {'yes' if u.outcome.passive else 'no'}; {gains})"
    )
    rel = "" if result.relative_cost is None else f" ({100 * result.relative_cost:.3g} %)"
    print(f"passivity cost: {value_text(kind, result.passivity_cost, unit)}{rel}")
