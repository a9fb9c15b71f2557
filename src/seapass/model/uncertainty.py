"""A design file's ``[uncertainty]`` table: the plant (or gain) intervals a robust verdict covers.

::

    [uncertainty]          # every plant in this box: check, bound and analyze use it
    m = [0.9, 1.1]         # kg, LO <= HI
    b = [8.0, 12.0]

Each entry names a parameter of the model and gives ``[LO, HI]``; ``check FILE``
and ``bound NAME FILE`` then decide "for every value in the box", exactly as
``--uncertain NAME=LO:HI`` does (a flag overrides the file's entry of its name).
`check_uncertainty` checks the table when the file is loaded, with the rules of
[`seapass.robust.box.uncertain_box`][seapass.robust.box.uncertain_box]:

* a known parameter of the model;
* ``LO <= HI``, finite, ``|LO|, |HI| <=`` `MAX_UNCERTAIN_MAGNITUDE`;
* physical: ``m > 0`` and ``b, k1, k2, b1, b2 >= 0`` on the whole interval;
* not fixed in a conflicting way: the file's nominal value (``[parameters]`` or
  ``[plant]``) lies in the interval;
* bounded work: at most `MAX_UNCERTAIN` entries and ``HI/LO <=`` `MAX_UNCERTAIN_RATIO`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from ..errors import FileFormatError
from ..files.limits import MAX_UNCERTAIN, MAX_UNCERTAIN_MAGNITUDE, MAX_UNCERTAIN_RATIO

__all__ = ["NONNEGATIVE", "POSITIVE", "check_uncertainty"]

POSITIVE = frozenset({"m"})
"""Parameters that must be positive on the whole interval."""

NONNEGATIVE = frozenset({"b", "k1", "k2", "b1", "b2"})
"""Plant parameters that must not be negative on the whole interval."""


def check_uncertainty(
    table: Mapping[str, tuple[float, float]],
    parameters: Sequence[str],
    values: Mapping[str, float],
    *,
    nominal: bool = True,
) -> dict[str, tuple[float, float]]:
    """The checked ``[uncertainty]`` table, sorted by name.

    Parameters
    ----------
    table : mapping of str to (lo, hi)
        The entries as read (pairs already numbers).
    parameters : sequence of str
        The model's parameters.
    values : mapping of str to float
        The file's nominal values.
    nominal : bool, default True
        Also require each nominal value in its interval (a design file; a box
        from elsewhere, e.g. a fitted rig's, may leave the nominal plant).

    Raises
    ------
    FileFormatError
        Naming the entry (``uncertainty.m``) and what to change.

    Examples
    --------
    >>> check_uncertainty({"m": (0.9, 1.1)}, ("b", "m"), {"m": 1.0, "b": 10.0})
    {'m': (0.9, 1.1)}
    >>> check_uncertainty({"m": (0.0, 1.1)}, ("b", "m"), {"m": 1.0, "b": 10.0})
    Traceback (most recent call last):
    ...
    seapass.errors.FileFormatError: uncertainty.m: [0, 1.1] includes non-physical values; m must be positive on the whole interval (give LO > 0)
    """
    if len(table) > MAX_UNCERTAIN:
        raise FileFormatError(
            f"[uncertainty]: {len(table)} entries exceed the limit of {MAX_UNCERTAIN}; keep "
            "the parameters known least"
        )
    out: dict[str, tuple[float, float]] = {}
    for name, (lo, hi) in sorted(table.items()):
        key, span = f"uncertainty.{name}", f"[{lo:g}, {hi:g}]"
        if name not in parameters:
            raise FileFormatError(f"{key}: not a parameter of the model ({', '.join(parameters)})")
        if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
            raise FileFormatError(f"{key}: {span} is empty or not finite; give LO <= HI")
        if max(abs(lo), abs(hi)) > MAX_UNCERTAIN_MAGNITUDE:
            raise FileFormatError(
                f"{key}: {span} exceeds |value| <= {MAX_UNCERTAIN_MAGNITUDE:g}; give SI units"
            )
        if name in POSITIVE and lo <= 0:
            raise FileFormatError(
                f"{key}: {span} includes non-physical values; {name} must be positive on the "
                "whole interval (give LO > 0)"
            )
        if name in NONNEGATIVE and lo < 0:
            raise FileFormatError(
                f"{key}: {span} includes non-physical values; {name} must not be negative "
                "(give LO >= 0)"
            )
        if lo > 0 and hi / lo > MAX_UNCERTAIN_RATIO:
            raise FileFormatError(
                f"{key}: {span} spans more than {math.log10(MAX_UNCERTAIN_RATIO):g} decades, too "
                "large for a bounded certified verdict; narrow it"
            )
        value = values.get(name)
        if nominal and value is not None and not lo <= value <= hi:
            raise FileFormatError(
                f"{key}: {span} does not contain the file's value {name} = {value:g}; the "
                "nominal value must lie in its interval"
            )
        out[name] = (float(lo), float(hi))
    return out
