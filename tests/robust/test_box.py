"""Uncertain boxes: parsing and the checks made before any work (issue 26)."""

from __future__ import annotations

import pytest

from seapass.errors import ParameterError
from seapass.files.limits import MAX_UNCERTAIN
from seapass.model.sea import SEA
from seapass.robust.box import parse_uncertain, uncertain_box

LP = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))


def test_a_box_keeps_its_intervals_sorted_by_name() -> None:
    box = uncertain_box(LP, {"m": (0.9, 1.1), "b": [8, 12]})
    assert box.names == ("b", "m")
    assert box.to_dict() == {"b": [8.0, 12.0], "m": [0.9, 1.1]}
    assert box.center() == {"b": 10.0, "m": 1.0}


def test_parse_uncertain_reads_name_lo_hi() -> None:
    assert parse_uncertain(["m=0.9:1.1", "kd=-5:5"]) == {"m": (0.9, 1.1), "kd": (-5.0, 5.0)}


@pytest.mark.parametrize(
    ("items", "words"),
    [
        (["m=0.9"], "expected NAME=LO:HI"),
        (["m=0.9:1.1:2"], "expected NAME=LO:HI"),
        (["=1:2"], "expected NAME=LO:HI"),
        (["m=1:2", "m=1:3"], "given twice"),
        (["m=a:2"], "not a number"),
        (["m=1:inf"], "not finite"),
    ],
)
def test_parse_uncertain_rejects_bad_text(items: list[str], words: str) -> None:
    with pytest.raises(ParameterError, match=words):
        parse_uncertain(items)


@pytest.mark.parametrize(
    ("box", "words"),
    [
        ({"m": (1.1, 0.9)}, "LO must not exceed HI"),
        ({"mass": (0.9, 1.1)}, "not a parameter of the model"),
        ({"m": (0.0, 1.1)}, "non-physical"),
        ({"m": (-1.0, 1.1)}, "non-physical"),
        ({"b": (-1.0, 1.0)}, "must not be negative"),
        ({"k1": (-1.0, 1.0)}, "must not be negative"),
        ({"m": (1e-3, 1e4)}, "decades"),
        ({"kd": (0.0, 1e13)}, "exceeds the limit"),
        ({"m": 1.0}, "pair"),
        ({}, "at least one"),
    ],
)
def test_bad_boxes_are_refused_before_any_work(box: dict, words: str) -> None:
    with pytest.raises(ParameterError, match=words):
        uncertain_box(LP, box)


def test_too_many_uncertain_parameters_are_refused() -> None:
    names = [f"p{i}" for i in range(MAX_UNCERTAIN + 1)]
    with pytest.raises(ParameterError, match="exceed the limit"):
        uncertain_box(LP, dict.fromkeys(names, (1.0, 2.0)))


def test_the_error_names_the_python_argument() -> None:
    with pytest.raises(ParameterError) as info:
        uncertain_box(LP, {"m": (2.0, 1.0)})
    assert info.value.argument == "box"


@pytest.mark.parametrize(
    "argv",
    [
        ["bound", "kd"],
        ["region", "kd", "k1", "--points", "2"],
    ],
)
def test_a_box_on_a_delayed_design_needs_the_delay_aware_route(argv: list[str], capsys) -> None:
    # the delay-free box machinery refuses a delayed design; check, bound and region over a
    # box go through seapass.robust.delayed / delayedgains instead and answer at the delay
    from seapass.cli import main
    from seapass.errors import DelayError
    from seapass.model.sea import SEA
    from seapass.robust.box import uncertain_box

    delayed = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(b=10, k1=1000, tau=0.001, kd=100))
    with pytest.raises(DelayError, match="robust verdicts over a box need a delay-free design"):
        uncertain_box(delayed, {"m": (0.9, 1.1)})
    assert uncertain_box(delayed, {"m": (0.9, 1.1)}, delay_ok=True).names == ("m",)
    model = ["--D1", "k1", "--CA", "kd*exp(-tau*s)", "--set", "b=10", "--set", "tau=0.001"]
    if argv[0] != "region":
        model += ["--set", "k1=1000"]
    assert main([*argv, *model, "--uncertain", "m=0.9:1.1"]) == 0
    captured = capsys.readouterr()
    assert captured.err == "" and "tau" in captured.out, captured
