"""``seapass explore``: the interactive design explorer in the browser."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import MissingExtraError
from .common import check_out_dir

EXAMPLE = """examples:
  seapass explore                          # the paper's LP design
  seapass explore examples/ours.toml       # start from a design file
  seapass explore APD --port 0 --no-browser   # a preset, on a free port

The page runs on 127.0.0.1 only and needs no network: every script and style
sheet ships with seapass. Stop it with Ctrl-C.
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "explore",
        help="interactive design explorer in the browser (live verdicts, regions, responses)",
        description="Start a local web app that shows, for the gains you move, the exact "
        "continuous and sampled passivity verdicts, the passive interval of a gain, the 2-D "
        "passive region, the rendered stiffness and Re Z(jw), the step response and, for a "
        "design that is not passive, a passive environment that destabilizes it.",
        epilog=EXAMPLE,
    )
    p.add_argument(
        "design",
        nargs="?",
        metavar="DESIGN.toml",
        help="design file, or a preset name (LP, APD, Ours or a Table I/II row); default LP",
    )
    p.add_argument(
        "--port",
        type=int,
        default=8765,
        help="port on 127.0.0.1 (default 8765; 0 picks a free one)",
    )
    p.add_argument("--no-browser", action="store_true", help="do not open a browser")
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        metavar="N",
        help="worker processes for the panels (default 5; 0 computes in the server)",
    )
    p.add_argument(
        "--reports",
        metavar="DIR",
        help="where 'Export report' writes (default: a new temporary directory)",
    )
    p.set_defaults(func=run)


def _initial(design: str | None) -> dict[str, object]:
    from ..explore.presets import design_state, presets
    from ..model.design_file import load_design

    known = {p["id"].lower(): p for p in presets()}
    if design is None:
        return dict(known["lp"]["state"])
    if design.lower() in known and not Path(design).exists():
        return dict(known[design.lower()]["state"])
    return design_state(load_design(design))


def run(args: argparse.Namespace) -> int:
    if not 0 <= args.port <= 65535:
        raise ValueError(f"--port {args.port}: give a port from 1 to 65535, or 0 for a free one")
    if args.workers is not None and not 0 <= args.workers <= 16:
        raise ValueError(f"--workers {args.workers}: give 0 to 16")
    try:
        import starlette  # noqa: F401
        import uvicorn  # noqa: F401
    except ImportError as exc:
        raise MissingExtraError(
            f"seapass explore needs the web extra ({exc.name} is missing): "
            "pip install 'seapass[explore]'"
        ) from None
    from ..explore.server import serve
    from ..explore.validation import check_state

    initial = _initial(args.design)
    check = check_state(initial)
    if check.state is None:
        field, message = next(iter(check.errors.items()))
        raise ValueError(f"{args.design}: {field}: {message}")
    reports = check_out_dir(args.reports, "--reports")  # writable, before the server starts

    from ..explore.server import graphical_session

    def ready(url: str) -> None:
        print(f"seapass explore: serving {url} (Ctrl-C stops)", flush=True)
        if not args.no_browser and not graphical_session():
            print("  no graphical session here: open that address in your browser", flush=True)

    try:
        serve(
            initial,
            port=args.port,
            open_browser=not args.no_browser,
            workers=args.workers,
            report_dir=reports,
            ready=ready,
        )
    except KeyboardInterrupt:
        pass  # Ctrl-C is how the explorer is meant to stop
    except OSError as exc:
        msg = str(exc)
        if msg.startswith("port: "):  # the library names its argument; say the option here
            msg = msg[6:].replace("port=0", "--port 0").replace("another port", "another --port")
            raise OSError(msg) from None
        raise
    print("seapass explore: stopped", file=sys.stderr)
    return 0
