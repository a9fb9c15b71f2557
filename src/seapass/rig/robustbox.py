"""The box of a robust verdict, from its sources: the design file, a fitted rig, the caller.

`robust_box` is the one rule every command follows (``check``, ``bound``,
``sampled``, ``tune``, ``analyze``, ``explore``, ``export c``):

1. the design file's ``[uncertainty]`` table
   ([`seapass.model.uncertainty`][seapass.model.uncertainty]);
2. over it, a fitted rig's ``[intervals]`` (``--robust RIGFILE``;
   [`seapass.rig.intervals`][seapass.rig.intervals]) at its stored level or at
   ``confidence`` (recomputed from the standard errors), restricted to the
   parameters the model uses, dampings cut at 0;
3. over both, the caller's intervals (``--uncertain NAME=LO:HI``);
4. a name the caller gives a value (``--set``) is fixed: it leaves the box of
   sources 1 and 2 (the flags override the file); an interval given with
   ``uncertain`` on such a name is an error.

The result is checked by [`uncertain_box`][seapass.robust.box.uncertain_box]
(known names, ``LO <= HI``, physical, bounded).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from typing import Any

from ..errors import ParameterError
from ..model.design_file import Design
from ..model.sea import SEA, Impedance
from ..robust.box import UncertainBox, uncertain_box
from .rigfile import Rig, load_rig

__all__ = ["rig_box", "robust_box"]


def rig_box(
    rig: Rig | str | os.PathLike[str],
    *,
    confidence: float | None = None,
    parameters: Iterable[str] | None = None,
) -> dict[str, tuple[float, float]]:
    """The fitted intervals of ``rig`` (a `Rig` or a rig file) as a box of plants.

    Parameters
    ----------
    rig : Rig or path
        A rig with ``[intervals]`` (written by ``rig fit --rig-out``).
    confidence : float, optional
        Level in (0, 1); default the stored one.  Another level needs the stored
        standard errors.
    parameters : iterable of str, optional
        Keep only these names (the model's).

    Raises
    ------
    ParameterError
        A rig without intervals, a level outside (0, 1) or one that cannot be
        recomputed, or a mass interval that reaches 0.
    """
    if confidence is not None and (
        isinstance(confidence, bool)
        or not isinstance(confidence, int | float)
        or not 0 < confidence < 1
    ):
        raise ParameterError(f"confidence must lie in (0, 1), e.g. 0.95; got {confidence!r}")
    loaded = rig if isinstance(rig, Rig) else load_rig(rig)
    where = "the rig" if isinstance(rig, Rig) else f"rig file {os.fspath(rig)}"
    if loaded.intervals is None:
        raise ParameterError(
            f"{where} has no [intervals] table: fit a log to it (seapass rig fit) and use "
            "the rig file the fit writes, or give the box with [uncertainty]"
        )
    fitted = loaded.intervals if confidence is None else loaded.intervals.at(confidence)
    return fitted.box(None if parameters is None else tuple(parameters))


def robust_box(
    system: SEA | Impedance,
    *,
    design: Design | Mapping[str, Any] | None = None,
    rig: Rig | str | os.PathLike[str] | None = None,
    confidence: float | None = None,
    uncertain: Mapping[str, Any] | None = None,
    fixed: Iterable[str] = (),
    required: bool = False,
) -> UncertainBox | None:
    """The checked box of ``system``'s robust verdict from every source (see above).

    Parameters
    ----------
    system : SEA or Impedance
        The model the box is checked against.
    design : Design or mapping, optional
        The design file (its ``uncertainty``) or an ``[uncertainty]`` mapping.
    rig : Rig or path, optional
        A fitted rig whose ``[intervals]`` give the box (over the design's).
    confidence : float, optional
        Level of the rig's intervals (needs ``rig``).
    uncertain : mapping of str to (lo, hi), optional
        The caller's intervals, over both.
    fixed : iterable of str
        Names the caller gave a value: they leave the box of ``design`` and ``rig``.
    required : bool
        Raise when no source gives a box (else return None).

    Returns
    -------
    UncertainBox or None
        None when no source gives an interval (the nominal verdict applies).

    Examples
    --------
    >>> from seapass.model.sea import SEA
    >>> sea = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))
    >>> robust_box(sea, design={"m": (0.9, 1.1)}, uncertain={"b": (8, 12)})
    UncertainBox(intervals={'b': (8.0, 12.0), 'm': (0.9, 1.1)})
    >>> robust_box(sea, design={"m": (0.9, 1.1)}, fixed=["m"]) is None
    True
    """
    if confidence is not None and rig is None:
        raise ParameterError("confidence applies to a fitted rig's intervals: give the rig too")
    fixed = set(fixed)
    given = dict(uncertain or {})
    clash = sorted(fixed & set(given))
    if clash:
        raise ParameterError(
            f"{clash[0]} is given a value and an interval; give one (the interval makes it "
            "uncertain)"
        )
    table = design.uncertainty if isinstance(design, Design) else dict(design or {})
    if required and not table and rig is None and not given:
        raise ParameterError(
            "no box to be robust over: the design has no [uncertainty] table; add one "
            "(e.g. m = [0.9, 1.1]) or give a fitted rig file"
        )
    merged: dict[str, Any] = dict(table)
    if rig is not None:
        merged.update(rig_box(rig, confidence=confidence, parameters=system.parameters))
    merged = {k: v for k, v in merged.items() if k not in fixed}
    merged.update(given)
    if not merged:
        if required:
            raise ParameterError(
                "no box to be robust over: every uncertain parameter is also given a value"
            )
        return None
    return uncertain_box(system, merged, delay_ok=True)  # the verdict decides a delay
