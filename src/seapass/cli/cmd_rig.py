"""``seapass rig``: the paper's hardware experiment on the digital twin."""

from __future__ import annotations

import argparse
import csv
import functools
import io
import math
from typing import Any

from ..errors import ParameterError
from ..files.limits import MAX_KD_GAINS_CLI
from ..rig.experiment import run_experiment
from ..rig.impacts import run_impacts
from ..rig.rigfile import Rig, load_rig, paper_rig
from .common import (
    add_json_option,
    add_out_dir_option,
    check_out_dir,
    print_json,
    save_plot,
    write_text,
)

_SWEEP_EPILOG = """\
examples:
  seapass rig sweep                                   # packaged paper rig, both designs, both masses
  seapass rig sweep --design LP --load-mass 0.1 --json
  seapass rig sweep --rig my_rig.toml --kd-max 1500 --kd-step 50 --out results/
"""
_IMPACT_EPILOG = """\
examples:
  seapass rig impacts --json
  seapass rig impacts --rig my_rig.toml --out results/
"""
_SHOW_EPILOG = """\
examples:
  seapass rig show                    # the packaged paper rig and its derived values
  seapass rig show --rig my_rig.toml  # validate a rig file (exit 2 naming the bad key)
"""


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


def register(subparsers: Any) -> None:
    rig = subparsers.add_parser(
        "rig",
        help="digital twin of the paper's hardware rig: kd sweep and impacts",
        description="Run the paper's Section VI experiment on the digital twin of a rig.",
        epilog=_SWEEP_EPILOG + _IMPACT_EPILOG,
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
        "--design", choices=["LP", "ours", "both"], default="both", help="controller (default both)"
    )
    sw.add_argument(
        "--load-mass",
        type=_nonneg,
        action="append",
        metavar="KG",
        help="load mass, repeatable (default: the rig file's experiment.load_masses)",
    )
    sw.add_argument("--kd-max", type=_positive, help="largest gain (N/m)")
    sw.add_argument("--kd-step", type=_positive, help="gain step (N/m)")
    sw.add_argument("--no-progress", action="store_true", help="no progress bar")
    sw.set_defaults(func=_sweep)

    im = sub.add_parser(
        "impacts",
        help="perceived stiffness k_out = F_L/X_L under impacts",
        description="Steps in load force on Ours; k_out mean ± std, dependence on b1 and "
        "on the impact time scale, Eq. (10) frequency response.",
        epilog=_IMPACT_EPILOG,
    )
    _common(im)
    im.set_defaults(func=_impacts)

    sh = sub.add_parser(
        "show",
        help="validate a rig file and print it with its derived values",
        epilog=_SHOW_EPILOG,
    )
    sh.add_argument("--rig", metavar="FILE", help="rig TOML file (default: packaged paper rig)")
    sh.set_defaults(func=_show)


def _rig(args: argparse.Namespace) -> Rig:
    return load_rig(args.rig) if args.rig else paper_rig()


def _csv(rows: list[dict[str, Any]]) -> str:
    if not rows:
        return ""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: "" if v is None else v for k, v in r.items()})
    return buf.getvalue()


def _sweep(args: argparse.Namespace) -> int:
    rig = _rig(args)
    out = check_out_dir(args.out)
    designs = ["LP", "ours"] if args.design == "both" else [args.design]
    kd_max = args.kd_max if args.kd_max is not None else rig.experiment.kd_max
    kd_step = args.kd_step if args.kd_step is not None else rig.experiment.kd_step
    if kd_max / kd_step > MAX_KD_GAINS_CLI:
        raise ParameterError(
            f"--kd-step {kd_step:g} gives more than {MAX_KD_GAINS_CLI} gains; use a larger step"
        )
    result = run_experiment(
        rig,
        designs=designs,
        load_masses=args.load_mass,
        kd_max=kd_max,
        kd_step=kd_step,
        progress=not args.no_progress and not args.json,
    )
    if out is not None:
        from ..plot.rig import plot_rig_sweep, plot_traces

        rows = [r for s in result.sweeps for r in s.rows()]
        write_text(out / "sweep.csv", _csv(rows))
        save_plot(lambda: plot_rig_sweep(result), out / "sweep", formats=("png", "pdf"))
        for s in result.sweeps:
            stem = out / f"traces_{s.design}_{s.load_mass:g}kg"
            save_plot(functools.partial(plot_traces, s), stem, formats=("png", "pdf"))
    if args.json:
        print_json(result.to_dict())
        return 0
    for s in result.sweeps:
        settled = [(k, t) for k, t in zip(s.kd, s.settling_time, strict=True) if not math.isnan(t)]
        best = min(settled, key=lambda kt: kt[1]) if settled else None
        print(
            f"{s.design:>4} m_L={s.load_mass:g} kg: settled {len(settled)}/{s.kd.size} gains"
            + (f", fastest {best[1]:.3f} s at kd={best[0]:g}" if best else "")
            + "; unstable from "
            + ", ".join(
                _gain(v, label)
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


def _gain(x: float | None, label: str) -> str:
    return f"no kd ({label})" if x is None else f"kd = {x:.0f} ({label})"


def _impacts(args: argparse.Namespace) -> int:
    rig = _rig(args)
    out = check_out_dir(args.out)
    result = run_impacts(rig)
    if out is not None:
        from ..plot.rig import plot_impacts

        rows = [
            {"impact": i, "force": float(f), "k_out": float(k)}
            for i, (f, k) in enumerate(zip(result.forces, result.k_out, strict=True))
        ]
        write_text(out / "impacts.csv", _csv(rows))
        save_plot(lambda: plot_impacts(result), out / "impacts", formats=("png", "pdf"))
    if args.json:
        print_json(result.to_dict())
        return 0
    print(
        f"k_out = {result.k_out_mean:.0f} ± {result.k_out_std:.0f} N/m "
        f"({result.forces.size} impacts, read at {result.window * 1e3:g} ms; paper 2292 ± 91.6; "
        f"k1 = {result.k1:g}; static {result.static_stiffness:.0f})"
    )
    for f in result.findings:
        tag = {True: "match", False: "MISMATCH", None: "n/a"}[f.match]
        print(f"[{tag}] {f.claim}: {f.detail}")
    return 0


def _show(args: argparse.Namespace) -> int:
    rig = _rig(args)
    print_json({"rig": rig.to_dict(), "derived": rig.derived()})
    return 0
