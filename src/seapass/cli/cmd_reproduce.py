"""``seapass reproduce``: every table and figure of the paper, and seapass's additions, as a report."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .common import (
    add_force_option,
    add_jobs_argument,
    add_json_option,
    print_json,
)
from .report_output import announce_report, print_section_problems, report_summary

EXAMPLE = """examples:
  seapass reproduce --out results/
  seapass reproduce --out /tmp/preview --quick
  seapass reproduce --out /tmp/core --stages core          # tables, stiffness, regions only
  seapass reproduce --out /tmp/sims --stages tables,simulation

Writes report.html (self-contained: open it in any browser, offline), report.md,
data/ (every number as CSV or JSON) and figures/ (PNG). The directory is
replaced only when the new report is complete, so an interrupted run leaves
the previous one intact. Stages: tables, stiffness, regions, simulation, rig,
sampled, deploy, tradeoff ('core' = the first three). With --jobs 2 (default)
independent stages run in two processes; the output is the same for any --jobs.
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "reproduce",
        help="regenerate the paper's tables and figures and seapass's checks as a report",
        description="Run every stage (tables, stiffness responses, exact passive regions, "
        "simulation study, rig experiment on the digital twin, sampled-data limits) and "
        "write a self-contained HTML report, a Markdown report and all data.",
        epilog=EXAMPLE,
    )
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument(
        "--quick", action="store_true", help="reduced optimiser budgets and grids (< 1 min)"
    )
    p.add_argument(
        "--stages",
        metavar="LIST",
        help="comma-separated stages to run (default: all; 'core' = tables,stiffness,regions)",
    )
    add_jobs_argument(p)
    p.add_argument("--no-progress", action="store_true", help="no progress on stderr")
    add_force_option(p)
    add_json_option(p, "a summary (files, sections, findings)")
    p.set_defaults(func=run)


def parse_stages(text: str | None) -> list[str] | None:
    if text is None:
        return None
    names = [s.strip() for s in text.split(",") if s.strip()]
    if not names:
        raise ValueError("--stages is empty; give e.g. --stages core or --stages tables,regions")
    return names


def run(args: argparse.Namespace) -> int:
    from ..report.document import Verdict
    from ..report.output import check_output_dir, write_report
    from ..report.reproduce import reproduce
    from .progress import choose_progress

    out = Path(args.out)
    check_output_dir(out, force=args.force)  # fail now, not after minutes of work
    t0 = time.perf_counter()
    with choose_progress(not args.no_progress) as progress:
        report = reproduce(
            quick=args.quick,
            stages=parse_stages(args.stages),
            progress=progress,
            log=lambda line: print(line, file=sys.stderr),
            jobs=args.jobs,
        )
    written = write_report(report, out, force=args.force)
    announce_report(out, written)
    counts = report.summary().counts
    agrees, differs = counts[Verdict.AGREES], counts[Verdict.DIFFERS]
    if args.json:
        findings = {"agrees": agrees, "differs": differs}
        print_json({**report_summary(report, out, written), "findings": findings})
    else:
        print(
            f"report in {time.perf_counter() - t0:.1f} s: {len(report.sections)} sections, "
            f"{agrees} findings agree with the paper, {differs} differ"
        )
    print_section_problems(report)
    return 1 if report.failed else 0
