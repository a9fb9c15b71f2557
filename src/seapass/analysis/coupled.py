"""Coupled stability of an SEA port with an environment impedance.

Joining the SEA's port impedance ``Z = N/D`` to an environment ``Z_e = N_e/D_e``
at a common port velocity (the person holds the port: ``(Z + Z_e) V = F_ext``)
gives the characteristic polynomial

``χ(s) = N D_e + N_e D``

with ``N, D`` as derived symbolically (a factor that cancels only for the
given numbers is kept, so such hidden modes count).  Factors common to ``D``
and ``D_e`` are removed from ``χ``: they are modes shared by both sides that
the port cannot reach, chiefly the pole ``s = 0`` of every spring-like port,
which only encodes the arbitrary rest position (with a passive environment
they are simple on the imaginary axis or stable, so removing them never hides
an instability of a passive environment).

The verdict is exact (rational arithmetic, Routh array and certified real-root
isolation, shared with [`seapass.analysis.passivity`][seapass.analysis.passivity]):

* ``"stable"``: every root of ``χ`` in the open left half-plane;
* ``"marginally stable"``: no root in the open right half-plane and the roots
  on the imaginary axis are simple (bounded, non-decaying oscillation; the
  expected outcome of a lossless SEA held by an undamped environment);
* ``"unstable"``: a root in the open right half-plane, or a repeated root on
  the axis (polynomial growth).

Passivity theorem [2]_: a passive (positive-real) ``Z`` coupled to any passive
environment is never ``"unstable"``.  So the result's ``outcome`` (what the
coupling proves about the passivity of ``Z``) is ``NOT_PASSIVE`` when a passive
environment makes it unstable, and ``UNDECIDED`` otherwise: one environment
never proves passivity.  `simulate_coupled` gives the
time-domain evidence: the response of the port displacement to a force
impulse, as an exact sum of modes.  The roots are reported in floating point
(mpmath at 30 digits) as evidence only.

References
----------
.. [1] E. J. Routh, *A Treatise on the Stability of a Given State of Motion*, 1877.
.. [2] J. E. Colgate and N. Hogan, "Robust control of dynamically interacting
   systems", Int. J. Control 48(1), 1988.
.. [3] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Sec. II.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from fractions import Fraction
from typing import Any, TypeAlias

import mpmath
import numpy as np
import sympy as sp
from flint import fmpq_poly

from ..errors import DegenerateModelError, ParameterError
from ..exact import poly as ep
from ..exact.axis import all_real_roots, at_j_omega, axis_factor, is_hurwitz
from ..model.expr import to_fraction
from ..model.sea import SEA, Impedance
from ..outcome import Outcome
from .impedance import exact_rational_function
from .passivity import positive_real_test

__all__ = [
    "CoupledResult",
    "Environment",
    "Stability",
    "SystemLike",
    "characteristic_from_polys",
    "classify_polynomial",
    "coupled_polynomial",
    "coupled_stability",
    "polynomial_roots",
    "system_polynomials",
    "to_float",
]

SystemLike: TypeAlias = SEA | Impedance | str | sp.Expr | tuple[Sequence[Any], Sequence[Any]]


class Stability(StrEnum):
    """Stability of a closed loop, decided from its characteristic polynomial."""

    STABLE = "stable"
    """Every root in the open left half-plane."""
    MARGINAL = "marginally stable"
    """No root in the open right half-plane; the roots on the imaginary axis are simple."""
    UNSTABLE = "unstable"
    """A root in the open right half-plane, or a repeated root on the axis."""


@dataclass(frozen=True)
class Environment:
    """A passive mass-spring-damper environment ``Z_e(s) = m s + b + k/s``.

    A model of a person (or object) holding the port: mass ``mass`` [kg],
    damping ``damping`` [N·s/m], stiffness ``stiffness`` [N/m], all finite
    and ``>= 0``.  All zero is a free port.
    """

    mass: float = 0.0
    damping: float = 0.0
    stiffness: float = 0.0

    def __post_init__(self) -> None:
        for name in ("mass", "damping", "stiffness"):
            val = getattr(self, name)
            if isinstance(val, bool) or not isinstance(val, int | float | Fraction):
                raise ParameterError(f"environment {name}: expected a number, got {val!r}")
            fval = float(val)
            if not math.isfinite(fval) or fval < 0:
                raise ParameterError(
                    f"environment {name} must be finite and >= 0 (a passive environment), "
                    f"got {val!r}"
                )
            object.__setattr__(self, name, fval)

    @property
    def is_free(self) -> bool:
        return self.mass == 0 and self.damping == 0 and self.stiffness == 0

    def polynomials(self) -> tuple[fmpq_poly, fmpq_poly]:
        """Exact reduced ``(N_e, D_e)`` as `flint.fmpq_poly`."""
        m, b, k = (to_fraction(v, n) for v, n in self._named())
        if self.is_free:
            return fmpq_poly([]), fmpq_poly([1])
        if k == 0:
            return ep.as_poly([b, m]), fmpq_poly([1])
        return ep.as_poly([k, b, m]), fmpq_poly([0, 1])

    def impedance(self, s: complex | np.ndarray) -> Any:
        """``Z_e(s)`` evaluated numerically (``s`` must not be 0 when ``stiffness > 0``)."""
        return self.mass * s + self.damping + self.stiffness / s

    def _named(self) -> tuple[tuple[float, str], ...]:
        return ((self.mass, "mass"), (self.damping, "damping"), (self.stiffness, "stiffness"))

    def to_dict(self) -> dict[str, float]:
        return {"mass": self.mass, "damping": self.damping, "stiffness": self.stiffness}


@dataclass(frozen=True, kw_only=True)
class CoupledResult:
    """Outcome of `coupled_stability`.

    Attributes
    ----------
    status : Stability
        Decided exactly.
    outcome : Outcome
        What the coupling proves about the passivity of the system:
        ``NOT_PASSIVE`` when the environment is passive and the coupled system
        unstable (passivity theorem), else ``UNDECIDED`` (never ``PASSIVE``).
    stable : bool
        Asymptotically stable (``status == "stable"``).
    bounded : bool
        Not unstable: no root in the open right half-plane, axis roots simple.
    rhp : bool
        A root lies in the open right half-plane (exact).
    repeated_axis : bool
        A repeated root lies on the imaginary axis (exact).
    characteristic : tuple of float
        ``χ`` (common modes removed), descending powers of ``s``.
    common : tuple of float
        The removed common factor ``gcd(D, D_e)``, descending.
    poles : ndarray of complex, shape (deg χ,)
        Roots of ``χ`` (floating point evidence), sorted by decreasing real part.
    max_real_part : float
        Largest real part of ``poles`` [1/s] (``-inf`` when ``χ`` is constant).
    """

    status: Stability
    rhp: bool
    repeated_axis: bool
    characteristic: tuple[float, ...]
    common: tuple[float, ...]
    poles: np.ndarray
    outcome: Outcome = Outcome.UNDECIDED

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "status", Stability(self.status))
        except ValueError:
            choices = ", ".join(s.value for s in Stability)
            raise ValueError(f"status must be one of {choices}, got {self.status!r}") from None

    @property
    def stable(self) -> bool:
        return self.status == Stability.STABLE

    @property
    def bounded(self) -> bool:
        return self.status != Stability.UNSTABLE

    @property
    def max_real_part(self) -> float:
        """Largest real part of ``poles``; ``nan`` when the roots could not be computed."""
        return float(np.max(self.poles.real)) if self.poles.size else -math.inf

    def to_dict(self) -> dict[str, Any]:
        return {
            "status": self.status,
            "stable": self.stable,
            "bounded": self.bounded,
            "rhp": self.rhp,
            "repeated_axis": self.repeated_axis,
            "characteristic": list(self.characteristic),
            "common": list(self.common),
            "poles": [[float(p.real), float(p.imag)] for p in self.poles],
            "max_real_part": self.max_real_part,
        }


# ---------------------------------------------------------------- exact core


def to_float(x: Fraction | float | Any) -> float:
    """``float(x)`` that saturates to ``±inf`` (or 0) instead of raising on overflow."""
    try:
        return float(x)
    except OverflowError:
        return math.inf if x > 0 else -math.inf


def _to_complex(z: Any) -> complex:
    return complex(to_float(mpmath.re(z)), to_float(mpmath.im(z)))


def classify_polynomial(p: ep.PolyLike) -> tuple[Stability, bool, bool]:
    """Exact ``(status, rhp, repeated_axis)`` of the roots of ``p``.

    ``p`` is a `flint.fmpq_poly` or ascending exact rationals.

    A constant nonzero ``p`` has no roots and is ``"stable"``.
    """
    p = ep.as_poly(p)
    if p.is_zero():
        raise DegenerateModelError("the characteristic polynomial is identically zero")
    if p.degree() == 0 or is_hurwitz(p):
        return Stability.STABLE, False, False
    re, im = at_j_omega(p)
    g = re.gcd(im)  # real roots w of g <-> roots s = jw of p, with multiplicity
    rest, repeated = p, False
    if g.degree() > 0:
        if not all_real_roots(g):
            return Stability.UNSTABLE, True, False  # a root pair mirrored about the axis
        repeated = ep.squarefree_part(g).degree() != g.degree()
        rest = p // axis_factor(g)
    rhp = not is_hurwitz(rest)
    if rhp or repeated:
        return Stability.UNSTABLE, rhp, repeated
    return Stability.MARGINAL, False, False


def _log2(x: Fraction) -> float:
    """``log2 |x|`` without converting ``x`` to a float (no overflow)."""
    n, d = abs(x.numerator), x.denominator
    shift = n.bit_length() - d.bit_length()
    return shift + math.log2(to_float(Fraction(n, d) / Fraction(2) ** shift))


def polynomial_roots(p: ep.PolyLike, *, fast: bool = False) -> np.ndarray:
    """Roots of ``p`` (`flint.fmpq_poly` or ascending rationals), by decreasing real part.

    The variable is first rescaled exactly by a power of two so that the
    coefficients are balanced (roots of order 1), which keeps the root finder
    fast and accurate for coefficients spanning hundreds of decades; then
    mpmath at 30 digits from the exact coefficients, with ``numpy.roots`` as a
    fallback.  Roots beyond the double range come out as ``inf``.  With
    ``fast=True`` numpy is used directly (for ranking candidates, not evidence).
    """
    p = ep.to_fractions(ep.as_poly(p))  # evidence only: mpmath from the exact coefficients
    n = len(p) - 1
    if n <= 0:
        return np.zeros(0, dtype=complex)
    low = next(i for i, c in enumerate(p) if c != 0)
    zeros = np.zeros(low, dtype=complex)
    q = p[low:]
    m = len(q) - 1
    if m == 0:
        return zeros
    e = round((_log2(q[0]) - _log2(q[-1])) / m)
    alpha = Fraction(2) ** e
    lead = q[-1] * alpha**m
    desc = [q[k] * alpha**k / lead for k in range(m, -1, -1)]
    try:
        if fast:
            raise mpmath.libmp.NoConvergence
        with mpmath.workdps(30):
            coeffs = [mpmath.mpf(c.numerator) / mpmath.mpf(c.denominator) for c in desc]
            roots = mpmath.polyroots(coeffs, maxsteps=100, extraprec=60)
            scaled = [mpmath.mpc(r) * mpmath.mpf(2) ** e for r in np.atleast_1d(roots)]
            out = np.array([_to_complex(r) for r in scaled], dtype=complex)
    except (mpmath.libmp.NoConvergence, ZeroDivisionError):
        fl = np.array([to_float(c) for c in desc])
        if not np.all(np.isfinite(fl)):
            return np.concatenate([zeros, np.full(m, np.nan, dtype=complex)])
        with np.errstate(over="ignore", invalid="ignore"):
            out = np.roots(fl).astype(complex) * 2.0**e
    out = np.concatenate([zeros, out])
    return out[np.argsort(-out.real, kind="stable")]


def system_polynomials(
    system: SystemLike | Environment, values: Mapping[str, float] | None
) -> tuple[fmpq_poly, fmpq_poly]:
    if isinstance(system, Environment):
        return system.polynomials()
    num, den = exact_rational_function(system, values)
    if den.leading_coefficient() < 0:
        num, den = -num, -den
    return num, den


def coupled_polynomial(
    system: SystemLike,
    environment: SystemLike | Environment,
    *,
    values: Mapping[str, float] | None = None,
) -> tuple[fmpq_poly, fmpq_poly]:
    """Exact ``(χ, common)``: ``χ = (N D_e + N_e D) / common``, ``common = gcd(D, D_e)``.

    Both are `flint.fmpq_poly`.  ``values`` apply to ``system`` only.
    """
    n, d = system_polynomials(system, values)
    ne, de = system_polynomials(environment, None)
    return characteristic_from_polys(n, d, ne, de)


def characteristic_from_polys(
    n: ep.PolyLike, d: ep.PolyLike, ne: ep.PolyLike, de: ep.PolyLike
) -> tuple[fmpq_poly, fmpq_poly]:
    """`coupled_polynomial` from exact ascending polynomials ``Z = n/d``, ``Z_e = ne/de``."""
    n, d, ne, de = (ep.as_poly(x) for x in (n, d, ne, de))
    full = n * de + ne * d
    if full.is_zero():
        raise DegenerateModelError(
            "the environment cancels the port impedance exactly (Z + Z_e = 0): "
            "the coupled system is undetermined"
        )
    common = d.gcd(de)
    chi, rem = divmod(full, common)
    if not rem.is_zero():  # pragma: no cover - common divides both terms
        raise ArithmeticError("common factor does not divide the characteristic polynomial")
    return chi, common


def coupled_stability(
    system: SystemLike,
    environment: SystemLike | Environment,
    *,
    values: Mapping[str, float] | None = None,
) -> CoupledResult:
    """Exact stability of ``system`` (SEA or impedance) held by ``environment``.

    Parameters
    ----------
    system : SEA, Impedance, str, sympy.Expr or (num, den)
        The port impedance, as accepted by [`seapass.analysis.passivity.is_passive`][seapass.analysis.passivity.is_passive].
    environment : Environment or any of the above
        The environment impedance ``Z_e`` (e.g. ``Environment(mass=2, stiffness=1e4)``).
    values : mapping, optional
        Parameter values for ``system``.

    Returns
    -------
    CoupledResult

    Examples
    --------
    >>> from seapass.analysis.coupled import Environment, coupled_stability
    >>> print(coupled_stability("k*s/(s**2 + k)", Environment(mass=1.0), values={"k": 4.0}).status)
    marginally stable
    >>> r = coupled_stability("(s - 1)/(s + 1)", Environment(damping=0.5))
    >>> print(r.status, r.outcome)
    unstable not_passive
    """
    chi, common = coupled_polynomial(system, environment, values=values)
    status, rhp, repeated = classify_polynomial(chi)
    if chi.leading_coefficient() < 0:
        chi = -chi
    proven = status is Stability.UNSTABLE and _passive_environment(environment)
    return CoupledResult(
        status=status,
        outcome=Outcome.NOT_PASSIVE if proven else Outcome.UNDECIDED,
        rhp=rhp,
        repeated_axis=repeated,
        characteristic=tuple(to_float(c) for c in reversed(chi.coeffs())),
        common=tuple(to_float(c) for c in reversed(common.coeffs())),
        poles=polynomial_roots(chi),
    )


def _passive_environment(environment: SystemLike | Environment) -> bool:
    """An `Environment` is passive by construction; anything else is tested exactly."""
    if isinstance(environment, Environment):
        return True
    return positive_real_test(*system_polynomials(environment, None)).passive


# ---------------------------------------------------------------- simulation
