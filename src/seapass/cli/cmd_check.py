"""``seapass check``: exact passivity of an SEA design or of a raw impedance ``Z(s)``."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from .common import add_json_option, add_model_options, print_json, warn_unrealizable
from .design_options import (
    add_design_argument,
    design_file_from_args,
    system_from_design_args,
    units_json,
)
from .uncertain_options import add_uncertain_options, run_robust_check, wants_box

if TYPE_CHECKING:  # the CLI starts fast: heavy modules load when a command runs
    from ..analysis.indices import PassivityIndices

EXAMPLE = """examples:
  seapass check examples/ours.toml
  seapass check examples/ours.toml --set kd=5000 --json     # the flags override the file
  seapass check --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 --set k1=1000 \\
      --set b1=20 --set bd=25 --set kd=5000 --json
  seapass check --Z "(s + 1)/(s + 2)"
  seapass check --Z "k*s/(s**2 + k)" --set k=1e8
  seapass check --D1 k1 --CL kd --set b=10 --set k1=1000 --set kd=500 \\
      --uncertain m=0.9:1.1 --uncertain b=8:12 --json     # every plant in the box
  seapass check --D1 "k1 + b1*s" --controller impedance --force-loop "kp + ki/s" \\
      --impedance "kv + bv*s" --damping-injection ba --feedforward --explain \\
      --set m=0.4 --set b=3 --set k1=2500 --set b1=2 --set kp=2 --set ki=20 \\
      --set kv=1000 --set bv=5 --set ba=20
  seapass check --D1 "k1 + b1*s" --CA "(kd + bd*s)*exp(-tau*s)" --set m=1 --set b=10 \\
      --set k1=1000 --set b1=20 --set kd=500 --set bd=25 --set tau=0.001 --json
  seapass check examples/ours.toml --delay-time 0.003 --uncertain m=0.9:1.1 \\
      --uncertain b1=270:330 --json     # every plant of the box at the loop latency

A delay factor exp(-NAME*s) (NAME a parameter in seconds) is decided with certified
ball arithmetic; an answer it cannot certify is 'undecided' (exit 1), never passive;
with --uncertain it is decided for every plant of the box at that delay (--budget counts
the cells of its branch and bound).

exit codes (like cmp, so a CI job can gate on it):
  0  passive
  1  not passive (with --uncertain: not passive for some plant of the box, or undecided;
     with a delay: or undecided)
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
    add_design_argument(p)
    add_model_options(p)
    p.add_argument("--Z", help="raw impedance Z(s) instead of an SEA model, e.g. '(s + 1)/(s + 2)'")
    add_uncertain_options(p)
    p.add_argument("--explain", action="store_true",
                   help="also show how C_A and C_L follow from the controller blocks")  # fmt: skip
    add_json_option(p)
    p.set_defaults(func=run, allow_delay=True)


def run(args: argparse.Namespace) -> int:
    from ..analysis.indices import passivity_indices
    from ..delay.passivity import DelayPassivityResult, is_passive

    file = design_file_from_args(args)  # read once, passed along
    if wants_box(args, file) and (code := run_robust_check(args, file)) is not None:
        return code  # a box: --uncertain, --robust, the file's [uncertainty]
    system, resolved = system_from_design_args(args, file=file)
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
    explained = _explanation(args, system) if args.explain else None
    if args.json:
        extra = {} if explained is None else {"derivation": explained[1]}
        print_json(
            {
                **result.to_dict(),
                "indices": indices.to_dict(),
                "realizable": realizable,
                **units_json(args, resolved),
                **extra,
            }
        )
    else:
        for line in () if explained is None else explained[0]:
            print(line)
        print(f"{result.status}: {result.detail or result.reason.description}")
        if result.omega is not None and "at w =" not in (result.detail or ""):
            print(f"witness: Re Z(jw) < 0 at w = {result.omega:.6g} rad/s")  # once, not twice
        print(_indices_text(indices))
    return 0 if result.passive else 1


def _explanation(args: argparse.Namespace, system: Any) -> tuple[list[str], Any]:
    """Lines and JSON of how ``C_A``, ``C_L`` were obtained (the blocks' derivation)."""
    from .controller_options import derivation_from_args

    if not hasattr(system, "CA"):
        return ["a raw impedance Z(s): no controller to explain"], None
    d = derivation_from_args(args, system.values)
    if d is None:
        lines = [f"C_A = {system.CA}", f"C_L = {system.CL}", "(given with --CA/--CL)"]
        return lines, {"CA": str(system.CA), "CL": str(system.CL), "controller": None}
    return d.lines(), d.to_dict()


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
