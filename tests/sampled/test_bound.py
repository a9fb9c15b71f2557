"""Sampled bounds: reported ends are proven passive, edges enclose the boundary, and the
branch and bound ends within a counted budget (issue 20, items 2 and 6).

Independent check: the point verdict `sampled_passivity` (its own precision ladder and
Descartes test on one polynomial) at the very doubles the bound reports or prints.
"""

from __future__ import annotations

import contextlib
import io
import re
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.cli import main
from seapass.errors import ParameterError
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.sampled.bound import EdgeKind, sampled_passive_bound
from seapass.sampled.passivity import sampled_passivity

LP = dict(D1="k1 + b1*s", CL="kd")
ISSUE_VALUES = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0)
ISSUE_ARGS = ["sampled", "bound", "kd", "--period", "0.00025", "--D1", "k1 + b1*s", "--CL", "kd",
              "--set", "m=1", "--set", "b=10", "--set", "k1=1000", "--set", "b1=20",
              "--range", "0:20000"]  # fmt: skip


SHORT = SampledLoop(period=0.00025)


def verdict(sea: SEA, value: float, loop: SampledLoop) -> Outcome:
    r = sampled_passivity(sea, loop=loop, values={"kd": float(value)}, continuous_gate=False)
    return r.outcome


def check_result(sea: SEA, res, loop: SampledLoop) -> None:
    """Ends passive, edges straddle the boundary, undecided never inside an interval."""
    for a, b in res.intervals:
        assert verdict(sea, a, loop) is Outcome.PASSIVE, a
        assert verdict(sea, b, loop) is Outcome.PASSIVE, b
    for e in res.edges:
        if e.kind is EdgeKind.SPECIAL:
            continue
        sides = {verdict(sea, e.lo, loop), verdict(sea, e.hi, loop)}
        assert Outcome.PASSIVE in sides and len(sides) == 2, e
    for u_lo, u_hi in res.undecided:
        assert not any(a <= u_lo and u_hi <= b for a, b in res.intervals)


def test_issue_design_ends_within_a_counted_budget():
    """T = 0.25 ms: the balls need 256 bits near the edge; the search used to split there
    at 128 bits down to the tolerance, box after box (minutes)."""
    sea = SEA(**LP, values=ISSUE_VALUES)
    res = sampled_passive_bound(sea, "kd", loop=SHORT, lo=0, hi=20000, max_boxes=300)
    assert not res.budget_exhausted and not res.undecided
    ((a, b),) = res.intervals
    assert a == 0.0 and b == pytest.approx(843.11513273860, rel=1e-9)
    (edge,) = res.edges
    assert edge.lo <= b <= edge.hi
    check_result(sea, res, SHORT)
    # cross-check on a grid: the point verdict agrees away from the edge
    for kd in [0.0, 100.0, 500.0, 843.0, 843.2, 900.0, 987.0, 5000.0, 20000.0]:
        expected = Outcome.PASSIVE if res.intervals[0][0] <= kd <= b else Outcome.NOT_PASSIVE
        assert verdict(sea, kd, SHORT) is expected, kd


def test_budget_stops_with_a_certified_partial_answer():
    sea = SEA(**LP, values=ISSUE_VALUES)
    res = sampled_passive_bound(sea, "kd", loop=SHORT, lo=0, hi=20000, max_boxes=20)
    assert res.budget_exhausted and res.undecided
    assert res.to_dict()["budget_exhausted"] is True
    check_result(sea, res, SHORT)
    with pytest.raises(ParameterError, match="max_boxes"):
        sampled_passive_bound(sea, "kd", loop=SHORT, lo=0, hi=1, max_boxes=0)


def cli(argv: list[str]) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(argv) == 0
    return out.getvalue()


README_VALUES = dict(m=1.02, b=10.0, k1=1005.0, b1=30.0)
README_ARGS = ["sampled", "bound", "kd", "--period", "0.002", "--D1", "k1 + b1*s", "--CL", "kd",
               "--set", "m=1.02", "--set", "b=10", "--set", "k1=1005", "--set", "b1=30",
               "--range", "0:5000", "--rtol", "1e-3"]  # fmt: skip


@pytest.mark.parametrize(
    ("argv", "values", "period", "hi", "rtol"),
    [
        (ISSUE_ARGS, ISSUE_VALUES, 0.00025, 20000.0, 1e-9),
        (README_ARGS, README_VALUES, 0.002, 5000.0, 1e-3),
    ],
)
def test_printed_ends_are_inside_the_proven_intervals(argv, values, period, hi, rtol):
    text = cli(argv)
    sea = SEA(**LP, values=values)
    loop = SampledLoop(period=period)
    res = sampled_passive_bound(sea, "kd", loop=loop, lo=0, hi=hi, rtol=rtol)
    line = text.splitlines()[0]
    printed = re.findall(r"\[([^,\]]+), ([^\]]+)\]", line.split(":", 1)[1])
    assert printed
    for (pa, pb), (a, b) in zip(printed, res.intervals, strict=True):
        assert Fraction(a) <= Fraction(pa) <= Fraction(pb) <= Fraction(b)
        assert verdict(sea, float(pa), loop) is Outcome.PASSIVE
        assert verdict(sea, float(pb), loop) is Outcome.PASSIVE
    for edge_line, e in zip(re.findall(r"edge in \[(\S+), (\S+)\]", text), res.edges, strict=True):
        lo, hi_ = (Fraction(x) for x in edge_line)
        assert lo <= Fraction(e.lo) and Fraction(e.hi) <= hi_  # rounded outward
        assert verdict(sea, float(lo), loop) is Outcome.PASSIVE
        assert verdict(sea, float(hi_), loop) is Outcome.NOT_PASSIVE


designs = st.sampled_from(
    [(LP, {}), (dict(D1="k1 + b1*s", CA="kd + bd*s"), {"bd": 20.0})]
)  # fmt: skip


@settings(max_examples=6)
@given(
    designs,
    st.sampled_from([0.0002, 0.00035, 0.001, 0.002]),
    st.floats(0.5, 3.0),
    st.floats(1.0, 30.0),
    st.floats(200.0, 5000.0),
    st.floats(5.0, 60.0),
    st.sampled_from([{}, {"delay": 1}, {"delay": 1, "velocity_filter": 50.0}]),
)
def test_random_designs_report_passive_ends_within_the_budget(design, period, m, b, k1, b1, opts):
    elements, extra = design
    values = {"m": round(m, 3), "b": round(b, 2), "k1": round(k1), "b1": round(b1, 1), **extra}
    sea = SEA(**elements, values=values)
    loop = SampledLoop(period=period, **opts)
    res = sampled_passive_bound(sea, "kd", loop=loop, lo=0, hi=20000, rtol=1e-6, max_boxes=2000)
    assert not res.budget_exhausted
    check_result(sea, res, loop)
