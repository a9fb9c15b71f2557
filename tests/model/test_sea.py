"""The API page's `SEA` table: every parameter its own description and its true default."""

from __future__ import annotations

from pathlib import Path

import griffe

SRC = Path(__file__).resolve().parents[2] / "src"


def _parameters() -> dict[str, tuple[str, str]]:
    sea = griffe.load("seapass.model.sea", search_paths=[str(SRC)])["SEA"]
    (params,) = [s for s in sea.docstring.parse("numpy") if s.kind.value == "parameters"]
    return {p.name: (str(p.default), p.description) for p in params.value}


def test_each_element_has_its_own_description_and_default() -> None:
    params = _parameters()
    names = ("D1", "D2", "CA", "CL", "m", "b")
    assert set(names) <= set(params)
    descriptions = [params[n][1] for n in names]
    assert len(set(descriptions)) == len(names)  # D1, D2, CA, CL, m, b: six descriptions
    assert params["b"][0].strip("\"'") == "b" and params["m"][0].strip("\"'") == "m"
    assert all(params[n][0] == "0" for n in ("D1", "D2", "CA", "CL"))
    # the documented defaults are the dataclass's
    from seapass.model.sea import SEA

    fields = SEA.__dataclass_fields__
    for n in names:
        assert str(fields[n].default) == params[n][0].strip("\"'")
