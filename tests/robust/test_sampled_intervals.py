"""Robust sampled passive sets (`robust_sampled_intervals`, issue 26 items 3-4), checked
against the ordinary certified sampled verdict at densely sampled values."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from seapass.errors import NotPassiveError, ParameterError
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.robust import RobustSampledIntervals, robust_sampled_intervals
from seapass.robust.intervals import RobustIntervals
from seapass.robust.pieces import intersect, merge, minus
from seapass.robust.sampled_intervals import DEFAULT_INTERVAL_BUDGET, MAX_INTERVAL_BUDGET
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.passivity import sampled_passivity

OURS = dict(b=10, k1=1000, b1=300, kd=1708, bd=300)
LOOP = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)


def _ours(**values: float | None) -> SEA:
    return SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**OURS, **values})


def _dense(a: float, b: float, n: int) -> list[float]:
    """``n`` values spread over ``[a, b]``, both ends included."""
    return sorted({a, b, *(float(x) for x in np.linspace(a, b, n))})


@pytest.fixture(scope="module")
def narrow() -> RobustSampledIntervals:
    # m within 2e-6 of 1.02: the kernel certifies it in one sub-interval
    return robust_sampled_intervals(_ours(), "m", loop=LOOP, lo=1.02, hi=1.020002, budget=3)


def test_every_value_of_the_inner_set_is_passive_by_the_plain_verdict(
    narrow: RobustSampledIntervals,
) -> None:
    assert narrow.intervals and narrow.kind == "plant"
    assert narrow.intervals[0][0] == 1.02 and narrow.intervals[-1][1] == 1.020002
    for a, b in narrow.intervals:
        for m in _dense(a, b, 40):
            assert sampled_passivity(_ours(m=m), loop=LOOP).passive, m
    assert narrow.undecided == () and narrow.outer == ((1.02, 1.020002),)
    assert 1 <= narrow.budget_used <= 3 and not narrow.budget_exhausted


def test_failing_plants_are_not_passive_and_never_inside_the_inner_set(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from seapass.robust import sampled_verdict

    monkeypatch.setattr(sampled_verdict, "PIECES", 150)  # less work per sub-box: counted
    # m = 0.95 fails at 500 Hz with one sample of delay, m = 1.05 passes
    r = robust_sampled_intervals(_ours(), "m", loop=LOOP, lo=0.95, hi=1.05, budget=3)
    assert r.budget_used == 3 and r.failing
    for w in r.failing:
        m = w.values["m"]
        assert not sampled_passivity(_ours(m=m), loop=LOOP).passive
        assert not r.contains(m)
        assert any(a <= m <= b for a, b in r.outer)
    for a, b in r.intervals:  # whatever is certified is passive at every sampled value
        for m in _dense(a, b, 20):
            assert sampled_passivity(_ours(m=m), loop=LOOP).passive
    # inner, undecided and outer fit together
    assert all(any(c <= a and b <= d for c, d in r.outer) for a, b in r.intervals)
    assert all(any(c <= a and b <= d for c, d in r.outer) for a, b in r.undecided)


def test_a_plant_parameter_with_a_box_of_the_others() -> None:
    r = robust_sampled_intervals(
        _ours(), "b", loop=LOOP, lo=10, hi=10.00001, box={"m": (1.02, 1.020001)}, budget=2
    )
    assert r.box is not None and r.box.names == ("m",)
    for a, b in r.intervals:
        for bv in _dense(a, b, 4):
            for m in _dense(1.02, 1.020001, 4):
                assert sampled_passivity(_ours(m=m, b=bv), loop=LOOP).passive
    assert r.to_dict()["box"] == {"m": [1.02, 1.020001]}


def test_a_point_box_gives_the_nominal_sampled_bound_of_a_gain() -> None:
    r = robust_sampled_intervals(
        _ours(kd=None), "kd", loop=LOOP, lo=0, hi=5000, box={"m": (1.02, 1.02)}
    )
    nominal = sampled_passive_bound(_ours(kd=None, m=1.02), "kd", loop=LOOP, lo=0, hi=5000)
    assert r.kind == "gain" and r.intervals == nominal.intervals
    assert all(any(c <= a and b <= d for c, d in r.outer) for a, b in r.intervals)
    assert r.budget_used == 1  # the centre is the only plant of a point box


def test_a_gain_over_a_box_certifies_the_outer_set_only() -> None:
    box = (0.95, 1.05)
    r = robust_sampled_intervals(
        _ours(kd=None), "kd", loop=LOOP, lo=0, hi=5000, box={"m": box}, budget=3
    )
    assert r.intervals == ()  # no gain interval x box is certified: never passive
    assert r.undecided == r.outer and r.outer
    assert r.budget_used == 3
    for w in r.failing:  # verified failing gains, each at a plant of the box
        assert box[0] <= w.values["m"] <= box[1]
        assert not sampled_passivity(_ours(**w.values), loop=LOOP).passive
        assert not any(a <= w.values["kd"] <= b for a, b in r.outer)
    # independent: a gain outside the outer set fails at one of the plants examined
    outside = [g for g in _dense(0, 5000, 41) if not any(a <= g <= b for a, b in r.outer)]
    assert outside
    for g in outside[::4]:
        assert any(
            not sampled_passivity(_ours(kd=g, m=m), loop=LOOP, continuous_gate=False).passive
            for m in (1.0, 0.95, 1.05)
        ), g


def test_the_json_extends_the_continuous_robust_bound(narrow: RobustSampledIntervals) -> None:
    from seapass.robust.box import UncertainBox

    cont = RobustIntervals(param="kd", lo=0, hi=1, box=UncertainBox(intervals={"m": (1, 1)}))
    d = narrow.to_dict()
    assert set(cont.to_dict()) <= set(d)
    assert d["robust"] is True and d["sampled"] is True and d["method"] == "certified"
    assert d["intervals"] == [[1.02, 1.020002]] and d["budget"] == 3
    assert "RobustSampledIntervals(param='m'" in repr(narrow)
    assert "Robust sampled passive set of m" in narrow._repr_html_()


def test_plot_draws_on_the_given_axes(narrow: RobustSampledIntervals) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    try:
        assert narrow.plot(ax=ax) is ax
        assert ax.get_xlim() == (1.02, 1.020002)
    finally:
        plt.close(fig)


def test_progress_is_one_task_of_budget_steps() -> None:
    seen: list[tuple[str, object]] = []

    class Recorder:
        def start(self, task: str, total: int | None = None) -> None:
            seen.append(("start", total))

        def advance(self, n: int = 1, *, note: str = "") -> None:
            seen.append(("advance", n))

        def close(self) -> None:
            seen.append(("close", None))

    # m = 0.95 fails: the whole range and its first half are never certified, whatever the kernel
    r = robust_sampled_intervals(
        _ours(), "m", loop=LOOP, lo=0.95, hi=1.05, budget=2, progress=Recorder()
    )
    assert seen == [("start", 2), ("advance", 1), ("advance", 1), ("close", None)]
    assert r.budget_used == 2 and r.budget_exhausted


def test_an_interruption_closes_the_progress_task(monkeypatch: pytest.MonkeyPatch) -> None:
    import seapass.robust.sampled_verdict as sv

    def stop(*args: object, **kwargs: object) -> object:
        raise KeyboardInterrupt

    monkeypatch.setattr(sv, "robust_sampled_check", stop)
    closed: list[bool] = []

    class Recorder:
        def start(self, task: str, total: int | None = None) -> None:
            pass

        def advance(self, n: int = 1, *, note: str = "") -> None:
            pass

        def close(self) -> None:
            closed.append(True)

    with pytest.raises(KeyboardInterrupt):
        robust_sampled_intervals(_ours(), "m", loop=LOOP, lo=1, hi=1.1, progress=Recorder())
    assert closed == [True]


def test_an_interrupt_from_the_progress_stops_cleanly_and_the_call_then_completes() -> None:
    calls: list[str] = []

    class Stopper:
        def start(self, task: str, total: int | None = None) -> None:
            calls.append("start")

        def advance(self, n: int = 1, *, note: str = "") -> None:
            calls.append("advance")
            raise KeyboardInterrupt

        def close(self) -> None:
            calls.append("close")

    with pytest.raises(KeyboardInterrupt):
        robust_sampled_intervals(_ours(), "m", loop=LOOP, lo=0.95, hi=1.05, progress=Stopper())
    assert calls == ["start", "advance", "close"]
    again = robust_sampled_intervals(_ours(), "m", loop=LOOP, lo=0.95, hi=1.05, budget=1)
    assert again.budget_used == 1 and again.failing


def test_throw_when_nothing_is_certified() -> None:
    with pytest.raises(NotPassiveError, match="certified"):
        robust_sampled_intervals(_ours(), "m", loop=LOOP, lo=0.95, hi=1.05, budget=1, throw=True)


@pytest.mark.parametrize(
    ("name", "kwargs", "needle"),
    [
        ("m", {"lo": 2.0, "hi": 1.0}, "lower end must not exceed"),
        ("m", {"lo": 0.0, "hi": 2.0}, "m must be positive"),
        ("m", {"lo": -1.0, "hi": 2.0}, "non-physical"),
        ("b", {"lo": -1.0, "hi": 2.0}, "must not be negative"),
        ("m", {"lo": 1.0, "hi": math.inf}, "finite range"),
        ("mm", {"lo": 1.0, "hi": 2.0}, "did you mean 'm'"),
        ("m", {"lo": 1.0, "hi": 2.0, "budget": 0}, "budget"),
        ("m", {"lo": 1.0, "hi": 2.0, "budget": MAX_INTERVAL_BUDGET + 1}, "budget"),
        ("m", {"lo": 1.0, "hi": 2.0, "budget": True}, "budget"),
        ("m", {"lo": 1.0, "hi": 2.0, "box": {"m": (1, 2)}}, "bounded parameter"),
        ("m", {"lo": 1.0, "hi": 2.0, "box": {"kd": (1, 2)}}, "not a plant parameter"),
        ("m", {"lo": 1.0, "hi": 2.0, "box": {"b": (2, 1)}}, "empty interval"),
        ("kd", {"lo": 0.0, "hi": 2.0}, "controller parameter"),
        ("m", {"lo": 1e-9, "hi": 1e3}, "the range of m"),  # unbounded work: 12 decades
    ],
)
def test_bad_input_is_one_clear_error(name: str, kwargs: dict, needle: str) -> None:
    with pytest.raises(ParameterError, match=needle):
        robust_sampled_intervals(_ours(kd=None, m=1.0) if name == "kd" else _ours(), name, loop=LOOP,
                                 **kwargs)  # fmt: skip


def test_missing_values_are_named() -> None:
    with pytest.raises(ParameterError, match="needs values for: bd"):
        robust_sampled_intervals(_ours(bd=None), "m", loop=LOOP, lo=1.0, hi=1.1)


def test_interval_helpers() -> None:
    f = Fraction
    assert merge([(f(2), f(3)), (f(0), f(1)), (f(1), f(2))]) == [(0, 3)]
    assert intersect([(f(0), f(2))], [(f(1), f(3)), (f(4), f(5))]) == [(1, 2)]
    assert minus([(f(0), f(4))], [(f(1), f(2))]) == [(0, 1), (2, 4)]
    assert minus([(f(0), f(4))], [(f(0), f(4))]) == []
    assert minus([(f(1), f(1))], []) == [(1, 1)]
    assert DEFAULT_INTERVAL_BUDGET >= 1


def test_the_outer_set_keeps_the_deployment_policy_of_sampled_check() -> None:
    # CL = kd: the continuous design is passive only for b >= 2.6049... (exact); sampled
    # check refuses to deploy below it, so the outer set starts there
    sea = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1.02, k1=1000, b1=30, kd=500))
    loop = SampledLoop(period=0.002)
    r = robust_sampled_intervals(sea, "b", loop=loop, lo=0.5, hi=10, budget=2)
    assert len(r.outer) == 1 and 2.6 < r.outer[0][0] < 2.61 and r.outer[0][1] == 10
    for b in (0.5, 1.0, 2.0, 2.6):  # independent: the plain verdict outside the outer set
        assert not sampled_passivity(sea, loop=loop, values={"b": b}).passive
    for w in r.failing:
        assert not sampled_passivity(sea, loop=loop, values={"b": w.values["b"]}).passive
