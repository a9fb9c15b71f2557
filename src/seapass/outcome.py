"""The one verdict vocabulary of every passivity result.

Every question seapass answers about passivity (continuous, sampled, two-port,
delayed, robust over a box) ends in one of three outcomes.  ``UNDECIDED`` means
the certified method could not decide at its budget; it is never reported as
passive.

Every passivity result exposes its verdict as ``outcome`` (an `Outcome`); the
convenience ``passive`` (bool) is ``outcome.passive``, so an undecided answer
reads as not passive.  Reasons and kinds are StrEnums of their own module, and
code compares enums, never strings: the JSON values are the strings.

One meaning of ``marginal``
---------------------------
A result is *marginal* when its verdict is **decided** (``PASSIVE`` or
``NOT_PASSIVE``) but lies within the result's stated relative margin of the
passivity boundary (the exact continuous test states ``MARGINAL_RTOL = 1e-9`` of
its scale-invariant margin).  A verdict the method could not decide is
``outcome is Outcome.UNDECIDED``, never "marginal"; a result that states no
margin (the certified sampled-data verdict) is never marginal.

This module imports nothing from seapass: it sits at the bottom layer so that
every subpackage can share it.

Examples
--------
>>> Outcome.PASSIVE.passive
True
>>> Outcome("not_passive")
<Outcome.NOT_PASSIVE: 'not_passive'>
>>> Outcome.from_bool(False).label
'not passive'
"""

from __future__ import annotations

from enum import StrEnum

__all__ = ["Outcome"]


class Outcome(StrEnum):
    """Certified outcome of a passivity question (the JSON value is the string)."""

    PASSIVE = "passive"
    NOT_PASSIVE = "not_passive"
    UNDECIDED = "undecided"

    @property
    def passive(self) -> bool:
        """Only a certified ``PASSIVE`` counts as passive."""
        return self is Outcome.PASSIVE

    @property
    def label(self) -> str:
        """Words for people: ``"passive"``, ``"not passive"``, ``"undecided"``."""
        return self.value.replace("_", " ")

    @classmethod
    def from_bool(cls, passive: bool) -> Outcome:
        """The outcome of an exact (always decided) test."""
        return cls.PASSIVE if passive else cls.NOT_PASSIVE
