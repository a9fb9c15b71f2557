"""Sweep output: dataset directories that readers open, fsspec URLs, the manifest journal,
hard kills, and directories of older seapass versions."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.dataset as ds
import pyarrow.parquet as pq
import pytest

from cpu_budget import limit_child_cpu
from seapass.errors import FileFormatError, ParameterError
from seapass.sweep import (
    MANIFEST,
    PartSummary,
    SweepSpec,
    heatmap_data,
    open_location,
    run_design_sweep,
)
from seapass.sweep.store import SweepStore

#: The fingerprint earlier seapass versions wrote for the ``small_sweep`` fixture: migration of old directories relies on it.
SPEC_FINGERPRINT_BEFORE = "57584e2fff83f3ef"


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory, small_sweep: SweepSpec) -> pa.Table:
    out = tmp_path_factory.mktemp("ref") / "ref.parquet"
    return pq.read_table(run_design_sweep(small_sweep, out).path)


def test_directory_output_reads_as_a_dataset(
    tmp_path: Path, reference: pa.Table, small_sweep: SweepSpec, assert_same_rows: Any
) -> None:
    out = tmp_path / "results"
    res = run_design_sweep(small_sweep, out)
    assert res.path == str(out) and (out / MANIFEST).is_file()
    assert not (out / "manifest.json").exists()
    # the documented read: the manifest's leading underscore makes pyarrow skip it
    table = ds.dataset(str(out)).to_table().sort_by("index")
    assert_same_rows(table, reference)
    manifest = json.loads((out / MANIFEST).read_text())
    assert manifest["complete"] and manifest["done"] == [[0, small_sweep.n_chunks]]
    assert (
        manifest["n_passive"] == res.n_passive
        and manifest["fingerprint"] == small_sweep.fingerprint()
    )


def test_directory_output_reads_in_duckdb(
    tmp_path: Path, reference: pa.Table, small_sweep: SweepSpec
) -> None:
    duckdb = pytest.importorskip("duckdb")
    out = tmp_path / "results"
    run_design_sweep(small_sweep, out)
    con = duckdb.connect()
    n, n_passive, kd_sum = con.execute(
        "SELECT count(*), sum(passive::INT), sum(kd) FROM read_parquet(?)", [str(out)]
    ).fetchone()
    assert n == reference.num_rows
    assert n_passive == int(np.count_nonzero(reference.column("passive").to_numpy(False)))
    assert kd_sum == pytest.approx(float(np.sum(reference.column("kd").to_numpy())))
    rows = con.execute(
        "SELECT index, settling_time FROM read_parquet(?) ORDER BY index", [f"{out}/*.parquet"]
    ).fetchall()
    np.testing.assert_array_equal(
        np.array([r[1] if r[1] is not None else np.nan for r in rows], dtype=float),
        reference.column("settling_time").to_numpy(),
    )


@pytest.mark.parametrize("name", ["x.parquet", "dir"])
def test_memory_filesystem_gives_the_same_rows(
    name: str, reference: pa.Table, small_sweep: SweepSpec, assert_same_rows: Any
) -> None:
    import fsspec

    url = f"memory://seapass-test/{os.getpid()}/{name}"
    fs = fsspec.filesystem("memory")
    try:
        res = run_design_sweep(small_sweep, url)
        assert res.path == url
        if name.endswith(".parquet"):
            with fs.open(url, "rb") as fh:
                table = pq.read_table(fh)
            assert not fs.exists(url + ".parts")  # parts are merged and removed
        else:
            assert fs.isfile(f"{url}/{MANIFEST}")
            table = ds.dataset(fsspec.core.url_to_fs(url)[1], filesystem=fs).to_table()
            table = table.sort_by("index")
        assert_same_rows(table, reference)
        data = heatmap_data(url, "kd", "b1")
        assert data.count.sum() == reference.num_rows
    finally:
        fs.rm(f"/seapass-test/{os.getpid()}", recursive=True)


def test_file_url_and_csv(
    tmp_path: Path, reference: pa.Table, small_sweep: SweepSpec, assert_same_rows: Any
) -> None:
    import pyarrow.csv as pacsv

    res = run_design_sweep(small_sweep, f"file://{tmp_path}/r.csv")
    assert Path(res.path.removeprefix("file://")).is_file()
    types = pacsv.ConvertOptions(column_types=reference.schema)
    assert_same_rows(pacsv.read_csv(tmp_path / "r.csv", convert_options=types), reference)


def test_memory_filesystem_is_refused_for_dask_workers(small_sweep: SweepSpec) -> None:
    with pytest.raises(ParameterError, match="inside this process"):
        run_design_sweep(small_sweep, "memory://x/y", scheduler="local")


def test_not_a_sweep_directory_is_refused_and_kept(tmp_path: Path, small_sweep: SweepSpec) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    with pytest.raises(FileFormatError, match="not a seapass sweep directory"):
        run_design_sweep(small_sweep, out)
    assert (out / "notes.txt").read_text() == "keep me"


def test_a_part_the_client_cannot_see_is_an_error(tmp_path: Path, small_sweep: SweepSpec) -> None:
    # what a Dask worker on another machine writing to its own disk looks like
    store = SweepStore.open(small_sweep, open_location(tmp_path / "d"), resume=False)
    lost = PartSummary(chunk=0, rows=4, n_passive=1, n_settled=0, nbytes=999, seconds=0.0,
                       columns=("index",))  # fmt: skip
    with pytest.raises(FileFormatError, match="shared by the client and every worker"):
        store.record(lost)


def test_journal_missing_parts_are_recounted(
    tmp_path: Path, reference: pa.Table, small_sweep: SweepSpec, assert_same_rows: Any
) -> None:
    out = tmp_path / "j"
    res = run_design_sweep(small_sweep, out)
    for c in (1, 3):  # parts the journal lists have gone: recount, recompute
        (out / f"part-{c:06d}.parquet").unlink()
    again = run_design_sweep(small_sweep, out, resume=True)
    assert again.chunks_computed == 2 and again.chunks_resumed == small_sweep.n_chunks - 2
    assert (again.n_passive, again.n_settled) == (res.n_passive, res.n_settled)
    assert_same_rows(ds.dataset(str(out)).to_table().sort_by("index"), reference)


KILLER = """
import os, signal, sys
import seapass.sweep.store
from seapass.model.sea import SEA
from seapass.sweep import GridAxis, SweepSpec, run_design_sweep

