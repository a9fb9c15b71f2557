"""Run the seapass benchmarks (peers, and the exact kernel before and after) into ``docs/benchmarks.md``.

Usage::

    .venv/bin/python benchmarks/run.py            # full run (a few minutes)
    .venv/bin/python benchmarks/run.py --quick    # under about a minute

Every throughput is designs per second of CPU time of this single-threaded
process (BLAS pinned to one thread; best of a few repeats for the fast batch
calls), so that other jobs on a shared machine do not distort the ratios.
python-control is called in a Python loop, as a user would, with its systems
built before timing.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from pathlib import Path

# single-core measurements: pin the BLAS/OpenMP pools before numpy is imported
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
sys.path.insert(0, str(Path(__file__).resolve().parent))

import bench_delay  # noqa: E402
import bench_exact  # noqa: E402
import bench_explore  # noqa: E402
import bench_export  # noqa: E402
import bench_metrics  # noqa: E402
import bench_passivity  # noqa: E402
import bench_ports  # noqa: E402
import bench_robust  # noqa: E402
import bench_sampled  # noqa: E402
import bench_startup  # noqa: E402
import bench_sweep  # noqa: E402
import bench_tune  # noqa: E402
from _util import Row, fmt_rate  # noqa: E402
from seapass.files.atomic import atomic_write_text  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent

PROFILE_NOTES = """\
## Profiling notes

Measured with cProfile before optimizing (`python -m cProfile -s tottime`):

* **Passivity.** The first version searched the minimum of `P(x)/Σ|c_i|x^i` on a
  log grid for every design whose real-part polynomial has coefficients of both
  signs; that search took 94 % of the time (80 k verdicts/s).  For the common
  case `Q = P/x^k` quadratic the witness is now the vertex `−q1/(2 q2)` and
  positivity is certified by the sign of the discriminant, derived symbolically
  and evaluated with its rounding-error bound (> 1 M verdicts/s).  The remaining
  cost is the evaluation of the compiled polynomials, done as one BLAS product
  `C @ monomials` plus `|C| @ |monomials|` for the error bounds.  The margin
  (roots of `P'A − PA'` by batched companion eigenvalues) costs about 3x the
  verdict, so it can be switched off (`margin=False`).
* **Settling time.** Complex `exp` on the full grid dominated; it was replaced by
  `cumprod` of `e^{p h}` (one complex multiply per sample), one pole per
  conjugate pair is kept (half the work), and the coarse grid went from 512 to
  256 points with a 64-point subdivision of the last uncertain interval.
  Settling times stayed within 1e-7 s of the previous version and of the scalar
  simulator (tests `tests/batch/test_step_metrics.py`).
