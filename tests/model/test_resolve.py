"""A design file merged with the caller's values: one rule for every command."""

from __future__ import annotations

from pathlib import Path

import pytest

from seapass.errors import ParameterError
from seapass.model.design_file import load_design
from seapass.model.loop import SampledLoop
from seapass.model.resolve import default_range, resolve_design, resolve_loop

OURS = load_design(Path(__file__).resolve().parents[2] / "examples" / "ours.toml")


def test_the_file_alone() -> None:
    r = resolve_design(OURS)
    assert r.sea == OURS.sea()
    assert r.loop == OURS.loop and r.loop is not None and r.loop.rate == 500.0
    assert (r.load_mass, r.step, r.horizon) == (10.0, 0.5, 10.0)
    assert r.range_of("kd") == (0.0, 100000.0)  # the file's [ranges]
    assert r.units["kd"] == "N/m"


def test_the_caller_overrides_the_file() -> None:
    r = resolve_design(
        OURS,
        values={"kd": 900.0},
        loop={"period": 0.001, "delay": None},
        step=0.1,
        units={"kd": "N/mm"},
    )
    assert r.sea.values["kd"] == 900.0 and r.sea.values["b1"] == 300.0
    assert r.loop == SampledLoop(period=0.001, delay=1, velocity_filter=50.0)
    assert r.step == 0.1 and r.horizon == 10.0
    assert r.units["kd"] == "N/mm"
    assert r.range_of("kd", (1.0, 2.0)) == (1.0, 2.0)


def test_an_element_replaced_drops_the_values_it_no_longer_uses() -> None:
    r = resolve_design(OURS, elements={"CA": "kd"}, free=["kd"])
    assert "bd" not in r.sea.values and r.sea.free_parameters == ("kd",)
    assert r.range_of("kd") == (0.0, 100000.0)


def test_the_default_range_rule() -> None:
    r = resolve_design(OURS, free=["k1"])  # no [ranges] k1: around the file's value
    assert r.range_of("k1") == default_range(1000.0) == (0.0, 10000.0)
    new = resolve_design(OURS, elements={"CA": "kd + kp*s"}, values={"kp": 5.0})
    assert new.sea.values["kp"] == 5.0 and "bd" not in new.sea.values
    bare = resolve_design(elements={"D1": "k1", "CL": "kd"}, values={"m": 1, "b": 1, "k1": 1})
    assert bare.range_of("kd") == (0.0, 1e5) and bare.loop is None and bare.step is None


def test_the_loop_rule() -> None:
    default = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
    assert resolve_loop(None, default, {}) == default
    assert resolve_loop(SampledLoop(rate=1000.0), default, {}) == SampledLoop(rate=1000.0)
    assert resolve_loop(None, None, {"delay": 1}) is None
    assert resolve_loop(None, None, {"period": 0.01}) == SampledLoop(period=0.01)


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"units": {"zz": "N"}}, r"units\['zz'\]: not a parameter"),
        ({"units": {"kd": "N/q"}}, "not a unit"),
        ({"values": {"zz": 1.0}}, "zz"),
        ({"elements": {"D3": "k"}}, "unknown element"),
        ({"loop": {"rate": 3}}, "unknown setting"),
    ],
)
def test_bad_overrides(kwargs: dict[str, object], needle: str) -> None:
    with pytest.raises(ParameterError, match=needle):
        resolve_design(OURS, **kwargs)  # type: ignore[arg-type]
