"""The ``seapass`` command line.

What lives here: `main` and one module per subcommand.  Each subcommand lives in its own module ``seapass.cli.cmd_<name>`` that defines
``register(subparsers)``; `COMMANDS` lists them in ``--help`` order (add a
command by adding its module and one line there).  Every
[`SeapassError`][seapass.errors.SeapassError] (and ``ValueError`` raised while
validating input) becomes one line on stderr and exit code 2.

May import: everything in seapass (the CLI is the top layer).  The backend
is never chosen here: figures are drawn on bare figures
([`seapass.plot.style.bare_figures`][seapass.plot.style.bare_figures]).
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from ..errors import SeapassError

__all__ = ["COMMANDS", "main", "run"]

COMMANDS: tuple[str, ...] = (
    "check",
    "bound",
    "region",
    "response",
    "witness",
    "tables",
    "simulate",
    "tune",
    "sampled",
    "sweep",
    "rig",
    "export",
    "analyze",
    "reproduce",
    "figure",
    "explore",
)
"""The subcommand modules (``seapass.cli.cmd_<name>``), in ``--help`` order."""


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors are one line and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise _UsageError(f"{self.prog}: {message} (see '{self.prog} --help')")


class _UsageError(Exception):
    pass


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="seapass",
        description="Design series elastic actuators that are passive (safe) and accurate.",
        epilog="Example: seapass check --D1 'k1 + b1*s' --CA 'kd + bd*s' --set m=1 --set b=10 "
        "--set k1=1000 --set b1=20 --set bd=25 --set kd=5000",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in COMMANDS:
        importlib.import_module(f"{__name__}.cmd_{name}").register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (``sys.argv[1:]`` if None); return the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(list(argv) if argv is not None else None)
        return int(args.func(args) or 0)
    except _UsageError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("error: interrupted; no partial output was written", file=sys.stderr)
        return 130
    except (SeapassError, ValueError, OSError) as exc:
        msg = " ".join(str(exc).split()) or type(exc).__name__
        print(f"error: {msg}", file=sys.stderr)
        return 2


def run() -> None:
    """Console-script entry point."""
    sys.exit(main())
