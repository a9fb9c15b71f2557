"""Scale-out of ``seapass sweep`` on a Dask LocalCluster of N workers, N = 1, 2, 4, ... cores.

Usage::

    .venv/bin/python benchmarks/bench_scaling.py                  # table on stdout
    .venv/bin/python benchmarks/bench_scaling.py --write-docs     # also into docs/benchmarks.md
    .venv/bin/python benchmarks/bench_scaling.py --designs 1e8 --max-workers 16

For every N a LocalCluster of N single-threaded worker processes is started in
a helper process (so the scheduler's CPU is not counted as the client's), its
workers are warmed up (kernels compiled), and the same sweep (exact passivity
verdict and margin per design, a directory of Parquet parts) runs twice:

* ``workers write`` (seapass's design): every task computes its chunk, writes
  the part itself and returns a `PartSummary` of a few numbers;
* ``client writes`` (the previous design, rebuilt here for comparison): every
  task returns the chunk's Arrow table and the client writes the part.

Reported per run: wall-clock time and designs/s, the speed-up over N = 1 of the
same design, the client's CPU time and the bytes it received per part, and the
*client ceiling*: the parts per second one client core can handle
(1 / client CPU per part) expressed in single-worker equivalents, i.e. the
largest speed-up the design allows however many workers there are.
"""

from __future__ import annotations

import argparse
import os
import pickle
import platform
import re
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

from seapass.model.sea import SEA  # noqa: E402
from seapass.sweep import GridAxis, SweepSpec, evaluate_chunk, open_location  # noqa: E402
from seapass.sweep.cluster import available_cores, run_bounded  # noqa: E402
from seapass.sweep.runner import run_design_sweep  # noqa: E402
from seapass.sweep.spec import spec_from_state, spec_state  # noqa: E402
from seapass.sweep.store import summarize_part, write_part  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
BEGIN, END = "<!-- scaling:begin -->", "<!-- scaling:end -->"

SEA_ = SEA(
    D1="k1 + b1*s",
    CA="kd + bd*s",
    values=dict(m=1.0, b=10.0, k1=1000.0, b1=50.0, kd=None, bd=None),
    name="proposed design",
)


def make_spec(designs: float, chunk_size: int) -> SweepSpec:
    """A kd × bd grid of about ``designs`` points, verdict and margin only."""
    side = max(2, round(float(designs) ** 0.5))
    return SweepSpec(
        sea=SEA_,
        grid=(
            GridAxis("kd", 100.0, 100.0 + 10.0 * (side - 1), 10.0),
            GridAxis("bd", 1.0, 1.0 + 0.5 * (side - 1), 0.5),
        ),
        metrics=False,
        chunk_size=chunk_size,
    )


# --------------------------------------------------------------------------- the cluster

CLUSTER = """
import sys
from dask.distributed import LocalCluster
if __name__ == "__main__":
    with LocalCluster(n_workers=int(sys.argv[1]), threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster:
        print(cluster.scheduler_address, flush=True)
        sys.stdin.read()  # until the benchmark closes our stdin
"""


