"""``seapass analyze``: the full report for a user's own design file."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

from .common import (
    add_force_option,
    add_jobs_argument,
    add_json_option,
    interrupted_code,
    print_json,
)
from .design_options import add_delay_time_option
from .report_output import announce_report, print_section_problems, report_summary
from .uncertain_options import add_robust_options, robust_design

EXAMPLE = """examples:
  seapass analyze examples/ours.toml --out results/ours
  seapass analyze examples/load_pd_not_passive.toml --out /tmp/lpd --quick
  seapass analyze my_design.toml --out /tmp/core --stages core   # verdict, stiffness, ranges
  seapass analyze my_design.toml --out /tmp/r --budget sampled=200 --budget zwidth=100
  seapass analyze my_design.toml --out /tmp/r --stages robust --robust fitted_rig.toml

The design file is TOML with [model] (D1, D2, CA, CL), [parameters] (a value for
every symbol, m and b included) and optional [ranges], [simulation], [control]
(rate in Hz, delay, velocity_filter) sections; see examples/*.toml. Unknown
keys, wrong types and missing fields are errors naming the key.

The report directory is written when the run starts and again as each stage
finishes: an interrupted run (Ctrl-C, SIGTERM) leaves a valid report of the
finished stages, marked incomplete. Every stage but passivity has a work budget
in counted steps (--budget STAGE=N; never seconds); a stage that reaches it is
reported "stopped at budget" with what it has (a certified search's unsettled
part is undecided, never passive).
"""


class _HelpWithStages(argparse.Action):
    """``-h/--help`` with the stage table, read from the library only when asked for."""

    def __init__(self, option_strings: list[str], dest: str, **kwargs: Any) -> None:
        super().__init__(
            option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, nargs=0,
            help="show this help message (with every stage and its budget) and exit",
        )  # fmt: skip

    def __call__(self, parser: argparse.ArgumentParser, *args: Any, **kwargs: Any) -> None:
        from ..report.analyze import stages_text

        parser.epilog = (
            f"{EXAMPLE}\nstages (--stages KEY,...; --budget KEY=N, default shown):\n{stages_text()}"
        )
        parser.print_help()
        parser.exit()


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "analyze",
        help="passivity, passive gain ranges, tuning, step response and sampled limits of a design file",
        description="Analyse a design given as a TOML file and write a self-contained HTML "
        "report, a Markdown report and all data (stages: passivity, witness, stiffness, "
        "frequency, ranges, twoport, robust, response, tuning, sampled, zwidth, rig; listed with "
        "their budgets below).",
        epilog=EXAMPLE,
        add_help=False,
    )
    p.add_argument("-h", "--help", action=_HelpWithStages)
    p.add_argument("design", metavar="DESIGN.toml", help="design file")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument("--quick", action="store_true", help="reduced budgets and scans")
    p.add_argument(
        "--stages",
        metavar="LIST",
        help="comma-separated stages (default: all; 'core' = passivity,stiffness,ranges)",
    )
    p.add_argument(
        "--budget",
        action="append",
        default=[],
        metavar="STAGE=N",
        help="work budget of a stage in its counted unit (repeatable; see the stage list), "
        "e.g. --budget sampled=500",
    )
    add_robust_options(p.add_argument_group("robust (the robust stage's box)"))
    add_jobs_argument(p)
    add_delay_time_option(p)
    p.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress on stderr (else a live bar on a terminal, one line per stage otherwise)",
    )
    add_force_option(p)
    add_json_option(p, "a summary (files, sections, verdict)")
    p.set_defaults(func=run)


def parse_budgets(items: list[str]) -> dict[str, int]:
    """``STAGE=N`` options as a mapping (the library checks the stages and ranges)."""
    from ..errors import ParameterError
    from .common import parse_named

    out: dict[str, int] = {}
    for name, (value,) in parse_named(items, "--budget", 1, "STAGE=N, e.g. sampled=500"):
        try:
            out[name] = int(value)
        except ValueError:
            raise ParameterError(
                f"--budget {name}={value}: N must be a whole number of the stage's steps"
            ) from None
    return out


def run(args: argparse.Namespace) -> int:
    from ..model.design_file import load_design
    from ..report.analyze import analyze, verdict_line
    from ..report.output import report_paths
    from .cmd_reproduce import parse_stages
    from .progress import choose_progress

    design = robust_design(args, load_design(args.design))  # --robust RIGFILE: the fit's box
    if args.delay_time is not None:  # the loop latency of the delay stage, replacing the file's
        import dataclasses

        from ..model.latency import check_delay_time

        check_delay_time(args.delay_time, argument="--delay-time")
        design = dataclasses.replace(design, delay_time=args.delay_time)
    if design.rig_file not in (None, "paper"):
        from ..rig.rigfile import load_rig

        load_rig(design.rig_file)  # a bad rig file fails now, not in the hardware stage
    out = Path(args.out)
    t0 = time.perf_counter()
    try:
        with choose_progress(not args.no_progress) as progress:
            report = analyze(
                design,
                quick=args.quick,
                stages=parse_stages(args.stages),
                budgets=parse_budgets(args.budget),
                progress=progress,
                log=lambda line: print(line, file=sys.stderr),
                jobs=args.jobs,
                out=out,
                force=args.force,
            )
    except KeyboardInterrupt as exc:
        if (out / "report.html").is_file():
            print(
                f"error: interrupted; the report of the finished stages is in {out} "
                "(marked incomplete)",
                file=sys.stderr,
            )
        else:
            print("error: interrupted before the report was started", file=sys.stderr)
        return interrupted_code(exc)
    written = report_paths(report)
    announce_report(out, written)
    line = verdict_line(report.sections, design)
    if args.json:
        summary = report_summary(report, out, written)
        print_json({**summary, "verdict": line or None, "units": design.unit_map()})
    else:
        if line:
            print(f"{design.name}: {line}")
        print(f"report in {time.perf_counter() - t0:.1f} s")
    print_section_problems(report)
    return 1 if report.failed else 0
