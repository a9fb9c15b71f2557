"""Exact gain intervals and 2-D maps, checked against point-by-point verdicts and bisection."""

from __future__ import annotations

import numpy as np
import pytest

from seapass.errors import ParameterError
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.ports import TwoPort, two_port
from seapass.ports.axes import CoupledAxes
from seapass.ports.bands import combine
from seapass.ports.bound import port_intervals, port_region
from seapass.ports.check import two_port_passivity
from seapass.ports.llewellyn import llewellyn_conditions
from seapass.ports.mimo import mimo_is_passive

RIG = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)
SEA_KL = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": None})
LIGHT = SEA(
    D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "b1": 2.0, "bd": 3.0, "kl": None}
)


def _verdict(system, criterion: str, param: str, v: float) -> bool:
    if isinstance(system, SEA):
        system = _two_port(system)
    if criterion == "absolute":  # the conditions only (absolute_stability adds η and a witness)
        m = system.exact({param: v})
        return combine([c.outcome for c in llewellyn_conditions(m)]) is Outcome.PASSIVE
    if isinstance(system, TwoPort):
        return two_port_passivity(system, values={param: v}).passive
    return mimo_is_passive(system, values={param: v}).passive


_CACHE: dict[int, TwoPort] = {}


def _two_port(sea: SEA) -> TwoPort:
    if id(sea) not in _CACHE:
        _CACHE[id(sea)] = two_port(sea)
    return _CACHE[id(sea)]


def _bisect(system, criterion: str, param: str, a: float, b: float, steps: int = 24) -> float:
    """The transition between a passing ``a`` and a failing ``b`` (or the reverse), by bisection."""
    va = _verdict(system, criterion, param, a)
    for _ in range(steps):
        mid = (a + b) / 2
        if mid in (a, b):
            break
        if _verdict(system, criterion, param, mid) == va:
            a = mid
        else:
            b = mid
    return (a + b) / 2


CASES = [
    (SEA_KL, "kl", -2000.0, 10000.0, "absolute"),
    (SEA_KL, "kl", -2000.0, 10000.0, "passive"),
    (LIGHT, "kl", -1000.0, 5000.0, "absolute"),
    (SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": 2000.0, "bd": None}), "bd", 0.0, 300.0, "absolute"),
]  # fmt: skip


@pytest.mark.parametrize(("system", "param", "lo", "hi", "criterion"), CASES)
def test_intervals_agree_with_pointwise_verdicts(system, param, lo, hi, criterion) -> None:
    r = port_intervals(system, param, lo, hi, criterion=criterion)
    crit = np.array(r.critical_values)
    grid = np.linspace(lo, hi, 31)
    for v in grid:
        if crit.size and np.min(np.abs(crit - v)) <= 1e-9 * max(1.0, abs(v)):
            continue
        assert r.contains(float(v)) == _verdict(system, criterion, param, float(v)), v
    for a, b in r.intervals:  # printed ends satisfy the criterion (rounded inward) ...
        assert _verdict(system, criterion, param, a) and _verdict(system, criterion, param, b)
        for end, outward in ((a, a - 1e-6 * max(1.0, abs(a))), (b, b + 1e-6 * max(1.0, abs(b)))):
            if lo < outward < hi and not _verdict(system, criterion, param, outward):
                # ... and sit where a bisection of the point verdicts puts the transition
                assert _bisect(system, criterion, param, end, outward) == pytest.approx(
                    end, rel=1e-9, abs=1e-9
                )


def test_mimo_bound_of_the_curl_gain() -> None:
    axes = CoupledAxes(
        axes=({"D1": "k1 + b1*s"},) * 2, K=[["kd", "kc"], ["kc2", "kd"]], B=[["bd", 0], [0, "bd"]],
        values={**RIG, "kc": 100.0, "kc2": None},
    )  # fmt: skip
    r = port_intervals(axes, "kc2", -500, 500, criterion="passive")
    assert r.intervals == ((100.0, 100.0),)  # only the symmetric stiffness: K = K^T
    assert _verdict(axes.n_port(), "passive", "kc2", 100.0)
    z = TwoPort.from_matrix(
        [["b + k/s", "c/s"], ["c/s", "b + k/s"]], values={"b": 10, "k": 100, "c": None}
    )
    assert port_intervals(z, "c", -200, 200, criterion="passive").intervals == ((-100.0, 100.0),)


def test_region_columns_are_the_intervals() -> None:
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kd": None, "kl": None})
    reg = port_region(sea, "kd", [0.0, 1000.0], "kl", (0.0, 5000.0))
    assert (
        reg.columns[1].intervals
        == port_intervals(sea.with_values(kd=1000.0), "kl", 0, 5000).intervals
    )
    d = reg.to_dict()
    assert d["x"] == [0.0, 1000.0] and len(d["intervals"]) == 2
    assert "PortRegion(" in repr(reg) and "<table>" in reg._repr_html_()


def test_bad_arguments() -> None:
    with pytest.raises(ParameterError, match="criterion"):
        port_intervals(SEA_KL, "kl", 0, 1, criterion="stable")
    with pytest.raises(ParameterError, match="does not appear"):
        port_intervals(SEA_KL, "kx", 0, 1)
    with pytest.raises(ParameterError, match="empty range"):
        port_intervals(SEA_KL, "kl", 1, 0)
    with pytest.raises(ParameterError, match="no value"):
        port_intervals(SEA_KL.with_values(kd=None), "kl", 0, 1)
    nport = TwoPort.from_matrix([[1, 0], [0, "c"]], values={"c": None})
    assert port_intervals(nport, "c", -1, 1, criterion="passive").intervals == ((0.0, 1.0),)


def test_a_mode_hidden_for_every_gain_is_critical_where_it_crosses_the_axis() -> None:
    # with a = 1 the factor s − k cancels for every k: a hidden mode, unstable for k > 0
    tp = TwoPort.from_matrix(
        [["(s - k*a)/((s - k)*(s + 1)) + 1", "0"], ["0", "1"]], values={"k": None, "a": 1}
    )
    for criterion in ("passive", "absolute"):
        assert port_intervals(tp, "k", -1, 1, criterion=criterion).intervals == ((-1.0, 0.0),)
