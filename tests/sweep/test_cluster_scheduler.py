"""A scheduler address that is not a Dask scheduler: the probe is bounded and the sweep
fails in one line (issue 12, item 4)."""

from __future__ import annotations

import contextlib
import socket
import struct
import threading
from pathlib import Path

import msgpack
import pytest

from cpu_budget import BLOCKED_S
from helpers import (
    LP_ARGV,
    one_error,
)
from seapass.sweep.cluster import probe_scheduler

# ------------------------ a scheduler that is not Dask (moved from test_hardening, issue 12 item 4)


@contextlib.contextmanager
def fake_server(reply: bytes | None):
    """A TCP server that sends ``reply`` (None: nothing) to every connection."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(4)
    conns: list[socket.socket] = []
    stop = threading.Event()

    def serve() -> None:
        srv.settimeout(0.1)
        while not stop.is_set():
            try:
                c, _ = srv.accept()
            except OSError:
                continue
            conns.append(c)
            if reply is not None:
                c.sendall(reply)

    t = threading.Thread(target=serve, daemon=True)
    t.start()
    try:
        yield f"tcp://127.0.0.1:{srv.getsockname()[1]}"
    finally:
        stop.set()
        t.join()
        for c in conns:
            c.close()
        srv.close()


def dask_greeting() -> bytes:
    """What a Dask scheduler sends first: a length prefix, one frame, a msgpack map."""
    frame = msgpack.packb({"compression": None, "python": (3, 11, 7), "pickle-protocol": 5})
    body = struct.pack("<QQ", 1, len(frame)) + frame
    return struct.pack("<Q", len(body)) + body


@pytest.mark.parametrize(
    ("reply", "needle"),
    [(None, "within"), (b"HTTP/1.1 200 OK\r\n\r\n" * 50, "answers like a Dask scheduler")],
    ids=["silent", "http"],
)
def test_scheduler_probe_is_bounded_and_one_line(reply: bytes | None, needle: str) -> None:
    with fake_server(reply) as address:
        # silent: the probe's own deadline must end it (whatever the load, nothing comes);
        # http: the answer ends it, the deadline only guards against a fake that never runs
        with pytest.raises(ConnectionError, match=needle):
            probe_scheduler(address, timeout=0.5 if reply is None else BLOCKED_S)


def test_scheduler_probe_accepts_a_dask_greeting_and_refuses_closed_ports() -> None:
    with fake_server(dask_greeting()) as address:
        probe_scheduler(address, timeout=BLOCKED_S)  # the greeting ends it
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    with pytest.raises(ConnectionError, match="refused"):
        probe_scheduler(f"tcp://127.0.0.1:{port}", timeout=BLOCKED_S)  # refused at once


def test_cli_sweep_with_a_fake_scheduler_is_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import seapass.sweep.cluster as cluster

    monkeypatch.setattr(cluster, "SCHEDULER_TIMEOUT", 0.5)
    with fake_server(b"\xff" * 64) as address:
        one_error(
            ["sweep", *LP_ARGV, "--grid", "kd=0:10:5", "--no-metrics", "--out", str(tmp_path / "s.csv"),
             "--scheduler", address],
            "Dask scheduler",
        )  # fmt: skip
