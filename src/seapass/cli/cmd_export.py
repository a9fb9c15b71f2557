"""``seapass export c``: the design's deployed controller as dependency-free C99."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from ..errors import CompilerError, ParameterError, SeapassError
from ..files.limits import MAX_RTOL, MIN_RTOL, check_rtol
from .common import add_force_option, add_json_option, announce, check_out_dir, print_json
from .uncertain_options import add_robust_options, robust_design

DEFAULT_ENVELOPE_BUDGET = 16  # seapass.export.robust_envelope.DEFAULT_ENVELOPE_BUDGET (tested)

EXAMPLE = """examples:
  seapass export c examples/ours.toml --out firmware/
  seapass export c examples/ours.toml --out firmware/ --hardware-delay 1 --verify
  seapass export c design.toml --out firmware/ --force-limit 120 --set-gains --tunable kd
  seapass export c design.toml --out firmware/ --force   # replace files seapass did not write
  seapass export c examples/ours.toml --out firmware/ --latency 0.002   # tau* must cover it
  seapass export c design.toml --out firmware/ --set-gains --robust --budget 24
  seapass export c design.toml --out firmware/ --set-gains --robust fitted_rig.toml

With --robust, every gain the guards accept is certified sampled passive (at the
[control] rate, delay and velocity filter) for every plant of the box (the design's
[uncertainty], or RIGFILE's fitted intervals): the certified inner set of 'seapass sampled
bound GAIN --uncertain ...' intersected with the nominal and the continuous robust
envelopes, rounded inward. --budget counts that work (sub-intervals per gain); when a
gain's value is left undecided (or fails at a plant) nothing is written, unless
--robust-fallback pin (fix that gain; certified when the design at its gains is) or
--robust-fallback nominal (the nominal-plant envelope, marked NOT certified for the box
in the header, the JSON and a warning).

With a loop latency ([control] delay_time or --latency), the design's passivity delay
margin tau* (C_A and C_L delayed) must cover it: every delay up to the latency certified
passive, else nothing is written (or, with --allow-nonpassive, the files say NOT
CERTIFIED); the header records tau* and the latency.

exit status: 0 written (and verified); 1 --verify found the compiled C and the Python
controller more than 1e-12 apart; 2 bad input, a design that is not passive (at its rate,
or within its loop latency), or no working C compiler for --verify (nothing is written
then).
"""

# the Python API's errors name its arguments; say the options here instead
_OPTIONS = {
    "force_limit=...": "--force-limit N",
    "allow_nonpassive=True": "--allow-nonpassive",
    "set_gains=True": "--set-gains",
    "tunable=[...]": "--tunable G1,G2",
    "hardware_delay": "--hardware-delay",
    "latency: must be": "--latency: must be",
    "see sampled_passive_bound": "see 'seapass sampled bound'",
    "robust_budget": "--budget",
    "robust_fallback='pin'": "--robust-fallback pin",
    "robust_fallback='nominal'": "--robust-fallback nominal",
    "robust_fallback=": "--robust-fallback ",
}


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "export",
        help="generate code for the deployed controller (C99 for microcontrollers)",
        description="Generate code that runs the design's deployed controller on hardware, "
        "with its passivity envelope built in.",
        epilog=EXAMPLE,
    )
    targets = p.add_subparsers(dest="export_target", metavar="{c}")
    targets.required = True
    c = targets.add_parser(
        "c",
        help="seapass_ctrl.h / seapass_ctrl.c: dependency-free C99",
        description="Write seapass_ctrl.h and seapass_ctrl.c: the design's discrete controller "
        "(actuator and load side, velocity filter), force saturation and delay line, with "
        "the certified period, delay, filter and gains. init refuses another period; the "
        "optional set_gains refuses gains outside the certified set. The design must be "
        "passive at its [control] rate, delay and velocity filter (decided at export time). "
        "See docs/deploy.md.",
        epilog=EXAMPLE,
    )
    c.add_argument("design", help="design TOML file (needs a [control] rate)")
    c.add_argument("--out", required=True, metavar="DIR", help="directory for the two files")
    c.add_argument(
        "--force-limit",
        type=float,
        metavar="N",
        help="saturation of the command in N (default: the peak force of the design's [rig])",
    )
    c.add_argument(
        "--hardware-delay",
        type=int,
        default=0,
        metavar="SAMPLES",
        help="delay the platform adds by itself; the code's delay line supplies the rest of "
        "the design's [control] delay (default: 0)",
    )
    c.add_argument(
        "--latency",
        type=float,
        metavar="SECONDS",
        help="continuous loop latency: C_A and C_L act SECONDS late; the design's delay "
        "margin tau* must cover it (default: the design file's [control] delay_time, else "
        "no latency check)",
    )
    c.add_argument(
        "--set-gains",
        action="store_true",
        help="generate seapass_ctrl_set_gains: runtime gain changes inside the certified set",
    )
    c.add_argument(
        "--tunable",
        metavar="G1,G2",
        help="gains set_gains may change (default: every controller gain)",
    )
    c.add_argument(
        "--allow-nonpassive",
        action="store_true",
        help="export a design that fails the sampled-data check (marked NOT CERTIFIED)",
    )
    c.add_argument(
        "--rtol",
        type=float,
        default=1e-6,
        help="relative width of the certified edge enclosures of each tunable gain's "
        f"interval, in [{MIN_RTOL:g}, {MAX_RTOL:g}] (default: 1e-6)",
    )
    c.add_argument(
        "--verify",
        action="store_true",
        help="compile the files with the system C compiler and compare them with the Python "
        "controller on 10,000 steps",
    )
    box = c.add_argument_group("robust (the guards hold for every plant in a box)")
    add_robust_options(box)
    box.add_argument(
        "--budget",
        type=int,
        metavar="N",
        help="with --robust: sub-intervals of each tunable gain (and sub-boxes of the "
        "design's own check) the certification may examine, counted, never timed; what is "
        f"left undecided is refused (default: {DEFAULT_ENVELOPE_BUDGET})",
    )
    box.add_argument(
        "--robust-fallback",
        choices=("pin", "nominal"),
        help="with --robust, when a gain's value is not certified for the box: 'pin' fixes "
        "that gain at its value (certified when the design at its gains is); 'nominal' keeps "
        "the nominal-plant envelope, marked NOT certified for the box (default: refuse)",
    )
    add_force_option(c)
    c.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress on stderr while the gains are certified",
    )
    add_json_option(c)
    c.set_defaults(func=run_c)


def run_c(args: argparse.Namespace) -> int:
    from ..export.c_code import HEADER, SOURCE, export_c
    from ..export.compiled import find_c_compiler, verify_c
    from ..model.design_file import load_design
    from .progress import choose_progress

    tunable = None
    if args.tunable is not None:
        tunable = [t.strip() for t in args.tunable.split(",") if t.strip()]
        if not tunable:
            raise ParameterError("--tunable needs gain names, e.g. --tunable kd,bd")
    check_rtol(args.rtol)
    robust = args.robust is not None  # --robust [RIGFILE]: the box's gain envelope in the guards
    if args.confidence is not None and not args.robust:
        raise ParameterError("--confidence LEVEL applies to --robust RIGFILE; give the rig file")
    if not robust and (args.budget is not None or args.robust_fallback is not None):
        raise ParameterError("--budget and --robust-fallback apply to --robust; add --robust")
    budget = DEFAULT_ENVELOPE_BUDGET if args.budget is None else args.budget
    check_out_dir(args.out, files=(HEADER, SOURCE), force=args.force)
    if args.verify and find_c_compiler() is None:  # before anything is written
        raise CompilerError("--verify needs a C compiler: none found (set CC or install gcc)")
    try:
        with choose_progress(not args.no_progress) as progress:
            res = export_c(
                robust_design(args, load_design(args.design)) if robust else args.design,
                args.out,
                force_limit=args.force_limit,
                hardware_delay=args.hardware_delay,
                set_gains=args.set_gains,
                tunable=tunable,
                allow_nonpassive=args.allow_nonpassive,
                rtol=args.rtol,
                progress=progress,
                force=args.force,
                latency=args.latency,
                robust=robust,
                robust_budget=budget,
                robust_fallback=args.robust_fallback,
            )
    except SeapassError as exc:
        text = str(exc)
        for python, option in _OPTIONS.items():
            text = text.replace(python, option)
        raise type(exc)(text) from None
    for path in (res.header, res.source):
        announce(path)
    if res.deployment.robust is not None:  # a fallback's warnings, also with --json
        for w in res.deployment.robust.warnings:
            print(f"warning: NOT CERTIFIED FOR EVERY PLANT OF THE BOX: {w}", file=sys.stderr)
    ver = verify_c(res) if args.verify else None
    ok = ver is None or ver.ok
    if args.json:
        out: dict[str, Any] = {
            "files": [str(res.header), str(res.source)],
            "deployment": res.deployment.to_dict(),
        }
        if res.latency is not None:
            out["latency"] = res.latency.to_dict()
        if ver is not None:
            out["verify"] = ver.to_dict()
        print_json(out)
    else:
        _print_summary(res, ver, ok)
    return 0 if ok else 1


def _print_summary(res: Any, ver: Any, ok: bool) -> None:
    from ..exact.rounding import exact_text, interval_text

    dep = res.deployment
    vf = f"{dep.velocity_filter:g} Hz" if dep.velocity_filter else "none"
    print(f"design {dep.design.name!r}: seapass_ctrl.h and seapass_ctrl.c in {res.header.parent}")
    print(
        f"  period {float(dep.period):g} s ({float(1 / dep.period):g} Hz), delay {dep.delay} "
        f"sample(s) ({dep.code_delay} in the code + {dep.hardware_delay} on the platform), "
        f"velocity filter {vf}, force limit ±{dep.force_limit:g} N"
    )
    if dep.certified:
        print(f"  certified: {dep.verdict}")
    else:
        print(f"  NOT CERTIFIED (exported on request): {dep.verdict}")
    for g in dep.gains:
        if g.tunable:
            shown = interval_text(g.low, g.high, digits=10)  # rounded inward
            print(f"  {g.name} = {exact_text(g.nominal)}, tunable in {shown}")
        else:
            print(f"  {g.name} = {g.nominal:g}")
    for note in dep.notes:
        print(f"  note: {note}")
    if dep.robust is not None:
        for line in dep.robust.banner():
            print(f"  {line}")
    if res.latency is not None:
        from ..export.latency import latency_banner

        for line in latency_banner(res.latency)[1:]:
            print(f"  {line}")
    if ver is not None:
        how = "identical to" if ver.identical else f"within {ver.max_rel:.3g} (relative) of"
        verdict = "ok" if ok else f"FAILED (more than {ver.rtol:g} apart)"
        print(
            f"  verify: {ver.steps} steps of the compiled C are {how} the Python controller "
            f"({ver.saturated} saturated): {verdict}"
        )
