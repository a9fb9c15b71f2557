"""Passivity-constrained tuning and the paper's simulation study (reduced budgets)."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from long_jobs import Recorder
from seapass.analysis.passivity import is_passive
from seapass.analysis.region import passive_intervals
from seapass.errors import ParameterError
from seapass.model.catalog import design as catalog_design
from seapass.paper.simstudy import SimulationStudy, StudyRow, run_simulation_study
from seapass.sim.metrics import Settling, TrackingMetrics
from seapass.tuning import QUICK_OPTIONS, TuningOptions, tune
from seapass.tuning.problem import design_sea

QUICK = replace(QUICK_OPTIONS, maxiter=8)


def test_lp_search_box_is_the_exact_passive_set():
    res = tune("LP", options=replace(QUICK, maxiter=3, popsize=4))
    assert res.bounds["kd"] == (0.0, 1000.0)  # kd <= k1, from passive_intervals
    assert 0.0 <= res.gains["kd"] <= 1000.0 and res.passive


def test_ours_is_passive_for_every_kd_by_the_exact_api():
    # the paper's condition kd <= ((b+bd)^2 + b b1 + b1 bd)/(2m) is sufficient, not necessary
    for bd, b1 in ((0.0, 50.0), (25.0, 20.0), (300.0, 300.0)):
        sea = design_sea("ours", gains={"bd": bd, "b1": b1})
        assert passive_intervals(sea, "kd", 0.0, 1e7).intervals == ((0.0, 1e7),)
    # while LP is passive exactly up to kd = k1
    lp = design_sea("LP")
    assert is_passive(lp.with_values(kd=1000.0)).passive
    assert not is_passive(lp.with_values(kd=1000.0 * (1 + 1e-12))).passive


@pytest.mark.parametrize("design", ["LP", "APD", "ours"])
def test_quick_tune_gives_passive_settling_design_within_limits(design):
    res = tune(design, options=QUICK)
    assert res.passive and is_passive(res.sea).passive
    assert res.metrics.settled and res.metrics.settling_time is not None
    assert res.metrics.peak_force <= QUICK.force_limit
    for gain, (lo, hi) in res.bounds.items():
        assert lo <= res.gains[gain] <= hi
    d = res.to_dict()
    assert d["design"] == design and set(d["gains"]) == set(catalog_design(design).gains)
    assert {"gains", "objective", "passive", "on_bound"} <= set(d)
    json.dumps(d)


def test_tuning_is_reproducible_and_seeded():
    a = tune("APD", options=QUICK)
    b = tune("APD", options=QUICK)
    assert dict(a.gains) == dict(b.gains)
    assert a.metrics.settling_time == b.metrics.settling_time


def test_force_limit_and_bounds_are_respected():
    opts = replace(QUICK, force_limit=100.0)
    res = tune("APD", tune={"kd": (0.0, 400.0), "bd": (0.0, 50.0)}, options=opts)
    assert res.gains["kd"] <= 400.0 and res.gains["bd"] <= 50.0
    assert res.metrics.peak_force <= 100.0 + 1e-9


def test_keyboard_interrupt_aborts_cleanly():
    stop = Recorder(stop_at=1)  # a seapass.progress.Progress that interrupts at its first advance
    with pytest.raises(KeyboardInterrupt):
        tune("ours", options=QUICK, progress=stop)
    assert stop.advances == 1 and stop.balanced  # stopped at once, every task closed


def test_bad_design_and_options():
    assert catalog_design("OURS").key == "ours" and catalog_design("apd").key == "APD"
    with pytest.raises(ParameterError, match="unknown design"):
        tune("PID", options=QUICK)
    with pytest.raises(ParameterError):
        TuningOptions(load_mass=0.0)
    with pytest.raises(ParameterError, match="horizon"):
        tune("LP", options=TuningOptions(horizon=1e-4))
    with pytest.raises(ParameterError):
        TuningOptions(step=0.0)


def test_quick_simulation_study():
    study = run_simulation_study(quick=True, horizon=6.0, dt=2e-3)
    assert study.designs == ("LP", "APD", "ours") and study.masses == (1.0, 10.0, 25.0)
    assert len(study.rows) == 9 and len(study.runs) == 9
    for r in study.rows:
        assert r.metrics.status in ("settled", "did not settle")
        if r.design != "LP":  # LP rings slowly at 25 kg and may not settle in 6 s
            assert r.metrics.settled and r.metrics.final_error < 0.01
    assert set(study.ours_fastest()) == {1.0, 10.0, 25.0}
    doc = json.loads(study.table_json())
    assert len(doc["rows"]) == 9 and set(doc["tuning"]) == {"LP", "APD", "ours"}
    assert study.table_csv().count("\n") == 10
    assert "Ours is" in study.summary()
    with pytest.raises(ParameterError):
        run_simulation_study(masses=(0.0,), quick=True)


@pytest.mark.parametrize(
    ("times", "expected"),
    [
        ({"LP": 4.0, "APD": 1.2, "ours": 0.7}, True),  # strictly fastest
        ({"LP": 4.0, "APD": 0.7, "ours": 0.7}, False),  # a tie is not faster
        ({"LP": None, "APD": 2.0, "ours": 1.0}, True),  # a design that never settles loses
        ({"LP": 0.5, "APD": None, "ours": None}, False),  # Ours did not settle
    ],
)
def test_ours_fastest_on_pinned_rows(times, expected):
    """``ours_fastest`` on hand-made rows: the comparison, not a recomputation of it."""
    rows = []
    for d, ts in times.items():
        status = Settling.SETTLED if ts is not None else Settling.NOT_SETTLED
        met = TrackingMetrics(
            status=status,
            settling_time=ts,
            final_error=0.0,
            overshoot=0.0,
            peak_force=0.0,
            energy=0.0,
            positive_work=0.0,
            band=0.01,
            target=0.5,
        )
        rows.append(StudyRow(design=d, load_mass=10.0, metrics=met))
    study = SimulationStudy(
        designs=("LP", "APD", "ours"),
        masses=(10.0,),
        tuning={},
        runs={},
        rows=tuple(rows),
        step=0.5,
        horizon=10.0,
        dt=1e-3,
    )
    assert study.ours_fastest() == {10.0: expected}
