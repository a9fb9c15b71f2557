"""The CLI's one sampled-loop helper: flags, then the design file, checked by the object."""

from __future__ import annotations

import argparse
import importlib
import io
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.cli.loop_options import add_loop_options, loop_from_args
from seapass.model.design_file import load_design
from seapass.model.loop import SampledLoop

ROOT = Path(__file__).resolve().parents[2]
LP = ["--D1", "k1 + b1*s", "--CL", "kd", "--set", "m=1.02", "--set", "b=10", "--set", "k1=1005",
      "--set", "b1=30"]  # fmt: skip


def _args(*argv: str, **defaults: object) -> argparse.Namespace:
    p = argparse.ArgumentParser()
    add_loop_options(p, **defaults)  # type: ignore[arg-type]
    return p.parse_args(list(argv))


def test_flags_then_the_design_file() -> None:
    ours = load_design(ROOT / "examples" / "ours.toml")  # 500 Hz, delay 1, 50 Hz filter
    assert loop_from_args(_args(), ours) is None  # no --period: no sampled loop
    assert loop_from_args(_args("--period", "0.001"), ours) == SampledLoop(
        period=0.001, delay=1, velocity_filter=50.0
    )
    assert loop_from_args(_args("--period", "0.001", "--delay", "0", "--method", "zoh"), ours) == (
        SampledLoop(period=0.001, velocity_filter=50.0, method="zoh")
    )
    assert loop_from_args(_args("--period", "0.002")) == SampledLoop(period=0.002)
    assert loop_from_args(_args(period=0.002, delay=1)) == SampledLoop(period=0.002, delay=1)


def _run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--delay", "101"], "error: --delay: must be a whole number of samples from 0 to 100"),
        (["--velocity-filter", "250"], "error: --velocity-filter: must be a positive cut-off"),
        (["--velocity-filter", "-1"], "error: --velocity-filter:"),
        (["--period", "0"], "error: --period: must be a positive number of seconds"),
        (["--period", "nan"], "error: --period:"),
        (["--max-precision", "10"], "error: --max-precision: must be in [64, 65536] bits"),
    ],
)
@pytest.mark.parametrize("command", [["check"], ["bound", "kd", "--range", "0:100"]])
def test_bad_loop_flags_give_one_error_line_before_any_work(
    command: list[str], extra: list[str], needle: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    def work(*a: object, **k: object) -> None:
        raise AssertionError("the certified decision ran although the input is invalid")

    for module, name in (("passivity", "decide"), ("bound", "decide"), ("bound", "bound_boxes")):
        monkeypatch.setattr(importlib.import_module(f"seapass.sampled.{module}"), name, work)
    values = [] if command[0] == "bound" else ["--set", "kd=500"]
    code, out, err = _run(["sampled", *command, *LP, *values, *extra])
    assert code == 2 and out == "" and err.count("\n") == 1 and err.startswith(needle), err


def test_region_overlays_the_librarys_default_setups(monkeypatch: pytest.MonkeyPatch) -> None:
    import seapass.sampled.region as region

    seen = {}

    def fake(sea, p1, p2, *, loop, **kw):  # type: ignore[no-untyped-def]
        seen["loop"], seen["kw"] = loop, kw
        raise SystemExit(0)

    monkeypatch.setattr(region, "sampled_region", fake)
    with pytest.raises(SystemExit):
        _run(["sampled", "region", "kd", "bd", "--D1", "k1 + b1*s", "--CA", "kd + bd*s",
              "--set", "m=1", "--set", "b=10", "--set", "k1=1005", "--set", "b1=30",
              "--range", "0:1e5", "--range2", "0:50", "--rows", "2"])  # fmt: skip
    assert seen["loop"] == SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
    assert "setups" not in seen["kw"]  # the setups are the library's default_setups(loop)
