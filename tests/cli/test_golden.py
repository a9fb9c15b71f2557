"""Behaviour is pinned: the README examples and the report's data files against a stored copy.

The stored copy in ``tests/data/golden/`` was written by seapass before the
restructure into subpackages; it changes only when a result changes on purpose.
To refresh it after an intended change, run::

    SEAPASS_UPDATE_GOLDEN=1 .venv/bin/python -m pytest tests/cli/test_golden.py

and review the diff of ``tests/data/golden`` like any other change.

Numbers are compared with a relative tolerance of 1e-9 (the outputs are
deterministic; the tolerance only absorbs the last bits a different BLAS kernel
may give), every other field exactly.  The simulation-study stage is left out:
its gains come from differential evolution, whose path may legitimately change
with such last bits.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import os
import shutil
from pathlib import Path
from typing import Any

import pytest

from seapass.cli import main

GOLDEN = Path(__file__).resolve().parents[1] / "data" / "golden"
UPDATE = os.environ.get("SEAPASS_UPDATE_GOLDEN") == "1"
RTOL = 1e-9
STAGES = "tables,stiffness,regions,rig,sampled,deploy,tradeoff"

README_COMMANDS: dict[str, list[str]] = {
    "check.json": ["check", "--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "m=1",
                   "--set", "b=10", "--set", "k1=1000", "--set", "b1=20", "--set", "bd=25",
                   "--set", "kd=5000", "--json"],
    "bound.json": ["bound", "kd", "--D1", "k1 + b1*s", "--CL", "kd", "--set", "m=1",
                   "--set", "b=10", "--set", "k1=1000", "--set", "b1=20", "--range", "kd=0:1e5",
                   "--json"],
    "simulate.json": ["simulate", "--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "m=1",
                      "--set", "b=10", "--set", "k1=1000", "--set", "b1=20", "--set", "bd=25",
                      "--set", "kd=1000", "--load-mass", "10", "--json"],
    "sampled_bound.json": ["sampled", "bound", "kd", "--period", "0.002", "--D1", "k1 + b1*s",
                           "--CA", "kd + bd*s", "--set", "m=1", "--set", "b=10",
                           "--set", "k1=1005", "--set", "b1=30", "--set", "bd=25",
                           "--range", "kd=0:50000", "--json"],
    "witness.json": ["witness", "--D1", "k1", "--D2", "k2", "--CL", "kd", "--set", "m=1",
                     "--set", "b=10", "--set", "k1=1000", "--set", "k2=1000", "--set", "kd=1500",
                     "--json"],
    "tables.json": ["tables", "--json"],
}  # fmt: skip


def _same(a: Any, b: Any, where: str) -> None:
    if isinstance(a, dict) and isinstance(b, dict):
        assert a.keys() == b.keys(), f"{where}: keys {sorted(a)} != {sorted(b)}"
        for k in a:
            _same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list) and isinstance(b, list):
        assert len(a) == len(b), f"{where}: length {len(a)} != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _same(x, y, f"{where}[{i}]")
    elif isinstance(a, float | int) and isinstance(b, float | int) and not isinstance(a, bool):
        ok = (math.isnan(a) and math.isnan(b)) or math.isclose(a, b, rel_tol=RTOL, abs_tol=1e-300)
        assert ok, f"{where}: {a!r} != {b!r}"
    else:
        assert a == b, f"{where}: {a!r} != {b!r}"


def _number(text: str) -> Any:
    try:
        return float(text)
    except ValueError:
        return text


def _compare_file(got: Path, want: Path) -> None:
    if want.suffix == ".json":
        _same(json.loads(got.read_text()), json.loads(want.read_text()), want.name)
    elif want.suffix == ".csv":
        rows_g = [[_number(c) for c in r] for r in csv.reader(io.StringIO(got.read_text()))]
        rows_w = [[_number(c) for c in r] for r in csv.reader(io.StringIO(want.read_text()))]
        _same(rows_g, rows_w, want.name)
    else:
        assert got.read_text() == want.read_text(), want.name


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("golden") / "report"
    args = ["reproduce", "--out", str(out), "--quick", "--stages", STAGES, "--no-progress"]
    with contextlib.redirect_stderr(io.StringIO()):
        assert main(args) == 0
    return out / "data"


def test_reproduce_writes_the_stored_data_files(report: Path) -> None:
    stored = GOLDEN / "reproduce"
    if UPDATE:
        shutil.rmtree(stored, ignore_errors=True)
        shutil.copytree(report, stored)
    written = sorted(p.name for p in report.iterdir())
    assert written == sorted(p.name for p in stored.iterdir()), "the set of data files changed"
    for name in written:
        _compare_file(report / name, stored / name)


@pytest.mark.parametrize("name", sorted(README_COMMANDS))
def test_readme_examples_print_the_stored_json(name: str) -> None:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        assert main(README_COMMANDS[name]) == 0
    path = GOLDEN / "readme" / name
    if UPDATE:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(out.getvalue())
    _same(json.loads(out.getvalue()), json.loads(path.read_text()), name)


def test_every_figure_is_also_svg(report: Path) -> None:
    # build figures with FigureData.of (PNG and SVG), never from PNG bytes alone
    pngs = sorted((report.parent / "figures").glob("*.png"))
    assert pngs
    assert [p.name for p in pngs if not p.with_suffix(".svg").is_file()] == []
