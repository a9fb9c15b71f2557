"""Certified decision of sampled-data passivity for one set of controllers.

Shared by the point verdict ([`seapass.sampled.passivity.sampled_passivity`][seapass.sampled.passivity.sampled_passivity]), the
bounds and the Z-width maps.  Inputs are exact (plant rationals, controller rationals);
the alias sums are balls at a working precision that is raised until the balls decide, up
to a cap; at the cap the answer is "undecided", never a guess.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum
from fractions import Fraction

import numpy as np
from flint import acb, acb_poly, arb, arb_poly, fmpq_poly

from ..errors import ParameterError
from ..exact.poly import as_poly, rational
from ..outcome import Outcome
from .alias import AliasSums, alias_sums
from .certified import Sign, precision, schur_stable, schur_stable_exact, sign_on
from .plant import plant_from_key
from .power import ControllerFamily, polynomial_degree, power_values, weighted_polynomials

__all__ = ["Decision", "Outcome", "SampledReason", "decide", "precision_ladder"]

#: Working precisions tried in turn (bits); the last one is the default cap.
PRECISIONS = (128, 256, 512, 1024, 2048, 4096)
#: Largest degree of the power polynomial (bounds time and memory; delays add 2 per sample).
MAX_POWER_DEGREE = 400


class SampledReason(StrEnum):
    """Why a sampled-data verdict came out as it did (the JSON value is the string)."""

    NONE = ""
    """Passive with control (or an undecided box leaf that is not an edge)."""
    NO_CONTROL = "no_control"
    """No control at all: the passive physics."""
    UNSTABLE = "unstable"
    """The sampled loop with the port held is unstable."""
    ALIAS_INJECTION = "alias_injection"
    """The controller samples the load position of an undamped transmission."""
    NEGATIVE_POWER = "negative_power"
    """``N(ω) < 0`` is proven at some ``ω > 0``."""
    LOW_FREQUENCY = "low_frequency"
    """``N < 0`` as ``ω → 0``: slow enough motions extract energy."""
    CONTINUOUS_NOT_PASSIVE = "continuous_not_passive"
    """The deployment policy's continuous-time gate (see `sampled_passivity`)."""
    UNDECIDED = "undecided"
    """Not decided at the precision cap."""
    BUDGET = "budget"
    """Not examined: the box budget of a bound ran out (bounds only)."""
    EDGE = "edge"
    """An undecided box leaf between proven boxes of opposite verdicts (bounds only)."""


@dataclass(frozen=True, kw_only=True)
class Decision:
    outcome: Outcome
    reason: SampledReason = SampledReason.NONE
    witness: Fraction | None = None  # x = cos(theta) with a proven negative power
    precision: int = 0
    degree: int = 0
    spectral_radius: float = math.nan


def precision_ladder(max_bits: int) -> tuple[int, ...]:
    ladder = tuple(p for p in PRECISIONS if p <= max_bits)
    return ladder or (max(64, int(max_bits)),)


def point_family(ka: object, kl: object) -> ControllerFamily:
    """``v' = (d_A d_L, n_A d_L, n_L d_A)`` of fixed controllers (λ-degree 0)."""
    na, da = as_poly(ka.num), as_poly(ka.den)  # type: ignore[attr-defined]
    nl, dl = as_poly(kl.num), as_poly(kl.den)  # type: ignore[attr-defined]
    return [[da * dl], [na * dl], [nl * da]]


def needed_sums(ka_zero: bool, kl_zero: bool) -> tuple[str, ...]:
    names: list[str] = []
    if not ka_zero:
        names += ["S1", "S2", "Sg"]
    if not kl_zero:
        names += ["S1", "S3", "S4"]
    return tuple(dict.fromkeys(names))


@functools.lru_cache(maxsize=64)
def cached_sums(key: str, period: Fraction, names: tuple[str, ...], prec: int) -> AliasSums:
    plant = plant_from_key(key)
    summands = plant.summands()
    return alias_sums({k: summands[k] for k in names}, rational(period), prec)


def alias_injection(key: str) -> bool:
    """``Σ 1/(|s_k|² Re Z0)`` diverges: sampled load feedback is never passive."""
    num, den = plant_from_key(key).summands()["S4"]
    return den.degree() - num.degree() < 2


def characteristic(
    sums: AliasSums, na: fmpq_poly, da: fmpq_poly, pad: int | None = None
) -> list[acb]:
    """Coefficients in ``z`` of ``χ = z^e d_A(1/z) den_g + z^e n_A(1/z) num_g`` (port held).

    ``g = num_g/den_g`` is the ZOH pulse transfer of ``P``; ``χ`` is linear in
    ``(n_A, d_A)`` for a fixed ``pad = e``.
    """
    num_g, den_g = sums.pulse_transfer("Sg")
    e = max(na.degree(), da.degree(), 0) if pad is None else pad

    def padded(p: fmpq_poly) -> list[acb]:
        return [acb(c) for c in p.coeffs()] + [acb(0)] * (e + 1 - len(p.coeffs()))

    na_z = acb_poly(list(reversed(padded(na))))
    da_z = acb_poly(list(reversed(padded(da))))
    return (da_z * den_g + na_z * num_g).coeffs()


def _radius(chi: Sequence[acb]) -> float:
    mids = [complex(float(c.real.mid()), float(c.imag.mid())) for c in reversed(chi)]
    while len(mids) > 1 and mids[0] == 0:
        mids.pop(0)
    roots = np.roots(mids) if len(mids) > 1 else np.zeros(0)
    return float(np.max(np.abs(roots))) if roots.size else 0.0


