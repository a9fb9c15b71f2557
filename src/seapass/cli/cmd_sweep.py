"""``seapass sweep``: passivity and step metrics over a grid or random sample of designs."""

from __future__ import annotations

import argparse
import sys

from ..errors import ParameterError
from ..sweep import SweepSpec, heatmap_data, parse_grid, parse_range, run_design_sweep
from ..sweep.cluster import available_cores
from .common import add_model_options, model_from_args, print_json, save_plot

EXAMPLE = """examples:
  seapass sweep --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 --set k1=1000 \\
      --set b1=20 --grid kd=0:5000:200 --grid bd=0:100:5 --load-mass 10 \\
      --out sweep.parquet --heatmap kd,bd --out-fig sweep.png
  seapass sweep --D1 k1 --CL kd --set m=1 --set b=10 --sample 100000 \\
      --range k1=100:5000 --range kd=0:5000 --seed 1 --no-metrics --out lp.csv
  seapass sweep ... --out big.parquet --resume            # continue an interrupted sweep
  seapass sweep ... --out big/ --scheduler local          # one Dask worker per core
  seapass sweep ... --out big/ --scheduler local --workers 4
  seapass sweep ... --out s3://bucket/big/ --scheduler tcp://HOST:8786

The workers write their parts themselves: with --scheduler, --out must be on a
file system that the workers share with this machine, or an fsspec URL
(s3://, gs://, abfs://, ...; credentials come from fsspec's usual environment
variables and configuration).  A directory output is a Parquet dataset with a
_manifest.json that readers skip: pyarrow.dataset.dataset("big/").

The load mass can be swept too: --grid m_L=1:25:1.  Output columns: index, the
swept parameters, passive, margin and (unless --no-metrics) settling_time [s],
final_error [m], overshoot [fraction of the step], status.
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "sweep",
        help="exact passivity and step metrics over a grid or random sample of designs",
        description="Evaluate many designs of one configuration: exact passivity verdict and "
        "margin, and settling time / final error / overshoot of a reference step with a load "
        "mass. Streams chunks to disk (resumable) and can run on a Dask cluster.",
        epilog=EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_model_options(p)
    g = p.add_argument_group("designs")
    g.add_argument("--grid", action="append", default=[], metavar="NAME=LO:HI:STEP",
                   help="grid axis, inclusive, repeatable, e.g. kd=0:5000:200")  # fmt: skip
    g.add_argument("--sample", type=int, metavar="N", help="number of random designs")
    g.add_argument("--range", action="append", default=[], metavar="NAME=LO:HI",
                   help="uniform random range, repeatable, e.g. kd=0:5000")  # fmt: skip
    g.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    m = p.add_argument_group("metrics")
    m.add_argument("--load-mass", type=float, default=10.0, help="load mass m_L [kg] (default 10)")
    m.add_argument("--step", type=float, default=0.5, help="reference step [m] (default 0.5)")
    m.add_argument("--horizon", type=float, default=5.0, help="simulated time [s] (default 5)")
    m.add_argument("--no-metrics", action="store_true", help="passivity only")
    m.add_argument(
        "--no-margin", action="store_true", help="skip the passivity margin (3x faster verdicts)"
    )
    o = p.add_argument_group("output and execution")
    o.add_argument(
        "--out",
        required=True,
        help="FILE.parquet, FILE.csv, a directory of parts, or an fsspec URL (s3://bucket/dir/)",
    )
    o.add_argument("--resume", action="store_true", help="continue an interrupted sweep")
    o.add_argument(
        "--chunk-size", type=int, default=65536, help="designs per chunk (default 65536)"
    )
    o.add_argument(
        "--scheduler",
        help="'local' (a Dask LocalCluster on this machine) or tcp://host:port of a running "
        "Dask scheduler (default: compute in this process)",
    )
    o.add_argument(
        "--workers",
        type=int,
        metavar="N",
        help=f"worker processes of --scheduler local (default: this machine's cores, "
        f"{available_cores()} here)",
    )
    o.add_argument("--no-progress", action="store_true", help="no progress bar")
    o.add_argument("--heatmap", metavar="X,Y", help="two parameters for the heat maps")
    o.add_argument("--out-fig", help="heat-map figure file (PNG, PDF or SVG)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    grid = [parse_grid(t) for t in args.grid]
    ranges = [parse_range(t) for t in args.range]
    heat = None
    if args.heatmap is not None:
        heat = [s.strip() for s in args.heatmap.split(",")]
        if len(heat) != 2 or not all(heat):
            raise ParameterError(f"--heatmap expects two names X,Y, got {args.heatmap!r}")
        if not args.out_fig:
            raise ParameterError("--heatmap needs --out-fig FILE.png")
    elif args.out_fig:
        raise ParameterError("--out-fig needs --heatmap X,Y")
    if args.workers is not None and args.scheduler != "local":
        raise ParameterError(
            "--workers N needs --scheduler local (a running scheduler has its own)"
        )
    if args.workers is not None and args.workers > available_cores():
        print(
            f"warning: --workers {args.workers} is more than this machine's "
            f"{available_cores()} cores; the workers will share them",
            file=sys.stderr,
        )
    names = tuple(n for n in [a.name for a in grid] + [a.name for a in ranges] if n != "m_L")
    sea = model_from_args(args, extra_free=names)
    spec = SweepSpec(
        sea=sea,
        grid=tuple(grid),
        ranges=tuple(ranges),
        samples=args.sample,
        seed=args.seed,
        load_mass=args.load_mass,
        step=args.step,
        horizon=args.horizon,
        metrics=not args.no_metrics,
        margin=not args.no_margin,
        chunk_size=args.chunk_size,
    )
    if heat is not None:
        for h in heat:
            if h not in spec.names:
                raise ParameterError(
                    f"--heatmap: {h!r} is not swept; swept parameters: {', '.join(spec.names)}"
                )
    try:
        result = run_design_sweep(
            spec,
            args.out,
            resume=args.resume,
            scheduler=args.scheduler,
            workers=args.workers,
            progress=not args.no_progress,
        )
    except KeyboardInterrupt:
        print(
            "error: interrupted; finished chunks are saved, rerun the same command with "
            "--resume to continue",
            file=sys.stderr,
        )
        return 130
    print(f"wrote {result.path}", file=sys.stderr)
    summary = result.to_dict()
    if heat is not None:
        from ..plot.sweep import plot_sweep_heatmap

        data = heatmap_data(result.path, heat[0], heat[1])
        written = save_plot(
            lambda: plot_sweep_heatmap(data, title=f"{spec.n_designs} designs"), args.out_fig
        )
        for path in written:
            print(f"wrote {path}", file=sys.stderr)
        summary["figure"] = args.out_fig
    print_json(summary)
    return 0
