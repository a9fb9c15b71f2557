"""Standard passivity indices of a port impedance: input feedforward ν and output feedback ρ.

The definitions are those of MATLAB's ``getPassiveIndex`` (and of
python-control's ``get_input_ff_index``/``get_output_fb_index``), for the port
with velocity in and force out, ``F = Z V``:

* **ν, the input feedforward passivity index**, is the largest ``ν`` with
  ``∫ F V dt ≥ ν ∫ V² dt`` for every motion from rest.  ``Z`` is input strictly
  passive when ``ν > 0``; a design with ``ν < 0`` becomes passive with ``|ν|``
  of extra damping in parallel.  For the SEA port ``ν`` is a damping (N·s/m).
* **ρ, the output feedback passivity index**, is the largest ``ρ`` with
  ``∫ F V dt ≥ ρ ∫ F² dt``: the input index of the admittance ``1/Z``, in m/(N·s).

For a rational ``G`` (``Z`` for ν, ``1/Z`` for ρ) the largest index is the
largest ``c`` for which ``G − c`` is positive real.  Subtracting a constant
changes neither the poles nor their residues, so

* if ``G`` has a pole that a positive-real function may not have (in the open
  right half-plane, repeated or with a residue that is not real and positive on
  the imaginary axis, a hidden unstable mode, or a pole at infinity of order
  above one or with a negative coefficient), no ``c`` works: the index is ``−∞``;
* otherwise the index is ``inf_ω Re G(jω)``, over every ``ω ≥ 0`` and the limit
  ``ω → ∞``.  With ``x = ω²``, ``Re G(jω) = P(x)/M(x)`` with
  ``P = Re a(jω) b(−jω)`` and ``M = |b(jω)|²`` for ``G = a/b``: the infimum of a
  rational function on the half-line, an algebraic number that
  [`minimum_on_half_line`][seapass.exact.halfline.minimum_on_half_line] locates
  exactly (``x = 0``, a root of ``P' M − P M'``, or ``x → ∞``), signs exactly and
  brackets by a certified rational enclosure.

The frequency-domain shortcut MATLAB uses for ρ is documented to fail (``−∞``)
when ``Z`` has a zero on the imaginary axis or at infinity; the exact test here
has no such restriction (``s/(s² + 0.2 s + 1)`` has ``ρ = 0.2``).

References
----------
.. [1] H. K. Khalil, *Nonlinear Systems*, 3rd ed., Prentice Hall, 2002, Def. 6.3
   (input feedforward and output feedback passivity).
.. [2] MathWorks, ``getPassiveIndex`` and "About Passivity and Passivity Indices",
   Control System Toolbox documentation.
.. [3] B. D. O. Anderson and S. Vongpanitlerd, *Network Analysis and Synthesis*,
   Prentice-Hall, 1973, sec. 5.1 (positive real functions).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from flint import fmpq

from ..exact import poly as ep
from ..exact.axis import real_part_polynomial, sqrt_float, squared_magnitude_polynomial
from ..exact.halfline import minimum_on_half_line
from ..model.display import html_card, short_repr
from ..outcome import Outcome
from .impedance import SystemLike, evaluate_system
from .passivity import Reason, positive_real_test

__all__ = ["PassivityIndex", "PassivityIndices", "index_of", "passivity_indices"]

_POLE_REASONS = frozenset(
    {
        Reason.RELATIVE_DEGREE,
        Reason.RHP_POLE,
        Reason.REPEATED_AXIS_POLE,
        Reason.AXIS_RESIDUE,
        Reason.INFINITY_RESIDUE,
        Reason.HIDDEN_UNSTABLE_MODE,
    }
)


@dataclass(frozen=True, repr=False, kw_only=True)
class PassivityIndex:
    """One passivity index (see the module docstring).

    Attributes
    ----------
    value : float
        The index; ``-inf`` when no constant makes the system passive, ``inf``
        for ``ρ`` of ``Z ≡ 0``.
    lower, upper : flint.fmpq or None
        A certified enclosure ``lower <= index <= upper`` (equal when exact).
    sign : int
        The exact sign of the index: ``> 0`` strictly passive in this sense,
        ``0`` passive without excess, ``< 0`` not passive.
    omega : float or None
        Where ``Re G(jω)`` attains the index [rad/s] (None: approached as
        ``ω → ∞``, or the index is infinite).
    reason : Reason
        Why the index is ``-inf`` (`Reason.NONE` otherwise).
    """

    value: float
    lower: fmpq | None
    upper: fmpq | None
    sign: int
    omega: float | None
    reason: Reason = Reason.NONE

    @property
    def strict(self) -> bool:
        """Strictly passive in this sense (``index > 0``), decided exactly."""
        return self.sign > 0

    @property
    def outcome(self) -> Outcome:
        """``PASSIVE`` when the index is ``>= 0`` (``G`` is positive real), decided exactly."""
        return Outcome.from_bool(self.sign >= 0)

    def to_dict(self) -> dict[str, Any]:
        return {
            "value": self.value,
            "lower": None if self.lower is None else _down(self.lower),
            "upper": None if self.upper is None else _up(self.upper),
            "sign": self.sign,
            "strict": self.strict,
            "omega": self.omega,
            "at_infinity": self.omega is None and math.isfinite(self.value),
            "reason": self.reason,
        }

    def describe(self) -> str:
        """The value, its certified enclosure (when not exact) and where it is attained."""
        text = f"{self.value:.6g}"
        if self.lower is not None and self.upper is not None:
            lo, hi = f"{_down(self.lower):.10g}", f"{_up(self.upper):.10g}"
            text += f" in [{lo}, {hi}]" if lo != hi else ""
        if self.reason:
            return f"{text} ({Reason(self.reason).description})"
        if math.isfinite(self.value):
            text += " as ω → ∞" if self.omega is None else f" at ω = {self.omega:.6g} rad/s"
        word = (
            "strictly passive" if self.sign > 0 else "passive" if self.sign == 0 else "not passive"
        )
        return f"{text}: {word}"

    def __repr__(self) -> str:
        return short_repr(
            "PassivityIndex",
            {
                "value": self.value,
                "sign": self.sign,
                "omega": self.omega,
                "reason": str(self.reason) or None,
            },
        )

    def _repr_html_(self) -> str:
        return html_card("Passivity index", [("index", self.describe())])


@dataclass(frozen=True, repr=False, kw_only=True)
class PassivityIndices:
    """ν and ρ of a port impedance (`passivity_indices`).

    Attributes
    ----------
    input : PassivityIndex
        ν, the input feedforward index of ``Z`` [N·s/m for an SEA port].
    output : PassivityIndex
        ρ, the output feedback index (the input index of ``1/Z``) [m/(N·s)].
    """

    input: PassivityIndex
    output: PassivityIndex

    @property
    def outcome(self) -> Outcome:
        """The exact passivity of ``Z``: ``ν >= 0`` (equivalently ``ρ >= 0``)."""
        return self.input.outcome

    @property
    def nu(self) -> float:
        return self.input.value

    @property
    def rho(self) -> float:
        return self.output.value

    def to_dict(self) -> dict[str, Any]:
        return {
            "nu": self.nu,
            "rho": self.rho,
            "input": self.input.to_dict(),
            "output": self.output.to_dict(),
            "definition": (
                "MATLAB getPassiveIndex: nu = largest nu with int F V >= nu int V^2 "
                "(input feedforward), rho = largest rho with int F V >= rho int F^2 "
                "(output feedback), for the port F = Z V; decided exactly, values "
                "enclosed by certified bounds [lower, upper]"
            ),
        }

    def __repr__(self) -> str:
        reasons = {"nu_reason": self.input.reason, "rho_reason": self.output.reason}
        return short_repr(
            "PassivityIndices",
            {"nu": self.nu, "rho": self.rho, **{k: str(r) or None for k, r in reasons.items()}},
        )

    def _repr_html_(self) -> str:
        rows = [
            ("ν, input feedforward [N·s/m]", self.input.describe()),
            ("ρ, output feedback [m/(N·s)]", self.output.describe()),
        ]
        return html_card(
            f"Passivity indices: ν = {self.nu:.6g}, ρ = {self.rho:.6g}",
            rows,
            note="Decided exactly; values enclosed by certified rational bounds.",
        )


def _down(q: fmpq) -> float:
    """The largest float ``<= q`` (outward rounding of an enclosure)."""
    f = _finite_float(q)
    return math.nextafter(f, -math.inf) if math.isfinite(f) and ep.rational(f) > q else f


def _up(q: fmpq) -> float:
    f = _finite_float(q)
    return math.nextafter(f, math.inf) if math.isfinite(f) and ep.rational(f) < q else f


def _finite_float(q: fmpq) -> float:
    try:
        return float(q)
    except OverflowError:
        return math.inf if q > 0 else -math.inf


def index_of(a: ep.PolyLike, b: ep.PolyLike) -> PassivityIndex:
    """The input feedforward index of ``G = a/b`` (exact, ascending coefficients).

    ``sup {c : G − c positive real}``; see the module docstring.
    """
    a, b = ep.as_poly(a), ep.as_poly(b)
    if b.is_zero():
        raise ZeroDivisionError("the denominator is identically zero")
    if a.is_zero():
        zero = fmpq(0)
        return PassivityIndex(value=0.0, lower=zero, upper=zero, sign=0, omega=0.0)
    # the poles of G - c are those of G: test them on G + K, which has relative degree
    # <= 0 (K chosen so that no leading coefficient cancels)
    k = fmpq(1)
    if a.degree() == b.degree():
        k += abs(a.leading_coefficient() / b.leading_coefficient())
    shifted = positive_real_test(a + k * b, b)
    if shifted.reason in _POLE_REASONS:
        return _minus_infinity(shifted.reason)
    p = real_part_polynomial(a, b)
    m = squared_magnitude_polynomial(b)
    low = minimum_on_half_line(p, m)
    if low.lower is None:  # pragma: no cover - admissible poles keep Re G bounded
        return _minus_infinity(Reason.AXIS_RESIDUE)
    omega = None if low.at is None else _sqrt(low.at)
    return PassivityIndex(
        value=low.value, lower=low.lower, upper=low.upper, sign=low.sign, omega=omega
    )


def _minus_infinity(reason: Reason) -> PassivityIndex:
    """No constant makes the system passive: a pole ``reason`` forbids."""
    return PassivityIndex(
        value=-math.inf, lower=None, upper=None, sign=-1, omega=None, reason=reason
    )


def _sqrt(point: Any) -> float:
    if point.is_rational:
        return sqrt_float(point.lower) if point.lower > 0 else 0.0
    return math.sqrt(float(point))


def passivity_indices(
    system: SystemLike,
    *,
    values: Mapping[str, float] | None = None,
) -> PassivityIndices:
    """ν and ρ of the port impedance of ``system``, decided exactly (see the module docstring).

    Parameters
    ----------
    system : SEA, Impedance, str, sympy.Expr or (num, den)
        As for [`is_passive`][seapass.analysis.passivity.is_passive].
    values : mapping, optional
        Parameter values overriding those stored in ``system``.

    Returns
    -------
    PassivityIndices

    Examples
    --------
    >>> ix = passivity_indices("s/(s**2 + 0.2*s + 1)")  # a mass-spring-dashpot admittance
    >>> round(ix.rho, 12), ix.nu, ix.output.strict, ix.input.strict
    (0.2, 0.0, True, False)
    """
    num, den, _support = evaluate_system(system, values)
    nu = index_of(num, den)
    if num.is_zero():
        inf = PassivityIndex(value=math.inf, lower=None, upper=None, sign=1, omega=None)
        return PassivityIndices(input=nu, output=inf)
    return PassivityIndices(input=nu, output=index_of(den, num))