spec = SweepSpec(
    sea=SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1.0, b=10.0, k1=1000.0, b1=None, kd=None)),
    grid=(GridAxis("b1", 0.0, 40.0, 20.0), GridAxis("kd", 500.0, 1500.0, 250.0)),
    chunk_size=4, horizon=1.0,
)

def hook(s):
    if s.chunk == int(sys.argv[3]):
        os.kill(os.getpid(), signal.SIGKILL)

if __name__ == "__main__":
    seapass.sweep.store.JOURNAL_INTERVAL = float(sys.argv[4])  # seconds between rewrites
    sched = None if sys.argv[2] == "-" else sys.argv[2]
    run_design_sweep(spec, sys.argv[1], scheduler=sched, workers=2 if sched else None, on_part=hook)
"""


def kill_midway(
    out: Path, scheduler: str | None, at_chunk: int, journal_interval: float = 1.0
) -> None:
    """Run the ``small_sweep`` fixture's sweep in a child process that SIGKILLs itself once chunk ``at_chunk`` is recorded."""
    script = out.parent / "killer.py"
    script.write_text(textwrap.dedent(KILLER))
    args = [str(out), scheduler or "-", str(at_chunk), str(journal_interval)]
    proc = subprocess.run(
        [sys.executable, str(script), *args],
        capture_output=True,
        preexec_fn=limit_child_cpu(300),  # work bounded in CPU time, not wall-clock time
    )
    assert proc.returncode == -signal.SIGKILL, proc.stderr.decode()[-2000:]


