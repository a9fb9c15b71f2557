"""Dask for sweeps: start or reach a cluster, and keep a bounded window of tasks in flight.

``scheduler="local"`` starts a ``LocalCluster`` of single-threaded worker
processes, one per core of this machine unless ``workers`` says otherwise;
``"tcp://host:port"`` connects to a running scheduler.  Dask is the optional
extra ``seapass[dask]``; without it these functions raise
[`MissingExtraError`][seapass.errors.MissingExtraError].
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from ..errors import MissingExtraError, ParameterError

__all__ = [
    "MALLOC_TRIM",
    "MAX_LOCAL_WORKERS",
    "SCHEDULER_TIMEOUT",
    "available_cores",
    "check_scheduler",
    "dask_client",
    "local_cluster",
    "probe_scheduler",
    "run_bounded",
    "total_threads",
]


#: Upper bound of ``workers`` for a LocalCluster (a typo guard, far above any machine's cores).
MAX_LOCAL_WORKERS = 1024


def available_cores() -> int:
    """Cores this process may run on (CPU affinity, else ``os.cpu_count()``), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # not on Linux
        return max(1, os.cpu_count() or 1)


def check_scheduler(scheduler: str | None, workers: int | None) -> None:
    """Validate ``scheduler`` and ``workers`` before any work starts."""
    if scheduler is not None and not (scheduler == "local" or scheduler.startswith("tcp://")):
        raise ParameterError(
            f"scheduler must be 'local' or a tcp://host:port address, got {scheduler!r}"
        )
    if workers is not None:
        if scheduler != "local":
            raise ParameterError(
                "workers: only with scheduler='local' (a running scheduler has its own workers)"
            )
        if not 1 <= workers <= MAX_LOCAL_WORKERS:
            raise ParameterError(f"workers must be in 1..{MAX_LOCAL_WORKERS}, got {workers}")


def _import_distributed() -> Any:
    try:
        import dask.distributed as distributed
    except ImportError:
        raise MissingExtraError(
            "scheduler: running on Dask needs the dask extra; install it with "
            "pip install 'seapass[dask]' (or run without a scheduler)"
        ) from None
    return distributed


#: Dask's nanny sets this in every worker's environment to return freed memory
#: to the system at once.  Setting it at all also turns off glibc's adaptive
#: mmap threshold, so every large numpy temporary is mmapped and unmapped
#: again: in a sweep chunk that doubles the CPU time (measured: 0.34 s → 0.7 s
#: for 12 chunks of 16,384 designs, nearly all of it page faults).
MALLOC_TRIM = "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_"


