"""Continuous time delay, certified: passivity with ``e^{-sτ}`` in the loop.

What lives here: the exact structure of a delayed impedance ``Z = N(s, E)/D(s, E)``,
``E = e^{-sτ}`` (`structure`); its real part on the imaginary axis as a trigonometric
polynomial in ``ωτ`` with exact polynomial coefficients (`trig`), its exact asymptotics
at ``ω → 0`` (`lowfreq`) and ``ω → ∞`` (`highfreq`) and a certified sign on the rest
with arb balls (`sign`); the characteristic quasi-polynomial ``P(s) + Q(s) e^{-sτ}``
and its right-half-plane roots (`stability`); the verdict at a given delay
(`passivity`), delay-independent passivity (`independent`), the passivity delay margin
``τ*`` (`margin`), the (gain, delay) region (`gain`), the certified passive set of a
gain at a fixed delay (`gainfamily`: the family certificate in the gain, `gainbound`:
``bound``, `gainmap`: ``region``) and a design against its stated loop latency
``[control] delay_time`` (`latency`).

Every verdict is a [`seapass.outcome.Outcome`][seapass.outcome.Outcome]; what the
balls cannot decide at their budget is ``undecided``, never passive.  No Padé
approximation is used anywhere.

May import: ``seapass.lazy``, [`seapass.errors`][seapass.errors], [`seapass.outcome`][seapass.outcome],
[`seapass.files`][seapass.files], [`seapass.exact`][seapass.exact],
[`seapass.model`][seapass.model], [`seapass.analysis`][seapass.analysis].  ``sim`` and everything above may import it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

_LAZY: dict[str, str] = {
    "DelayGainEdges": "gain",
    "DelayRegion": "gain",
    "delay_gain_edges": "gain",
    "delay_region": "gain",
    "DelayGainIntervals": "gainbound",
    "passive_gain_intervals": "gainbound",
    "DelayPassiveMap": "gainmap",
    "delay_passive_map": "gainmap",
    "DelayMarginResult": "margin",
    "delay_margin": "margin",
    "DelayPassivityResult": "passivity",
    "delayed_passivity": "passivity",
}
"""Public name -> the module that defines it (loaded on first use)."""

__all__ = [
    "DelayGainEdges",
    "DelayGainIntervals",
    "DelayMarginResult",
    "DelayPassiveMap",
    "DelayPassivityResult",
    "DelayRegion",
    "delay_gain_edges",
    "delay_margin",
    "delay_passive_map",
    "delay_region",
    "delayed_passivity",
    "passive_gain_intervals",
]


__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())


if TYPE_CHECKING:  # what type checkers and IDEs see
    from .gain import DelayGainEdges, DelayRegion, delay_gain_edges, delay_region
    from .gainbound import DelayGainIntervals, passive_gain_intervals
    from .gainmap import DelayPassiveMap, delay_passive_map
    from .margin import DelayMarginResult, delay_margin
    from .passivity import DelayPassivityResult, delayed_passivity
