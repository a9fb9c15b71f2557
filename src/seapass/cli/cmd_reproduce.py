"""``seapass reproduce``: every table and figure of the paper, and seapass's additions, as a report."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .common import print_section_problems

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
        formatter_class=argparse.RawDescriptionHelpFormatter,
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
    p.add_argument("--no-progress", action="store_true", help="never show the progress bar")
    p.set_defaults(func=run)


def add_jobs_argument(p: argparse.ArgumentParser) -> None:
    """``--jobs N``: worker processes for a report's independent stages."""
    p.add_argument(
        "--jobs",
        type=int,
        default=2,
        metavar="N",
        help="worker processes for the independent stages (default 2; 1 = sequential)",
    )


def parse_stages(text: str | None) -> list[str] | None:
    if text is None:
        return None
    names = [s.strip() for s in text.split(",") if s.strip()]
    if not names:
        raise ValueError("--stages is empty; give e.g. --stages core or --stages tables,regions")
    return names


def run(args: argparse.Namespace) -> int:
    from ..report.output import check_output_dir, write_report
    from ..report.reproduce import reproduce

    out = Path(args.out)
    check_output_dir(out)  # fail now, not after minutes of work
    t0 = time.perf_counter()
    report = reproduce(
        quick=args.quick,
        stages=parse_stages(args.stages),
        progress=False if args.no_progress else None,
        log=lambda line: print(line, file=sys.stderr),
        jobs=args.jobs,
    )
    write_report(report, out)
    _summary(report, out, time.perf_counter() - t0)
    return 1 if report.failed else 0


def _summary(report: object, out: Path, seconds: float) -> None:
    from ..report.document import Report

    assert isinstance(report, Report)
    n = {v: sum(1 for _s, f in report.findings if f.verdict == v) for v in ("agrees", "differs")}
    print(
        f"wrote {out / 'report.html'} and {out / 'report.md'} in {seconds:.1f} s: "
        f"{len(report.sections)} sections, {n['agrees']} findings agree with the paper, "
        f"{n['differs']} differ"
    )
    print_section_problems(report)
