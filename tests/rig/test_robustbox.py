"""`robust_box`: the one rule that turns the design file, a fitted rig and the caller into a box."""

from __future__ import annotations

import pytest

from seapass.errors import ParameterError
from seapass.model.design_file import Design
from seapass.model.sea import SEA
from seapass.rig.intervals import FitIntervals
from seapass.rig.rigfile import paper_rig
from seapass.rig.robustbox import rig_box, robust_box

SEA1 = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0))
DESIGN = Design(name="x", D1="k1 + b1*s", CL="kd", values=dict(SEA1.values),
                uncertainty={"m": (0.9, 1.1), "k1": (900.0, 1100.0)})  # fmt: skip
FITTED = paper_rig().replace(
    intervals=FitIntervals(
        confidence=0.95, intervals={"m": (1.0, 1.04), "b": (-0.2, 0.3), "b1": (19.0, 21.0)},
        stderr={"m": 0.01, "b": 0.125, "b1": 0.5}, dof=50,
    ).to_table()
)  # fmt: skip


def test_the_sources_stack_design_then_rig_then_caller() -> None:
    assert robust_box(SEA1) is None
    assert dict(robust_box(SEA1, design=DESIGN).intervals) == {
        "k1": (900.0, 1100.0),
        "m": (0.9, 1.1),
    }
    box = robust_box(SEA1, design=DESIGN, rig=FITTED)
    # the rig overrides m, adds b (cut at 0: a damping is not negative) and b1; k1 stays
    assert dict(box.intervals) == {
        "b": (0.0, 0.3),
        "b1": (19.0, 21.0),
        "k1": (900.0, 1100.0),
        "m": (1.0, 1.04),
    }
    box = robust_box(SEA1, design=DESIGN, rig=FITTED, uncertain={"m": (0.95, 1.05)})
    assert box.intervals["m"] == (0.95, 1.05)


def test_a_value_given_by_the_caller_fixes_the_name() -> None:
    box = robust_box(SEA1, design=DESIGN, fixed=["m"])
    assert dict(box.intervals) == {"k1": (900.0, 1100.0)}
    assert robust_box(SEA1, design={"m": (0.9, 1.1)}, fixed=["m"]) is None
    with pytest.raises(ParameterError, match="given a value and an interval"):
        robust_box(SEA1, uncertain={"m": (0.9, 1.1)}, fixed=["m"])


def test_a_rig_drops_the_parameters_the_model_does_not_use() -> None:
    lp = SEA(D1="k1", CL="kd", values=dict(m=1.0, b=10.0, k1=1000.0, kd=500.0))
    assert set(robust_box(lp, rig=FITTED).intervals) == {"b", "m"}


def test_the_confidence_level_recomputes_the_rig_intervals() -> None:
    wide = rig_box(FITTED, confidence=0.999)
    assert wide["m"][0] < 1.0 and wide["m"][1] > 1.04
    assert rig_box(FITTED) == {"m": (1.0, 1.04), "b": (0.0, 0.3), "b1": (19.0, 21.0)}


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"rig": paper_rig()}, "the rig has no \\[intervals\\] table"),
        ({"rig": FITTED, "confidence": 1.5}, "confidence must lie in \\(0, 1\\)"),
        ({"rig": FITTED, "confidence": 0.0}, "confidence must lie in \\(0, 1\\)"),
        ({"confidence": 0.9}, "confidence applies to a fitted rig"),
        ({"required": True}, "no box to be robust over"),
        ({"design": {"m": (0.0, 1.0)}}, "non-physical"),
        ({"uncertain": {"q": (0.0, 1.0)}}, "not a parameter of the model"),
    ],
)
def test_bad_sources_are_parameter_errors(kwargs: dict, message: str) -> None:  # type: ignore[type-arg]
    with pytest.raises(ParameterError, match=message):
        robust_box(SEA1, **kwargs)
