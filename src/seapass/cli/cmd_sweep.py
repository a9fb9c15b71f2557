"""``seapass sweep``: passivity and step metrics over a grid or random sample of designs."""

from __future__ import annotations

import argparse
import pathlib
import sys
from typing import Any

from ..errors import ParameterError, did_you_mean
from ..files.atomic import check_writable
from .common import (
    add_force_option,
    add_json_option,
    add_model_options,
    add_plot_option,
    announce,
    check_step,
    deprecated_alias,
    interrupted_code,
    parse_named,
    plot_path,
    print_json,
    save_plot,
    warn,
)
from .design_options import add_design_argument, design_from_args

EXAMPLE = """examples:
  seapass sweep examples/ours.toml --grid kd=0:5000:500 --grid bd=0:300:50 --out ours.csv
  seapass sweep --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 --set k1=1000 \\
      --set b1=20 --grid kd=0:5000:200 --grid bd=0:100:5 --load-mass 10 \\
      --out sweep.parquet --heatmap kd,bd --plot sweep.png
  seapass sweep --D1 k1 --CL kd --set m=1 --set b=10 --sample 100000 \\
      --range k1=100:5000 --range kd=0:5000 --seed 1 --no-metrics --out lp.csv
  seapass sweep examples/ours.toml --sample 1000 --range kd --range bd --out ours.csv
  seapass sweep ... --out big.parquet --resume            # continue an interrupted sweep
  seapass sweep ... --out lp.csv --force    # replace an lp.csv that seapass did not write
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
        "mass. Streams chunks to disk (resumable) and can run on a Dask cluster. Swept "
        "parameters are free: do not also give them with --set.",
        epilog=EXAMPLE,
    )
    add_design_argument(p)
    add_model_options(p)
    g = p.add_argument_group("designs")
    g.add_argument("--grid", action="append", default=[], metavar="NAME=LO:HI:STEP",
                   help="grid axis, inclusive, repeatable, e.g. kd=0:5000:200")  # fmt: skip
    g.add_argument("--sample", type=int, metavar="N", help="number of random designs")
    g.add_argument("--range", action="append", default=[], metavar="NAME=LO:HI",
                   help="uniform random range, repeatable, e.g. kd=0:5000; NAME alone: the "
                   "design file's [ranges] box")  # fmt: skip
    g.add_argument("--seed", type=int, default=0, help="random seed")
    m = p.add_argument_group("metrics")
    m.add_argument(
        "--load-mass",
        type=float,
        help="load mass m_L [kg] (default: the design file's tune_mass, else the paper's 10)",
    )
    m.add_argument("--step", type=float, metavar="M",
                   help="reference step [m] (default: the design file's, else the paper's 0.5)")  # fmt: skip
    m.add_argument(
        "--horizon",
        type=float,
        help="simulated time [s] (default: the design file's, else a 5 s screen)",
    )
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
        help="worker processes of --scheduler local (default: one per core this process may use)",
    )
    o.add_argument("--no-progress", action="store_true", help="no progress on stderr")
    o.add_argument(
        "--heatmap", metavar="X,Y", help="two parameters for the heat maps (needs --plot)"
    )
    add_plot_option(o, "the heat maps")
    o.add_argument("--out-fig", help=argparse.SUPPRESS)  # before 0.3; now --plot
    add_force_option(o)
    add_json_option(o, "the summary")
    p.set_defaults(func=run)


def _file_ranges(args: argparse.Namespace, names: list[str], given: list[Any]) -> list[Any]:
    """``--range NAME`` (no bounds): the box of NAME in the design file's ``[ranges]``."""
    from ..model.design_file import load_design
    from ..sweep import RangeAxis

    if not names:
        return []
    path = getattr(args, "design", None)
    if path is None:
        raise ParameterError(
            f"--range {names[0]}: without bounds it takes them from a design file's [ranges]; "
            f"give a design file or --range {names[0]}=LO:HI"
        )
    design = load_design(path)
    out = []
    seen = {a.name for a in given}
    for name in names:
        if not name.isidentifier():
            raise ParameterError(f"--range {name!r}: expected NAME=LO:HI or NAME, e.g. kd=0:5000")
        if name in seen:
            raise ParameterError(f"--range {name} is given twice; give each name once")
        seen.add(name)
        if name not in design.ranges:
            listed = ", ".join(sorted(design.ranges)) or "none"
            raise ParameterError(
                f"--range {name}: {path} has no [ranges] entry for {name} (it has: {listed}); "
                f"give --range {name}=LO:HI or add '{name} = [LO, HI]' to its [ranges]"
            )
        out.append(RangeAxis(name, *design.ranges[name]))
    return out


