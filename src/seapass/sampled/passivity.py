"""Passivity of the *sampled-data* SEA: continuous port, digital controller, certified.

The person (or environment) moves the continuous load port; the controller samples
``x_A(kT)`` and ``x_L(kT)``, computes ``u_k = −K_A(z) x_A − K_L(z) x_L`` (``K = z^-d C(z)``
discretized, see [`seapass.sampled.controllers`][seapass.sampled.controllers]) and holds it (ZOH) on the actuator.
Passivity of this linear *periodically time-varying* port is decided with the
Colgate–Schenkel alias argument [1]_, generalised to the SEA transmission.

Derivation (``s_k = j(ω + 2πk/T)``, ``z = e^{jωT}``)
------------------------------------------------------
Physical part: ``Z0 = [D1 α + D2 (α + D1)]/(s(α + D1))``, ``α = m s² + b s``,
``a = D1/(α + D1)``, ``P = 1/(α + D1)``.  For a port velocity with alias components
``V_k`` the port force is ``F_k = Z0(s_k) V_k + c_k (wᵀV)/d`` with
``c_k = a_k (1 − z⁻¹)/s_k``, ``w_k = (K_A a_k + K_L)/(T s_k)``, ``d = 1 + K_A g`` and
``g = (1 − z⁻¹) Σ_k P(s_k)/(T s_k)`` (ZOH pulse transfer of ``P``).  Minimising the
dissipative part ``Σ r_k |V_k|²`` (``r = Re Z0 > 0``) for given values of the two
functionals shows: the port is passive iff the loop with the port held is stable and

``N(ω) = |d|² + Re(d̄ Γ21) − (Γ11 Γ22 − |Γ21|²)/4 ≥ 0``  for all ``ω``,

``Γ11 = Σ|c_k|²/r_k``, ``Γ21 = Σ w_k c_k/r_k``, ``Γ22 = Σ|w_k|²/r_k``.  ``N`` is a
Hermitian form in ``(1, K_A, K_L)`` whose entries are alias sums of the plant alone
([`seapass.sampled.alias.hermitian_entries`][seapass.sampled.alias.hermitian_entries]).

Certified decision
------------------
* Alias sums in closed form with certified balls ([`seapass.sampled.alias`][seapass.sampled.alias]).
* ``P̃(x) = N·|d_A d_L|²·Π_{q≠1}|z − q|^{2m}`` is a polynomial in ``x = cos ωT``
  ([`seapass.sampled.power`][seapass.sampled.power]), interpolated exactly as balls from nodes that avoid
  ``ω = 0``; its sign on ``[−1, 1]`` is decided by Descartes' rule on Möbius-transformed
  intervals ([`seapass.sampled.certified.sign_on`][seapass.sampled.certified.sign_on]), ``ω → 0`` included (``x = 1``).
* Stability with the port held: Schur–Cohn on the ball characteristic polynomial.
* The working precision is raised (128 … 4096 bits) until the balls decide; at the cap the
  answer is ``undecided``, never a guess.

References
----------
.. [1] J. E. Colgate, G. G. Schenkel, "Passivity of a class of sampled-data systems:
   application to haptic interfaces", J. Robotic Systems 14(1), 1997.
.. [2] S. A. Mehta, D. P. Losey, "Combining Performance and Passivity in Linear Control
   of Series Elastic Actuators", Sections IV–VI.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ModelError, NotPassiveError, ParameterError
from ..model.display import html_card, short_repr
from ..model.loop import LoopAttributes, SampledLoop, loop_argument
from ..model.sea import SEA
from .controllers import DiscreteController, controller_parts, controller_tfs
from .lowfreq import LowFrequency, low_frequency_of
from .plant import plant_key, plant_of
from .power import power_values
from .verdict import (
    PRECISIONS,
    Outcome,
    SampledReason,
    alias_injection,
    cached_sums,
    decide,
    needed_sums,
    point_family,
    theta_of,
)

if TYPE_CHECKING:
    from ..analysis.passivity import PassivityResult

__all__ = [
    "METHOD",
    "PRECISION_RANGE",
    "SampledPassivityResult",
    "SampledReason",
    "SampledStatus",
    "check_precision",
    "check_values",
    "power_curve_csv",
    "sampled_passivity",
    "sampled_power_curve",
]

METHOD = "certified alias sums (arb balls) + Descartes on cos(wT) + Schur-Cohn"

#: Magnitudes accepted (bounds the precision the balls may need); the period's range is
#: [`seapass.model.loop.PERIOD_RANGE`][seapass.model.loop.PERIOD_RANGE].
VALUE_RANGE = (1e-100, 1e100)

#: Caps (bits) a caller may put on the working precision of the balls.
PRECISION_RANGE = (64, 65536)

SampledStatus = Outcome
"""The former name of [`Outcome`][seapass.outcome.Outcome] here (the same class)."""

_DETAILS = {
    SampledReason.NO_CONTROL: "no control: passive physics",
    SampledReason.UNSTABLE: "the sampled loop with the port held is unstable",
    SampledReason.ALIAS_INJECTION: (
        "the port has vanishing dissipation at high frequency (undamped transmission) and the "
        "controller samples the load position: aliased motion injects energy"
    ),
    SampledReason.UNDECIDED: (
        "undecided at the precision cap: the design is within the balls' resolution of the "
        "passivity boundary (treat as not passive)"
    ),
}


@dataclass(frozen=True, repr=False, kw_only=True)
class SampledPassivityResult(LoopAttributes):
    """Certified verdict of `sampled_passivity`.

    Attributes
    ----------
    outcome : Outcome
        ``PASSIVE``, ``NOT_PASSIVE`` or ``UNDECIDED`` (never reported as passive);
        ``status`` is the same value (its former name), ``passive`` is ``outcome.passive``.
    reason : SampledReason
        ``""``, ``"no_control"``, ``"unstable"``, ``"alias_injection"``,
        ``"negative_power"``, ``"low_frequency"`` (``N < 0`` as ``ω → 0``),
        ``"continuous_not_passive"`` (policy gate, see `sampled_passivity`) or
        ``"undecided"``.
    detail : str
    omega : float or None
        A frequency (rad/s, in ``(0, π/T]``) where ``N(ω) < 0`` is proven.
    loop : SampledLoop or None
        The sampled loop analysed (``period``, ``delay`` and ``velocity_filter`` are its).
    method : str
        How the verdict was decided.
    spectral_radius : float
        Of the loop with the port held (floating point, for information only).
    degree : int
        Degree of the decided polynomial in ``cos ωT``.
    precision : int
        Working precision (bits) at which the balls decided.
    low_frequency : LowFrequency or None
        The closed-form low-frequency resistance ``R_lf`` (``R_lf ≥ 0`` is necessary).
    """

    outcome: Outcome
    reason: SampledReason = SampledReason.NONE
    detail: str = ""
    omega: float | None = None
    loop: SampledLoop | None = None
    method: str = METHOD
    spectral_radius: float = math.nan
    degree: int = 0
    precision: int = 0
    low_frequency: LowFrequency | None = None

    @property
    def status(self) -> Outcome:
        """The former name of `outcome`."""
        return self.outcome

    @property
    def passive(self) -> bool:
        return self.outcome.passive

    @property
    def period(self) -> float:
        return math.nan if self.loop is None else self.loop.period

    @property
    def marginal(self) -> bool:
        """Always False: the certified verdict states no relative margin.

        An answer the balls could not decide is ``outcome is Outcome.UNDECIDED``, never
        marginal (the one meaning of [`seapass.outcome`][seapass.outcome]).
        """
        return False

    def to_dict(self) -> dict[str, Any]:
        return {
            "passive": self.passive,
            "status": self.outcome.value,
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
            "precision_bits": self.precision,
            "low_frequency": None if self.low_frequency is None else self.low_frequency.to_dict(),
        }

    def __repr__(self) -> str:
        return short_repr(
            "SampledPassivityResult",
            {
                "status": self.outcome.value,
                "reason": str(self.reason) or None,
                "omega": self.omega,
                "period": self.period,
                "delay": self.delay,
                "velocity_filter": self.velocity_filter,
            },
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [
            ("verdict", self.outcome.label),
            ("detail", self.detail),
            ("loop", "none" if self.loop is None else self.loop.summary),
        ]
        if self.omega is not None:
            rows.append(("witness", f"N(ω) < 0 at ω = {self.omega:.6g} rad/s (proven)"))
        lf = self.low_frequency
        if lf is not None and lf.resistance is not None:
            rows.append(("low-frequency resistance R_lf", f"{float(lf.resistance):.6g} N·s/m"))
        rows += [
            ("spectral radius (port held)", f"{self.spectral_radius:.6g}"),
            ("decided at", f"degree {self.degree} in cos ωT, {self.precision} bits"),
        ]
        title = f"Sampled passivity at T = {self.period * 1e3:g} ms: {rows[0][1]}"
        return html_card(title, rows, note=f"Method: {self.method}.")


def check_precision(max_precision: object) -> int:
    """``max_precision`` as a whole number of bits in `PRECISION_RANGE`."""
    lo, hi = PRECISION_RANGE
    if (
        isinstance(max_precision, bool)
        or not isinstance(max_precision, int)
        or not lo <= max_precision <= hi
    ):
        raise ParameterError(
            f"max_precision: must be in [{lo}, {hi}] bits, got {max_precision!r}",
            argument="max_precision",
        )
    return max_precision


def check_values(sea: SEA) -> None:
    """Refuse parameter magnitudes the certified analysis does not support."""
    lo, hi = VALUE_RANGE
    for name, v in sea.values.items():
        if v is not None and v != 0 and not lo <= abs(v) <= hi:
            raise ParameterError(
                f"{name} = {v!r} is outside the range the sampled-data analysis supports "
                f"(0 or |value| in [{lo:g}, {hi:g}]); rescale the units"
            )


def _omega(x: Fraction | None, period: float) -> float | None:
    if x is None:
        return None
    return max(theta_of(x), 1e-300) / period


def sampled_passivity(
    sea: SEA,
    *,
    loop: SampledLoop | None = None,
    values: Mapping[str, float] | None = None,
    controller: DiscreteController | None = None,
    continuous_gate: bool = True,
    max_precision: int = PRECISIONS[-1],
    throw: bool = False,
    box: Any = None,
    **old: Any,
) -> SampledPassivityResult:
    """Decide passivity of the load port of ``sea`` under sampled-data control (certified).

    Parameters
    ----------
    sea : SEA
        Continuous plant (``m, b, D1, D2``) and controllers ``CA``, ``CL``; all
        parameters need values.
    loop : SampledLoop
        The sampled loop: period ``T`` (``SampledLoop(period=0.002)`` is 500 Hz), whole
        samples of computational delay, velocity filter and discretization method.
    values : mapping, optional
        Parameter values overriding those in ``sea``.
    controller : DiscreteController, optional
        Analyse this deployed controller (its exact transfer functions, delayed by
        ``loop.delay``) instead of discretizing ``sea.CA``/``sea.CL``.
    continuous_gate : bool, default True
        Also require continuous-time passivity of ``sea`` (a documented *policy*: an extra
        necessary condition seapass imposes before deployment; the sampled verdict does
        not depend on it).
    max_precision : int, default 4096
        Cap (bits) of the working precision; beyond it the verdict is ``UNDECIDED``.
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] unless the verdict is passive.
    box : mapping, optional
        Refused: the verdict for every plant of a box is
        [`robust_sampled_check`][seapass.robust.sampled_verdict.robust_sampled_check].
    **old
        ``period=, delay=, velocity_filter=, method=``: the loop's old spelling, still
        accepted for one release with a
        [`SeapassDeprecationWarning`][seapass.errors.SeapassDeprecationWarning].

    Returns
    -------
    SampledPassivityResult

    Examples
    --------
    >>> lp = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1, b=10, k1=1005, b1=30, kd=500))
    >>> sampled_passivity(lp, loop=SampledLoop(period=0.002)).passive
    True
    >>> slow = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1, b=10, k1=1000, b1=1e6, kd=950))
    >>> r = sampled_passivity(slow, loop=SampledLoop(period=0.002))
    >>> print(r.outcome, r.reason)
    not_passive low_frequency
    """
    if box is not None:  # one plant here; every plant of a box is seapass.robust's job
        raise ParameterError(
            "sampled_passivity decides one plant; for every plant in a box use "
            "seapass.robust.robust_sampled_check(sea, loop=..., box=...)",
            argument="box",
        )
    loop = loop_argument(loop, old, where="sampled_passivity")
    max_precision = check_precision(max_precision)
    if values:
        sea = sea.with_values(**values)
    if sea.free_parameters and controller is None:
        raise ParameterError(
            "sampled passivity needs values for: " + ", ".join(sea.free_parameters)
        )
    check_values(sea)
    if controller is None:
        controller = DiscreteController.for_loop(sea, loop)
    ka, kl, hidden = controller_parts(controller, loop.delay)
    key = plant_key(sea)
    plant_of(sea)  # validates the physical plant (ModelError outside the supported class)
    d = decide(key, ka, kl, loop.exact_period, max_precision=max_precision, hidden=hidden)
    lf = low_frequency_of(
        sea,
        ka,
        kl,
        delay=loop.delay,
        method=loop.method,
        explain=d.reason is SampledReason.LOW_FREQUENCY,
    )
    base: dict[str, Any] = {
        "loop": loop,
        "spectral_radius": d.spectral_radius,
        "degree": d.degree,
        "precision": d.precision,
        "low_frequency": lf,
    }
    omega = _omega(d.witness, loop.period)
    gate = None
    if d.outcome is Outcome.PASSIVE and continuous_gate and not sea.free_parameters:
        # a controller in z has no continuous counterpart: the gate does not apply
        gate = _continuous_gate(sea) if sea.discrete is None else None
    if gate is not None:
        nyquist = math.pi / loop.period
        result = SampledPassivityResult(
            outcome=Outcome.NOT_PASSIVE,
            reason=SampledReason.CONTINUOUS_NOT_PASSIVE,
            detail=f"not passive in continuous time ({gate.detail}); seapass does not deploy "
            "it sampled either",
            omega=gate.omega if gate.omega is not None and gate.omega <= nyquist else None,
            **base,
        )
    elif d.outcome is Outcome.PASSIVE:
        result = SampledPassivityResult(
            outcome=Outcome.PASSIVE,
            reason=d.reason,
            detail=_DETAILS.get(d.reason, "passive at this sampling period"),
            **base,
        )
    elif d.outcome is Outcome.UNDECIDED:
        result = SampledPassivityResult(
            outcome=Outcome.UNDECIDED,
            reason=SampledReason.UNDECIDED,
            detail=_DETAILS[SampledReason.UNDECIDED],
            **base,
        )
    else:
        detail = _DETAILS.get(d.reason, "")
        proven = (SampledReason.NEGATIVE_POWER, SampledReason.LOW_FREQUENCY)
        if d.reason in proven and omega is not None:
            detail = (
                f"the sampled loop can deliver net energy at w = {omega:.6g} rad/s "
                f"({omega / (2 * math.pi):.4g} Hz)"
            )
            if d.reason is SampledReason.LOW_FREQUENCY:
                detail += "; N(0) < 0, so slow enough motions extract energy"
                detail += f" ({lf.explanation})" if lf is not None and lf.explanation else ""
        elif d.reason is SampledReason.UNSTABLE:
            detail += f" (spectral radius about {d.spectral_radius:.6g})"
        result = SampledPassivityResult(
            outcome=Outcome.NOT_PASSIVE, reason=d.reason, detail=detail, omega=omega, **base
        )
    if throw and not result.passive:
        raise NotPassiveError(f"not passive at T = {loop.period:g} s: {result.detail}")
    return result


def _continuous_gate(sea: SEA) -> PassivityResult | None:
    """Deployment policy: a design that is not passive in continuous time is not deployed.

    Not part of the sampled-data verdict (which stands on its own): an extra necessary
    condition seapass imposes, so a "passive" answer always means passive both ways.
    Returns the failing continuous verdict, or None when the design passes the gate.
    """
    from ..analysis.passivity import is_passive
    from .plant import continuous_impedance

    num, den = continuous_impedance(sea)
    cont = is_passive(
        tuple([Fraction(int(c.p), int(c.q)) for c in reversed(p.coeffs())] for p in (num, den))
    )
    return None if cont.passive else cont


def sampled_power_curve(
    sea: SEA, *, loop: SampledLoop, n: int = 400
) -> tuple[np.ndarray, np.ndarray]:
    """``(ω, N(ω))`` on ``n`` frequencies in ``(0, π/T]`` — for figures, never for verdicts."""
    if not 2 <= int(n) <= 100_000:
        raise ParameterError(f"n must be in [2, 100000], got {n!r}")
    check_values(sea)
    T = loop.exact_period
    ka, kl = controller_tfs(sea, loop)
    key = plant_key(sea)
    plant_of(sea)
    if not kl.is_zero and alias_injection(key):
        raise ModelError("N(w) is unbounded for this design (aliased load-side feedback)")
    names = tuple(dict.fromkeys((*needed_sums(ka.is_zero, kl.is_zero), "S1")))
    sums = cached_sums(key, T, names, 128)
    theta = np.linspace(math.pi / n, math.pi, int(n))
    vals = power_values(sums, point_family(ka, kl), [float(t) for t in theta])
    return theta / loop.period, np.array([float(v.mid()) for v in vals])


def power_curve_csv(omega: np.ndarray, power: np.ndarray) -> str:
    """The curve of `sampled_power_curve` as CSV: ``omega_rad_s,N``, numbers written exactly."""
    rows = "".join(f"{w!r},{n!r}\n" for w, n in zip(omega.tolist(), power.tolist(), strict=True))
    return "omega_rad_s,N\n" + rows
