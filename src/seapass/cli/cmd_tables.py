"""``seapass tables``: Tables I and II and the proposed design, derived and compared with the paper."""

from __future__ import annotations

import argparse
import functools
from pathlib import Path
from typing import TYPE_CHECKING

from .common import (
    add_force_option,
    add_json_option,
    add_out_dir_option,
    check_out_dir,
    deprecated_alias,
    print_json,
    save_plot,
)

if TYPE_CHECKING:  # the CLI starts fast: heavy modules load when a command runs
    from ..paper.tables import TableRow

EXAMPLE = """examples:
  seapass tables
  seapass tables --json
  seapass tables --format markdown --out figures/
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "tables",
        help="derive Tables I and II and the proposed design; compare with the paper",
        description="Derive every row from first principles and compare it with the paper's printed row.",
        epilog=EXAMPLE,
    )
    add_json_option(p, "a list of rows")
    p.add_argument(
        "--format", choices=("text", "markdown", "latex"), default="text", help="text layout"
    )
    add_out_dir_option(p, "each row's stiffness frequency response (PNG)")
    p.add_argument("--plots", help=argparse.SUPPRESS)  # before 0.3; now --out
    add_force_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..paper.tablefmt import format_latex, format_markdown, format_text
    from ..paper.tables import PAPER_ROWS, build_tables

    out = check_out_dir(
        deprecated_alias(args, "plots", "out"),
        files=[_row_file(r.name) for r in PAPER_ROWS],
        force=args.force,
    )
    rows = build_tables()
    if out is not None:
        write_row_plots(rows, out, force=args.force)
    if args.json:
        print_json([r.to_dict() for r in rows])
    elif args.format == "markdown":
        print(format_markdown(rows))
    elif args.format == "latex":
        print(format_latex(rows))
    else:
        print(format_text(rows))
    return 0


def write_row_plots(rows: list[TableRow], out: Path, *, force: bool = False) -> list[Path]:
    """One PNG per row with the reference values of `REFERENCE_VALUES`.

    Every file is checked before the first is drawn: one seapass did not write
    is replaced only with ``force``.
    """
    from ..analysis.freqresp import stiffness_response
    from ..files.owned import check_replaceable
    from ..model.catalog import REFERENCE_VALUES
    from ..plot.response import plot_stiffness_response

    for r in rows:
        check_replaceable(out / _row_file(r.paper.name), force=force, argument="--out")
    paths = []
    for r in rows:
        vals = {k: REFERENCE_VALUES[k] for k in r.sea.parameters}
        resp = stiffness_response(r.sea, values=vals, label=r.paper.name)
        shown = ", ".join(f"{k}={v:g}" for k, v in vals.items())
        path = out / _row_file(r.paper.name)
        draw = functools.partial(
            plot_stiffness_response,
            resp,
            title=f"{r.paper.title}\n{shown}",
            reference=vals.get("k1"),
        )
        save_plot(draw, path, force=force)
        paths.append(path)
    return paths


def _row_file(name: str) -> str:
    return f"{name.replace('/', '_')}.png"
