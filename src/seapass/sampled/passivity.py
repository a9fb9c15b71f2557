"""Passivity of the *sampled-data* SEA: continuous port, 500 Hz digital controller.

The person (or environment) moves the continuous load port; the controller
samples ``x_A(kT)`` and ``x_L(kT)``, computes ``u_k = −K_A(z) x_A − K_L(z) x_L``
(``K = z^-d C(z)`` discretized, see [`seapass.sampled.controllers`][seapass.sampled.controllers]) and holds it
(ZOH) on the actuator.  Passivity of this linear *periodically time-varying*
port is decided with the Colgate–Schenkel alias argument [1]_, generalised here
to the SEA transmission.

Derivation (``s_k = j(ω + 2πk/T)``, ``z = e^{jωT}``)
------------------------------------------------------
Physical part: ``Z0 = [D1 α + D2 (α + D1)]/(s(α + D1))``, ``α = m s² + b s``,
``a = D1/(α + D1)`` (actuator force → port force), ``P = 1/(α + D1)``.  For a
port velocity with alias components ``V_k`` the port force is

``F_k = Z0(s_k) V_k + c_k (wᵀV)/d``, ``c_k = a_k (1 − z⁻¹)/s_k``,
``w_k = (K_A a_k + K_L)/(T s_k)``, ``d = 1 + K_A g``,

with ``g = (1 − z⁻¹) Σ_k P(s_k)/(T s_k)`` the ZOH pulse transfer of ``P``.  The
supplied power ``Re VᴴF`` is a diagonal part ``Σ r_k |V_k|²`` (``r = Re Z0 > 0``)
plus a rank-two part.  Minimising the diagonal part for given values of the
two functionals ``cᴴV`` and ``wᵀV`` (a 2×2 Gram matrix ``Γ``) shows that the
port is passive iff the internal sampled loop is stable and, for all ``ω``,

``N(ω) = |d|² + Re(d̄ Γ21) − (Γ11 Γ22 − |Γ21|²)/4 ≥ 0``,
``Γ11 = Σ|c_k|²/r_k``, ``Γ21 = Σ w_k c_k/r_k``, ``Γ22 = Σ|w_k|²/r_k``.

For a rigid transmission (``c ∥ w̄``) this reduces exactly to Colgate–Schenkel's
``b ≥ (T/2) Re{(1 − e^{−jωT}) H(e^{jωT})}/(1 − cos ωT)``.  Every alias sum is
a rational function of ``z`` in closed form: partial fractions of the summand
``ψ(s) = Σ A_{p,j}/(s − p)^j`` and ``Σ_k 1/(s_k − p) = (T/2)(z + e^{pT})/(z − e^{pT})``
(and its ``p``-derivatives).  ``N·|L(z)|²`` (``L`` clears every pole) is then a
trigonometric polynomial, recovered exactly from ``M`` samples by a discrete
cosine transform in 50-digit arithmetic, written as a polynomial in
``x = cos ωT`` with rational coefficients (the 50-digit values, exactly), and
its sign on ``[−1, 1]`` decided by Sturm sequences ([`seapass.exact.poly`][seapass.exact.poly]).
No frequency grid decides anything: the samples only determine coefficients,
and a coefficient tail that does not vanish is an error, not a verdict.

Assumptions: linear plant, massless port, ``Re Z0(jω) > 0`` for every ``ω``
(strictly dissipative physics, e.g. ``b > 0``), ideal sampler and ZOH, no
quantization.  If ``Re Z0 → 0`` at high frequency (undamped transmission) and
the controller reads the load (``K_L ≠ 0``), ``Γ22`` diverges: the person can
inject aliased motion at almost no cost and the loop is never passive.

References
----------
.. [1] J. E. Colgate, G. G. Schenkel, "Passivity of a class of sampled-data
   systems: application to haptic interfaces", J. Robotic Systems 14(1), 1997.
.. [2] S. A. Mehta, D. P. Losey, "Combining Performance and Passivity in Linear
   Control of Series Elastic Actuators", Sections IV–VI.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import mpmath
import numpy as np

from ..analysis.passivity import is_passive
from ..errors import ModelError, NotPassiveError, ParameterError, SymbolicLimitError
from ..exact import fraction_poly as ep
from ..model.sea import SEA
from .alias import (
    COEFFICIENT_TAIL,
    DPS,
    PlantSums,
    plant_key,
    plant_sums,
    to_mp,
)
from .controllers import (
    DiscreteController,
    DiscreteTF,
    Method,
    clamped_spectral_radius,
    controller_tfs,
)

__all__ = [
    "SampledPassivityResult",
    "sampled_passivity",
    "sampled_power_curve",
]


@dataclass(frozen=True)
class SampledPassivityResult:
    """Verdict of `sampled_passivity`.

    Attributes
    ----------
    passive : bool
    reason : str
        ``""``, ``"unstable"`` (internal sampled loop), ``"alias_injection"``,
        ``"negative_power"`` or ``"continuous_not_passive"`` (the continuous design
        already fails; see `_continuous_gate`).
    detail : str
    omega : float or None
        Witness frequency (rad/s, in ``(0, π/T]``) where ``N(ω) < 0``.
    period, delay, velocity_filter, method
        The sampled loop analysed.
    marginal : bool
        ``N`` touches zero on ``(0, π/T]`` or the loop is at the edge of stability.
    spectral_radius : float
        Of the internal loop with the port held (floating point).
    degree : int
        Degree of the decided polynomial in ``cos ωT``.
    """

    passive: bool
    reason: str = ""
    detail: str = ""
    omega: float | None = None
    period: float = math.nan
    delay: int = 0
    velocity_filter: float | None = None
    method: str = "colgate-schenkel alias sums + Sturm on cos(wT)"
    marginal: bool = False
    spectral_radius: float = math.nan
    degree: int = 0

    def to_dict(self) -> dict[str, Any]:
        return {
            "passive": self.passive,
            "reason": self.reason,
            "detail": self.detail,
            "omega": self.omega,
            "period": self.period,
            "delay": self.delay,
            "velocity_filter": self.velocity_filter,
            "method": self.method,
            "marginal": self.marginal,
            "spectral_radius": self.spectral_radius,
            "degree": self.degree,
        }


# ------------------------------------------------------------------ alias sums


# ------------------------------------------------------------------ controllers


# ------------------------------------------------------------------ the test


def _cheb_to_mono(a: list[Fraction]) -> ep.Poly:
    """``Σ a_k T_k(x)`` in the monomial basis (exact)."""
    out = [Fraction(0)] * max(len(a), 1)
    t_prev: list[Fraction] = [Fraction(1)]
    t_cur: list[Fraction] = [Fraction(0), Fraction(1)]
    for k, c in enumerate(a):
        if k == 0:
            tk = t_prev
        elif k == 1:
            tk = t_cur
        else:
            nxt = [Fraction(0), *(2 * x for x in t_cur)]
            for i, x in enumerate(t_prev):
                nxt[i] -= x
            t_prev, t_cur = t_cur, nxt
            tk = t_cur
        for i, x in enumerate(tk):
            out[i] += c * x
    return ep.normalize(out)


def _to_fraction(x: Any) -> Fraction:
    sign, man, exp, _bc = mpmath.mpf(x)._mpf_
    if not man:
        return Fraction(0)
    return (-1) ** sign * Fraction(int(man)) * Fraction(2) ** int(exp)


def _trig_poly(fn: Any, weight_deg: int) -> list[Any]:
    """Cosine coefficients of the even trigonometric polynomial ``fn(θ)``."""
    M = 1 << max(6, (4 * weight_deg + 16).bit_length())
    while True:
        half = M // 2
        thetas = [2 * mpmath.pi * (n + mpmath.mpf(1) / 2) / M for n in range(half)]
        vals = [fn(t) for t in thetas]
        coef = []
        for k in range(half):
            s = mpmath.fsum(v * mpmath.cos(k * t) for v, t in zip(vals, thetas, strict=True))
            coef.append(s * (2 if k == 0 else 4) / M)
        scale = max(abs(c) for c in coef) or mpmath.mpf(1)
        top = max((k for k, c in enumerate(coef) if abs(c) > COEFFICIENT_TAIL * scale), default=0)
        if top < half // 2:
            return coef[: top + 1]
        if M >= 4096:
            raise SymbolicLimitError(
                "the sampled passivity polynomial did not close (coefficients do not decay); "
                "this model is outside the supported class"
            )
        M *= 2


def sampled_passivity(
    sea: SEA,
    *,
    period: float,
    delay: int = 0,
    velocity_filter: float | None = None,
    values: Mapping[str, float] | None = None,
    method: Method = "tustin",
    controller: DiscreteController | None = None,
    throw: bool = False,
) -> SampledPassivityResult:
    """Decide passivity of the load port of ``sea`` under sampled-data control.

    Parameters
    ----------
    sea : SEA
        Continuous plant (``m, b, D1, D2``) and controllers ``CA``, ``CL``; all
        parameters need values.
    period : float
        Control period ``T`` (s), e.g. ``0.002`` for 500 Hz.
    delay : int, default 0
        Whole samples of computational delay before the command is applied.
    velocity_filter : float, optional
        Cutoff (Hz) of the first-order low-pass on the finite-difference velocity.
    values : mapping, optional
        Parameter values overriding those in ``sea``.
    method : {"tustin", "zoh", "backward"}
        Discretization of strictly proper controller parts.
    controller : DiscreteController, optional
        Analyse this deployed controller (its exact transfer functions, delayed
        by ``delay``) instead of discretizing ``sea.CA``/``sea.CL``.
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] instead of returning.

    Returns
    -------
    SampledPassivityResult

    Examples
    --------
    >>> lp = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1, b=10, k1=1005, b1=30, kd=500))
    >>> sampled_passivity(lp, period=0.002).passive
    True
    """
    if values:
        sea = sea.with_values(**values)
    if sea.free_parameters and controller is None:
        raise ParameterError(
            "sampled passivity needs values for: " + ", ".join(sea.free_parameters)
        )
    T = Fraction(repr(float(period)))
    if T <= 0:
        raise ParameterError(f"period must be positive, got {period!r}")
    _check_ranges(sea, float(period))
    if controller is not None:
        ka, kl = (tf.delayed(int(delay)) for tf in controller.transfer_functions())
    else:
        ka, kl = controller_tfs(
            sea, period=period, delay=delay, velocity_filter=velocity_filter, method=method
        )
    base = {"period": float(period), "delay": int(delay), "velocity_filter": velocity_filter}
    result = _decide(sea, ka, kl, T, base)
    if result.passive and not sea.free_parameters:
        result = _continuous_gate(sea, result)
    if throw and not result.passive:
        raise NotPassiveError(f"not passive at T = {float(period):g} s: {result.detail}")
    return result


VALUE_RANGE = (1e-100, 1e100)
"""Magnitudes the 50-digit alias sums handle reliably; outside them seapass refuses."""
PERIOD_RANGE = (1e-7, 10.0)


def _check_ranges(sea: SEA, period: float) -> None:
    """Refuse values the sampled analysis cannot treat faithfully (denormals, 1e300...)."""
    lo, hi = PERIOD_RANGE
    if not lo <= period <= hi:
        raise ParameterError(
            f"period {period!r} s is outside the supported range [{lo:g}, {hi:g}] s"
        )
    lo, hi = VALUE_RANGE
    for name, v in sea.values.items():
        if v is not None and v != 0 and not lo <= abs(v) <= hi:
            raise ParameterError(
                f"{name} = {v!r} is outside the range the sampled-data analysis supports "
                f"(0 or |value| in [{lo:g}, {hi:g}]); rescale the units"
            )


def _continuous_gate(sea: SEA, result: SampledPassivityResult) -> SampledPassivityResult:
    """Never report a sampled loop passive when the continuous design is not.

    Conservative policy: the alias-sum decision has been seen to miss
    violations confined to very low ``ωT`` (a continuous violation that the
    coupled simulation in [`seapass.sampled.coupling`][seapass.sampled.coupling] confirms).  Requiring
    the exact continuous verdict as well can only turn "passive" into "not
    passive", never the reverse.
    """
    cont = is_passive(sea)
    if cont.passive:
        return result
    nyquist = math.pi / result.period
    omega = cont.omega if cont.omega is not None and cont.omega <= nyquist else None
    return dataclasses.replace(
        result,
        passive=False,
        reason="continuous_not_passive",
        detail=f"not passive in continuous time ({cont.detail}); treated as not passive when sampled",
        omega=omega,
    )


def _power_function(
    plant: PlantSums, ka: DiscreteTF, kl: DiscreteTF, T: Fraction, with_weight: bool = True
) -> tuple[Any, int]:
    """``θ ↦ N(θ)·|L(e^{jθ})|²`` (call inside ``mpmath.workdps(DPS)``) and the weight degree."""
    s: dict[str, Any] = plant.sums
    Tm = to_mp(T)
    inside = [(q, m) for q, m in plant.poles.items() if abs(q) < 1 - mpmath.mpf(10) ** -30]
    ctrl_poles = []
    for tf in (ka, kl):
        if not tf.is_zero:
            dz = [to_mp(c) for c in tf.den]
            while len(dz) > 1 and dz[-1] == 0:
                dz.pop()
            if len(dz) > 1:
                ctrl_poles += mpmath.polyroots(dz, maxsteps=200, extraprec=2 * DPS)
    weight_deg = 1 + sum(2 * m for _q, m in inside) + 2 * len(ctrl_poles)

    def N(theta: Any) -> Any:
        z = mpmath.expj(theta)
        zi = 1 / z
        KA = ka.evaluate(zi)
        KL = kl.evaluate(zi)
        one_m = 1 - zi
        S1 = s["S1"](z).real
        g = one_m / Tm * s["Sg"](z)
        d = 1 + KA * g
        g11 = abs(one_m) ** 2 * S1
        sum21 = KA * s["S2"](z)
        g22 = abs(KA) ** 2 * S1
        if not kl.is_zero:
            sum21 += KL * s["S5"](z)
            g22 += 2 * (KA * mpmath.conj(KL) * s["S3"](z)).real
            g22 += abs(KL) ** 2 * s["S4"](z).real
        g21 = one_m / Tm * sum21
        g22 = g22 / Tm**2
        val = abs(d) ** 2 + (mpmath.conj(d) * g21).real - (g11 * g22 - abs(g21) ** 2) / 4
        w = abs(z - 1) ** 2
        for q, m in inside:
            w *= abs(z - q) ** (4 * m)
        for q in ctrl_poles:
            w *= abs(z - q) ** 4
        return val * w if with_weight else val

    return N, weight_deg


def sampled_power_curve(
    sea: SEA,
    *,
    period: float,
    delay: int = 0,
    velocity_filter: float | None = None,
    method: Method = "tustin",
    n: int = 400,
) -> tuple[np.ndarray, np.ndarray]:
    """``(ω, N(ω))`` on ``n`` frequencies in ``(0, π/T]`` — for plots only, never for verdicts.

    ``N`` is the normalised power function of the module docstring (``N ≥ 0``
    everywhere iff passive, given a stable internal loop).
    """
    T = Fraction(repr(float(period)))
    ka, kl = controller_tfs(
        sea, period=period, delay=delay, velocity_filter=velocity_filter, method=method
    )
    plant = plant_sums(plant_key(sea), T)
    if not kl.is_zero and plant.sums["S4"] is None:
        raise ModelError("N(w) is unbounded for this design (aliased load-side feedback)")
    theta = np.linspace(math.pi / n, math.pi, n)
    with mpmath.workdps(DPS):
        fn, _ = _power_function(plant, ka, kl, T, with_weight=False)
        vals = np.array([float(fn(mpmath.mpf(float(t)))) for t in theta])
    return theta / float(T), vals


def _decide(
    sea: SEA, ka: DiscreteTF, kl: DiscreteTF, T: Fraction, base: dict[str, Any]
) -> SampledPassivityResult:
    plant = plant_sums(plant_key(sea), T)
    rho = clamped_spectral_radius(sea, ka, kl, float(T))
    base = {**base, "spectral_radius": rho}
    if ka.is_zero and kl.is_zero:
        return SampledPassivityResult(True, detail="no control: passive physics", **base)
    if rho >= 1.0:
        return SampledPassivityResult(
            False,
            "unstable",
            f"the sampled loop with the port held is unstable (spectral radius {rho:.6g}"
            + (
                "; a pole on the unit circle, e.g. integral action)" if abs(rho - 1) < 1e-9 else ")"
            ),
            omega=None,
            marginal=abs(rho - 1.0) < 1e-9,
            **base,
        )
    s = plant.sums
    if not kl.is_zero and s["S4"] is None:
        return SampledPassivityResult(
            False,
            "alias_injection",
            "the port has vanishing dissipation at high frequency (undamped transmission) and "
            "the controller samples the load position: aliased motion injects energy",
            omega=math.pi / float(T),
            **base,
        )
    with mpmath.workdps(DPS):
        N, weight_deg = _power_function(plant, ka, kl, T)
        coef = _trig_poly(N, weight_deg)
        scale = max(abs(c) for c in coef)
        fr = [_to_fraction(c / scale) for c in coef]
    p = _cheb_to_mono(fr)
    # the weight |z-1|^2 = 2(1 - x) vanishes at x = 1; remove it (remainder is rounding)
    tol = Fraction(1, 10 ** (DPS - 15))
    if abs(ep.evaluate(p, Fraction(1))) <= tol * sum(abs(c) for c in p):
        p = ep.pdivmod(p, (Fraction(1), Fraction(-1)))[0]
    return _sign_on_interval(p, T, base)


def _sign_on_interval(p: ep.Poly, T: Fraction, base: dict[str, Any]) -> SampledPassivityResult:
    deg = ep.degree(p)
    lo, hi = Fraction(-1), Fraction(1)
    odd = ep.positive_roots_odd_multiplicity(p)
    roots = ep.isolate_real_roots(p, lo - 1, hi) if deg > 0 else []
    sf = ep.squarefree_part(p) if deg > 0 else p
    inner: list[tuple[Fraction, Fraction]] = []
    for a, b in roots:
        a, b = ep.refine(sf, a, b, Fraction(1, 2**40))
        if b > lo and a < hi:
            inner.append((a, b))
    pts = [lo, hi]
    prev = lo
    for a, b in inner:
        if a > prev:
            pts.append((prev + a) / 2)
        prev = max(prev, b)
    if prev < hi:
        pts.append((prev + hi) / 2)
    neg = [x for x in pts if lo <= x <= hi and ep.evaluate(p, x) < 0]
    changes = ep.count_real_roots(odd, lo, hi) - (1 if ep.evaluate(odd, hi) == 0 else 0)
    if neg or changes > 0:
        if not neg:  # sign change at an isolated point: refine until negative found
            for a, b in inner:
                for x in (a, b):
                    if lo <= x <= hi and ep.evaluate(p, x) < 0:
                        neg.append(x)
        x = min(neg, key=lambda v: float(ep.evaluate(p, v))) if neg else Fraction(0)
        omega = math.acos(max(-1.0, min(1.0, float(x)))) / float(T)
        return SampledPassivityResult(
            False,
            "negative_power",
            f"the sampled loop can deliver net energy at w = {omega:.6g} rad/s "
            f"({omega / (2 * math.pi):.4g} Hz)",
            omega=omega,
            degree=deg,
            **base,
        )
    marginal = bool(inner) or base["spectral_radius"] > 1 - 1e-9
    return SampledPassivityResult(
        True, "", "passive at this sampling period", degree=deg, marginal=marginal, **base
    )


# ------------------------------------------------------------------ bounds
