"""The sampled-loop options of the commands that run a digital controller.

``--period --delay --velocity-filter [--method]`` on the command line, read back
into one [`SampledLoop`][seapass.model.loop.SampledLoop]; what a flag leaves out
comes from the design file's ``[control]``.
"""

from __future__ import annotations

import argparse
from typing import Any

from .common import check_period

__all__ = ["add_loop_options", "loop_from_args"]


def add_loop_options(
    p: argparse.ArgumentParser,
    *,
    period: float | None = None,
    delay: int | None = None,
    velocity_filter: float | None = None,
    method: bool = True,
    what: str = "sampled loop",
    period_help: str = "control period T in s",
) -> argparse._ArgumentGroup:
    """``--period --delay --velocity-filter [--method]``, read back by `loop_from_args`.

    A default of None means "the design file's, else none" (``--period``: no sampled loop).
    """
    from ..files.limits import MAX_DELAY_SAMPLES

    file = " (default: the design file's, else {})"
    g = p.add_argument_group(what)
    g.add_argument("--period", type=float, default=period, metavar="T", help=period_help)
    g.add_argument("--delay", type=int, default=delay, metavar="N",
                   help=f"computational delay in samples, 0 to {MAX_DELAY_SAMPLES}"
                   + ("" if delay is not None else file.format(0)))  # fmt: skip
    g.add_argument("--velocity-filter", type=float, default=velocity_filter, metavar="HZ",
                   help="first-order low-pass on the finite-difference velocity, cut-off in Hz "
                   "below the Nyquist frequency 1/(2T)"
                   + ("" if velocity_filter is not None else file.format("none")))  # fmt: skip
    if method:
        g.add_argument("--method", choices=("tustin", "zoh", "backward"),
                       help="discretization of strictly proper controller parts; derivatives "
                       "always use backward differences" + file.format("tustin"))  # fmt: skip
    return g


def loop_from_args(args: argparse.Namespace, design: Any = None) -> Any:
    """The [`SampledLoop`][seapass.model.loop.SampledLoop] of the loop options, or None.

    ``--period`` gives the period (None: no sampled loop); ``--delay``,
    ``--velocity-filter`` and ``--method`` not given come from ``design``'s ``[control]``
    (a [`Design`][seapass.model.design_file.Design]), else 0, none and Tustin.  The
    object checks every value; its errors name the flags.  A period that looks like a
    rate in Hz gets a warning first.
    """
    from ..model.loop import SampledLoop

    period = args.period
    check_period(period)
    if period is None:
        return None
    file = None if design is None else design.loop
    kw: dict[str, Any] = {"period": period}
    for name in ("delay", "velocity_filter", "method"):
        given = getattr(args, name, None)
        if given is None and file is not None:
            given = getattr(file, name)
        if given is not None:
            kw[name] = given
    return SampledLoop(**kw)
