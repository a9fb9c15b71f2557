"""The ``seapass`` command line.

What lives here: `main` and one module per subcommand.  Each subcommand lives in its own module ``seapass.cli.cmd_<name>`` that defines
``register(subparsers)``; `COMMANDS` lists them in ``--help`` order (add a
command by adding its module and one line there).  Every
[`SeapassError`][seapass.errors.SeapassError] (and ``ValueError`` raised while
validating input) becomes one line on stderr and exit code 2.  The shared
conventions (options, output, messages) live in [`common`][seapass.cli.common].

May import: everything in seapass (the CLI is the top layer).  The backend
is never chosen here: figures are drawn on bare figures
([`seapass.plot.style.bare_figures`][seapass.plot.style.bare_figures]).
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import threading
import warnings
from collections.abc import Sequence
from typing import Any

from ..errors import SeapassDeprecationWarning, SeapassError
from ..version import __version__
from .common import EXIT_CODES, HelpFormatter, Terminated, error_text, interrupted_code, warn

__all__ = ["COMMANDS", "main", "run"]

COMMANDS: tuple[str, ...] = (
    "check",
    "bound",
    "region",
    "response",
    "plot",
    "witness",
    "twoport",
    "mimo",
    "tables",
    "simulate",
    "tune",
    "sampled",
    "delay_margin",
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
    """ArgumentParser for every seapass command.

    Usage errors are one line and exit code 2; ``--help`` shows defaults
    ([`HelpFormatter`][seapass.cli.common.HelpFormatter]); a value with a leading
    minus is a value, not an unknown option (``--range -100:100``, ``--CL "-k1*x"``).
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        if kwargs.get("formatter_class") in (
            None,
            argparse.HelpFormatter,
            argparse.RawDescriptionHelpFormatter,
        ):
            kwargs["formatter_class"] = HelpFormatter
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> None:  # type: ignore[override]
        raise _UsageError(f"{self.prog}: {message} (see '{self.prog} --help')")

    def _parse_optional(self, arg_string: str) -> Any:
        found = super()._parse_optional(arg_string)
        if found is None or arg_string.startswith("--") or not arg_string.startswith("-"):
            return found
        # a single-dash word that names no option is a value: -100:100, -k1*x, -1e-3
        tuples = found if isinstance(found, list) else [found]
        if all(t[0] is None for t in tuples):
            return None
        return found


class _UsageError(Exception):
    pass


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="seapass",
        description="Design series elastic actuators that are passive (safe) and accurate.",
        epilog="Example: seapass check --D1 'k1 + b1*s' --CA 'kd + bd*s' --set m=1 --set b=10 "
        "--set k1=1000 --set b1=20 --set bd=25 --set kd=5000\n\n" + EXIT_CODES,
    )
    parser.add_argument("--version", action="version", version=f"seapass {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in COMMANDS:
        importlib.import_module(f"{__name__}.cmd_{name}").register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (``sys.argv[1:]`` if None); return the exit code.

    Exit codes: 0 success, 1 a negative verdict of a check (``check``: not
    passive), 2 bad input or another error (one ``error:`` line on stderr),
    130 interrupted (Ctrl-C), 141 standard output closed early (``seapass check … | head
    -1``: quietly, as a command killed by ``SIGPIPE``), 143 terminated (SIGTERM: stopped
    as cleanly as Ctrl-C).
    """
    previous = _on_sigterm(_terminate)
    try:
        return _main(argv)
    finally:
        _on_sigterm(previous)


def _terminate(signum: int, frame: Any) -> None:
    raise Terminated()


def _on_sigterm(handler: Any) -> Any:
    """Install ``handler`` for SIGTERM (main thread only); the previous handler, or None."""
    if handler is None or threading.current_thread() is not threading.main_thread():
        return None
    return signal.signal(signal.SIGTERM, handler)


def _main(argv: Sequence[str] | None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(list(argv) if argv is not None else None)
        with warnings.catch_warnings():  # an old spelling (a rig-file key) is one warning line
            warnings.simplefilter("default", SeapassDeprecationWarning)
            warnings.showwarning = _show_deprecation(warnings.showwarning)
            code = int(args.func(args) or 0)
        sys.stdout.flush()  # a closed pipe fails here, not in the interpreter's exit
        return code
    except _UsageError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError as exc:
        if _stdout_closed():
            return EXIT_STDOUT_CLOSED
        print(f"error: {error_text(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        print("error: interrupted; no partial output was written", file=sys.stderr)
        return interrupted_code(exc)
    except (SeapassError, ValueError, OSError) as exc:
        print(f"error: {error_text(exc)}", file=sys.stderr)
        return 2
    except (RecursionError, MemoryError) as exc:
        print(f"error: the input is too large to process ({type(exc).__name__})", file=sys.stderr)
        return 2
    except Exception as exc:  # a bug: still one line, the traceback on request
        if os.environ.get("SEAPASS_TRACEBACK"):
            raise
        print(
            f"error: internal error ({type(exc).__name__}: {error_text(exc)}); please report "
            "it with the command line (SEAPASS_TRACEBACK=1 shows the traceback)",
            file=sys.stderr,
        )
        return 2


EXIT_STDOUT_CLOSED = 141
"""Exit code when the reader of standard output went away (128 + SIGPIPE, as a shell reports
a command killed by the signal); nothing is printed."""


def _stdout_closed() -> bool:
    """Standard output's reader is gone: point it at ``os.devnull`` so nothing more fails.

    A `BrokenPipeError` raised by writing some other file is not this: standard
    output is polled for the error condition a pipe without reader reports.
    """
    try:
        fd = sys.stdout.fileno()
    except (OSError, ValueError, AttributeError):
        return False
    try:
        import select

        poller = select.poll()
        poller.register(fd, select.POLLOUT)
        events = dict(poller.poll(0)).get(fd, 0)
        if not events & (select.POLLERR | select.POLLHUP):
            return False
    except (OSError, ValueError, AttributeError):  # no poll on this platform: trust the error
        pass
    try:  # the interpreter flushes stdout again at exit; let that write go nowhere
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, fd)
        os.close(devnull)
    except OSError:
        pass
    return True


def _show_deprecation(show: Any) -> Any:
    def shown(message: Any, category: type[Warning], *args: Any, **kwargs: Any) -> None:
        if issubclass(category, SeapassDeprecationWarning):
            warn(str(message))
        else:
            show(message, category, *args, **kwargs)

    return shown


def run() -> None:
    """Console-script entry point."""
    sys.exit(main())
