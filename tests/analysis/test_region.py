"""Reported end points of the exact passive set are passive (issue 20, item 2).

Every double reported as an interval end, and every number printed for one, is checked
with `is_passive` at that very double (an exact test, independent of the critical values
that produced the interval); every enclosure in ``edges`` is checked to hold the true
boundary: passive on the inner side, not passive on the outer one.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import re

from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.analysis.passivity import is_passive
from seapass.analysis.region import passive_intervals, passive_map
from seapass.cli import main
from seapass.model.sea import SEA

ISSUE = dict(m=14.214, b=11.6744, b1=15.1808, bd=387.517, k1=108.642)
ISSUE_ELEMENTS = dict(D1="k1 + b1*s", CA="kd + bd*s", CL="kd")
ISSUE_ARGS = ["--D1", "k1+b1*s", "--CA", "kd+bd*s", "--CL", "kd", "--set", "m=14.214",
              "--set", "b=11.6744", "--set", "b1=15.1808", "--set", "bd=387.517",
              "--set", "k1=108.642", "--range", "0:20000"]  # fmt: skip


def passive(sea: SEA, param: str, value: float) -> bool:
    return is_passive(sea.with_values(**{param: float(value)})).passive


def check_reported(sea: SEA, param: str, lo: float, hi: float) -> None:
    res = passive_intervals(sea, param, lo, hi)
    assert len(res.edges) == len(res.intervals)
    for (a, b), ((la, ha), (lb, hb)) in zip(res.intervals, res.edges, strict=True):
        assert a <= b
        # the reported doubles are passive, and so are the printed numbers
        assert passive(sea, param, a) and passive(sea, param, b), (a, b)
        for text in (f"{a!r}", f"{b!r}", *res_text(a, b)):
            assert passive(sea, param, float(text)), text
        # each enclosure holds the true end: inward of it passive, outward not
        assert la <= a <= hb and lb <= b <= hb
        if a != lo:
            assert la < ha or la == a
            assert not passive(sea, param, math.nextafter(a, -math.inf)), a
        if b != hi:
            assert not passive(sea, param, math.nextafter(b, math.inf)), b
            assert not passive(sea, param, hb) or hb == b


def res_text(a: float, b: float) -> tuple[str, str]:
    from seapass.exact.rounding import inward_text

    return inward_text(a, b, 10)


def test_issue_design_reports_passive_end_points():
    sea = SEA(**ISSUE_ELEMENTS, values=ISSUE)
    res = passive_intervals(sea, "kd", 0, 20000)
    assert res.intervals == ((0.0, 118.46721557324217), (1309.9473633290556, 20000.0))
    assert not passive(sea, "kd", 118.46721557324219)  # the double printed before
    assert not passive(sea, "kd", 1309.9473633290554)
    assert not res.contains(118.46721557324219) and not res.contains(118.4672156)
    check_reported(sea, "kd", 0, 20000)


def test_cli_prints_passive_end_points_and_edges():
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["bound", "kd", *ISSUE_ARGS]) == 0
    sea = SEA(**ISSUE_ELEMENTS, values=ISSUE)
    numbers = re.findall(r"passive for (\S+) <= kd <= (\S+)", out.getvalue())
    assert numbers == [("0", "118.4672155"), ("1309.947364", "20000")]
    for pair in numbers:
        for text in pair:
            assert passive(sea, "kd", float(text)), text
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["bound", "kd", *ISSUE_ARGS, "--json"]) == 0
    data = json.loads(out.getvalue())
    for (a, b), (ea, eb) in zip(data["intervals"], data["edges"], strict=True):
        assert passive(sea, "kd", a) and passive(sea, "kd", b)
        assert ea[0] <= a <= ea[1] or ea[1] <= a  # an enclosure, then the inward double
        assert eb[0] <= b <= eb[1]
    assert data["edges"][0][1] == [118.46721557324217, 118.46721557324219]


def test_rational_passive_ends_are_exact_and_points_stay():
    # load-side P on a pure spring: passive iff kd <= k1, a rational end
    sea = SEA(D1="k1", CL="kd", values=dict(m=1.0, b=10.0, k1=1000.0))
    res = passive_intervals(sea, "kd", 0, 1e5)
    assert res.intervals == ((0.0, 1000.0),) and res.edges == (((0.0, 0.0), (1000.0, 1000.0)),)
    # an isolated passive value keeps its width-0 interval
    pd = SEA(D1="k1", CL="kd + bd*s", values=dict(m=1.0, b=10.0, k1=1000.0, kd=100.0))
    assert passive_intervals(pd, "bd", 0, 100).intervals == ((0.0, 0.0),)


def test_map_columns_are_rounded_inward():
    sea = SEA(**ISSUE_ELEMENTS, values={k: v for k, v in ISSUE.items() if k != "b1"})
    pm = passive_map(sea, "b1", [15.1808], "kd", (0, 20000), y_points=5)
    assert pm.intervals[0][0] == (0.0, 118.46721557324217)


designs = st.sampled_from(
    [
        (dict(D1="k1 + b1*s", CL="kd"), {}),
        (dict(D1="k1 + b1*s", CA="kd + bd*s", CL="kd"), {"bd": 1.0}),
        (dict(D1="k1", D2="b2*s", CL="kd"), {"b2": 1.0}),
        (dict(D1="k1 + b1*s", CA="kd", CL="kl"), {"kl": 1.0}),
    ]
)
positive = st.floats(0.05, 50.0).map(lambda x: float(f"{x:.4g}"))


@settings(max_examples=12)
@given(designs, positive, positive, positive, positive, positive)
def test_reported_ends_of_random_designs_are_passive(design, m, b, k1, b1, scale):
    elements, extra = design
    values = dict(m=m, b=b, k1=100 * k1)
    if "b1" in elements["D1"]:
        values["b1"] = b1
    values.update({k: v * scale * 10 for k, v in extra.items()})
    sea = SEA(**elements, values=values)
    check_reported(sea, "kd", 0.0, 2e4)
