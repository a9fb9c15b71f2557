"""Plants at points of the box (seapass.robust.witness)."""

from __future__ import annotations

from flint import fmpq

from seapass.analysis.passivity import is_passive
from seapass.model.sea import SEA, Impedance
from seapass.outcome import Outcome
from seapass.robust.box import UncertainBox
from seapass.robust.family import Condition, ConditionKind
from seapass.robust.witness import as_floats, failing, inside_near, with_values, worst_at

LP = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))


def test_worst_at_is_the_plain_exact_test() -> None:
    w = worst_at(LP, {}, {"kd": 3000.0})
    assert w is not None and not is_passive(LP, values={"kd": 3000.0}).passive
    assert w.values == {"kd": 3000.0} and worst_at(LP, {}, {"kd": 10.0}) is None


def test_inside_near_moves_a_lossless_face_point_inwards_to_a_failing_plant() -> None:
    """c·s + 1/s + a·(1 − s)/(s + 1) is lossless at a = 0 and active for a > 0."""
    z = Impedance(expr="c*s + 1/s + a*(1 - s)/(s + 1)", values={"a": 0.5, "c": 1.0})
    box = UncertainBox(intervals={"a": (0.0, 1.0), "c": (1.0, 2.0)})
    assert worst_at(z, {}, {"a": 0.0, "c": 1.0}) is None
    w, at = inside_near(z, {}, box, {"a": 0.0, "c": 1.0})
    assert w is not None and at["a"] > 0 and not is_passive(z, values=at).passive


def test_failing_gives_the_frequency_of_the_compactified_point() -> None:
    w = worst_at(LP, {}, {"kd": 3000.0})
    assert w is not None
    w = type(w)(values=w.values, frequency=None, result=w.result)
    cond = Condition(kind=ConditionKind.REAL_PART, label="re", coeffs=None)  # type: ignore[arg-type]
    box = UncertainBox(intervals={"kd": (2000.0, 4000.0)})
    r = failing(w, {"kd": 3000.0}, cond, (fmpq(1, 2), fmpq(3000)), box, 7)
    assert r.outcome is Outcome.NOT_PASSIVE and r.worst is not None and r.boxes == 7
    assert r.worst.frequency == 1.0  # t = 1/2: x = t/(1 - t) = 1


def test_as_floats_and_with_values() -> None:
    assert as_floats(("a", "b"), (fmpq(1, 2), fmpq(3))) == {"a": 0.5, "b": 3.0}
    assert with_values(LP, {"m": 2.0}).values["m"] == 2.0
    z = with_values(Impedance(expr="a/s", values={"a": 1.0}), {"a": 3.0})
    assert isinstance(z, Impedance) and z.values["a"] == 3.0
