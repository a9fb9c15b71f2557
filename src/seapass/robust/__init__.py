"""Robust passivity: a verdict for every plant in a box of uncertain parameters.

What lives here: [`box`][seapass.robust.box] (uncertain parameters ``NAME=LO:HI``,
checked: known names, not also fixed, physical, bounded),
[`bernstein`][seapass.robust.bernstein] (exact Bernstein enclosures of a
multivariate polynomial on a box and a certified branch and bound with a counted
budget), [`family`][seapass.robust.family] (the positive-real conditions of a
family of impedances as polynomials in the uncertain parameters),
[`verdict`][seapass.robust.verdict] (`robust_check`: passive for every plant in
the box, a verified worst-case plant, or undecided),
[`intervals`][seapass.robust.intervals] (robust passive intervals of a gain),
[`region`][seapass.robust.region] (robust passive regions over two gains, beside the
nominal one), [`api`][seapass.robust.api] (``is_passive`` and ``passive_intervals`` with ``box=``),
[`sampled_plant`][seapass.robust.sampled_plant] (alias sums of every plant of a box as
arb balls), [`sampled_local`][seapass.robust.sampled_local] (mean-value enclosures of the
sampled power over a box, decided piece by piece in ``cos ωT``) and
[`sampled_verdict`][seapass.robust.sampled_verdict]
(`robust_sampled_check`: the sampled-data verdict for every plant of a box),
[`sampled_intervals`][seapass.robust.sampled_intervals] (`robust_sampled_intervals`: the
certified sampled passive set of a plant parameter, or of a gain over a box) and
[`sampled_gains`][seapass.robust.sampled_gains] (its gain case: the outer set from the
plants of the box), [`pieces`][seapass.robust.pieces] (unions of closed intervals with
exact ends, rounded in or out).

May import: ``seapass.lazy``, [`seapass.errors`][seapass.errors], [`seapass.outcome`][seapass.outcome], [`seapass.progress`][seapass.progress], [`seapass.files`][seapass.files], [`seapass.exact`][seapass.exact], [`seapass.model`][seapass.model], [`seapass.analysis`][seapass.analysis], [`seapass.delay`][seapass.delay] (the front door `is_passive` without a box), [`seapass.sampled`][seapass.sampled] (the certified sampled-data kernel).
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_exports
from .box import UncertainBox, uncertain_box
from .intervals import RobustIntervals, robust_passive_intervals
from .region import RobustPassiveMap, robust_passive_map
from .verdict import RobustResult, WorstCase, robust_check

__all__ = [
    "RobustIntervals",
    "RobustPassiveMap",
    "RobustResult",
    "RobustSampledIntervals",
    "RobustSampledResult",
    "UncertainBox",
    "WorstCase",
    "robust_check",
    "robust_passive_intervals",
    "robust_passive_map",
    "robust_sampled_check",
    "robust_sampled_intervals",
    "uncertain_box",
]


# the sampled-data entry points load on first use (they import the sampled kernel)
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "robust_sampled_check": "sampled_verdict",
        "RobustSampledResult": "sampled_verdict",
        "robust_sampled_intervals": "sampled_intervals",
        "RobustSampledIntervals": "sampled_intervals",
    },
    globals(),
)


if TYPE_CHECKING:
    from .sampled_intervals import RobustSampledIntervals, robust_sampled_intervals
    from .sampled_verdict import RobustSampledResult, robust_sampled_check
