"""``seapass witness``: a passive environment that destabilizes a non-passive design."""

from __future__ import annotations

import argparse

from ..analysis.witness import find_destabilizing_environment
from .common import (
    add_json_option,
    add_model_options,
    add_out_dir_option,
    check_out_dir,
    json_text,
    print_json,
    save_plot,
    system_from_args,
    warn_unrealizable,
    write_text,
)

EXAMPLE = """examples:
  seapass witness --D1 k1 --CL kd --set m=1 --set b=10 --set k1=1000 --set kd=2000 --json
  seapass witness --D1 k1 --CL kd --set m=1 --set b=10 --set k1=1000 --set kd=2000 --out witness/
  seapass witness --Z "(s - 1)/(s + 1)"
"""


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
    add_json_option(p)
    add_out_dir_option(p, "witness.png and witness.json")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    out = check_out_dir(args.out)
    system = system_from_args(args)
    warn_unrealizable(system)
    result = find_destabilizing_environment(system, simulate=True)
    data = result.to_dict()
    if out is not None:
        data["figure"] = None
        if result.found and result.simulation is not None:
            from ..plot.witness import plot_witness

            save_plot(lambda: plot_witness(result), out / "witness.png")
            data["figure"] = str(out / "witness.png")
        write_text(out / "witness.json", json_text(data))
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
    return 0