def _below_one(p: arb_poly) -> Fraction | None:
    """The largest ``x = 1 − 2^-k`` with a proven ``p(x) < 0`` (``p(1) < 0``: ``ω > 0``)."""
    for k in range(4, 400, 4):
        x = 1 - Fraction(1, 2**k)
        if p(arb(rational(x))) < 0:
            return x
    return None


def _deepest_witness(
    sums: AliasSums, family: ControllerFamily, p: arb_poly, x: Fraction
) -> Fraction:
    """A proven negative point where ``N`` itself is most negative among nearby candidates.

    The first negative point found can sit next to a zero of ``N``; a witness deep inside
    the negative region is what an independent check (or a user) can reproduce.
    """
    theta0 = theta_of(x) if x < 1 else 0.05
    cands = [theta0 * 2.0 ** (k / 2) for k in range(-24, 13)] + [
        math.pi * i / 32 for i in range(1, 33)
    ]
    cands = sorted({t for t in cands if 0 < t <= math.pi})
    values = power_values(sums, family, cands)
    order = sorted(range(len(cands)), key=lambda i: float(values[i].mid()))
    for i in order[:8]:
        t = Fraction(cands[i])
        xi = 1 - t * t / 2 if t < Fraction(1, 10**4) else Fraction(math.cos(cands[i]))
        if xi < 1 and p(arb(rational(xi))) < 0:
            return xi
    return x


def theta_of(x: Fraction) -> float:
    """``acos x`` accurate near ``x = 1`` (``2 asin √((1 − x)/2)`` with ``1 − x`` exact)."""
    return 2.0 * math.asin(math.sqrt(max(0.0, min(1.0, float((1 - x) / 2)))))


def loop_radius(key: str, ka: object, kl: object, period: Fraction) -> float:
    """Spectral radius (floating point, for information) of the loop with the port held:
    the roots of ``χ`` and the load-side controller's own poles."""
    sums = cached_sums(key, period, ("Sg",), PRECISIONS[0])
    with precision(sums.prec):
        chi = characteristic(sums, as_poly(ka.num), as_poly(ka.den))  # type: ignore[attr-defined]
    rho = _radius(chi)
    poles = kl.poles()  # type: ignore[attr-defined]
    if not kl.is_zero and poles.size:  # type: ignore[attr-defined]
        rho = max(rho, float(np.max(np.abs(poles))))
    return rho


def decide(
    key: str,
    ka: object,
    kl: object,
    period: Fraction,
    *,
    max_precision: int = PRECISIONS[-1],
) -> Decision:
    """Certified sampled-data passivity of the plant ``key`` under ``(K_A, K_L)``."""
    ka_zero, kl_zero = ka.is_zero, kl.is_zero  # type: ignore[attr-defined]
    if ka_zero and kl_zero:
        return Decision(
            outcome=Outcome.PASSIVE,
            reason=SampledReason.NO_CONTROL,
            spectral_radius=loop_radius(key, ka, kl, period),
        )
    if not kl_zero and not schur_stable_exact(list(reversed(kl.den))):  # type: ignore[attr-defined]
        rho = loop_radius(key, ka, kl, period)
        return Decision(
            outcome=Outcome.NOT_PASSIVE,
            reason=SampledReason.UNSTABLE,
            spectral_radius=max(rho, 1.0),
        )
    if not kl_zero and alias_injection(key):
        rho = loop_radius(key, ka, kl, period)
        return Decision(
            outcome=Outcome.NOT_PASSIVE, reason=SampledReason.ALIAS_INJECTION, spectral_radius=rho
        )
    names = needed_sums(ka_zero, kl_zero)
    if "Sg" not in names:
        names = (*names, "Sg")  # the modes with the port held, for the stability test
    family = point_family(ka, kl)
    ladder = precision_ladder(max_precision)
    degree = 0
    for prec in ladder:
        sums = cached_sums(key, period, names, prec)
        degree = polynomial_degree(sums, family)
        if degree > MAX_POWER_DEGREE:
            raise ParameterError(
                f"the controllers and delay make the power polynomial of degree {degree}, "
                f"above the supported {MAX_POWER_DEGREE}; use fewer samples of delay or a "
                "lower-order controller"
            )
        with precision(prec):
            chi = characteristic(sums, as_poly(ka.num), as_poly(ka.den))  # type: ignore[attr-defined]
            stable = schur_stable(chi)
            rho = _radius(chi)
            if stable is False:
                return Decision(
                    outcome=Outcome.NOT_PASSIVE,
                    reason=SampledReason.UNSTABLE,
                    precision=prec,
                    degree=degree,
                    spectral_radius=max(rho, 1.0),
                )
            (poly,) = weighted_polynomials(sums, family)
            result = sign_on(
                [poly], Fraction(-1), Fraction(1), budget=60 if prec < ladder[-1] else 2000
            )
            if result.sign is Sign.NEGATIVE:
                low = poly(arb(1)) < 0
                reason = SampledReason.LOW_FREQUENCY if low else SampledReason.NEGATIVE_POWER
                witness = result.witness if result.witness is not None else Fraction(1)
                if witness == 1:
                    witness = _below_one(poly) or witness
                witness = _deepest_witness(sums, family, poly, witness)
                return Decision(
                    outcome=Outcome.NOT_PASSIVE,
                    reason=reason,
                    witness=witness,
                    precision=prec,
                    degree=degree,
                    spectral_radius=rho,
                )
            if result.sign is Sign.POSITIVE and stable:
                return Decision(
                    outcome=Outcome.PASSIVE, precision=prec, degree=degree, spectral_radius=rho
                )
    return Decision(
        outcome=Outcome.UNDECIDED,
        reason=SampledReason.UNDECIDED,
        precision=ladder[-1],
        degree=degree,
    )