@contextmanager
def local_cluster(n: int) -> Iterator[str]:
    """A LocalCluster of ``n`` workers in a helper process; yields its address."""
    proc = subprocess.Popen(
        [sys.executable, "-c", CLUSTER, str(n)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    try:
        assert proc.stdout is not None
        address = proc.stdout.readline().strip()
        if not address.startswith("tcp://"):
            raise RuntimeError(f"the LocalCluster of {n} workers did not start")
        yield address
    finally:
        if proc.stdin is not None:
            proc.stdin.close()
        try:
            proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def _warm(state: dict[str, Any]) -> None:
    spec = spec_from_state(state)
    evaluate_chunk(spec, 0)


# --------------------------------------------------------------------------- one run


@dataclass
class Run:
    workers: int
    design: str
    seconds: float
    designs: int
    parts: int
    client_cpu: float
    client_bytes: int

    @property
    def rate(self) -> float:
        return self.designs / self.seconds

    @property
    def cpu_per_part(self) -> float:
        return self.client_cpu / self.parts

    @property
    def bytes_per_part(self) -> float:
        return self.client_bytes / self.parts


def _evaluate_task(c: int, state: dict[str, Any]) -> Any:
    return evaluate_chunk(spec_from_state(state), c)


def run_workers_write(spec: SweepSpec, address: str | None, out: Path, n: int) -> Run:
    received: list[int] = []
    c0, t0 = time.process_time(), time.perf_counter()
    run_design_sweep(
        spec,
        out,
        scheduler=address,
        progress=False,
        on_part=lambda s: received.append(len(pickle.dumps(s))),
    )
    t, c = time.perf_counter() - t0, time.process_time() - c0
    design = "workers write" if address else "one process"
    return Run(n, design, t, spec.n_designs, spec.n_chunks, c, sum(received))


def run_client_writes(spec: SweepSpec, address: str, out: Path, n: int) -> Run:
    from dask.distributed import Client

    parts = open_location(out)
    parts.makedirs()
    state = spec_state(spec)
    received = 0
    c0, t0 = time.process_time(), time.perf_counter()  # like run_design_sweep: connect too
    with Client(address) as client:
        for table in run_bounded(client, _evaluate_task, range(spec.n_chunks), state):
            # results arrive in any order; the table's first index gives its chunk
            chunk = int(table.column("index")[0].as_py()) // spec.chunk_size
            received += table.nbytes
            write_part(parts, chunk, table)
            summarize_part(chunk, table)
    t, cpu = time.perf_counter() - t0, time.process_time() - c0
    return Run(n, "client writes", t, spec.n_designs, spec.n_chunks, cpu, received)


def measure(spec: SweepSpec, counts: list[int]) -> list[Run]:
    """The one-process run first, then both designs for every N."""
    from dask.distributed import Client

    runs: list[Run] = []
    with tempfile.TemporaryDirectory() as tmp:
        _warm(spec_state(spec))
        runs.append(run_workers_write(spec, None, Path(tmp) / "one", 1))
        print(_row(runs[-1], runs[-1], runs[-1]), file=sys.stderr, flush=True)
        for n in counts:
            with local_cluster(n) as address:
                with Client(address) as client:
                    client.run(_warm, spec_state(spec))
                for design in ("workers write", "client writes"):
                    out = Path(tmp) / f"{design.split()[0]}-{n}"
                    run = (
                        run_workers_write(spec, address, out, n)
                        if design == "workers write"
                        else run_client_writes(spec, address, out, n)
                    )
                    runs.append(run)
                    first = next(r for r in runs if r.design == run.design)
                    print(_row(run, first, runs[0]), file=sys.stderr, flush=True)
    return runs


# --------------------------------------------------------------------------- the table


def _row(r: Run, first: Run, single: Run) -> str:
    """One table line; ``first`` is the N = 1 run of the same design, ``single`` one process."""
    if r.design == "one process":
        rest = "1.00x | — | — | — |"
    else:
        # designs per second one client core keeps up with, over one core's computing rate
        # (both CPU times, so the load of a shared machine cancels out)
        ceiling = (r.designs / r.parts) / r.cpu_per_part / (single.designs / single.client_cpu)
        rest = (
            f"{r.rate / first.rate:.2f}x | {r.cpu_per_part * 1e3:.2f} | "
            f"{_bytes(r.bytes_per_part)} | {ceiling:,.0f} |"
        )
    return (
        f"| {r.workers} | {r.design} | {r.seconds:.2f} | {r.rate / 1e3:,.0f} k | "
        f"{r.rate / single.rate:.2f}x | {rest}"
    )


def _bytes(b: float) -> str:
    return (
        f"{b / 2**20:.2f} MiB"
        if b >= 2**20
        else f"{b / 1024:.1f} KiB"
        if b >= 1024
        else f"{b:.0f} B"
    )


def table(runs: list[Run], spec: SweepSpec, seconds: float, load: str) -> list[str]:
    lines = [
        f"Generated by `benchmarks/bench_scaling.py` on "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} in {seconds:.0f} s.  Machine: "
        f"{platform.machine()}, {available_cores()} cores, load average before the run "
        f"{load}.  Sweep: {spec.n_designs:,} designs (exact passivity verdict and margin), "
        f"{spec.n_chunks} parts of {spec.chunk_size:,} designs, written as a directory of "
        "Parquet parts.  Wall-clock times; workers warmed up (kernels compiled) first.",
        "",
        "| workers | design | time [s] | designs/s | speed-up vs one process | speed-up vs "
        "1 worker | client CPU per part [ms] | client received per part | client ceiling "
        "[workers] |",
        "|---:|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in runs:
        first = next(x for x in runs if x.design == r.design)
        lines.append(_row(r, first, runs[0]))
    return lines


def _load() -> str:
    try:
        return ", ".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:  # pragma: no cover
        return "unknown"


def write_docs(lines: list[str], path: Path) -> None:
    from seapass.files.atomic import atomic_write_text

    text = path.read_text() if path.exists() else "# Benchmarks\n"
    block = "\n".join([BEGIN, *lines, END])
    if BEGIN in text:
        text = re.sub(re.escape(BEGIN) + ".*?" + re.escape(END), lambda _m: block, text, flags=re.S)
    else:
        text = text.rstrip("\n") + "\n\n## Scale-out on Dask\n\n" + block + "\n"
    atomic_write_text(path, text)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--designs", type=float, default=4e6, help="designs per run (default 4e6)")
    ap.add_argument(
        "--chunk-size", type=int, default=16384, help="designs per part (default 16384)"
    )
    ap.add_argument(
        "--max-workers", type=int, default=available_cores(), help="largest N (default: cores)"
    )
    ap.add_argument("--write-docs", action="store_true", help="update docs/benchmarks.md")
    args = ap.parse_args(argv)
    counts = [1]
    while counts[-1] * 2 <= args.max_workers:
        counts.append(counts[-1] * 2)
    if counts[-1] != args.max_workers:
        counts.append(args.max_workers)
    spec = make_spec(args.designs, args.chunk_size)
    load = _load()
    t0 = time.perf_counter()
    runs = measure(spec, counts)
    lines = table(runs, spec, time.perf_counter() - t0, load)
    print("\n".join(lines))
    if args.write_docs:
        write_docs(lines, ROOT / "docs" / "benchmarks.md")
        print(f"wrote {ROOT / 'docs' / 'benchmarks.md'}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
