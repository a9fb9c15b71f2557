"""``seapass analyze``: the full report for a user's own design file."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .common import (
    add_force_option,
    add_jobs_argument,
    add_json_option,
    announce_report,
    print_json,
    print_section_problems,
    report_summary,
)

EXAMPLE = """examples:
  seapass analyze examples/ours.toml --out results/ours
  seapass analyze examples/load_pd_not_passive.toml --out /tmp/lpd --quick
  seapass analyze my_design.toml --out /tmp/core --stages core   # verdict, stiffness, ranges

The design file is TOML with [model] (D1, D2, CA, CL), [parameters] (a value for
every symbol, m and b included) and optional [ranges], [simulation], [control]
(rate in Hz, delay, velocity_filter) sections; see examples/*.toml. Unknown
keys, wrong types and missing fields are errors naming the key.
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "analyze",
        help="passivity, passive gain ranges, tuning, step response and sampled limits of a design file",
        description="Analyse a design given as a TOML file and write a self-contained HTML "
        "report, a Markdown report and all data (stages: passivity, stiffness, ranges, "
        "response, tuning, sampled).",
        epilog=EXAMPLE,
    )
    p.add_argument("design", metavar="DESIGN.toml", help="design file")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument("--quick", action="store_true", help="reduced tuning budget and scans")
    p.add_argument(
        "--stages",
        metavar="LIST",
        help="comma-separated stages (default: all; 'core' = passivity,stiffness,ranges)",
    )
    add_jobs_argument(p)
    p.add_argument("--no-progress", action="store_true", help="never show the progress bar")
    add_force_option(p)
    add_json_option(p, "a summary (files, sections, verdict)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..model.design_file import load_design
    from ..report.analyze import analyze, verdict_line
    from ..report.output import check_output_dir, write_report
    from .cmd_reproduce import parse_stages

    design = load_design(args.design)
    if design.rig_file not in (None, "paper"):
        from ..rig.rigfile import load_rig

        load_rig(design.rig_file)  # a bad rig file fails now, not in the hardware stage
    check_output_dir(args.out, force=args.force)  # fail now, not after the work
    t0 = time.perf_counter()
    report = analyze(
        design,
        quick=args.quick,
        stages=parse_stages(args.stages),
        progress=False if args.no_progress else None,
        log=lambda line: print(line, file=sys.stderr),
        jobs=args.jobs,
    )
    out = Path(args.out)
    written = write_report(report, out, force=args.force)
    announce_report(out, written)
    line = verdict_line(report.sections, design)
    if args.json:
        print_json({**report_summary(report, out, written), "verdict": line or None})
    else:
        if line:
            print(f"{design.name}: {line}")
        print(f"report in {time.perf_counter() - t0:.1f} s")
    print_section_problems(report)
    return 1 if report.failed else 0
