""" "Export report": ``seapass analyze`` on the current design, in a child process.

Each report gets its own directory under the reports directory, holding the
design file (``design.toml``), the analyze output (``report/``) and its log.
One report runs at a time; a running one is stopped when the server stops.
"""

from __future__ import annotations

import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from enum import StrEnum
from pathlib import Path
from typing import Any

from ..files.atomic import atomic_write_text

__all__ = ["JobStatus", "ReportJob", "ReportJobs"]

#: How long one ``analyze`` run may take.
REPORT_TIMEOUT = 1800.0
_LAUNCH = "import sys; from seapass.cli import main; sys.exit(main(sys.argv[1:]))"


class JobStatus(StrEnum):
    """Where an ``analyze`` run of the explorer is (the JSON value is the string)."""

    RUNNING = "running"
    DONE = "done"
    FAILED = "failed"


@dataclass
class ReportJob:
    """One ``analyze`` run."""

    id: int
    name: str
    directory: Path
    quick: bool
    status: JobStatus = JobStatus.RUNNING
    returncode: int | None = None
    started: float = field(default_factory=time.monotonic)
    seconds: float | None = None
    process: subprocess.Popen[bytes] | None = field(default=None, repr=False)

    @property
    def report_dir(self) -> Path:
        return self.directory / "report"

    def log(self) -> str:
        try:
            return (self.directory / "analyze.log").read_text(errors="replace")[-4000:]
        except OSError:
            return ""

    def to_json(self) -> dict[str, Any]:
        html = self.report_dir / "report.html"
        return {
            "id": self.id,
            "name": self.name,
            "status": self.status,
            "returncode": self.returncode,
            "seconds": self.seconds,
            "directory": str(self.directory),
            "design": str(self.directory / "design.toml"),
            "url": f"/reports/{self.id}/report.html" if html.is_file() else None,
            "log": self.log(),
        }


class ReportJobs:
    """Runs ``seapass analyze DESIGN --out DIR`` for the explorer, one at a time."""

    def __init__(self, base: Path) -> None:
        self.base = Path(base)
        self._jobs: dict[int, ReportJob] = {}
        self._lock = threading.Lock()

    def start(self, name: str, toml_text: str, *, quick: bool) -> ReportJob:
        """Write the design file and start ``analyze`` on it (raises RuntimeError when busy)."""
        with self._lock:
            if any(j.status is JobStatus.RUNNING for j in self._jobs.values()):
                raise RuntimeError("a report is already running; wait for it to finish")
            job_id = max(self._jobs, default=0) + 1
            directory = self.base / f"{job_id:03d}-{name}"
            directory.mkdir(parents=True, exist_ok=False)
            design = directory / "design.toml"
            atomic_write_text(design, toml_text)
            job = ReportJob(job_id, name, directory, quick)
            cmd = [
                sys.executable,
                "-c",
                _LAUNCH,
                "analyze",
                str(design),
                "--out",
                str(job.report_dir),
                "--no-progress",
            ]
            if quick:
                cmd.append("--quick")
            with open(directory / "analyze.log", "wb") as log:
                job.process = subprocess.Popen(
                    cmd, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL
                )
            self._jobs[job_id] = job
        threading.Thread(target=self._wait, args=(job,), daemon=True).start()
        return job

    def _wait(self, job: ReportJob) -> None:
        assert job.process is not None
        try:
            rc = job.process.wait(timeout=REPORT_TIMEOUT)
        except subprocess.TimeoutExpired:
            job.process.kill()
            rc = job.process.wait()
        job.returncode = rc
        job.seconds = time.monotonic() - job.started
        # analyze exits 1 when a stage failed but the report was written
        done = rc in (0, 1) and (job.report_dir / "report.html").is_file()
        job.status = JobStatus.DONE if done else JobStatus.FAILED

    def get(self, job_id: int) -> ReportJob | None:
        return self._jobs.get(job_id)

    def file(self, job_id: int, relpath: str) -> Path | None:
        """A file of a finished report, or None (never a path outside that report)."""
        job = self._jobs.get(job_id)
        if job is None:
            return None
        root = job.report_dir.resolve()
        try:
            path = (root / relpath).resolve()
        except (OSError, RuntimeError, ValueError):
            return None
        return path if path.is_relative_to(root) and path.is_file() else None

    def close(self) -> None:
        for job in self._jobs.values():
            if job.process is not None and job.process.poll() is None:
                job.process.kill()
                job.process.wait()
