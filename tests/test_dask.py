"""Dask scale-out gives exactly the single-process results."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyarrow.csv as pacsv
import pyarrow.parquet as pq
import pytest

from seapass.model.sea import SEA
from seapass.sweep import GridAxis, SweepSpec, run_design_sweep

distributed = pytest.importorskip("dask.distributed")

SPEC = SweepSpec(
    sea=SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1.0, b=10.0, k1=1000.0, b1=None, kd=None)),
    grid=(GridAxis("b1", 0.0, 40.0, 20.0), GridAxis("kd", 500.0, 1500.0, 250.0)),
    chunk_size=4,
    horizon=1.0,
)


def _assert_same(a, b) -> None:
    assert a.column_names == b.column_names and a.num_rows == b.num_rows
    for name in a.column_names:  # NaN-aware, bit-for-bit
        np.testing.assert_array_equal(
            a.column(name).to_numpy(zero_copy_only=False),
            b.column(name).to_numpy(zero_copy_only=False),
        )


def test_local_cluster_matches_single_process(tmp_path: Path) -> None:
    ref = pq.read_table(run_design_sweep(SPEC, tmp_path / "ref.parquet", progress=False).path)
    res = run_design_sweep(SPEC, tmp_path / "dask.parquet", scheduler="local", progress=False)
    assert res.chunks_computed == SPEC.n_chunks
    _assert_same(pq.read_table(res.path), ref)


def test_existing_scheduler_address(tmp_path: Path) -> None:
    ref = pacsv.read_csv(run_design_sweep(SPEC, tmp_path / "ref.csv", progress=False).path)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        res = run_design_sweep(
            SPEC, tmp_path / "d.csv", scheduler=cluster.scheduler_address, progress=False
        )
    _assert_same(pacsv.read_csv(res.path), ref)
