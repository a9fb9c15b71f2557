"""``seapass rig``: rig files, the paper's hardware experiment on the twin, and fitting a rig to a log."""

from __future__ import annotations

import argparse
import functools
import math
import sys
from typing import TYPE_CHECKING, Any

from ..errors import ParameterError
from .common import (
    add_force_option,
    add_json_option,
    add_out_dir_option,
    check_out_dir,
    check_out_file,
    plot_path,
    print_json,
    save_plot,
    warn,
    write_figure,
    write_text,
)

if TYPE_CHECKING:  # the CLI starts fast: heavy modules load when a command runs
    from ..rig.rigfile import Rig

_SWEEP_EPILOG = """\
examples:
  seapass rig sweep                                   # packaged paper rig, both designs, both masses
  seapass rig sweep --design LP --load-mass 0.1 --json
  seapass rig sweep --rig my_rig.toml --kd-max 1500 --kd-step 50 --out results/
  seapass rig sweep --design cascade.toml --gain kv --json   # any design file, any gain
"""
_IMPACT_EPILOG = """\
examples:
  seapass rig impacts --json
  seapass rig impacts --rig my_rig.toml --out results/
  seapass rig impacts --design cascade.toml --json     # any design file's controller holds the output
"""
_SHOW_EPILOG = """\
examples:
  seapass rig show                    # the packaged paper rig as TOML, derived values as comments
  seapass rig show --rig my_rig.toml  # validate a rig file (exit 2 naming the bad key)
  seapass rig show --json             # the rig and its derived values as JSON
"""
_TEMPLATE_EPILOG = """\
example:
  seapass rig template > myrig.toml   # then edit it and check it with: seapass rig show --rig myrig.toml
"""
_CHIRP_EPILOG = """\
The file has '#' comment lines saying what to play (amplitude, band, duration, rate) and
how to log it, then time [s], force [N], one row per control sample. Play it with the
load free to move, log time, commanded force, x_A and x_L at the same rate, and fit:
seapass rig fit LOG.csv --rig FILE.

examples:
  seapass rig chirp --rig myrig.toml --out command.csv
  seapass rig chirp --rig myrig.toml --amplitude 20 --band 2:40 --duration 12 --out command.csv
"""
_FIT_EPILOG = """\
The log is a CSV file with the columns time [s], commanded force [N], x_A [m], x_L [m],
one row per control sample (a header row is optional). Log a chirp of force (e.g. 5-25 Hz;
`seapass rig chirp` writes the command to play) with the load free to move, at the rig's
control rate. Only the actuator's equation is
fitted: the load side does not enter.

examples:
  seapass rig fit chirp.csv --rig myrig.toml
  seapass rig fit chirp.csv --rig myrig.toml --plot fit.png --rig-out fitted.toml --json
  seapass rig fit response.csv --frf --rig myrig.toml --rig-out fitted.toml
"""


def _examples(*epilogs: str) -> str:
    """One ``examples:`` block with the example lines of several subcommands' epilogs."""
    lines = [
        ln
        for e in epilogs
        for ln in e.split("examples:\n", 1)[-1].splitlines()
        if ln.startswith("  ")
    ]
    return "examples:\n" + "\n".join(lines) + "\n"


def _positive(text: str) -> float:
    try:
        val = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(val) or val <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return val


def _nonneg(text: str) -> float:
    try:
        val = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(val) or val < 0:
        raise argparse.ArgumentTypeError(f"expected a number >= 0, got {text!r}")
    return val


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--rig", metavar="FILE", help="rig TOML file (default: packaged paper rig)")
    add_json_option(p, "the full result")
    add_out_dir_option(p, "figures (PNG and PDF) and CSV")
    add_force_option(p)


