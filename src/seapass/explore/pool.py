"""Worker processes that compute panels, each killable, each with warm caches.

Panels run in separate processes so that the server stays responsive while
sympy and the exact arithmetic work (they hold the GIL), so that slow panels
(the sampled verdict, the destabilizing environment) run beside fast ones,
and so that a computation over its time or memory budget can be stopped: its
worker is killed and replaced, and the panel reports the budget it exceeded.
Each panel kind always goes to the same worker, so its caches stay warm.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import multiprocessing.connection
import os
import signal
import threading
import time
from collections.abc import Mapping
from typing import Any

from .panels import REGION_RESOLUTIONS, compute, error_message
from .validation import check_state

__all__ = ["AFFINITY", "PanelPool", "run_panel"]

#: Worker slot of each panel kind; the refined 2-D region has its own slot so that a
#: long refinement never delays the coarse panels of the next change.
AFFINITY: Mapping[str, int] = {
    "verdict": 0,
    "frequency": 0,
    "twoport": 0,
    "step": 1,
    "interval": 1,
    "region": 1,
    "region-fine": 2,
    "sampled": 3,
    "delay": 3,
    "witness": 4,
    "robust": 3,
}
SLOTS = 5


def run_panel(kind: str, state: Any, options: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Validate ``state`` and compute one panel: ``{"ok": True, "data": ...}`` or ``{"ok": False, "error": ...}``.

    ``options`` are the keyword options of `seapass.explore.panels.compute`
    (``resolution``, ``rows``).  Never raises for bad input: every failure is data.
    """
    check = check_state(state)
    if check.state is None:
        field, message = next(iter(check.errors.items()))
        return {"ok": False, "error": f"{field}: {message}", "errors": dict(check.errors)}
    try:
        t0 = time.perf_counter()
        data = compute(kind, check.state, **dict(options or {}))
        return {"ok": True, "data": data, "ms": (time.perf_counter() - t0) * 1e3}
    except MemoryError:
        return {"ok": False, "error": "the computation ran out of its memory budget"}
    except RecursionError:
        return {"ok": False, "error": "the expression is too deeply nested"}
    except Exception as exc:  # failure is data: the server must never crash on a panel
        return {"ok": False, "error": error_message(exc)}


def _worker_main(conn: multiprocessing.connection.Connection, memory_limit: int) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the server's to handle
    with contextlib.suppress(Exception):
        from threadpoolctl import threadpool_limits

        threadpool_limits(1)  # the workers already run in parallel: no BLAS threads on top
    if memory_limit > 0:
        with contextlib.suppress(ValueError, OSError, ImportError):
            import resource

            resource.setrlimit(resource.RLIMIT_AS, (memory_limit, memory_limit))
    while True:
        try:
            kind, state, options = conn.recv()
        except (EOFError, OSError):
            return
        reply = run_panel(kind, state, options)
        try:
            conn.send(reply)
        except (BrokenPipeError, OSError):
            return


class _Worker:
    def __init__(self, ctx: Any, memory_limit: int) -> None:
        self._ctx = ctx
        self._memory_limit = memory_limit
        self._lock = threading.Lock()
        self._proc: Any = None
        self._conn: multiprocessing.connection.Connection | None = None

    def _start(self) -> None:
        parent, child = self._ctx.Pipe()
        proc = self._ctx.Process(target=_worker_main, args=(child, self._memory_limit), daemon=True)
        proc.start()
        child.close()
        self._proc, self._conn = proc, parent

    def stop(self) -> None:
        if self._conn is not None:
            self._conn.close()
        if self._proc is not None and self._proc.is_alive():
            self._proc.kill()
            self._proc.join(timeout=5)
        self._proc = self._conn = None

    def call(self, job: tuple[str, Any, Any], timeout: float | None) -> dict[str, Any]:
        """Run one job (blocking; one at a time per worker)."""
        with self._lock:
            if self._proc is None or not self._proc.is_alive():
                self.stop()
                self._start()
            assert self._conn is not None
            try:
                self._conn.send(job)
                if self._conn.poll(timeout):
                    return dict(self._conn.recv())
            except (EOFError, OSError, BrokenPipeError):
                self.stop()
                return {"ok": False, "error": "the computation stopped unexpectedly; try again"}
            self.stop()  # over budget: kill it, a fresh worker takes the next job
            return {
                "ok": False,
                "error": f"the computation took longer than {timeout:g} s and was stopped; "
                "simplify the model or change the values",
            }


class PanelPool:
    """Panel workers, one slot per group of panel kinds (see `AFFINITY`).

    Parameters
    ----------
    workers : int
        Worker processes (slots beyond this share workers); 0 computes in the
        calling thread (no time limit, for tests).
    timeout : float or None
        Seconds one panel may take before its worker is killed (``None``: no limit,
        for tests, whose outcome must not depend on how busy the machine is).
    memory_limit : int
        Address-space limit of each worker in bytes (0: none).
    """

    def __init__(
        self, workers: int = SLOTS, *, timeout: float | None = 60.0, memory_limit: int = 4 << 30
    ):
        if workers < 0:
            raise ValueError(f"workers must be >= 0, got {workers}")
        self.timeout = timeout
        ctx = multiprocessing.get_context("forkserver" if os.name == "posix" else "spawn")
        if os.name == "posix":
            ctx.set_forkserver_preload([__name__])
        self._workers = [_Worker(ctx, memory_limit) for _ in range(workers)]
        self._closed = False

    def _slot(self, kind: str, options: Mapping[str, Any]) -> int:
        fine = (
            kind == "region"
            and options.get("resolution", REGION_RESOLUTIONS[0]) > REGION_RESOLUTIONS[0]
        )
        return AFFINITY.get("region-fine" if fine else kind, 0) % max(1, len(self._workers))

    def call(
        self, kind: str, state: Any, options: Mapping[str, Any] | None = None
    ) -> dict[str, Any]:
        """Compute one panel (blocking); see `run_panel`."""
        opts = dict(options or {})
        if self._closed:
            return {"ok": False, "error": "the server is shutting down"}
        if not self._workers:
            return run_panel(kind, state, opts)
        return self._workers[self._slot(kind, opts)].call((kind, state, opts), self.timeout)

    def warm_up(self, state: Any) -> None:
        """Start every worker and compute the panels of ``state`` once (fills the caches)."""
        jobs: list[tuple[str, dict[str, Any]]] = [(k, {}) for k in AFFINITY if k != "region-fine"]
        jobs.append(("region", {"resolution": REGION_RESOLUTIONS[1], "rows": [0, 1]}))
        threads = [threading.Thread(target=self.call, args=(k, state, o)) for k, o in jobs]
        for t in threads:
            t.start()
        for t in threads:
            t.join()

    def close(self) -> None:
        self._closed = True
        for w in self._workers:
            w.stop()
