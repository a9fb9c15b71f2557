"""``seapass figure``: regenerate a paper figure with its data (target ``sims``: Fig. 4)."""

from __future__ import annotations

import argparse
import sys

from .common import (
    add_force_option,
    add_json_option,
    add_out_dir_option,
    check_out_dir,
    save_plot,
    write_text,
)

FILES = ("sims.png", "sims.pdf", "sims.csv", "sims_table.csv", "sims_table.json")
"""What ``seapass figure`` writes into ``--out``."""

EXAMPLE = """examples:
  seapass figure sims --out figures/
  seapass figure sims --out /tmp/preview --quick

'sims' tunes LP, APD and Ours at m_L = 10 kg (0.5 m step, exact passivity
constraint) and simulates each at m_L = 1, 10 and 25 kg. It writes sims.png,
sims.pdf, sims.csv (time series), sims_table.csv and sims_table.json to --out.
"""

TARGETS = ("sims",)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "figure",
        help="regenerate a paper figure and its data (sims: the simulation study)",
        description="Regenerate a figure of the paper from first principles, with the data "
        "behind it. Every file is written atomically.",
        epilog=EXAMPLE,
    )
    p.add_argument("target", choices=TARGETS, help="which figure")
    add_out_dir_option(p, "the figure (PNG, PDF) and its data (CSV, JSON)", required=True)
    add_force_option(p)
    p.add_argument("--quick", action="store_true", help="small optimiser budget (preview)")
    p.add_argument("--horizon", type=float, default=10.0, help="evaluation horizon [s]")
    p.add_argument("--seed", type=int, default=0, help="optimiser seed")
    p.add_argument("--no-progress", action="store_true", help="no progress on stderr")
    add_json_option(p, "the table of the figure")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from ..paper.simstudy import run_simulation_study
    from ..plot.sim import plot_simulation_study
    from ..tuning.problem import TuningOptions
    from .progress import choose_progress

    out = check_out_dir(args.out, files=FILES, force=args.force)
    assert out is not None  # --out is required
    opts = replace(TuningOptions(), seed=args.seed, horizon=args.horizon)
    with choose_progress(not args.no_progress) as progress:
        study = run_simulation_study(
            options=opts, quick=args.quick, horizon=args.horizon, progress=progress
        )
    # compute everything first, then write each file atomically
    save_plot(
        lambda: plot_simulation_study(study), out / "sims", formats=("png", "pdf"), force=args.force
    )
    write_text(out / "sims.csv", study.timeseries_csv(), force=args.force)
    write_text(out / "sims_table.csv", study.table_csv(), force=args.force)
    write_text(out / "sims_table.json", study.table_json(), force=args.force)
    if args.json:
        sys.stdout.write(study.table_json().rstrip("\n") + "\n")
    else:
        print(study.summary())
    return 0