def run(args: argparse.Namespace) -> int:
    from ..model.expr import parse_value
    from ..sweep import GridAxis, RangeAxis, SweepSpec, heatmap_data, run_design_sweep
    from ..sweep.cluster import available_cores
    from ..sweep.spec import LOAD_MASS
    from .progress import choose_progress

    grid = [
        GridAxis(name, *(parse_value(v, f"--grid {name}") for v in parts))
        for name, parts in parse_named(
            args.grid, "--grid", 3, "NAME=LO:HI:STEP, e.g. kd=0:5000:200"
        )
    ]
    given = [r for r in args.range if "=" in r]
    ranges = [
        RangeAxis(name, *(parse_value(v, f"--range {name}") for v in parts))
        for name, parts in parse_named(given, "--range", 2, "NAME=LO:HI, e.g. kd=0:5000")
    ]
    ranges += _file_ranges(args, [r.strip() for r in args.range if "=" not in r], ranges)
    if bool(grid) == bool(ranges):
        raise ParameterError(
            "give grid axes (--grid NAME=LO:HI:STEP, repeatable) or random ranges "
            "(--sample N --range NAME=LO:HI, repeatable), not both or neither"
        )
    if ranges and args.sample is None:
        raise ParameterError("--range needs --sample N, the number of random designs")
    if grid and args.sample is not None:
        raise ParameterError("--sample is only for random ranges; a grid has its own size")
    figure = plot_path(deprecated_alias(args, "out_fig", "plot"), force=args.force)
    heat = None
    if args.heatmap is not None:
        heat = [s.strip() for s in args.heatmap.split(",")]
        if len(heat) != 2 or not all(heat):
            raise ParameterError(f"--heatmap expects two names X,Y, got {args.heatmap!r}")
        if figure is None:
            raise ParameterError("--heatmap needs --plot FILE.png")
    elif figure is not None:
        raise ParameterError("--plot needs --heatmap X,Y (the two parameters of the maps)")
    if args.workers is not None and args.scheduler != "local":
        raise ParameterError(
            "--workers N needs --scheduler local (a running scheduler has its own)"
        )
    if args.workers is not None and args.workers > available_cores():
        warn(
            f"--workers {args.workers} is more than this machine's {available_cores()} cores; "
            "the workers will share them"
        )
    check_step(args.step)
    swept = {a.name: f"--grid {a.name}" for a in grid} | {
        a.name: f"--range {a.name}" for a in ranges
    }
    both = sorted(set(a.name for a in grid) & set(a.name for a in ranges))
    if both:
        raise ParameterError(f"{both[0]} is given with both --grid and --range; give it once")
    resolved = design_from_args(args, {k: v for k, v in swept.items() if k != LOAD_MASS})
    spec = SweepSpec(
        sea=resolved.sea,
        grid=tuple(grid),
        ranges=tuple(ranges),
        samples=args.sample,
        seed=args.seed,
        load_mass=resolved.load_mass,
        step=resolved.step,
        horizon=resolved.horizon,
        metrics=not args.no_metrics,
        margin=not args.no_margin,
        chunk_size=args.chunk_size,
    )
    if heat is not None:
        for h in heat:
            if h not in spec.names:
                raise ParameterError(
                    f"--heatmap: {h!r} is not swept{did_you_mean(h, spec.names)}; swept "
                    f"parameters: {', '.join(spec.names)}"
                )
    if "://" not in args.out and "::" not in args.out:  # a URL is checked by fsspec
        out = pathlib.Path(args.out)
        check_writable(out, directory=out.suffix.lower() not in (".parquet", ".csv"))
    try:
        with choose_progress(not args.no_progress) as progress:
            result = run_design_sweep(
                spec,
                args.out,
                resume=args.resume,
                scheduler=args.scheduler,
                workers=args.workers,
                progress=progress,
                force=args.force,
            )
    except KeyboardInterrupt as exc:
        print(
            "error: interrupted; finished chunks are saved, rerun the same command with "
            "--resume to continue",
            file=sys.stderr,
        )
        return interrupted_code(exc)
    announce(result.path)
    summary = result.to_dict()
    if heat is not None and figure is not None:
        from ..plot.sweep import plot_sweep_heatmap

        data = heatmap_data(result.path, heat[0], heat[1])
        save_plot(
            lambda: plot_sweep_heatmap(data, title=f"{spec.n_designs} designs"),
            figure,
            force=args.force,
            flag="--plot",
        )
        summary["figure"] = str(figure)
    if args.json:
        print_json(summary)
    else:
        print(
            f"{result.n_designs:,} designs in {result.n_chunks} chunk(s) "
            f"({result.chunks_resumed} resumed), {result.seconds:.1f} s"
        )
        frac = summary["passive_fraction"]
        print(f"passive: {result.n_passive:,}" + ("" if frac is None else f" ({100 * frac:.1f} %)"))
        if result.n_settled is not None:
            print(f"settled within {spec.horizon:g} s: {result.n_settled:,}")
        print(f"results: {result.path} (columns: {', '.join(result.columns)})")
    return 0
