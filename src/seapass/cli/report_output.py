"""What ``analyze`` and ``reproduce`` print about a report directory they wrote."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = ["announce_report", "print_section_problems", "report_summary"]


def announce_report(out: Path, written: Sequence[Path]) -> None:
    """``wrote`` lines for a report directory: the two reports, then a count of the rest."""
    from .output import announce

    names = {p.as_posix() for p in written}
    for main in ("report.html", "report.md"):
        if main in names:
            announce(out / main)
    data = sum(1 for n in names if n.startswith("data/"))
    figures = sum(1 for n in names if n.startswith("figures/"))
    print(f"wrote {data} data files and {figures} figures in {out}", file=sys.stderr)


def report_summary(report: Any, out: Path, written: Sequence[Path]) -> dict[str, Any]:
    """The ``--json`` summary of a report directory: files, sections and their status."""
    return {
        "out": str(out),
        "files": [p.as_posix() for p in written],
        "sections": [{"key": s.key, "title": s.title, "status": s.status} for s in report.sections],
        "failed": list(report.failed),
    }


def print_section_problems(report: Any) -> None:
    """One stderr line naming the skipped sections of a report, one naming those stopped at
    their budget, one per failed section."""
    from ..report.document import SectionStatus

    skipped = [s.key for s in report.sections if s.status == SectionStatus.SKIPPED]
    if skipped:
        print(f"  skipped (reason in the report): {', '.join(skipped)}", file=sys.stderr)
    stopped = [s.key for s in report.sections if s.status == SectionStatus.STOPPED_AT_BUDGET]
    if stopped:
        print(
            f"  stopped at budget (what it has is in the report; raise it with --budget "
            f"STAGE=N): {', '.join(stopped)}",
            file=sys.stderr,
        )
    for s in report.sections:
        if s.status == SectionStatus.FAILED:
            print(f"  {s.key} FAILED: {s.text}", file=sys.stderr)
