"""``seapass check``: exact passivity of an SEA design or of a raw impedance ``Z(s)``."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from .common import (
    add_json_option,
    add_model_options,
    print_json,
    system_from_args,
    warn_unrealizable,
)

if TYPE_CHECKING:  # the CLI starts fast: heavy modules load when a command runs
    from ..analysis.indices import PassivityIndices

EXAMPLE = """examples:
  seapass check --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 --set k1=1000 \\
      --set b1=20 --set bd=25 --set kd=5000 --json
  seapass check --Z "(s + 1)/(s + 2)"
  seapass check --Z "k*s/(s**2 + k)" --set k=1e8
  seapass check --D1 "k1 + b1*s" --CA "(kd + bd*s)*exp(-tau*s)" --set m=1 --set b=10 \
      --set k1=1000 --set b1=20 --set kd=500 --set bd=25 --set tau=0.001 --json

A delay factor exp(-NAME*s) (NAME a parameter in seconds) is decided with certified
ball arithmetic; an answer it cannot certify is 'undecided' (exit 1), never passive.

exit codes (like cmp, so a CI job can gate on it):
  0  passive
  1  not passive (or, with a delay, undecided)
  2  bad input or another error (one 'error:' line on stderr)
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "check",
        help="decide exactly whether a design (or an impedance Z(s)) is passive (exit 1 if not)",
        description="Exact positive-real test of the load impedance Z_L = F_L/(s X_L), "
        "or of a raw impedance given with --Z. Decided by exact rational arithmetic and "
        "certified root isolation, never by a frequency grid. Also the passivity indices of "
        "MATLAB's getPassiveIndex: input feedforward nu (N*s/m for an SEA port; nu < 0: "
        "|nu| of parallel damping makes it passive) and output feedback rho, exact. Exit code 0: passive, 1: not passive, 2: bad input.",
        epilog=EXAMPLE,
    )
    add_model_options(p)
    p.add_argument("--Z", help="raw impedance Z(s) instead of an SEA model, e.g. '(s + 1)/(s + 2)'")
    add_json_option(p)
    p.set_defaults(func=run, allow_delay=True)


def run(args: argparse.Namespace) -> int:
    from ..analysis.indices import passivity_indices
    from ..delay.passivity import DelayPassivityResult, is_passive

    system = system_from_args(args)
    realizable = warn_unrealizable(system)
    result = is_passive(system)
    if isinstance(result, DelayPassivityResult):  # a delay exp(-NAME*s): certified, no indices
        if args.json:
            print_json({**result.to_dict(), "indices": None, "realizable": realizable})
        else:
            print(f"{result.status}: {result.detail}")
            if result.omega is not None:
                print(f"witness: Re Z(jw) < 0 at w = {result.omega:.6g} rad/s (proven)")
            print(
                f"delay: {result.delay} = {result.tau:g} s; loop with the port held: {result.stability}"
            )
        return 0 if result.passive else 1
    indices = passivity_indices(system)
    if args.json:
        print_json({**result.to_dict(), "indices": indices.to_dict(), "realizable": realizable})
    else:
        print(f"{result.status}: {result.detail or result.reason.description}")
        if result.omega is not None:
            print(f"witness: Re Z(jw) < 0 at w = {result.omega:.6g} rad/s")
        print(_indices_text(indices))
    return 0 if result.passive else 1


def _indices_text(ix: PassivityIndices) -> str:
    """One line: ν and ρ with where they are attained."""

    def where(omega: float | None, value: float) -> str:
        if omega is None:
            return " (as w -> inf)" if abs(value) != float("inf") else ""
        return f" (at w = {omega:.6g} rad/s)"

    return (
        f"passivity indices: input feedforward nu = {ix.nu:.6g}{where(ix.input.omega, ix.nu)}, "
        f"output feedback rho = {ix.rho:.6g}{where(ix.output.omega, ix.rho)}"
    )