@contextmanager
def local_cluster(workers: int | None = None) -> Iterator[Any]:
    """A ``LocalCluster`` of ``workers`` single-threaded processes (default: one per core).

    Workers keep glibc's default memory allocator settings (see `MALLOC_TRIM`),
    unless ``MALLOC_TRIM_THRESHOLD_`` is set in this process's environment.
    """
    distributed = _import_distributed()
    import dask

    n = workers if workers is not None else available_cores()
    with (
        dask.config.set({MALLOC_TRIM: None}),
        distributed.LocalCluster(
            n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
    ):
        yield cluster


SCHEDULER_TIMEOUT = 10.0
"""Seconds to reach a Dask scheduler, to hear its greeting and to find a worker."""


def probe_scheduler(address: str, timeout: float = SCHEDULER_TIMEOUT) -> None:
    """Raise `ConnectionError` unless a Dask scheduler answers at ``tcp://host:port``.

    Dask's client waits without a deadline for the greeting of whatever
    listens at the address, and reads any bytes it gets as a message length
    (an HTTP server makes it allocate gigabytes).  So first, with a plain
    socket and a deadline: connect, read the scheduler's handshake (a length
    prefix, then a small msgpack map with ``python`` and ``pickle-protocol``)
    and check it, reading at most 64 KiB.
    """
    import socket
    import struct

    import msgpack

    hostport = address.removeprefix("tcp://")
    host, _, port_text = hostport.rpartition(":")
    host = host.strip("[]")
    if not host or not port_text.isdigit() or not 0 < int(port_text) < 65536:
        raise ParameterError(
            f"scheduler: {address!r} is not a tcp://host:port address", argument="scheduler"
        )
    what = f"scheduler: nothing at {address} answers like a Dask scheduler"
    deadline = time.monotonic() + timeout

    def recv_exactly(sock: socket.socket, n: int) -> bytes:
        data = b""
        while len(data) < n:
            sock.settimeout(max(deadline - time.monotonic(), 0.01))
            chunk = sock.recv(n - len(data))
            if not chunk:
                raise ConnectionError(f"{what} (it closed the connection)")
            data += chunk
        return data

    try:
        with socket.create_connection((host, int(port_text)), timeout=timeout) as sock:
            (size,) = struct.unpack("<Q", recv_exactly(sock, 8))
            if not 16 <= size <= 65536:
                raise ConnectionError(what)
            body = recv_exactly(sock, size)
            (frames,) = struct.unpack("<Q", body[:8])
            if not 1 <= frames <= 16 or 8 + 8 * frames > size:
                raise ConnectionError(what)
            first = struct.unpack("<Q", body[8:16])[0]
            start = 8 + 8 * frames
            info = msgpack.unpackb(body[start : start + first], raw=False)
            if not isinstance(info, dict) or "python" not in info:
                raise ConnectionError(what)
    except TimeoutError:
        raise ConnectionError(f"{what} within {timeout:g} s") from None
    except ConnectionError as exc:
        if exc.errno is None:  # raised above, already says what is wrong
            raise
        raise ConnectionError(f"{what} ({exc.strerror})") from None
    except (OSError, ValueError, struct.error, msgpack.UnpackException) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise ConnectionError(f"{what} ({reason})") from None


@contextmanager
def dask_client(scheduler: str, workers: int | None = None) -> Iterator[Any]:
    """A ``dask.distributed.Client`` on a new LocalCluster (``"local"``) or at an address.

    The LocalCluster (see [`local_cluster`][seapass.sweep.cluster.local_cluster])
    has ``workers`` single-threaded processes, one per available core by
    default, and is closed on exit.
    """
    distributed = _import_distributed()
    if scheduler == "local":
        with local_cluster(workers) as cluster, distributed.Client(cluster) as client:
            yield client
    else:
        probe_scheduler(scheduler, SCHEDULER_TIMEOUT)
        with distributed.Client(scheduler, timeout=SCHEDULER_TIMEOUT) as client:
            try:
                client.wait_for_workers(1, timeout=SCHEDULER_TIMEOUT)
            except TimeoutError:
                raise ConnectionError(
                    f"scheduler: the Dask scheduler at {scheduler} has no workers "
                    f"(waited {SCHEDULER_TIMEOUT:g} s); start some with 'dask worker {scheduler}'"
                ) from None
            yield client


def total_threads(client: Any) -> int:
    """Worker threads in the cluster now (workers may join or leave while a sweep runs)."""
    return max(1, sum(client.nthreads().values()))


def run_bounded(
    client: Any, fn: Callable[..., Any], items: Sequence[Any], *args: Any, per_thread: int = 2
) -> Iterator[Any]:
    """Yield ``fn(item, *args)`` for every item, as tasks finish, in any order.

    At most ``per_thread`` tasks per worker thread are in flight, which bounds
    the scheduler's and the client's memory for any number of items and keeps
    every worker busy while the client handles a result.
    """
    distributed = _import_distributed()
    pending = list(reversed(items))
    done = distributed.as_completed()
    in_flight = 0
    window = per_thread * total_threads(client)

    def top_up() -> None:
        nonlocal in_flight
        while pending and in_flight < window:
            done.add(client.submit(fn, pending.pop(), *args, pure=False))
            in_flight += 1

    top_up()
    for k, future in enumerate(done, start=1):
        in_flight -= 1
        result = future.result()
        if k % 64 == 0:  # workers may have joined (adaptive clusters)
            window = per_thread * total_threads(client)
        top_up()
        yield result
