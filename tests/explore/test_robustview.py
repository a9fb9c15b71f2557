"""The explorer's box verdict (``robust`` panel): the design at the sliders over ``[uncertainty]``.

Independent check: the plain exact test at the worst plant it reports, and at a grid of
plants of a box it calls passive.
"""

from __future__ import annotations

import itertools
import json

import numpy as np

from seapass.analysis.passivity import is_passive
from seapass.explore.panels import KINDS, compute
from seapass.explore.pool import AFFINITY
from seapass.explore.presets import design_state
from seapass.explore.validation import check_state
from seapass.model.design_file import Design

DESIGN = Design(name="lpbox", D1="k1", CL="kd", values={"m": 1.0, "b": 10.0, "k1": 1e3, "kd": 500.0},
                uncertainty={"m": (0.9, 1.1), "b": (8.0, 12.0)})  # fmt: skip


def _state(**changes: object):  # type: ignore[no-untyped-def]
    raw = {**design_state(DESIGN), **changes}
    check = check_state(json.loads(json.dumps(raw)))  # as the browser sends it
    assert check.state is not None, check.errors
    return check.state


def test_the_view_of_a_design_file_carries_its_box_and_the_panel_is_registered() -> None:
    st = _state()
    assert dict(st.uncertainty) == {"b": (8.0, 12.0), "m": (0.9, 1.1)}
    assert st.to_json()["uncertainty"] == {"b": [8.0, 12.0], "m": [0.9, 1.1]}
    assert "robust" in KINDS and AFFINITY["robust"] == AFFINITY["sampled"]


def test_passive_for_the_whole_box_agrees_with_the_plain_test_on_a_grid() -> None:
    st = _state()
    d = compute("robust", st)
    assert d["analysed"] and d["status"] == "passive" and d["worst"] is None
    sea = st.sea()
    for m, b in itertools.product(np.linspace(0.9, 1.1, 7), np.linspace(8.0, 12.0, 7)):
        assert is_passive(sea.with_values(m=float(m), b=float(b))).passive


def test_the_sliders_move_the_verdict_and_the_worst_plant_is_verified() -> None:
    st = _state(values={"m": 1.0, "b": 10.0, "k1": 1e3, "kd": 5e4})
    d = compute("robust", st)
    assert d["status"] == "not_passive" and d["worst"] is not None
    worst = d["worst"]["values"]
    assert 0.9 <= worst["m"] <= 1.1 and 8.0 <= worst["b"] <= 12.0
    assert not is_passive(st.sea().with_values(**worst)).passive


def test_without_a_box_the_panel_says_so_and_a_bad_box_names_the_field() -> None:
    d = compute("robust", check_state({"model": {"D1": "k1", "CL": "kd"}}).state)
    assert d == {
        "analysed": False,
        "detail": "no box: open a design file with an [uncertainty] table",
    }
    bad = check_state({**design_state(DESIGN), "uncertainty": {"m": [1.1, 0.9]}})
    assert bad.state is None and "uncertainty.m" in bad.errors
    unphysical = _state(uncertainty={"m": [-1.0, 1.0]})
    d = compute("robust", unphysical)
    assert d["analysed"] is False and "non-physical" in d["detail"]
    # a name the edited model no longer has leaves the box
    assert dict(_state(uncertainty={"m": [0.9, 1.1], "b9": [1, 2]}).uncertainty) == {
        "m": (0.9, 1.1)
    }
