"""Sweeps: enumeration, chunked atomic output, resumption, CSV/Parquet, heat maps, CLI."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyarrow.csv as pacsv
import pyarrow.parquet as pq
import pytest

from seapass.batch.step_metrics import batch_step_metrics
from seapass.batch.verdicts import batch_is_passive
from seapass.cli import main
from seapass.errors import FileFormatError, ParameterError
from seapass.model.catalog import PAPER_VALUES, design
from seapass.model.sea import SEA
from seapass.sweep import (
    GridAxis,
    PartSummary,
    RangeAxis,
    SweepSpec,
    heatmap_data,
    parse_grid,
    parse_range,
    run_design_sweep,
)

LPD = design("mech/parallel-spring-damper").sea(PAPER_VALUES, b1=None)
OURS = SEA(
    D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=None, bd=None)
)
MODEL_ARGS = [
    "--D1",
    "k1 + b1*s",
    "--CL",
    "kd",
    "--set",
    "m=1",
    "--set",
    "b=10",
    "--set",
    "k1=1000",
]


def _spec(**kw) -> SweepSpec:
    base = dict(
        sea=LPD,
        grid=(GridAxis("b1", 0.0, 60.0, 20.0), GridAxis("kd", 0.0, 1500.0, 250.0)),
        chunk_size=5,
        horizon=2.0,
    )
    base.update(kw)
    return SweepSpec(**base)


def test_parse_grid_and_range() -> None:
    g = parse_grid("kd=0:1:0.1")
    assert g.size == 11 and g.values(np.arange(11))[-1] == pytest.approx(1.0)
    assert parse_grid("kd = 0:5000:200").size == 26
    r = parse_range("bd=1e-3:2")
    assert (r.lo, r.hi) == (1e-3, 2.0)
    for bad in ("kd", "kd=0:1", "kd=0:1:0", "kd=5:1:1", "kd=a:1:1", "=0:1:1"):
        with pytest.raises(ParameterError, match="grid"):
            parse_grid(bad)
    with pytest.raises(ParameterError, match="--range"):
        parse_range("kd=0:1:2")


def test_grid_sweep_rows_match_batch_functions(tmp_path: Path) -> None:
    spec = _spec()
    res = run_design_sweep(spec, tmp_path / "out.parquet")
    t = pq.read_table(res.path)
    assert t.num_rows == 4 * 7 == res.n_designs
    assert t.column("index").to_pylist() == list(range(28))
    b1 = t.column("b1").to_numpy()
    kd = t.column("kd").to_numpy()
    # C order: the first grid axis varies slowest
    np.testing.assert_array_equal(b1, np.repeat([0.0, 20.0, 40.0, 60.0], 7))
    np.testing.assert_array_equal(kd, np.tile(np.arange(7) * 250.0, 4))
    ref = batch_is_passive(LPD, {"b1": b1, "kd": kd})
    np.testing.assert_array_equal(t.column("passive").to_numpy(zero_copy_only=False), ref.passive)
    met = batch_step_metrics(LPD, {"b1": b1, "kd": kd}, load_mass=10.0, horizon=2.0)
    np.testing.assert_allclose(t.column("final_error").to_numpy(), met.final_error, rtol=1e-12)
    assert res.n_passive == int(ref.passive.sum())
    assert not (tmp_path / "out.parquet.parts").exists()


def test_csv_output_has_the_same_rows(tmp_path: Path) -> None:
    spec = _spec(metrics=False)
    a = pq.read_table(run_design_sweep(spec, tmp_path / "a.parquet").path)
    b = pacsv.read_csv(run_design_sweep(spec, tmp_path / "b.csv").path)
    assert a.column_names == b.column_names == ["index", "b1", "kd", "passive", "margin"]
    for name in a.column_names:
        np.testing.assert_array_equal(
            a.column(name).to_numpy(zero_copy_only=False),
            b.column(name).to_numpy(zero_copy_only=False),
        )


def test_interrupted_sweep_resumes_without_duplicates(tmp_path: Path) -> None:
    spec = _spec(metrics=False, chunk_size=3)
    out = tmp_path / "r.parquet"

    def boom(s: PartSummary) -> None:
        if s.chunk == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_design_sweep(spec, out, on_part=boom)
    parts = tmp_path / "r.parquet.parts"
    assert sorted(p.name for p in parts.glob("part-*.parquet")) == [
        f"part-{c:06d}.parquet" for c in range(4)
    ]
    assert not out.exists()
    with pytest.raises(FileFormatError, match="resume=True"):
        run_design_sweep(spec, out)
    res = run_design_sweep(spec, out, resume=True)
    assert res.chunks_resumed == 4 and res.chunks_computed == spec.n_chunks - 4
    fresh = run_design_sweep(spec, tmp_path / "fresh.parquet")
    a, b = pq.read_table(res.path), pq.read_table(fresh.path)
    assert a.equals(b)
    assert res.n_passive == fresh.n_passive


def test_resume_refuses_a_different_sweep(tmp_path: Path) -> None:
    out = tmp_path / "dir"
    run_design_sweep(_spec(metrics=False), out)  # a directory dataset is kept
    assert (out / "_manifest.json").is_file()
    with pytest.raises(FileFormatError, match="different sweep"):
        run_design_sweep(_spec(metrics=False, seed=3), out, resume=True)
    data = heatmap_data(out, "kd", "b1")
    assert data.passive_fraction.shape == (4, 7)


def test_random_sampling_is_reproducible_and_in_range(tmp_path: Path) -> None:
    spec = SweepSpec(
        sea=OURS,
        ranges=(RangeAxis("kd", 0.0, 5000.0), RangeAxis("bd", 1.0, 100.0)),
        samples=50,
        seed=7,
        chunk_size=16,
        metrics=False,
    )
    a = pq.read_table(run_design_sweep(spec, tmp_path / "a.parquet").path)
    b = pq.read_table(run_design_sweep(spec, tmp_path / "b.parquet").path)
    assert a.equals(b) and a.num_rows == 50
    kd = a.column("kd").to_numpy()
    assert kd.min() >= 0 and kd.max() <= 5000 and np.unique(kd).size == 50
    assert a.column("passive").to_numpy(zero_copy_only=False).all()


def test_huge_sweep_is_enumerated_by_index_without_materializing() -> None:
    spec = SweepSpec(
        sea=OURS,
        grid=(GridAxis("kd", 0.0, 9999.0, 1.0), GridAxis("bd", 0.0, 9999.0, 1.0)),
        chunk_size=65536,
    )
    assert spec.n_designs == 10**8
    idx, vals = spec.chunk_values(spec.n_chunks - 1)
    assert idx[-1] == 10**8 - 1 and vals["kd"][-1] == 9999.0 and vals["bd"][-1] == 9999.0
    with pytest.raises(ParameterError, match="chunk"):
        spec.chunk_values(spec.n_chunks)


def test_load_mass_can_be_swept(tmp_path: Path) -> None:
    spec = SweepSpec(
        sea=OURS.with_values(kd=2000.0, bd=60.0, b1=100.0),
        grid=(GridAxis("m_L", 1.0, 25.0, 12.0),),
        chunk_size=2,
    )
    t = pq.read_table(run_design_sweep(spec, tmp_path / "m.parquet").path)
    ts = t.column("settling_time").to_numpy()
    assert t.column("passive").to_numpy(zero_copy_only=False).all()
    assert np.all(np.diff(ts) > 0)  # heavier loads settle later


def test_spec_validation_messages() -> None:
    with pytest.raises(ParameterError, match="either grid"):
        SweepSpec(sea=LPD)
    with pytest.raises(ParameterError, match="do not appear"):
        _spec(grid=(GridAxis("zz", 0, 1, 1), GridAxis("kd", 0, 1, 1), GridAxis("b1", 0, 1, 1)))
    with pytest.raises(ParameterError, match="b1"):
        _spec(grid=(GridAxis("kd", 0, 1, 1),))
    with pytest.raises(ParameterError, match="samples"):
        SweepSpec(sea=OURS, ranges=(RangeAxis("kd", 0, 1), RangeAxis("bd", 0, 1)))


def test_cli_sweep_with_heatmap(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out, fig = tmp_path / "s.parquet", tmp_path / "s.png"
    argv = ["sweep", *MODEL_ARGS, "--grid", "b1=0:40:20", "--grid", "kd=0:1500:500"]
    argv += ["--horizon", "1", "--out", str(out), "--heatmap", "kd,b1", "--plot", str(fig)]
    argv += ["--json"]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["n_designs"] == 12 and summary["complete"]
    assert fig.stat().st_size > 1000 and out.is_file()


def test_cli_errors_are_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    cases = [
        ["--grid", "kd=0:1", "--grid", "b1=0:1:1"],
        ["--grid", "kd=0:1:1"],
        ["--grid", "kd=0:1:1", "--grid", "b1=0:1:1", "--heatmap", "kd,zz", "--plot", "x.png"],
        ["--grid", "kd=0:1:1", "--grid", "b1=0:1:1", "--scheduler", "nonsense"],
        ["--grid", "kd=0:1:1", "--grid", "b1=0:1:1", "--workers", "2"],
        ["--grid", "kd=0:1:1", "--grid", "b1=0:1:1", "--scheduler", "local", "--workers", "0"],
        ["--grid", "kd=0:1:1", "--grid", "b1=0:1:1", "--scheduler", "tcp://h:1", "--workers", "2"],
    ]
    for extra in cases:
        code = main(["sweep", *MODEL_ARGS, *extra, "--out", str(tmp_path / "e.parquet")])
        err = capsys.readouterr().err
        assert code == 2 and err.startswith("error:") and err.count("\n") == 1, err


def test_cli_help_shows_an_example(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["sweep", "--help"])
    assert "seapass sweep --D1" in capsys.readouterr().out


def test_scheduler_without_the_dask_extra_is_one_clear_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    import sys

    # as if seapass[dask] were not installed
    monkeypatch.setitem(sys.modules, "dask", None)
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    args = ["sweep", "--D1", "k1", "--CL", "kd", "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--grid", "kd=0:1000:500", "--no-metrics",
            "--scheduler", "local", "--out", str(tmp_path / "s.parquet")]  # fmt: skip
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "seapass[dask]" in err and "Traceback" not in err
