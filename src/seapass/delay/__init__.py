"""Continuous time delay, certified: passivity with ``e^{-sτ}`` in the loop.

What lives here: the exact structure of a delayed impedance ``Z = N(s, E)/D(s, E)``,
``E = e^{-sτ}`` (`structure`); its real part on the imaginary axis as a trigonometric
polynomial in ``ωτ`` with exact polynomial coefficients (`trig`), its exact asymptotics
at ``ω → 0`` (`lowfreq`) and ``ω → ∞`` (`highfreq`) and a certified sign on the rest
with arb balls (`sign`); the characteristic quasi-polynomial ``P(s) + Q(s) e^{-sτ}``
and its right-half-plane roots (`stability`); the verdict at a given delay
(`passivity`), delay-independent passivity (`independent`), the passivity delay margin
``τ*`` (`margin`), passive sets of a gain at a fixed delay (`gain`) and a design against
its stated loop latency ``[control] delay_time`` (`latency`).

Every verdict is a [`seapass.outcome.Outcome`][seapass.outcome.Outcome]; what the
balls cannot decide at their budget is ``undecided``, never passive.  No Padé
approximation is used anywhere.

May import: [`seapass.errors`][seapass.errors], [`seapass.outcome`][seapass.outcome],
[`seapass.files`][seapass.files], [`seapass.exact`][seapass.exact],
[`seapass.model`][seapass.model], [`seapass.analysis`][seapass.analysis].  ``sim`` and everything above may import it.
"""
