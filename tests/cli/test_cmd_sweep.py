"""``seapass sweep --range NAME`` without bounds takes them from the design file's [ranges]."""

from __future__ import annotations

import contextlib
import csv
import io
from pathlib import Path

import pytest

from seapass.cli import main


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def test_a_bare_range_uses_the_files_box(tmp_path: Path) -> None:
    out = tmp_path / "ours.csv"
    code, _, err = _cli(["sweep", "examples/ours.toml", "--sample", "20", "--range", "kd",
                         "--range", "bd=0:10", "--no-metrics", "--no-progress", "--out", str(out)])  # fmt: skip
    assert code == 0, err
    rows = list(csv.DictReader(out.read_text().splitlines()))
    assert len(rows) == 20
    kd = [float(r["kd"]) for r in rows]
    bd = [float(r["bd"]) for r in rows]
    assert 0 <= min(kd) and max(kd) <= 100000 and max(kd) > 5000  # ours.toml: kd in [0, 1e5]
    assert 0 <= min(bd) and max(bd) <= 10


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["examples/ours.toml", "--range", "k1"], "has no [ranges] entry for k1"),
        (
            [
                "--D1",
                "k1",
                "--CL",
                "kd",
                "--set",
                "m=1",
                "--set",
                "b=10",
                "--set",
                "k1=1000",
                "--range",
                "kd",
            ],
            "takes them from a design file's [ranges]",
        ),
        (["examples/ours.toml", "--range", "kd", "--range", "kd=0:1"], "given twice"),
    ],
)
def test_a_bare_range_without_a_file_box_is_one_error(
    argv: list[str], says: str, tmp_path: Path
) -> None:
    code, _out, err = _cli(["sweep", *argv, "--sample", "5", "--no-progress",
                           "--out", str(tmp_path / "x.csv")])  # fmt: skip
    assert code == 2 and err.count("\n") == 1 and err.startswith("error: ") and says in err, err
