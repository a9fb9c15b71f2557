"""Robust passivity: a verdict for every plant in a box of uncertain parameters.

What lives here: [`box`][seapass.robust.box] (uncertain parameters ``NAME=LO:HI``,
checked: known names, not also fixed, physical, bounded),
[`bernstein`][seapass.robust.bernstein] (exact Bernstein enclosures of a
multivariate polynomial on a box and a certified branch and bound with a counted
budget), [`family`][seapass.robust.family] (the positive-real conditions of a
family of impedances as polynomials in the uncertain parameters),
[`verdict`][seapass.robust.verdict] (`robust_check`: passive for every plant in
the box, a verified worst-case plant, or undecided; faces where the structure changes
in [`faces`][seapass.robust.faces], corners where they meet blown up into charts in
[`corners`][seapass.robust.corners], the exact test at points of the box in
[`witness`][seapass.robust.witness]),
[`intervals`][seapass.robust.intervals] (robust passive intervals of a gain),
[`region`][seapass.robust.region] (robust passive regions over two gains, beside the
nominal one), [`api`][seapass.robust.api] (``is_passive`` and ``passive_intervals`` with ``box=``),
[`sampled_plant`][seapass.robust.sampled_plant] (alias sums of every plant of a box as
arb balls), [`sampled_local`][seapass.robust.sampled_local] (mean-value enclosures of the
sampled power over a box, decided piece by piece in ``cos ωT``) and
[`sampled_verdict`][seapass.robust.sampled_verdict]
(`robust_sampled_check`: the sampled-data verdict for every plant of a box),
[`delayform`][seapass.robust.delayform] (mean-value ball enclosures of a delayed real part
over frequency × delays × box) and [`delayed`][seapass.robust.delayed]
(`robust_delayed_check`, `robust_delay_margin`: delayed designs over a box; the result
in [`delayresult`][seapass.robust.delayresult]; robust gain sets at a delay in
[`delayedgains`][seapass.robust.delayedgains]),
[`portfamily`][seapass.robust.portfamily] (a two-port's Llewellyn and passivity
conditions as polynomials on the box), [`twoport`][seapass.robust.twoport]
(`robust_two_port_check`: absolute stability and passivity of a two-port for every
plant of a box; its results in [`portresult`][seapass.robust.portresult]), [`portbound`][seapass.robust.portbound] (robust gain sets of a
two-port),
[`sampled_intervals`][seapass.robust.sampled_intervals] (`robust_sampled_intervals`: the
certified sampled passive set of a plant parameter, or of a gain over a box),
[`sampled_gains`][seapass.robust.sampled_gains] (its gain case: the outer set from the
plants of the box) and [`pieces`][seapass.robust.pieces] (unions of closed intervals with
exact ends, rounded in or out).

May import: ``seapass.lazy``, [`seapass.errors`][seapass.errors], [`seapass.outcome`][seapass.outcome], [`seapass.progress`][seapass.progress], [`seapass.files`][seapass.files], [`seapass.exact`][seapass.exact], [`seapass.model`][seapass.model], [`seapass.analysis`][seapass.analysis], [`seapass.ports`][seapass.ports] (the exact two-port verdicts), [`seapass.delay`][seapass.delay] (the front door `is_passive` without a box), [`seapass.sampled`][seapass.sampled] (the certified sampled-data kernel).
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_exports
from .box import UncertainBox, uncertain_box
from .intervals import RobustIntervals, robust_passive_intervals
from .region import RobustPassiveMap, robust_passive_map
from .verdict import RobustResult, WorstCase, robust_check

__all__ = [
    "RobustDelayMargin",
    "RobustIntervals",
    "RobustPassiveMap",
    "RobustPortIntervals",
    "RobustResult",
    "RobustSampledIntervals",
    "RobustSampledResult",
    "RobustTwoPortResult",
    "UncertainBox",
    "WorstCase",
    "robust_check",
    "robust_delay_margin",
    "robust_delayed_check",
    "robust_passive_intervals",
    "robust_passive_map",
    "robust_port_intervals",
    "robust_sampled_check",
    "robust_sampled_intervals",
    "robust_two_port_check",
    "uncertain_box",
]


# the sampled-data and delayed entry points load on first use (the sampled and delay kernels)
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "robust_sampled_check": "sampled_verdict",
        "RobustSampledResult": "sampled_verdict",
        "robust_delay_margin": "delayed",
        "robust_delayed_check": "delayed",
        "RobustDelayMargin": "delayresult",
        "robust_two_port_check": "twoport",
        "RobustTwoPortResult": "portresult",
        "robust_port_intervals": "portbound",
        "RobustPortIntervals": "portbound",
        "robust_sampled_intervals": "sampled_intervals",
        "RobustSampledIntervals": "sampled_intervals",
    },
    globals(),
)


if TYPE_CHECKING:
    from .delayed import robust_delay_margin, robust_delayed_check
    from .delayresult import RobustDelayMargin
    from .portbound import RobustPortIntervals, robust_port_intervals
    from .portresult import RobustTwoPortResult
    from .sampled_intervals import RobustSampledIntervals, robust_sampled_intervals
    from .sampled_verdict import RobustSampledResult, robust_sampled_check
    from .twoport import robust_two_port_check
