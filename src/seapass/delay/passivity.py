"""Passivity of a delayed design at a given delay, certified.

A delayed impedance ``Z(s) = N(s, e^{-sτ})/D(s, e^{-sτ})`` is positive real (passive) when

1. the loop with the port held is stable: ``D`` has no root in ``Re s ≥ 0`` except a pole
   at ``s = 0`` that is a polynomial factor of ``D`` ([`stability`][seapass.delay.stability]);
2. that pole is simple with a positive residue (exact Taylor series at ``s = 0``);
3. ``Z`` grows at most like ``c s`` with ``c > 0`` in the right half-plane (exact, from the
   leading coefficients);
4. ``Re Z(jω) ≥ 0`` for every ``ω > 0`` ([`sign`][seapass.delay.sign]).

1-3 make ``Z`` analytic in ``Re s > 0`` with at most linear growth, so by the
Phragmén–Lindelöf principle 4 gives ``Re Z ≥ 0`` in the whole half-plane.  Conditions that
fail exactly give ``not_passive``; what the balls cannot decide is ``undecided`` and is
never reported as passive.  At ``τ = 0`` the exact rational test of
[`seapass.analysis.passivity`][seapass.analysis.passivity] decides.

References
----------
.. [1] B. D. O. Anderson and S. Vongpanitlerd, *Network Analysis and Synthesis*,
   Prentice-Hall, 1973, sec. 5.1 (positive real functions).
.. [2] J. E. Colgate and G. Schenkel, "Passivity of a class of sampled-data systems:
   application to haptic interfaces", J. Robotic Systems 14(1), 1997.
.. [3] P. Koosis, *Introduction to H_p Spaces*, 2nd ed., Cambridge, 1998, ch. III
   (Phragmén–Lindelöf in a half-plane).

Examples
--------
>>> from seapass.model.sea import SEA
>>> sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
...           values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25, tau=0.001))
>>> r = delayed_passivity(sea)
>>> r.outcome, r.passive
(<Outcome.PASSIVE: 'passive'>, True)
>>> delayed_passivity(sea, values=dict(tau=0.05))
DelayPassivityResult(outcome='not_passive', reason='negative_real_part', witness_frequency=..., tau=0.05)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

from flint import fmpq, fmpq_poly

from ..analysis.passivity import PassivityResult, positive_real_test
from ..analysis.passivity import is_passive as rational_is_passive
from ..errors import NotPassiveError
from ..exact.axis import safe_float
from ..model.display import html_card, short_repr
from ..outcome import Outcome
from .balls import PRECISIONS
from .sign import DEFAULT_BUDGET, certify
from .stability import Characteristic, LoopKind, characteristic, stability_at
from .structure import DelayedImpedance, SystemLike, delayed_impedance, has_model_delay
from .trig import real_part

__all__ = [
    "TOLERANCE_POLICY",
    "DelayPassivityResult",
    "DelayReason",
    "LoopStability",
    "decide",
    "delayed_passivity",
    "growth_at_infinity",
    "is_passive",
]

TOLERANCE_POLICY = (
    "certified: the structure N(s,E)/D(s,E) is exact (every float is the rational it "
    "represents, a delay the decimal it was written as); Re Z(jw) at the delay is decided "
    "with exact asymptotics at w -> 0 and w -> infinity and arb balls in between; stability "
    "from exact axis crossings; an answer the balls cannot give within the budget is "
    "'undecided', never passive; no Pade approximation is used"
)


class LoopStability(StrEnum):
    """The loop with the port held, at the delay."""

    STABLE = "stable"
    UNSTABLE = "unstable"
    UNDECIDED = "undecided"


class DelayReason(StrEnum):
    """Why a delayed impedance is not passive (or why it is undecided); ``""`` when passive."""

    NONE = ""
    RELATIVE_DEGREE = "relative_degree"
    RHP_POLE = "rhp_pole"
    REPEATED_AXIS_POLE = "repeated_axis_pole"
    AXIS_RESIDUE = "axis_residue"
    INFINITY_RESIDUE = "infinity_residue"
    NEGATIVE_REAL_PART = "negative_real_part"
    HIDDEN_UNSTABLE_MODE = "hidden_unstable_mode"
    UNDECIDED = "undecided"


@dataclass(frozen=True, kw_only=True, repr=False)
class DelayPassivityResult:
    """Certified passivity of a delayed design at one delay.

    Attributes
    ----------
    outcome : Outcome
        ``passive`` (proven), ``not_passive`` (proven) or ``undecided``.
    reason : DelayReason
        Why not passive (or ``"undecided"``); ``""`` when passive.
    detail : str
        One sentence for people.
    omega : float or None
        Witness frequency [rad/s] with ``Re Z(jω) < 0`` proven, when there is one.
    delay : str
        The delay parameter.
    tau : float
        The delay [s].
    stability : LoopStability
        ``"stable"``, ``"unstable"`` or ``"undecided"`` (the loop with the port held).
    characteristic : LoopKind or None
        ``"rational"``, ``"retarded"``, ``"neutral"``, ``"advanced"`` or ``"unsupported"``.
    evaluations : int
        Ball evaluations spent on ``Re Z(jω)`` (the counted budget).
    precision : int
        Highest working precision used [bits].
    """

    outcome: Outcome
    reason: DelayReason = DelayReason.NONE
    detail: str = ""
    omega: float | None = None
    delay: str = ""
    tau: float = 0.0
    stability: LoopStability = LoopStability.STABLE
    characteristic: LoopKind | None = None
    evaluations: int = 0
    precision: int = 0
    tolerance: str = TOLERANCE_POLICY
    impedance: DelayedImpedance | None = field(default=None, compare=False)

    @property
    def passive(self) -> bool:
        """Only a certified ``passive`` counts."""
        return self.outcome.passive

    @property
    def status(self) -> str:
        """``"passive"``, ``"not passive"`` or ``"undecided"``."""
        return self.outcome.label

    @property
    def witness_frequency(self) -> float | None:
        """The witness frequency [rad/s] (same as ``omega``)."""
        return self.omega

    def to_dict(self) -> dict[str, Any]:
        return {
            "passive": self.passive,
            "outcome": str(self.outcome),
            "status": self.status,
            "reason": str(self.reason),
            "detail": self.detail,
            "witness_frequency": self.omega,
            "omega": self.omega,
            "delay": {"name": self.delay, "tau": self.tau},
            "stability": str(self.stability),
            "characteristic": None if self.characteristic is None else str(self.characteristic),
            "evaluations": self.evaluations,
            "precision": self.precision,
            "tolerance": self.tolerance,
        }

    def response(self, omega: Any = None, *, label: str = "") -> Any:
        """``Z(jω)`` at the delay (floats, for pictures) and the certified failing bands."""
        from .response import delayed_response

        if self.impedance is None:
            raise ValueError("this result holds no impedance (built by hand)")
        return delayed_response(self.impedance, omega, label=label)

    def plot(self, kind: str = "real", *, ax: Any = None, omega: Any = None, **kwargs: Any) -> Any:
        """``Re Z(jω)`` at the delay with the failing bands shaded; returns the Axes."""
        from ..plot.delay import plot_delay_response

        return plot_delay_response(self.response(omega), kind=kind, ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "DelayPassivityResult",
            {
                "outcome": str(self.outcome),
                "reason": str(self.reason) or None,
                "witness_frequency": self.omega,
                "tau": self.tau,
            },
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [
            ("verdict", self.status),
            ("detail", self.detail),
            ("delay", f"{self.delay} = {self.tau:g} s"),
            ("loop with the port held", self.stability),
        ]
        if self.omega is not None:
            rows.append(("witness", f"Re Z(jω) < 0 at ω = {self.omega:.6g} rad/s"))
        return html_card(
            f"Passivity with delay: {self.status}", rows,
            note="Certified (exact structure, arb balls); undecided is never passive.",
        )  # fmt: skip


def _taylor_at_zero(parts: tuple[fmpq_poly, ...], tau: fmpq, order: int) -> list[fmpq]:
    """Taylor coefficients of ``Σ_k N_k(s) e^{-ksτ}`` at ``s = 0`` up to ``s^order``."""
    out = [fmpq(0)] * (order + 1)
    for k, p in enumerate(parts):
        c = p.coeffs()
        for j in range(order + 1):
            acc = fmpq(0)
            fact = fmpq(1)
            for i in range(j, -1, -1):  # e^{-ksτ} term of s^(j-i)
                if i < len(c) and c[i] != 0:
                    acc += c[i] * fact
                fact = fact * fmpq(-k) * tau / (j - i + 1)
            out[j] += acc
    return out


def _at_zero(z: DelayedImpedance, ch: Characteristic, tau: fmpq) -> DelayPassivityResult | None:
    """The pole at ``s = 0`` (exact); None when it is admissible."""
    k = ch.s_power
    if k == 0:
        return None
    coeffs = _taylor_at_zero(z.num, tau, k)
    order = next((j for j, c in enumerate(coeffs) if c != 0), k + 1)
    if min(k, order) >= 2:
        return _fail(DelayReason.HIDDEN_UNSTABLE_MODE, "a cancelled repeated mode at s = 0")
    if k - order >= 2:
        return _fail(DelayReason.REPEATED_AXIS_POLE, f"a pole of order {k - order} at s = 0")
    if k - order == 1:
        rest = ch.common * (ch.p + ch.q)
        if coeffs[order] / rest(fmpq(0)) <= 0:
            return _fail(
                DelayReason.AXIS_RESIDUE,
                "the pole at s = 0 has a residue that is not positive",
            )
    return None


def _top(parts: tuple[fmpq_poly, ...], deg: int) -> list[fmpq]:
    return [p[deg] if p.degree() >= deg else fmpq(0) for p in parts]


def growth_at_infinity(z: DelayedImpedance) -> tuple[DelayPassivityResult | None, bool]:
    """Growth at infinity: ``(exact failure or None, whether the axis test must confirm)``."""
    dn = max((p.degree() for p in z.num if not p.is_zero()), default=-1)
    dd = max(p.degree() for p in z.den if not p.is_zero())
    if dn < 0 or dn - dd <= 0:
        return None, False
    if dn - dd >= 2:
        n0, d0 = z.num[0], z.den[0]
        if not n0.is_zero() and n0.degree() - d0.degree() >= 2:
            return _fail(DelayReason.RELATIVE_DEGREE, f"Z grows like s^{dn - dd}"), False
        return None, True
    n, d = _top(z.num, dn), _top(z.den, dd)
    n += [fmpq(0)] * (len(d) - len(n))
    d += [fmpq(0)] * (len(n) - len(d))
    ratio = n[0] / d[0] if d[0] != 0 else None
    if ratio is not None and all(a == ratio * b for a, b in zip(n, d, strict=True)):
        if ratio <= 0:
            return _fail(
                DelayReason.INFINITY_RESIDUE, "Z ~ c*s at high frequency with c <= 0"
            ), False
        return None, False
    return None, True


def _fail(reason: DelayReason, detail: str, **kw: Any) -> DelayPassivityResult:
    return DelayPassivityResult(outcome=Outcome.NOT_PASSIVE, reason=reason, detail=detail, **kw)


def _float(q: fmpq | None) -> float | None:
    return None if q is None else safe_float(q)


def decide(
    z: DelayedImpedance,
    *,
    budget: int = DEFAULT_BUDGET,
    max_precision: int = PRECISIONS[-1],
) -> DelayPassivityResult:
    """Decide the passivity of an exact delayed impedance at its delay ``z.tau``."""
    if z.tau is None:
        raise ValueError("the delay has no value")
    tau = z.tau
    base: dict[str, Any] = {"delay": z.name, "tau": safe_float(tau), "impedance": z}
    ch = characteristic(z.den)
    base["characteristic"] = ch.kind
    if tau == 0:
        res = positive_real_test(*z.at(fmpq(1)))
        return DelayPassivityResult(
            outcome=Outcome.from_bool(res.passive), reason=DelayReason(str(res.reason)),
            detail=res.detail, omega=res.omega, **base,
        )  # fmt: skip
    st = stability_at(ch, tau)
    base["stability"] = {
        True: LoopStability.STABLE,
        False: LoopStability.UNSTABLE,
        None: LoopStability.UNDECIDED,
    }[st.stable]
    if st.stable is False:
        return _fail(DelayReason.RHP_POLE, f"the loop is unstable: {st.detail}", **base)
    zero = _at_zero(z, ch, tau) if st.stable else None
    if zero is not None:
        return _fail(zero.reason, zero.detail, **base)
    inf, confirm = growth_at_infinity(z)
    if inf is not None:
        return _fail(inf.reason, inf.detail, **base)
    cert = certify(real_part(z), tau, budget=budget, max_precision=max_precision)
    base["evaluations"], base["precision"] = cert.evaluations, cert.precision
    if cert.outcome is Outcome.NOT_PASSIVE:
        w = _float(cert.witness)
        return _fail(
            DelayReason.NEGATIVE_REAL_PART, f"Re Z(jw) < 0 at w = {w:.6g} rad/s (proven)",
            omega=w, **base,
        )  # fmt: skip
    if cert.outcome is Outcome.UNDECIDED:
        why = {
            "budget": f"the sign of Re Z(jw) was not settled within {budget} ball evaluations",
            "precision": f"Re Z(jw) is too close to 0 to decide at {max_precision} bits",
            "high_frequency_tangency": "Re Z(jw) touches 0 as w -> infinity (a tangency the "
            "leading term does not decide)",
            "low_frequency_degenerate": "no nonzero Taylor coefficient of Re Z at w = 0",
            "unbounded_band": "no witness found in the unbounded band",
        }.get(cert.reason, cert.reason)
        return DelayPassivityResult(outcome=Outcome.UNDECIDED, reason=DelayReason.UNDECIDED, detail=why, **base)  # fmt: skip
    if st.stable is None:
        return DelayPassivityResult(
            outcome=Outcome.UNDECIDED, reason=DelayReason.UNDECIDED,
            detail=f"Re Z(jw) >= 0 is proven but stability is undecided: {st.detail}", **base,
        )  # fmt: skip
    if confirm:
        return DelayPassivityResult(
            outcome=Outcome.UNDECIDED, reason=DelayReason.UNDECIDED,
            detail="Z grows faster than s on some path (the leading terms are not a "
            "positive multiple of s); no negative value of Re Z(jw) was found", **base,
        )  # fmt: skip
    detail = "positive real (certified)" if not cert.lossless else "lossless"
    return DelayPassivityResult(outcome=Outcome.PASSIVE, detail=detail, **base)


def delayed_passivity(
    system: SystemLike,
    *,
    values: Mapping[str, float] | None = None,
    budget: int = DEFAULT_BUDGET,
    max_precision: int = PRECISIONS[-1],
    throw: bool = False,
) -> DelayPassivityResult:
    """Certified passivity of a design with a delay factor ``exp(-NAME*s)`` at its delay.

    Parameters
    ----------
    system : SEA, Impedance, str or sympy.Expr
        A design whose elements contain one delay ``exp(-NAME*s)`` (its load impedance
        ``Z_L`` is tested) or a raw impedance.
    values : mapping, optional
        Parameter values overriding the stored ones (the delay in seconds, e.g.
        ``{"tau": 0.002}``).
    budget : int, default `DEFAULT_BUDGET`
        Ball evaluations of ``Re Z(jω)`` before the answer is undecided.
    max_precision : int, default 1024
        Highest working precision of the balls [bits].
    throw : bool, default False
        Raise `NotPassiveError` unless the outcome is ``passive`` (undecided included).

    Returns
    -------
    DelayPassivityResult
    """
    if not (isinstance(budget, int) and budget > 0):
        from ..errors import ParameterError

        raise ParameterError(f"budget must be a positive whole number, got {budget!r}")
    result = decide(delayed_impedance(system, values), budget=budget, max_precision=max_precision)
    if throw and not result.passive:
        raise NotPassiveError(f"not certified passive ({result.status}): {result.detail}")
    return result


def is_passive(
    system: Any,
    *,
    values: Mapping[str, float] | None = None,
    throw: bool = False,
) -> PassivityResult | DelayPassivityResult:
    """Passivity of any design: exact when rational, certified when it has a delay.

    The front door ``seapass.is_passive``.  A design without a delay goes to the exact
    rational test [`seapass.analysis.passivity.is_passive`][seapass.analysis.passivity.is_passive]
    (a `PassivityResult`); one with a delay factor ``exp(-NAME*s)`` to `delayed_passivity`
    (a `DelayPassivityResult` with the same ``passive``, ``reason``, ``detail``, ``omega``,
    ``status``, ``to_dict`` and ``plot``, plus ``outcome``).

    Examples
    --------
    >>> is_passive("(s + 1)/(s + 2)").passive
    True
    >>> is_passive("m*s + b + K*exp(-tau*s)/s", values=dict(m=1, b=2, K=50, tau=0.05)).status
    'not passive'
    """
    if isinstance(system, tuple) or not has_model_delay(system):
        return rational_is_passive(system, values=values, throw=throw)
    return delayed_passivity(system, values=values, throw=throw)
