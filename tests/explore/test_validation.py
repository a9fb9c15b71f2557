"""The explorer's view: field-by-field validation, defaults, and the design file it exports."""

from __future__ import annotations

import tomllib

import pytest
from hypothesis import given
from hypothesis import strategies as st

from seapass.explore.state import LIMITS, default_range, slider_scale
from seapass.explore.validation import check_state
from seapass.model.design_file import load_design

LP = {
    "name": "LP",
    "model": {"D1": "k1", "CL": "kd"},
    "values": {"m": 1, "b": 10, "k1": 1000, "kd": 500},
}


def _with(**changes: object) -> dict[str, object]:
    view = {**LP, **changes}
    return view


@pytest.mark.parametrize(
    ("view", "field", "says"),
    [
        (_with(model={"D1": "k1 +", "CL": "kd"}), "model.D1", "cannot parse"),
        (
            _with(model={"D1": "__import__('os').system('x')"}),
            "model.D1",
            "function call is not allowed",
        ),
        (_with(model={"D1": "k1", "CL": "kd.real"}), "model.CL", "attribute access"),
        (_with(model={"D1": "0", "CL": "kd"}), "model.D1", "D1 = D2 = 0"),
        (_with(model={"D1": "k1", "CA": "kd/(s - s)"}), "model.CA", "division by zero"),
        (_with(model={"D1": "k1", "CA": "1/(s + kd)^13"}), "model.CA", "exceeds the limit"),
        (_with(model={"D1": "k1", "CL": "x" * 3000}), "model.CL", "limit"),
        (_with(model={"D1": "k1", "CL": 5}), "model.CL", "expected text"),
        (_with(values={"m": 0, "b": 10, "k1": 1000, "kd": 1}), "values.m", "positive"),
        (_with(values={"m": 1, "b": 10, "k1": 1000, "kd": "abc"}), "values.kd", "not a number"),
        (_with(values={"m": 1, "b": 10, "k1": 1000, "kd": "nan"}), "values.kd", "finite"),
        (_with(values={"m": 1, "b": 10, "k1": 1000, "kd": 1e300}), "values.kd", "at most"),
        (_with(values={"m": 1, "b": 10, "k1": 1000, "kd": True}), "values.kd", "expected a number"),
        (_with(ranges={"kd": [5, 1]}), "ranges.kd", "lo < hi"),
        (_with(ranges={"kd": "0:5"}), "ranges.kd", "expected [lo, hi]"),
        (_with(period="fast"), "period", "not a number"),
        (_with(period=10.0), "period", "between"),
        (_with(delay=1.5), "delay", "whole number"),
        (_with(delay=10**9), "delay", "whole number"),
        (_with(velocity_filter=-1), "velocity_filter", "between"),
        (_with(load_mass=0), "load_mass", "between"),
        (_with(step=0), "step", "nonzero"),
        (_with(horizon=1e9), "horizon", "between"),
    ],
)
def test_bad_fields_are_named(view: dict[str, object], field: str, says: str) -> None:
    check = check_state(view)
    assert check.state is None
    assert field in check.errors, check.errors
    assert says in check.errors[field]


def test_defaults_and_normalization() -> None:
    check = check_state({"model": {"D1": "k1 + b1*s", "CA": "kd + bd*s"}, "values": {"kd": "5e2"}})
    s = check.state
    assert s is not None and not check.errors
    assert s.values["kd"] == 500.0 and s.values["b1"] == 20.0  # paper reference values
    assert s.gains == ("bd", "kd") and s.gain == "kd"
    assert s.region == ("kd", "bd")
    assert s.ranges["kd"] == (0.0, 5000.0) and s.ranges["m"] == (0.01, 100.0)
    assert s.period is None and s.delay == 0


def test_new_names_become_parameters_and_values_widen_ranges() -> None:
    check = check_state(
        _with(
            model={"D1": "k1", "CA": "kd*(1 + tz*s)/(1 + tp*s)"},
            values={"kd": 9000.0},
            ranges={"kd": [0, 5000]},
        )
    )
    s = check.state
    assert s is not None
    assert s.new_parameters == ("tz", "tp")
    assert s.values["tz"] == 1.0 and s.ranges["kd"] == (0.0, 9000.0)


@pytest.mark.parametrize(
    ("lo", "hi", "scale"),
    [(0.0, 5000.0, "log"), (10.0, 1e5, "log"), (1.0, 50.0, "lin"), (-5.0, 5.0, "lin")],
)
def test_slider_scale(lo: float, hi: float, scale: str) -> None:
    assert slider_scale(lo, hi) == scale


def test_default_ranges() -> None:
    assert default_range("kd", 500.0, gain=True) == (0.0, 5000.0)
    assert default_range("k1", 1000.0, gain=False) == (10.0, 1e5)
    assert default_range("x", -2.0, gain=False) == (-20.0, 20.0)


@pytest.mark.parametrize(
    "view",
    [
        LP,
        _with(period=0.002, delay=1, velocity_filter=50.0, load_mass=2.5, step=-0.25, horizon=3.0),
        {
            "name": "mech/pure spring?",
            "model": {"D1": "k1", "D2": "b2*s", "CL": "kd"},
            "values": {},
        },
        {
            "name": "lead",
            "title": 'a "quoted" title\twith tab',
            "model": {"D1": "k1", "CA": "kd*(1 + tz*s)/(1 + tp*s)"},
            "values": {"tz": 0.01, "tp": 0.001},
        },
    ],
)
def test_design_file_round_trip(view: dict[str, object], tmp_path) -> None:
    s = check_state(view).state
    assert s is not None
    path = tmp_path / "d.toml"
    path.write_text(s.design_toml(), encoding="utf-8")
    d = load_design(path)
    assert dict(d.values) == dict(s.values)
    assert (d.D1, d.D2, d.CA, d.CL) == tuple(s.model[k] for k in ("D1", "D2", "CA", "CL"))
    assert d.period == s.period and d.control_delay == s.delay
    assert d.velocity_filter == s.velocity_filter
    assert d.load_masses == (s.load_mass,) and d.step == s.step and d.horizon == s.horizon
    assert d.title == s.title
    assert tomllib.loads(path.read_text())["name"] == s.name


_json = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=30),
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=20,
)
_views = st.fixed_dictionaries(
    {},
    optional={
        "model": st.dictionaries(
            st.sampled_from(["D1", "D2", "CA", "CL", "X"]),
            st.one_of(
                st.text(max_size=40), st.sampled_from(["k1", "kd + bd*s", "s**20", "1/s"]), _json
            ),
        ),
        "values": st.dictionaries(
            st.sampled_from(["m", "b", "k1", "kd", "bd", "zz", "s"]), _json | st.floats()
        ),
        "ranges": _json,
        "period": _json,
        "delay": _json,
        "velocity_filter": _json,
        "load_mass": _json,
        "step": _json,
        "horizon": _json,
        "gain": _json,
        "region": _json,
        "name": _json,
    },
)


@given(_views | _json)
def test_any_json_is_a_state_or_field_errors(view: object) -> None:
    check = check_state(view)
    assert (check.state is None) == bool(check.errors)
    for key, message in check.errors.items():
        assert isinstance(key, str) and isinstance(message, str) and message
    if check.state is not None:
        s = check.state
        assert len(s.values) <= LIMITS["parameters"]
        assert all(lo <= s.values[p] <= hi for p, (lo, hi) in s.ranges.items())
        assert s.gain in s.values and s.region[0] != s.region[1]
