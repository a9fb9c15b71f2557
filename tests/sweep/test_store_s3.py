"""Sweep output on S3, against moto's S3 server on loopback (offline).

Opt-in: s3fs and ``moto[server]`` add some fifty packages, so they are not in
the ``test`` extra and CI skips this module.  To run it::

    .venv/bin/pip install s3fs "moto[server]"
    .venv/bin/python -m pytest tests/sweep/test_store_s3.py
"""

from __future__ import annotations

import socket
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pyarrow.dataset as ds
import pyarrow.parquet as pq
import pytest

from seapass.sweep import MANIFEST, SweepSpec, heatmap_data, run_design_sweep

s3fs = pytest.importorskip("s3fs")
moto_server = pytest.importorskip("moto.server")
boto3 = pytest.importorskip("boto3")


@pytest.fixture(scope="module")
def s3() -> Iterator[tuple[Any, dict[str, Any]]]:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = moto_server.ThreadedMotoServer(ip_address="127.0.0.1", port=port)
    server.start()
    endpoint = f"http://127.0.0.1:{port}"
    boto3.client(
        "s3", endpoint_url=endpoint, region_name="us-east-1",
        aws_access_key_id="test", aws_secret_access_key="test",
    ).create_bucket(Bucket="sweeps")  # fmt: skip
    opts = {"key": "test", "secret": "test", "client_kwargs": {"endpoint_url": endpoint}}
    try:
        yield s3fs.S3FileSystem(**opts), opts
    finally:
        server.stop()


def test_s3_directory_file_resume_and_dask_workers(
    s3: Any, tmp_path: Path, small_sweep: SweepSpec, assert_same_rows: Any
) -> None:
    fs, opts = s3
    SPEC, _assert_same = small_sweep, assert_same_rows
    ref = pq.read_table(run_design_sweep(SPEC, tmp_path / "ref.parquet").path)

    one = run_design_sweep(SPEC, "s3://sweeps/one.parquet", storage_options=opts)
    with fs.open("sweeps/one.parquet", "rb") as fh:
        _assert_same(pq.read_table(fh), ref)
    assert fs.ls("sweeps", refresh=True) == ["sweeps/one.parquet"]  # parts merged and removed

    res = run_design_sweep(SPEC, "s3://sweeps/dir/", storage_options=opts)
    assert fs.isfile(f"sweeps/dir/{MANIFEST}") and res.n_passive == one.n_passive
    _assert_same(ds.dataset("sweeps/dir", filesystem=fs).to_table().sort_by("index"), ref)
    assert (
        heatmap_data("s3://sweeps/dir", "kd", "b1", storage_options=opts).count.sum()
        == SPEC.n_designs
    )

    fs.rm(["sweeps/dir/part-000001.parquet", "sweeps/dir/part-000003.parquet"])
    again = run_design_sweep(SPEC, "s3://sweeps/dir/", storage_options=opts, resume=True)
    assert again.chunks_computed == 2 and again.n_passive == one.n_passive

    pytest.importorskip("dask.distributed")
    from seapass.sweep.cluster import local_cluster

    with local_cluster(2) as cluster:
        dask_res = run_design_sweep(
            SPEC, "s3://sweeps/dask/", storage_options=opts,
            scheduler=cluster.scheduler_address,
        )  # fmt: skip
    assert dask_res.workers == 2 and dask_res.chunks_computed == SPEC.n_chunks
    _assert_same(ds.dataset("sweeps/dask", filesystem=fs).to_table().sort_by("index"), ref)
