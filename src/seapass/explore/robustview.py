"""The explorer's box verdict: is the design at the current sliders passive for every plant?

A view may carry a box of uncertain parameters (``uncertainty``: a design file's
``[uncertainty]`` table, ``{"m": [0.9, 1.1], ...}``).  The ``robust`` panel
decides the design at the current slider values over that box with
[`robust_check`][seapass.robust.verdict.robust_check] (the sliders of the
uncertain parameters are ignored: every value of their interval counts) and
returns *passive for the whole box*, the *worst plant* (a point of the box,
verified not passive by the exact test) or *undecided* (the counted budget
`EXPLORE_BUDGET` ran out; never shown as passive).  `parse_box` checks the
field of a view; the physical rules are `uncertain_box`'s, applied by the panel.
"""

from __future__ import annotations

import math
from typing import Any

from ..errors import SeapassError
from ..files.limits import MAX_UNCERTAIN
from ..robust.box import uncertain_box
from ..robust.verdict import robust_check
from .state import ExploreState

__all__ = ["EXPLORE_BUDGET", "parse_box", "robust_panel"]

EXPLORE_BUDGET = 2000
"""Boxes the certified branch and bound may examine per view (counted, never timed)."""


def parse_box(
    raw: Any, params: list[str], errors: dict[str, str]
) -> dict[str, tuple[float, float]]:
    """The ``uncertainty`` field of a view: ``{name: [lo, hi]}`` of known parameters.

    Bad entries go to ``errors`` under ``uncertainty.NAME`` (``uncertainty``: the field);
    a name the (edited) model no longer has leaves the box.

    >>> errors = {}
    >>> parse_box({"m": [0.9, 1.1], "q": [1, 2]}, ["m", "b"], errors), errors
    ({'m': (0.9, 1.1)}, {})
    >>> parse_box({"m": [1.1, 0.9]}, ["m"], errors), errors
    ({}, {'uncertainty.m': 'expected [LO, HI] with finite LO <= HI'})
    """
    if raw is None:
        return {}
    if not isinstance(raw, dict) or len(raw) > MAX_UNCERTAIN:
        errors["uncertainty"] = f"expected at most {MAX_UNCERTAIN} entries NAME: [LO, HI]"
        return {}
    out: dict[str, tuple[float, float]] = {}
    for name, pair in raw.items():
        key = f"uncertainty.{name}"
        if name not in params:
            continue
        ok = isinstance(pair, list | tuple) and len(pair) == 2
        ok = ok and all(isinstance(v, int | float) and not isinstance(v, bool) for v in pair)
        if not ok or not all(math.isfinite(v) for v in pair) or pair[0] > pair[1]:
            errors[key] = "expected [LO, HI] with finite LO <= HI"
            continue
        out[str(name)] = (float(pair[0]), float(pair[1]))
    return out


def robust_panel(state: ExploreState) -> dict[str, Any]:
    """The box verdict of the view (``analysed`` False without a box)."""
    if not state.uncertainty:
        return {
            "analysed": False,
            "detail": "no box: open a design file with an [uncertainty] table",
        }
    try:
        box = uncertain_box(state.sea(), dict(state.uncertainty))
    except SeapassError as exc:
        return {"analysed": False, "detail": str(exc)}
    res = robust_check(state.sea(), box=box, budget=EXPLORE_BUDGET)
    return {"analysed": True, **res.to_dict()}


def robust_key(state: ExploreState) -> str:
    """Cache key: the model, every value and the box."""
    return state.key() + repr(sorted(state.uncertainty.items()))
