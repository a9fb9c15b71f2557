"""The sampled CSV files come from the library (the CLI wrote them by hand, numpy reprs and all)."""

from __future__ import annotations

import csv
import io
from pathlib import Path

from seapass.cli import main
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.passivity import power_curve_csv, sampled_power_curve

OURS = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1.02, b=10, k1=1005, b1=30, bd=25))
ARGS = ["--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "m=1.02", "--set", "b=10",
        "--set", "k1=1005", "--set", "b1=30", "--set", "bd=25"]  # fmt: skip


def _rows(text: str) -> list[list[str]]:
    return list(csv.reader(io.StringIO(text)))


def test_power_curve_csv_holds_plain_exact_numbers() -> None:
    w, n = sampled_power_curve(OURS.with_values(kd=2000), loop=SampledLoop(period=0.002), n=5)
    rows = _rows(power_curve_csv(w, n))
    assert rows[0] == ["omega_rad_s", "N"] and len(rows) == 6
    assert [[float(a), float(b)] for a, b in rows[1:]] == [
        [a, b] for a, b in zip(w, n, strict=True)
    ]


def test_bound_csv_is_the_partition() -> None:
    res = sampled_passive_bound(OURS, "kd", loop=SampledLoop(period=0.002), lo=0, hi=2e4, rtol=1e-3)
    rows = _rows(res.to_csv())
    assert rows[0] == ["kd_lo", "kd_hi", "status"]
    assert [(float(a), float(b), s) for a, b, s in rows[1:]] == [
        (a, b, str(s)) for a, b, s in res.partition
    ]


def test_the_cli_writes_the_library_csvs(tmp_path: Path) -> None:
    out = tmp_path / "o"
    argv = ["sampled", "check", "--period", "0.002", *ARGS, "--set", "kd=2000", "--out", str(out)]
    assert main(argv) == 0
    text = (out / "sampled_power.csv").read_text()
    assert "np." not in text and text.startswith("omega_rad_s,N\n")
    argv = ["sampled", "bound", "kd", "--period", "0.002", *ARGS, "--range", "0:2e4",
            "--rtol", "1e-3", "--out", str(out)]  # fmt: skip
    assert main(argv) == 0
    res = sampled_passive_bound(OURS, "kd", loop=SampledLoop(period=0.002), lo=0, hi=2e4, rtol=1e-3)
    assert (out / "sampled_bound_kd.csv").read_text() == res.to_csv()
