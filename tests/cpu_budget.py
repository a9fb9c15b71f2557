"""Bounding work in tests by CPU time, never by wall-clock time (issue 20, item 7).

A test that fails because the machine is busy is a defect: CI shares machines.  What a
test may bound is the work of the process under test, and CPU time measures that work
whatever else runs beside it:

* `cpu_budget` (this process): ``ITIMER_PROF`` counts the CPU time of this process
  (user + system, all threads) and raises `OverBudget` when the budget is spent;
* `limit_child_cpu` (a child process): ``RLIMIT_CPU`` in the child, which the kernel
  ends with ``SIGXCPU``/``SIGKILL`` when it has computed that long.

Waits on other processes (a server, a browser) carry no time limit: they end when the
awaited thing happens, and the processes doing the work carry CPU limits instead.  Where
an API needs a deadline for a wait that spends no CPU (a socket that may stay silent),
it gets `BLOCKED_S`: an hour, far beyond anything a busy machine can add to work that
takes seconds, so it only ends a wait on something that never comes.
"""

from __future__ import annotations

import contextlib
import resource
import signal
from collections.abc import Callable, Iterator

__all__ = ["BLOCKED_S", "OverBudget", "cpu_budget", "limit_child_cpu"]

#: Deadline [s] of a wait that spends no CPU time and is expected to end by itself.
BLOCKED_S = 3600


class OverBudget(Exception):
    """The code under test used more CPU time than its budget."""


@contextlib.contextmanager
def cpu_budget(seconds: float) -> Iterator[None]:
    """Raise `OverBudget` inside the block once it has used ``seconds`` of CPU time."""

    def _fire(signum: int, frame: object) -> None:
        raise OverBudget(f"more than {seconds} s of CPU time")

    old = signal.signal(signal.SIGPROF, _fire)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0.0)
        signal.signal(signal.SIGPROF, old)


def limit_child_cpu(seconds: int) -> Callable[[], None]:
    """A ``preexec_fn`` for `subprocess`: the child may compute ``seconds`` of CPU time."""

    def _limit() -> None:
        resource.setrlimit(resource.RLIMIT_CPU, (seconds, seconds + 5))

    return _limit
