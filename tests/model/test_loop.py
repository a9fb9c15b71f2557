"""SampledLoop: every check at construction, the one [control] spelling, the old spellings."""

from __future__ import annotations

import dataclasses
import math
import re
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from seapass.errors import FileFormatError, ParameterError, SeapassDeprecationWarning
from seapass.files.limits import MAX_DELAY_SAMPLES
from seapass.files.toml import dump_toml
from seapass.model.design_file import parse_design
from seapass.model.loop import METHODS, PERIOD_RANGE, SampledLoop, loop_argument
from seapass.model.sea import SEA
from seapass.rig.rigfile import paper_rig
from seapass.rig.twin import simulate_loop
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.passivity import sampled_passivity
from seapass.sampled.region import default_setups, sampled_region
from seapass.sampled.runtime import SimulatedHardware
from seapass.tuning.problem import TuningOptions

SRC = Path(__file__).resolve().parents[2] / "src" / "seapass"
LP = SEA(D1="k1 + b1*s", CL="kd", values={"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 30.0})
T = 0.002


def _refused(argument: str, **kw: object) -> None:
    with pytest.raises(ParameterError) as info:
        SampledLoop(**kw)  # type: ignore[arg-type]
    assert info.value.argument == argument
    assert str(info.value).startswith(f"{argument}: ")


# ----------------------------------------------------------------- construction


NOT_A_NUMBER = st.one_of(st.booleans(), st.text(max_size=3), st.none(), st.just([1.0]))


@given(
    st.one_of(
        NOT_A_NUMBER.filter(lambda v: v is not None),
        st.floats(max_value=0.0),
        st.floats(min_value=0.0, max_value=PERIOD_RANGE[0], exclude_min=True, exclude_max=True),
        st.floats(min_value=PERIOD_RANGE[1], exclude_min=True),
        st.just(math.inf),
        st.integers(max_value=0),
    )
)
def test_a_bad_period_is_refused_naming_period(period: object) -> None:
    _refused("period", period=period)


@given(
    st.one_of(
        st.floats(max_value=0.0),
        st.floats(min_value=1 / PERIOD_RANGE[0], exclude_min=True),
        st.just(math.inf),
        st.just(True),
    )
)
def test_a_bad_rate_is_refused_naming_rate(rate: object) -> None:
    _refused("rate", rate=rate)


@given(
    st.one_of(
        st.integers(max_value=-1),
        st.integers(min_value=MAX_DELAY_SAMPLES + 1),
        st.floats(allow_nan=True).filter(lambda d: not (math.isfinite(d) and d == int(d))),
        st.booleans(),
        st.text(max_size=3),
    )
)
def test_a_bad_delay_is_refused_naming_delay(delay: object) -> None:
    _refused("delay", period=T, delay=delay)


@given(
    period=st.floats(1e-5, 1.0),
    fraction=st.one_of(st.floats(max_value=0.0), st.floats(min_value=1.0)),
)
def test_a_filter_at_or_above_nyquist_or_not_positive_is_refused(
    period: float, fraction: float
) -> None:
    _refused("velocity_filter", period=period, velocity_filter=fraction * 0.5 / period)


@given(st.one_of(st.just(math.nan), st.just(math.inf), st.booleans(), st.text(max_size=3)))
def test_a_filter_that_is_not_a_finite_number_is_refused(value: object) -> None:
    _refused("velocity_filter", period=T, velocity_filter=value)


@given(st.text(max_size=8).filter(lambda m: m not in METHODS))
def test_an_unknown_method_is_refused(method: str) -> None:
    _refused("method", period=T, method=method)


def test_period_or_rate_exactly_one() -> None:
    _refused("period")
    _refused("period", period=0.002, rate=400.0)
    assert SampledLoop(period=0.002, rate=500.0) == SampledLoop(period=0.002)  # a copy agrees


LOOPS = st.builds(
    lambda period, delay, fraction, method: SampledLoop(
        period=period,
        delay=delay,
        velocity_filter=None if fraction is None else fraction * 0.5 / period,
        method=method,
    ),
    period=st.floats(1e-6, 1.0),
    delay=st.integers(0, MAX_DELAY_SAMPLES),
    fraction=st.one_of(st.none(), st.floats(1e-6, 0.999)),
    method=st.sampled_from(METHODS),
)


@given(LOOPS)
def test_a_valid_loop_is_kept_as_given(loop: SampledLoop) -> None:
    assert loop.rate == 1 / loop.period and loop.nyquist == 0.5 / loop.period
    assert loop.exact_period == loop.exact_period.limit_denominator(10**20)
    assert dataclasses.replace(loop, delay=0) == loop.replace(delay=0)  # both spellings copy
    assert loop.replace(period=loop.period) == loop
    assert set(loop.to_dict()) == {"period", "delay", "velocity_filter", "method"}


def test_a_rate_is_kept_exactly() -> None:
    loop = SampledLoop(rate=49.0, delay=1)
    assert loop.rate == 49.0 and loop.period == 1 / 49.0
    assert loop.replace(delay=0).rate == 49.0
    assert loop.label == "1-sample delay" and loop.replace(velocity_filter=5.0).label == (
        "1-sample delay + 5 Hz filter"
    )
    assert SampledLoop(period=T).label == "ideal ZOH"


# ----------------------------------------------------------------- the one TOML spelling


@given(LOOPS)
def test_the_control_table_round_trips_through_toml_text(loop: SampledLoop) -> None:
    table = loop.to_table()
    text = dump_toml({"control": table})
    again = SampledLoop.from_table(tomllib.loads(text)["control"])
    assert again == loop and again.period == loop.period
    assert again.delay == loop.delay and again.velocity_filter == loop.velocity_filter


@given(LOOPS)
def test_a_design_file_reads_the_same_table(loop: SampledLoop) -> None:
    doc = {
        "name": "d",
        "model": {"D1": "k1 + b1*s", "CL": "kd"},
        "parameters": {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 30.0, "kd": 500.0},
        "control": loop.to_table(),
    }
    design = parse_design(tomllib.loads(dump_toml(doc)))
    assert design.loop == loop and design.period == loop.period
    assert design.control_delay == loop.delay and design.velocity_filter == loop.velocity_filter


@pytest.mark.parametrize(
    ("table", "key"),
    [
        ({"delay": 1}, "missing control.rate"),
        ({"rate": 500.0, "period": 0.002}, "not both"),
        ({"rate": 0.5}, "control.rate"),
        ({"rate": 500.0, "delay": 1.0}, "control.delay"),
        ({"rate": 500.0, "velocity_filter": 250.0}, "control.velocity_filter: must be a positive"),
        ({"rate": 500.0, "method": "euler"}, "control.method"),
    ],
)
def test_a_bad_control_table_names_its_key(table: dict, key: str) -> None:
    with pytest.raises(FileFormatError, match=re.escape(key)):
        SampledLoop.from_table(table)


# ----------------------------------------------------------------- old spellings, one release


def test_old_keywords_of_sampled_passivity_warn_and_agree() -> None:
    lp = LP.with_values(kd=700.0)
    new = sampled_passivity(lp, loop=SampledLoop(period=T, delay=1, velocity_filter=50.0))
    with pytest.warns(SeapassDeprecationWarning, match="loop=SampledLoop"):
        old = sampled_passivity(lp, period=T, delay=1, velocity_filter=50.0)
    assert old.to_dict() == new.to_dict()
    with pytest.raises(ParameterError, match="loop="):
        sampled_passivity(lp, loop=SampledLoop(period=T), period=T)
    with pytest.raises(TypeError, match="perod"):
        sampled_passivity(lp, perod=T)
    with pytest.raises(ParameterError, match="loop: give the sampled loop"):
        sampled_passivity(lp)


def test_old_keywords_of_the_bound_and_the_region_warn_and_agree() -> None:
    free = LP.with_values(kd=None)
    new = sampled_passive_bound(free, "kd", loop=SampledLoop(period=T), lo=0, hi=2000, rtol=1e-6)
    with pytest.warns(SeapassDeprecationWarning):
        old = sampled_passive_bound(free, "kd", period=T, lo=0, hi=2000, rtol=1e-6)
    assert old.to_dict() == new.to_dict()
    wall = SEA(D1="k1 + b1*s", CA="kd + bd*s", values={"m": 1, "b": 10, "k1": 1005, "b1": 30})
    kw = {"p1_range": (0, 1e5), "p2_range": (0, 50), "n": 2, "rtol": 1e-3}
    with pytest.warns(SeapassDeprecationWarning):
        old_map = sampled_region(wall, "kd", "bd", period=T, **kw)  # type: ignore[arg-type]
    new_map = sampled_region(
        wall, "kd", "bd", loop=SampledLoop(period=T, delay=1, velocity_filter=50.0), **kw
    )  # type: ignore[arg-type]
    assert old_map.to_dict() == new_map.to_dict()
    assert [s.label for s in new_map.setups] == [
        s.label for s in default_setups(SampledLoop(period=T, velocity_filter=50.0))
    ]


def test_old_keywords_of_the_twin_warn_and_agree() -> None:
    rig = paper_rig()
    kw = {"load_mass": 0.1, "duration": 0.05, "kp_actuator": 500.0, "x0": 0.01}
    new = simulate_loop(rig, loop=rig.loop.replace(delay=0, velocity_filter=None), **kw)
    with pytest.warns(SeapassDeprecationWarning, match="simulate_loop"):
        old = simulate_loop(rig, delay_samples=0, velocity_filter_hz=0.0, **kw)
    np.testing.assert_array_equal(old.x_L, new.x_L)
    assert old.meta["loop"] == new.meta["loop"] == rig.loop.replace(delay=0, velocity_filter=None)
    with pytest.warns(SeapassDeprecationWarning, match="delay="):
        hw = SimulatedHardware(object(), delay_samples=1)
    assert hw.delay == 1
    with pytest.raises(TypeError):
        SimulatedHardware(object(), delays=1)


def test_old_tuning_fields_build_the_loop() -> None:
    with pytest.warns(SeapassDeprecationWarning):
        opts = TuningOptions(period=T, delay=1, velocity_filter=50.0)
    assert opts.loop == SampledLoop(period=T, delay=1, velocity_filter=50.0)
    with pytest.warns(SeapassDeprecationWarning):
        assert opts.replace(delay=0).loop == SampledLoop(period=T, velocity_filter=50.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the new spelling is silent
        assert TuningOptions(loop=opts.loop).replace(seed=3).loop == opts.loop
        assert TuningOptions().loop is None


def test_loop_argument_is_the_one_shim() -> None:
    base = SampledLoop(period=T, delay=1)
    assert loop_argument(None, {}, where="f", base=base) is base
    with pytest.warns(SeapassDeprecationWarning, match=r"f\(velocity_filter_hz=\)"):
        assert loop_argument(None, {"velocity_filter_hz": 0}, where="f", base=base) == base
    old_names = re.compile(r"delay_samples|velocity_filter_hz|_loop_kw|LoopSetup")
    hits = sorted(
        str(p.relative_to(SRC))
        for p in SRC.rglob("*")
        if p.suffix in (".py", ".toml", ".j2", ".js", ".html")
        and old_names.search(p.read_text(encoding="utf-8"))
    )
    assert hits == ["model/loop.py"], hits


# ----------------------------------------------------------------- the precision cap


@pytest.mark.parametrize("bits", [10, 10**6, True, 100.0])
def test_max_precision_is_checked_by_the_library(bits: object) -> None:
    loop = SampledLoop(period=T)
    for call in (
        lambda: sampled_passivity(LP.with_values(kd=500.0), loop=loop, max_precision=bits),
        lambda: sampled_passive_bound(
            LP.with_values(kd=None), "kd", loop=loop, lo=0, hi=1, max_precision=bits
        ),
        lambda: sampled_region(
            SEA(D1="k1", CA="kd + bd*s", values={"m": 1, "b": 1, "k1": 1}), "kd", "bd",
            loop=loop, p1_range=(0, 1), p2_range=(0, 1), max_precision=bits,
        ),
    ):  # fmt: skip
        with pytest.raises(ParameterError, match=r"^max_precision: must be in \[64, 65536\]"):
            call()