def test_resume_after_kill_9_is_lossless(
    tmp_path: Path, reference: pa.Table, small_sweep: SweepSpec, assert_same_rows: Any
) -> None:
    out = tmp_path / "k.parquet"
    kill_midway(out, None, at_chunk=2, journal_interval=float("inf"))
    parts = tmp_path / "k.parquet.parts"
    on_disk = sorted(p.name for p in parts.glob("part-*.parquet"))
    assert on_disk == [f"part-{c:06d}.parquet" for c in range(3)] and not out.exists()
    # the kill came before the journal's next rewrite: the parts are found by listing
    assert json.loads((parts / MANIFEST).read_text())["n_done"] == 0
    # a write that a kill interrupted leaves a hidden temporary file: removed on resume
    (parts / ".part-000003.parquet.0123456789ab.part").write_bytes(b"PAR1 half")
    res = run_design_sweep(small_sweep, out, resume=True)
    assert res.chunks_resumed == 3 and res.chunks_computed == small_sweep.n_chunks - 3
    assert_same_rows(pq.read_table(out), reference)
    ref_passive = int(np.count_nonzero(reference.column("passive").to_numpy(False)))
    assert res.n_passive == ref_passive
    assert not parts.exists()


def test_resume_after_kill_9_of_a_dask_client_is_lossless(
    tmp_path: Path, reference: pa.Table, small_sweep: SweepSpec, assert_same_rows: Any
) -> None:
    pytest.importorskip("dask.distributed")
    out = tmp_path / "dk"
    kill_midway(out, "local", at_chunk=1)  # with 2 workers writing parts
    assert (out / MANIFEST).is_file()
    res = run_design_sweep(small_sweep, out, resume=True)
    assert (
        res.chunks_resumed >= 1 and res.chunks_resumed + res.chunks_computed == small_sweep.n_chunks
    )
    assert_same_rows(ds.dataset(str(out)).to_table().sort_by("index"), reference)
    assert res.n_passive == int(np.count_nonzero(reference.column("passive").to_numpy(False)))


def _make_old_directory(spec: SweepSpec, out: Path) -> None:
    """A directory as earlier seapass versions left it: parts beside ``manifest.json``."""
    run_design_sweep(spec, out)
    (out / MANIFEST).unlink()
    (out / "part-000002.parquet").unlink()  # interrupted before chunk 2 was written
    legacy = {"fingerprint": spec.fingerprint(), "spec": spec.describe(), "format": 1}
    (out / "manifest.json").write_text(json.dumps(legacy, indent=2, default=str) + "\n")


def test_spec_fingerprint_is_stable_across_versions(small_sweep: SweepSpec) -> None:
    assert small_sweep.fingerprint() == SPEC_FINGERPRINT_BEFORE


def test_old_manifest_directory_is_refused_with_the_fix(
    tmp_path: Path, small_sweep: SweepSpec
) -> None:
    out = tmp_path / "old"
    _make_old_directory(small_sweep, out)
    with pytest.raises(pa.ArrowInvalid, match=r"manifest\.json"):  # the bug issue 14 reported
        ds.dataset(str(out), format="parquet").to_table()
    with pytest.raises(
        FileFormatError,
        match=r"old-style manifest\.json.*resume=True to migrate it to _manifest\.json",
    ):
        run_design_sweep(small_sweep, out)
    assert (out / "manifest.json").is_file()  # nothing touched


def test_old_manifest_directory_is_migrated_on_resume(
    tmp_path: Path, reference: pa.Table, small_sweep: SweepSpec, assert_same_rows: Any
) -> None:
    out = tmp_path / "old"
    _make_old_directory(small_sweep, out)
    res = run_design_sweep(small_sweep, out, resume=True)
    assert res.migrated and res.chunks_computed == 1
    assert not (out / "manifest.json").exists() and (out / MANIFEST).is_file()
    assert_same_rows(ds.dataset(str(out)).to_table().sort_by("index"), reference)
    assert res.n_passive == int(np.count_nonzero(reference.column("passive").to_numpy(False)))


def test_a_newer_manifest_format_is_refused(tmp_path: Path, small_sweep: SweepSpec) -> None:
    out = tmp_path / "new"
    run_design_sweep(small_sweep, out)
    doc = json.loads((out / MANIFEST).read_text())
    doc["format"] = 99
    (out / MANIFEST).write_text(json.dumps(doc))
    with pytest.raises(FileFormatError, match="upgrade seapass"):
        run_design_sweep(small_sweep, out, resume=True)


def test_unknown_url_protocol_is_one_clear_error(tmp_path: Path) -> None:
    with pytest.raises(ParameterError, match="not a path or a known fsspec URL"):
        open_location("foo://bucket/x/")