def register(subparsers: Any) -> None:
    rig = subparsers.add_parser(
        "rig",
        help="rig files, the digital twin (kd sweep, impacts) and fitting a rig to a log",
        description="Run the paper's Section VI experiment on the digital twin of a rig, "
        "write and check rig files, and fit a rig's actuator to a logged run.",
        epilog=_examples(_SWEEP_EPILOG, _IMPACT_EPILOG, _SHOW_EPILOG, _CHIRP_EPILOG, _FIT_EPILOG),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = rig.add_subparsers(dest="rig_command", metavar="ACTION")
    sub.required = True

    sw = sub.add_parser(
        "sweep",
        help="settling time and steady-state error against kd (LP vs Ours)",
        description="Closed-loop kd sweep: load from 20 mm to 0, settling time (2 %% band, "
        "2 s cap) and steady-state error; LP instability gain from twin and linear models.",
        epilog=_SWEEP_EPILOG,
    )
    _common(sw)
    sw.add_argument(
        "--design",
        default="both",
        metavar="LP|ours|both|FILE",
        help="the paper's LP, Ours, both, or a design file whose controller (any) runs on "
        "the twin (default both)",
    )
    sw.add_argument(
        "--gain",
        metavar="NAME",
        help="with --design FILE: the gain to sweep (default: the first in the file's [ranges])",
    )
    sw.add_argument(
        "--load-mass",
        type=_nonneg,
        action="append",
        metavar="KG",
        help="load mass, repeatable (default: the rig file's experiment.load_masses)",
    )
    sw.add_argument(
        "--kd-max", type=_positive, help="largest gain (N/m; with --design FILE: of the swept gain)"
    )
    sw.add_argument(
        "--kd-step", type=_positive, help="gain step (N/m; with --design FILE: of the swept gain)"
    )
    sw.add_argument("--no-progress", action="store_true", help="no progress on stderr")
    sw.set_defaults(func=_sweep)

    im = sub.add_parser(
        "impacts",
        help="perceived stiffness k_out = F_L/X_L under impacts",
        description="Steps in load force on Ours; k_out mean ± std, dependence on b1 and "
        "on the impact time scale, Eq. (10) frequency response.",
        epilog=_IMPACT_EPILOG,
    )
    _common(im)
    im.add_argument(
        "--design",
        default="ours",
        metavar="ours|FILE",
        help="the paper's Ours (the rig's impacts.kd, impacts.bd), or a design file whose "
        "controller (continuous or [discrete]) holds the output on the twin, as in "
        "'rig sweep --design FILE' (default ours)",
    )
    im.set_defaults(func=_impacts)

    sh = sub.add_parser(
        "show",
        help="validate a rig file and print it with its derived values",
        epilog=_SHOW_EPILOG,
    )
    sh.add_argument("--rig", metavar="FILE", help="rig TOML file (default: packaged paper rig)")
    sh.add_argument("--json", action="store_true", help="print the rig and derived values as JSON")
    sh.set_defaults(func=_show)

    tp = sub.add_parser(
        "template",
        help="print a commented rig file to start your own from",
        epilog=_TEMPLATE_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    tp.set_defaults(func=_template)

    ch = sub.add_parser(
        "chirp",
        help="write the chirp of force to play on a bench (then log it and run rig fit)",
        description="Write the command that identifies a bench: a linear chirp of force, one "
        "row per control sample, within the rig's force limit and below its Nyquist frequency.",
        epilog=_CHIRP_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ch.add_argument("--rig", metavar="FILE", help="rig TOML file (default: packaged paper rig)")
    ch.add_argument("--out", metavar="FILE", help="write the command CSV (default: print it)")
    ch.add_argument("--amplitude", type=_positive, metavar="N",
                    help="peak force in N (default: 60, at most half the force limit)")  # fmt: skip
    ch.add_argument("--band", metavar="LO:HI", default="5:25",
                    help="start and stop frequency in Hz (default: 5:25)")  # fmt: skip
    ch.add_argument("--duration", type=_positive, default=8.0, metavar="S",
                    help="length in s (default: 8)")  # fmt: skip
    ch.add_argument("--rate", type=_positive, metavar="HZ",
                    help="samples per second (default: the rig's control.rate)")  # fmt: skip
    ch.add_argument("--json", action="store_true", help="print the plan (without samples) as JSON")
    add_force_option(ch)
    ch.set_defaults(func=_chirp)

    ft = sub.add_parser(
        "fit",
        help="fit m, b, b1 and Coulomb friction of a rig to a logged run",
        description="Fit the actuator's mass m, damping b, damper b1 and the Coulomb levels "
        "of actuator and damper to a logged chirp or step, with confidence intervals "
        "(modulating-function least squares; see seapass.rig.identify).",
        epilog=_FIT_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ft.add_argument("log", metavar="LOG.csv", help="the logged run (time, force, x_A, x_L)")
    ft.add_argument(
        "--frf",
        action="store_true",
        help="LOG.csv is a measured frequency response instead: frequency [Hz], |x_A/F| [m/N], "
        "phase [deg], |x_L/F| [m/N], phase [deg]; fits m, b, b1 (not Coulomb friction)",
    )
    ft.add_argument(
        "--rig", metavar="FILE", required=True, help="rig TOML file (k1, encoders, rate, delay)"
    )
    ft.add_argument(
        "--window", type=int, default=16, help="samples per modulating window (default: 16)"
    )
    ft.add_argument(
        "--delay",
        type=int,
        help="samples between a logged command and its action (default: the rig's control.delay)",
    )
    ft.add_argument(
        "--confidence", type=float, default=0.95, help="level of the intervals (default: 0.95)"
    )
    ft.add_argument("--plot", metavar="FILE", help="write the fit plot (.png, .svg or .pdf)")
    ft.add_argument(
        "--rig-out", metavar="FILE", help="write the rig file with the fitted values (TOML)"
    )
    ft.add_argument("--json", action="store_true", help="print the fit as JSON")
    add_force_option(ft)
    ft.set_defaults(func=_fit)


def _rig(args: argparse.Namespace) -> Rig:
    from ..rig.rigfile import load_rig, paper_rig

    return load_rig(args.rig) if args.rig else paper_rig()


def _sweep(args: argparse.Namespace) -> int:
    from ..rig.design_runs import rig_sweep
    from .progress import choose_progress

    rig = _rig(args)
    out = check_out_dir(args.out, files=("sweep.csv", "sweep.png", "sweep.pdf"), force=args.force)
    with choose_progress(not args.no_progress and not args.json) as progress:
        result = rig_sweep(
            rig, design=args.design, gain=args.gain, load_masses=args.load_mass,
            kd_max=args.kd_max, kd_step=args.kd_step, progress=progress,
        )  # fmt: skip
    return _report_sweep(args, result, out)


def _report_sweep(args: argparse.Namespace, result: Any, out: Any) -> int:
    if out is not None:
        from ..plot.rig import plot_rig_sweep, plot_traces

        write_text(out / "sweep.csv", result.to_csv(), force=args.force)
        save_plot(
            lambda: plot_rig_sweep(result), out / "sweep", formats=("png", "pdf"), force=args.force
        )
        for s in result.sweeps:
            stem = out / f"traces_{s.design}_{s.load_mass:g}kg"
            save_plot(
                functools.partial(plot_traces, s), stem, formats=("png", "pdf"), force=args.force
            )
    if args.json:
        print_json(result.to_dict())
        return 0
    for s in result.sweeps:
        settled = [(k, t) for k, t in zip(s.kd, s.settling_time, strict=True) if not math.isnan(t)]
        best = min(settled, key=lambda kt: kt[1]) if settled else None
        print(
            f"{s.design:>4} m_L={s.load_mass:g} kg: settled {len(settled)}/{s.kd.size} gains"
            + (f", fastest {best[1]:.3f} s at {s.gain}={best[0]:g}" if best else "")
            + "; unstable from "
            + ", ".join(
                _gain(v, label, s.gain)
                for v, label in (
                    (s.unstable_gain_twin, "twin"),
                    (s.unstable_gain_sampled, "sampled linear"),
                    (s.unstable_gain_continuous, "continuous"),
                )
            )
        )
    for f in result.findings:
        tag = {True: "match", False: "MISMATCH", None: "n/a"}[f.match]
        print(f"[{tag}] {f.claim}")
    return 0


def _gain(x: float | None, label: str, name: str = "kd") -> str:
    return f"no {name} ({label})" if x is None else f"{name} = {x:.0f} ({label})"


def _impacts(args: argparse.Namespace) -> int:
    from ..rig.design_runs import rig_impacts

    rig = _rig(args)
    out = check_out_dir(
        args.out, files=("impacts.csv", "impacts.png", "impacts.pdf"), force=args.force
    )
    result = rig_impacts(rig, design=args.design)
    if out is not None:
        from ..plot.rig import plot_impacts

        write_text(out / "impacts.csv", result.to_csv(), force=args.force)
        save_plot(
            lambda: plot_impacts(result), out / "impacts", formats=("png", "pdf"), force=args.force
        )
    if args.json:
        print_json(result.to_dict())
        return 0
    paper = "" if result.paper_k_out is None else "; paper {:g} ± {:g}".format(*result.paper_k_out)
    static = "none" if result.static_stiffness is None else f"{result.static_stiffness:.0f}"
    if result.design is not None:
        print(f"design {result.design}: its controller holds the output on the twin")
    print(
        f"k_out = {result.k_out_mean:.0f} ± {result.k_out_std:.0f} N/m "
        f"({result.forces.size} impacts, read at {result.window * 1e3:g} ms{paper}; "
        f"k1 = {result.k1:g}; static {static})"
    )
    if result.paper_k_out is None:
        by_b1 = zip(result.b1_values, result.k_out_vs_b1, strict=True)
        print("k_out against b1: " + ", ".join(f"b1 = {b:g}: {k:.0f}" for b, k in by_b1))
        by_t = zip(result.windows, result.k_out_vs_window, strict=True)
        print(
            "k_out against read-out time: " + ", ".join(f"{t * 1e3:g} ms: {k:.0f}" for t, k in by_t)
        )
    for f in result.findings:
        tag = {True: "match", False: "MISMATCH", None: "n/a"}[f.match]
        print(f"[{tag}] {f.claim}: {f.detail}")
    return 0


def _show(args: argparse.Namespace) -> int:
    rig = _rig(args)
    if args.json:
        print_json({"rig": rig.to_dict(), "derived": rig.derived()})
    else:
        sys.stdout.write(rig.to_toml())
    return 0


def _template(args: argparse.Namespace) -> int:
    from ..rig.packaged import rig_template

    sys.stdout.write(rig_template())
    return 0


def _chirp(args: argparse.Namespace) -> int:
    from ..rig.chirp import chirp_plan
    from .common import parse_range

    check_out_file(args.out, "--out", force=args.force)
    plan = chirp_plan(
        _rig(args),
        amplitude=args.amplitude,
        band=parse_range(args.band, "--band"),
        duration=args.duration,
        rate=args.rate,
    )
    if args.out:
        write_text(args.out, plan.to_csv(), force=args.force, flag="--out")
    elif not args.json:
        sys.stdout.write(plan.to_csv())
        return 0
    if args.json:
        print_json(plan.to_dict())
    else:
        print("\n".join(plan.header()))
    return 0


def _fit(args: argparse.Namespace) -> int:
    from ..rig.identify import fit_rig
    from ..rig.log import load_log
    from ..rig.rigfile import load_rig

    rig = load_rig(args.rig)
    if args.frf:
        return _fit_frf(args, rig)
    plot = plot_path(args.plot, force=args.force)  # before the work
    check_out_file(args.rig_out, "--rig-out", force=args.force)
    log = load_log(args.log)
    for message in log.warnings:
        warn(message)
    fit = fit_rig(log, rig, window=args.window, delay=args.delay, confidence=args.confidence)
    updated = None
    if args.rig_out:  # the rig file's own text, its comments kept; the log named relatively
        from ..files.textfile import read_text_file

        text = read_text_file(args.rig, what="rig file")
        updated = fit.updated_rig_text(text, relative_to=args.rig_out)
    if plot is not None:
        write_figure(fit.plot, plot, force=args.force)
    if updated is not None:
        write_text(args.rig_out, updated, force=args.force, flag="--rig-out")
    for message in fit.warnings:
        warn(message)
    if args.json:
        print_json(fit.to_dict())
        return 0
    pct = f"{fit.confidence * 100:g} %"
    print(f"fit of {log.source} ({log.size} samples, {fit.windows_used} windows), k1 = "
          f"{rig.damper.k1:g} N/m from the rig file; {pct} intervals:")  # fmt: skip
    zero = set(fit.consistent_with_zero)
    for p in fit.parameters:
        bound = " (consistent with 0)" if p.name in zero else ""
        print(
            f"  {p.name:<15} = {p.value:<11.6g} ± {p.stderr:<9.2g} [{p.low:.6g}, {p.high:.6g}] "
            f"{p.unit}{bound}"
        )
    print(f"residual force: {fit.residual_std:.3g} N (standard deviation per window)")
    return 0


def _fit_frf(args: argparse.Namespace, rig: Rig) -> int:
    from ..files.textfile import read_text_file
    from ..rig.frf import fit_frf, load_frf
    from ..rig.identify import rig_text

    if args.plot:
        raise ParameterError("--plot draws a time log's fit; it does not go with --frf")
    check_out_file(args.rig_out, "--rig-out", force=args.force)
    fit = fit_frf(load_frf(args.log), rig, delay=args.delay, confidence=args.confidence)
    if args.rig_out:
        text = read_text_file(args.rig, what="rig file")
        write_text(args.rig_out, rig_text(rig, fit.updated_rig(), text), force=args.force,
                   flag="--rig-out")  # fmt: skip
    if args.json:
        print_json(fit.to_dict())
        return 0
    pct = f"{fit.confidence * 100:g} %"
    print(f"fit of the frequency response {fit.source}, k1 = {rig.damper.k1:g} N/m from the rig "
          f"file; {pct} intervals (Coulomb friction is not seen in a frequency response):")  # fmt: skip
    for p in fit.parameters:
        print(
            f"  {p.name:<4} = {p.value:<11.6g} ± {p.stderr:<9.2g} [{p.low:.6g}, {p.high:.6g}] {p.unit}"
        )
    print(
        f"residual: {fit.residual_std:.3g} (standard deviation of the force equation, per unit force)"
    )
    return 0
