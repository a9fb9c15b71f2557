"""Dask scale-out: workers write the parts, and the results are exactly the single-process ones."""

from __future__ import annotations

import contextlib
import json
import os
import socket
import struct
import threading
from pathlib import Path
from typing import Any

import msgpack
import pyarrow.csv as pacsv
import pyarrow.parquet as pq
import pytest

import seapass.sweep.cluster
from cpu_budget import BLOCKED_S
from helpers import (
    LP_ARGV,
    one_error,
)
from seapass.cli import main
from seapass.sweep import PartSummary, SweepSpec, run_design_sweep
from seapass.sweep.cluster import probe_scheduler

distributed = pytest.importorskip("dask.distributed")


def test_local_cluster_matches_single_process(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, small_sweep: SweepSpec, assert_same_rows: Any
) -> None:
    ref = pq.read_table(run_design_sweep(small_sweep, tmp_path / "ref.parquet").path)
    # the default is one worker per core; pretend this machine has 2 whatever it has
    monkeypatch.setattr(seapass.sweep.cluster, "available_cores", lambda: 2)
    seen: list[object] = []
    res = run_design_sweep(
        small_sweep,
        tmp_path / "dask.parquet",
        scheduler="local",
        on_part=seen.append,
    )
    assert res.chunks_computed == small_sweep.n_chunks and res.workers == 2
    # the client receives a few numbers per part, never the table
    assert all(type(s) is PartSummary for s in seen)
    assert sorted(s.chunk for s in seen) == list(range(small_sweep.n_chunks))  # type: ignore[attr-defined]
    assert_same_rows(pq.read_table(res.path), ref)
    assert res.compute_seconds > 0


def test_cli_local_cluster_with_workers(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], small_sweep: SweepSpec
) -> None:
    out = tmp_path / "results"
    args = ["sweep", "--D1", "k1 + b1*s", "--CL", "kd", "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--grid", "b1=0:40:20", "--grid", "kd=500:1500:250",
            "--horizon", "1", "--chunk-size", "4", "--no-progress",
            "--scheduler", "local", "--workers", "1", "--out", str(out), "--json"]  # fmt: skip
    assert main(args) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert summary["workers"] == 1 and summary["n_designs"] == small_sweep.n_designs
    assert f"wrote {out}" in captured.err
    ref = run_design_sweep(small_sweep, tmp_path / "ref")
    assert (summary["n_passive"], summary["n_settled"]) == (ref.n_passive, ref.n_settled)


def _worker_env() -> tuple[str | None, str | None]:

    return os.environ.get("MALLOC_TRIM_THRESHOLD_"), os.environ.get("OMP_NUM_THREADS")


def test_existing_scheduler_address(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, small_sweep: SweepSpec, assert_same_rows: Any
) -> None:
    ref = pacsv.read_csv(run_design_sweep(small_sweep, tmp_path / "ref.csv").path)
    monkeypatch.delenv("MALLOC_TRIM_THRESHOLD_", raising=False)
    with (
        seapass.sweep.cluster.local_cluster(2) as cluster,
        distributed.Client(cluster) as client,
    ):
        # Dask's default MALLOC_TRIM_THRESHOLD_ would double a chunk's CPU time (page faults)
        assert set(client.run(_worker_env).values()) == {(None, "1")}
        res = run_design_sweep(small_sweep, tmp_path / "d.csv", scheduler=cluster.scheduler_address)
    assert_same_rows(pacsv.read_csv(res.path), ref)


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
