"""``export c`` and the loop latency: τ* must cover ``[control] delay_time`` (or ``--latency``)."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest

import seapass
from seapass.cli import main
from seapass.errors import NotPassiveError, ParameterError
from seapass.exact.rounding import decimal_down
from seapass.export import export_c
from seapass.export.compiled import compile_c, find_c_compiler
from seapass.export.latency import latency_banner, latency_guard
from seapass.model.design_file import parse_design

PARAMS = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


def ours(delay_time: float | None = 0.01, name: str = "ours", title: str = ""):
    control: dict = {"rate": 500.0}
    if delay_time is not None:
        control["delay_time"] = delay_time
    return parse_design({"name": name, "title": title,
                         "model": {"D1": "k1 + b1*s", "CA": "kd + bd*s"},
                         "parameters": dict(PARAMS), "control": control})  # fmt: skip


def run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = int(exc.code or 0)
    assert "Traceback" not in err.getvalue()
    return code, out.getvalue(), err.getvalue()


def test_a_latency_within_tau_star_is_certified_and_recorded(tmp_path: Path) -> None:
    design = ours(0.01, title="latency */ test")  # a comment terminator in user text
    res = export_c(design, tmp_path, force_limit=100.0)
    m = seapass.delay_margin(design, "delay_time")
    assert res.latency is not None and res.latency.certified
    assert res.latency.margin.tau_star == m.tau_star  # the same tau* as delay_margin
    header = res.header.read_text(encoding="utf-8")
    assert "Loop latency (certified by seapass at export time):" in header
    assert "latency delay_time = 0.01 s on C_A and C_L" in header
    assert f"passive for every delay up to {decimal_down(m.tau_star[0], 6)} s" in header
    banner = header[: header.index("#ifndef SEAPASS_CTRL_H")]
    assert banner.count("*/") == 1  # escaped: only the banner's own end closes the comment
    if find_c_compiler() is not None:
        compile_c(res)  # the header still compiles


def test_a_latency_beyond_tau_star_is_refused_and_nothing_is_written(tmp_path: Path) -> None:
    with pytest.raises(NotPassiveError, match=r"loop latency 0\.05 s is not certified"):
        export_c(ours(0.05), tmp_path / "out", force_limit=100.0)
    assert not (tmp_path / "out").exists()
    with pytest.raises(NotPassiveError, match="allow_nonpassive=True"):
        export_c(ours(None), tmp_path / "out", force_limit=100.0, latency=0.05)
    assert not (tmp_path / "out").exists()


def test_allow_nonpassive_exports_it_marked_not_certified(tmp_path: Path) -> None:
    res = export_c(ours(0.05), tmp_path, force_limit=100.0, allow_nonpassive=True)
    assert res.latency is not None and not res.latency.certified
    header = res.header.read_text(encoding="utf-8")
    assert "NOT CERTIFIED for the loop latency" in header


def test_between_the_ends_of_tau_star_is_undecided_never_certified() -> None:
    design = ours(None)
    lo, hi = seapass.delay_margin(design, "delay_time").tau_star
    mid = latency_guard(design, (lo + hi) / 2, allow_nonpassive=True)
    assert mid is not None and str(mid.outcome) == "undecided" and not mid.certified
    with pytest.raises(NotPassiveError, match="inside the enclosure of tau"):
        latency_guard(design, (lo + hi) / 2)
    printed = float(decimal_down(lo, 6))  # "passive up to" as printed
    at_lo = latency_guard(design, printed)
    assert at_lo is not None and at_lo.certified and str(at_lo.outcome) == "passive"
    above = latency_guard(design, hi * 1.01, allow_nonpassive=True)
    assert above is not None and str(above.outcome) == "not_passive"


def test_no_latency_no_guard_and_bad_latency() -> None:
    assert latency_guard(ours(None)) is None and latency_banner(None) == []
    with pytest.raises(ParameterError, match=r"^latency: must be"):
        latency_guard(ours(None), -1.0)


def test_cli_latency_flag_and_the_file_latency(tmp_path: Path) -> None:
    path = tmp_path / "ours.toml"
    path.write_text(
        'name = "ours"\n[model]\nD1 = "k1 + b1*s"\nCA = "kd + bd*s"\n[parameters]\n'
        + "".join(f"{k} = {v}\n" for k, v in PARAMS.items())
        + "[control]\nrate = 500.0\ndelay_time = 0.01\n",
        encoding="utf-8",
    )
    code, out, err = run(["export", "c", str(path), "--out", str(tmp_path / "fw"),
                          "--force-limit", "100", "--no-progress", "--json"])  # fmt: skip
    assert code == 0
    d = json.loads(out)
    assert d["latency"]["certified"] and d["latency"]["latency"] == 0.01
    code, out, err = run(["export", "c", str(path), "--out", str(tmp_path / "fw2"),
                          "--force-limit", "100", "--no-progress", "--latency", "0.05"])  # fmt: skip
    assert code == 2 and out == "" and err.count("\n") == 1
    assert (
        err.startswith("error: the loop latency 0.05 s is not certified")
        and "--allow-nonpassive" in err
    )
    assert not (tmp_path / "fw2").exists()
    code, out, err = run(["export", "c", str(path), "--out", str(tmp_path / "fw3"),
                          "--no-progress", "--latency", "-1"])  # fmt: skip
    assert (
        code == 2
        and err == "error: --latency: must be a number of seconds in [0, 1000], got -1.0\n"
    )
    code, out, _ = run(["export", "c", "--help"])
    assert code == 0 and "--latency SECONDS" in out