* numba was not needed: numpy reaches the targets, so there is a single code path.
"""


def _fmt_ratio(ratio: float) -> str:
    if ratio != ratio:  # nan: the peer did not run
        return "n/a"
    return f"{ratio:,.{1 if ratio < 10 else 0}f}x"


def _table(rows: list[Row]) -> list[str]:
    out = [
        "| task | ours | ours [designs/s] | peer | peer [designs/s] | ratio | notes |",
        "|---|---|---:|---|---:|---:|---|",
    ]
    for r in rows:
        out.append(
            f"| {r.task} | {r.ours} | {fmt_rate(r.ours_rate)} | {r.peer} | "
            f"{fmt_rate(r.peer_rate)} | {_fmt_ratio(r.ratio)} | {r.note} |"
        )
    return out


SCALING_BEGIN, SCALING_END = "<!-- scaling:begin -->", "<!-- scaling:end -->"


def _scaling_section(path: Path) -> list[str]:
    """The Dask scale-out section, kept as ``bench_scaling.py --write-docs`` last wrote it."""
    text = path.read_text() if path.exists() else ""
    start, stop = text.find(SCALING_BEGIN), text.find(SCALING_END)
    if start < 0 or stop < start:
        return []
    head = text.rfind("\n## ", 0, start)
    return [text[head + 1 if head >= 0 else start : stop + len(SCALING_END)], ""]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--quick", action="store_true", help="small sizes, under about a minute")
    ap.add_argument("--out", default=str(ROOT / "docs" / "benchmarks.md"), help="markdown report")
    args = ap.parse_args(argv)
    import control

    t0 = time.perf_counter()
    rows: list[Row] = []
    notes: list[str] = []
    for mod in (
        bench_passivity,
        bench_metrics,
        bench_sweep,
        bench_export,
        bench_sampled,
        bench_ports,
        bench_robust,
        bench_delay,
        bench_tune,
    ):
        print(f"running {mod.__name__} ...", file=sys.stderr, flush=True)
        r, n = mod.run(args.quick)
        rows += r
        notes += n
        for row in r:
            print(
                f"  {row.task}: ours {fmt_rate(row.ours_rate)}, peer {fmt_rate(row.peer_rate)}, "
                f"ratio {row.ratio:,.0f}x",
                file=sys.stderr,
            )
    print("running bench_exact ...", file=sys.stderr, flush=True)
    r, n, exact_section = bench_exact.run(args.quick)
    rows += r
    notes += n
    for row in r:
        print(f"  {row.task}: ratio {row.ratio:,.1f}x", file=sys.stderr)
    print("running bench_startup ...", file=sys.stderr, flush=True)
    r, n, startup_section = bench_startup.run(args.quick)
    rows += r
    notes += n
    verdicts = bench_passivity.verdict_table()
    print("running bench_explore (headless Chromium) ...", file=sys.stderr, flush=True)
    try:
        explore = bench_explore.markdown(bench_explore.run(5 if args.quick else 20))
    except (ImportError, RuntimeError) as exc:
        explore = f"Not measured in this run: {exc}."
    print(explore, file=sys.stderr)
    elapsed = time.perf_counter() - t0
    import numpy as np

    lines = [
        "# Benchmarks",
        "",
        f"Generated by `benchmarks/run.py{' --quick' if args.quick else ''}` on "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} in {elapsed:.0f} s "
        f"(`make bench` runs it).  Machine: {platform.machine()}, {os.cpu_count()} CPUs, "
        f"Python {platform.python_version()}, numpy {np.__version__}, "
        f"python-control {control.__version__}.  Throughput is designs per second of "
        "CPU time of one single-threaded process (BLAS pinned to one thread), so other "
        "jobs on the shared machine do not distort it; on an idle machine wall-clock "
        "time is the same.",
        "",
        "## Results",
        "",
        *_table(rows),
        "",
        *[f"* {n}" for n in notes],
        "",
        *exact_section,
        *startup_section,
        "## Explorer latency (`seapass explore`)",
        "",
        "Wall-clock time in headless Chromium from a click on the `kd` slider to the frame "
        "after all eight panels were redrawn, measured by the page itself "
        "(`benchmarks/bench_explore.py`); the peer is one `seapass check` process on the "
        "same design, which answers one of the eight panels.  Unlike the rows above this "
        "is wall-clock time of several processes, so a busy machine slows it down.",
        "",
        explore,
        "",
        "## Where python-control's passivity verdict differs from ours",
        "",
        "`control.ispassive` solves the KYP linear matrix inequality numerically "
        "(cvxopt) with a tolerance; seapass decides positive-realness exactly in "
        "rational arithmetic (`seapass.analysis.passivity.is_passive`).  The 'truth' column "
        "gives the reason the exact verdict holds.",
        "",
        "| case | seapass (exact) | python-control | right | truth |",
        "|---|---|---|---|---|",
        *verdicts,
        "",
        *_scaling_section(Path(args.out)),
        PROFILE_NOTES,
    ]
    atomic_write_text(args.out, "\n".join(lines) + "\n")
    print(f"wrote {args.out} ({elapsed:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
