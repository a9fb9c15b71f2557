"""``seapass witness``: a passive environment that destabilizes a non-passive design."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..errors import ParameterError
from .common import (
    add_force_option,
    add_json_option,
    add_model_options,
    add_out_dir_option,
    check_out_dir,
    json_text,
    parse_range,
    print_json,
    save_plot,
    system_from_args,
    warn_unrealizable,
    write_text,
)

if TYPE_CHECKING:  # the CLI starts fast: heavy modules load when a command runs
    from ..analysis.environment_box import EnvironmentBounds
    from ..analysis.witness import WitnessResult

EXAMPLE = """examples:
  seapass witness --D1 k1 --CL kd --set m=1 --set b=10 --set k1=1000 --set kd=2000 --json
  seapass witness --D1 k1 --CL kd --set m=1 --set b=10 --set k1=1000 --set kd=2000 --out witness/
  seapass witness --D1 k1 --CL "kd + bd*s" --set m=1 --set b=10 --set k1=1000 --set kd=500 \\
      --set bd=25 --mass 0.5:5 --stiffness 0:2000
  seapass witness --Z "(s - 1)/(s + 1)" --unbounded

The environment is a passive mass-spring-damper m_e s + b_e + k_e/s within the
bounds; the default is a human limb and what a hand holds: mass 0.1-10 kg,
damping 0-100 N*s/m (none: the worst case), stiffness 0-5000 N/m (a free mass
to a co-contracted arm). When nothing in the bounds destabilizes the design,
the output says whether that is proven exactly or only not found, and names an
environment outside the bounds that does.
"""


#: The default box in ``--help``: `seapass.analysis.environment_box.HUMAN_LIMB` (a test keeps
#: them equal; written out so that the CLI starts without importing the analysis).
HELP_DEFAULTS = {"mass": (0.1, 10.0), "damping": (0.0, 100.0), "stiffness": (0.0, 5000.0)}


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "witness",
        help="find a passive mass-spring-damper that destabilizes a non-passive design",
        description="For a design that is not passive, construct a passive environment "
        "Z_e = m_e s + b_e + k_e/s (m_e, b_e, k_e >= 0) that makes the coupled system "
        "unstable, verified exactly; print it with the coupled poles and optionally plot "
        "the growing oscillation. A passive design has no such environment.",
        epilog=EXAMPLE,
    )
    add_model_options(p)
    p.add_argument("--Z", help="raw impedance Z(s) instead of an SEA model, e.g. '(s - 1)/(s + 1)'")
    g = p.add_argument_group("the environments allowed (default: a human limb)")
    for name, unit in (("mass", "kg"), ("damping", "N*s/m"), ("stiffness", "N/m")):
        lo, hi = HELP_DEFAULTS[name]
        g.add_argument(f"--{name}", metavar="LO:HI",
                       help=f"range of the environment's {name} [{unit}] (default: {lo:g}:{hi:g})")  # fmt: skip
    g.add_argument("--unbounded", action="store_true",
                   help="any passive mass-spring-damper (may find physically meaningless ones)")  # fmt: skip
    add_json_option(p)
    add_out_dir_option(p, "witness.png and witness.json")
    add_force_option(p)
    p.set_defaults(func=run)


def bounds_from_args(args: argparse.Namespace) -> EnvironmentBounds | None:
    """The environment box of the command line (None with --unbounded)."""
    from ..analysis.environment_box import HUMAN_LIMB, EnvironmentBounds

    given = {n: getattr(args, n) for n in ("mass", "damping", "stiffness") if getattr(args, n)}
    if args.unbounded:
        if given:
            raise ParameterError(f"--unbounded and --{next(iter(given))}: give one or the other")
        return None
    ranges = {n: parse_range(v, f"--{n}") for n, v in given.items()}
    return EnvironmentBounds(**{**HUMAN_LIMB.to_dict(), **ranges})  # type: ignore[arg-type]


def run(args: argparse.Namespace) -> int:
    from ..analysis.witness import find_destabilizing_environment

    out = check_out_dir(args.out, files=("witness.png", "witness.json"), force=args.force)
    system = system_from_args(args)
    warn_unrealizable(system)
    bounds = bounds_from_args(args)
    result = find_destabilizing_environment(system, bounds=bounds, simulate=True)
    data = result.to_dict()
    if out is not None:
        data["figure"] = None
        if result.found and result.simulation is not None:
            from ..plot.witness import plot_witness

            save_plot(lambda: plot_witness(result), out / "witness.png", force=args.force)
            data["figure"] = str(out / "witness.png")
        write_text(out / "witness.json", json_text(data), force=args.force)
    if args.json:
        print_json(data)
    elif result.found:
        env = result.environment
        assert env is not None and result.coupled is not None
        print(result.detail)
        print(
            f"environment: m_e = {env.mass:.6g} kg, b_e = {env.damping:.6g} N*s/m, "
            f"k_e = {env.stiffness:.6g} N/m ({result.method})"
        )
        print(f"max real part of the coupled poles: {result.coupled.max_real_part:.6g} 1/s")
        if result.simulation is not None:
            print(
                f"simulated {result.simulation.output}: grows x{result.simulation.growth_factor:.3g} "
                f"over {result.simulation.t[-1]:.4g} s"
            )
    else:
        print(result.detail)
        _print_bounds_verdict(result)
    return 0


def _print_bounds_verdict(result: WitnessResult) -> None:
    """The plain answer when nothing in the bounds destabilizes the design."""
    if result.passive or result.bounds is None:
        return
    if result.certified:
        print("within the bounds: no destabilizing environment (proven exactly)")
    else:
        print("within the bounds: none found (a search, not a proof)")
