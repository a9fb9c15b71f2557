"""Dask scale-out: workers write the parts, and the results are exactly the single-process ones."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pyarrow.csv as pacsv
import pyarrow.parquet as pq
import pytest

import seapass.sweep.cluster
from seapass.cli import main
from seapass.sweep import PartSummary, SweepSpec, run_design_sweep

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
    import os

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
