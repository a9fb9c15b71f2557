"""One strict-JSON conversion for every output: the CLI's --json, report and paper data."""

from __future__ import annotations

import json
import math
from types import MappingProxyType

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from seapass.files.jsontext import json_text, strict_json


def test_non_finite_numpy_and_tuples() -> None:
    data = {
        "nan": float("nan"),
        "inf": (float("inf"), -math.inf),
        "np": [np.float64(0.25), np.int64(3), np.bool_(True), np.float32("nan")],
        "array": np.array([[1.0, np.inf], [2.0, 3.0]]),
        "proxy": MappingProxyType({1: "one"}),
    }
    out = strict_json(data)
    assert out == {
        "nan": None,
        "inf": [None, None],
        "np": [0.25, 3, True, None],
        "array": [[1.0, None], [2.0, 3.0]],
        "proxy": {"1": "one"},
    }
    assert [type(v) for v in out["np"]] == [float, int, bool, type(None)]
    assert json.loads(json_text(data)) == out  # strict: allow_nan=False did not raise


@given(
    st.recursive(
        st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=5),
        lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=3), inner),
        max_leaves=20,
    )
)
def test_any_value_gives_strict_json(value: object) -> None:
    text = json_text(value)
    assert "NaN" not in text and "Infinity" not in text
    json.loads(text, parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))


def test_every_writer_uses_it() -> None:
    # the CLI, the report and the paper study once had a cleaner each, with other rules
    from seapass.cli import output
    from seapass.report import document

    assert output.json_text is json_text
    assert document.to_json is json_text
