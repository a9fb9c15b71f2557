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

The verdict is exact (rational arithmetic, Routh array and Sturm sequences,
shared with :mod:`seapass.analysis.passivity`):

* ``"stable"``: every root of ``χ`` in the open left half-plane;
* ``"marginally stable"``: no root in the open right half-plane and the roots
  on the imaginary axis are simple (bounded, non-decaying oscillation; the
  expected outcome of a lossless SEA held by an undamped environment);
* ``"unstable"``: a root in the open right half-plane, or a repeated root on
  the axis (polynomial growth).

Passivity theorem [2]_: a passive (positive-real) ``Z`` coupled to any passive
environment is never ``"unstable"``.  :func:`simulate_coupled` gives the
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

import itertools
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, TypeAlias

import mpmath
import numpy as np
import sympy as sp

from ..errors import DegenerateModelError, ParameterError
from ..exact import poly as ep
from ..exact.axis import all_real_roots, at_j_omega, axis_factor, is_hurwitz
from ..model.expr import to_fraction
from ..model.sea import SEA, Impedance
from .passivity import exact_rational_function

__all__ = [
    "CoupledResult",
    "CoupledSimulation",
    "Environment",
    "characteristic_from_polys",
    "classify_polynomial",
    "coupled_polynomial",
    "coupled_stability",
    "polynomial_roots",
    "simulate_coupled",
    "to_float",
]

SystemLike: TypeAlias = SEA | Impedance | str | sp.Expr | tuple[Sequence[Any], Sequence[Any]]

STATUSES = ("stable", "marginally stable", "unstable")

#: Samples per oscillation period and the cap on samples in a simulation.
SAMPLES_PER_PERIOD = 24
MAX_SAMPLES = 20000


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

    def polynomials(self) -> tuple[ep.Poly, ep.Poly]:
        """Exact reduced ``(N_e, D_e)``, ascending Fraction coefficients."""
        m, b, k = (to_fraction(v, n) for v, n in self._named())
        if self.is_free:
            return (), (Fraction(1),)
        if k == 0:
            return ep.normalize([b, m]), (Fraction(1),)
        return ep.normalize([k, b, m]), (Fraction(0), Fraction(1))

    def impedance(self, s: complex | np.ndarray) -> Any:
        """``Z_e(s)`` evaluated numerically (``s`` must not be 0 when ``stiffness > 0``)."""
        return self.mass * s + self.damping + self.stiffness / s

    def _named(self) -> tuple[tuple[float, str], ...]:
        return ((self.mass, "mass"), (self.damping, "damping"), (self.stiffness, "stiffness"))

    def to_dict(self) -> dict[str, float]:
        return {"mass": self.mass, "damping": self.damping, "stiffness": self.stiffness}


@dataclass(frozen=True)
class CoupledResult:
    """Outcome of :func:`coupled_stability`.

    Attributes
    ----------
    status : str
        ``"stable"``, ``"marginally stable"`` or ``"unstable"`` (exact).
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

    status: str
    rhp: bool
    repeated_axis: bool
    characteristic: tuple[float, ...]
    common: tuple[float, ...]
    poles: np.ndarray

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"status must be one of {STATUSES}, got {self.status!r}")

    @property
    def stable(self) -> bool:
        return self.status == "stable"

    @property
    def bounded(self) -> bool:
        return self.status != "unstable"

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


def classify_polynomial(p: ep.Poly) -> tuple[str, bool, bool]:
    """Exact ``(status, rhp, repeated_axis)`` of the roots of ``p`` (ascending Fractions).

    A constant nonzero ``p`` has no roots and is ``"stable"``.
    """
    p = ep.normalize(p)
    if not p:
        raise DegenerateModelError("the characteristic polynomial is identically zero")
    if ep.degree(p) == 0 or is_hurwitz(p):
        return "stable", False, False
    re, im = at_j_omega(p)
    g = ep.pgcd(re, im)  # real roots w of g <-> roots s = jw of p, with multiplicity
    rest, repeated = p, False
    if ep.degree(g) > 0:
        if not all_real_roots(g):
            return "unstable", True, False  # a root pair mirrored about the axis
        repeated = ep.degree(ep.squarefree_part(g)) != ep.degree(g)
        rest = ep.pdivmod(p, axis_factor(g))[0]
    rhp = not is_hurwitz(rest)
    if rhp or repeated:
        return "unstable", rhp, repeated
    return "marginally stable", False, False


def _log2(x: Fraction) -> float:
    """``log2 |x|`` without converting ``x`` to a float (no overflow)."""
    n, d = abs(x.numerator), x.denominator
    shift = n.bit_length() - d.bit_length()
    return shift + math.log2(to_float(Fraction(n, d) / Fraction(2) ** shift))


def polynomial_roots(p: ep.Poly, *, fast: bool = False) -> np.ndarray:
    """Roots of ``p`` (ascending Fractions), sorted by decreasing real part.

    The variable is first rescaled exactly by a power of two so that the
    coefficients are balanced (roots of order 1), which keeps the root finder
    fast and accurate for coefficients spanning hundreds of decades; then
    mpmath at 30 digits from the exact coefficients, with ``numpy.roots`` as a
    fallback.  Roots beyond the double range come out as ``inf``.  With
    ``fast=True`` numpy is used directly (for ranking candidates, not evidence).
    """
    p = ep.normalize(p)
    n = ep.degree(p)
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


def _as_polys(
    system: SystemLike | Environment, values: Mapping[str, float] | None
) -> tuple[ep.Poly, ep.Poly]:
    if isinstance(system, Environment):
        return system.polynomials()
    num, den = exact_rational_function(system, values)
    if den[-1] < 0:
        num, den = ep.scale(num, Fraction(-1)), ep.scale(den, Fraction(-1))
    return num, den


def coupled_polynomial(
    system: SystemLike,
    environment: SystemLike | Environment,
    *,
    values: Mapping[str, float] | None = None,
) -> tuple[ep.Poly, ep.Poly]:
    """Exact ``(χ, common)``: ``χ = (N D_e + N_e D) / common``, ``common = gcd(D, D_e)``.

    Ascending Fraction coefficients.  ``values`` apply to ``system`` only.
    """
    n, d = _as_polys(system, values)
    ne, de = _as_polys(environment, None)
    return characteristic_from_polys(n, d, ne, de)


def characteristic_from_polys(
    n: ep.Poly, d: ep.Poly, ne: ep.Poly, de: ep.Poly
) -> tuple[ep.Poly, ep.Poly]:
    """:func:`coupled_polynomial` from exact ascending polynomials ``Z = n/d``, ``Z_e = ne/de``."""
    full = ep.add(ep.mul(n, de), ep.mul(ne, d))
    if not full:
        raise DegenerateModelError(
            "the environment cancels the port impedance exactly (Z + Z_e = 0): "
            "the coupled system is undetermined"
        )
    common = ep.pgcd(d, de)
    chi, rem = ep.pdivmod(full, common)
    if rem:  # pragma: no cover - common divides both terms
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
        The port impedance, as accepted by :func:`seapass.analysis.passivity.is_passive`.
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
    >>> coupled_stability("k*s/(s**2 + k)", Environment(mass=1.0), values={"k": 4.0}).status
    'marginally stable'
    >>> coupled_stability("(s - 1)/(s + 1)", Environment(damping=0.5)).status
    'unstable'
    """
    chi, common = coupled_polynomial(system, environment, values=values)
    status, rhp, repeated = classify_polynomial(chi)
    if chi[-1] < 0:
        chi = ep.scale(chi, Fraction(-1))
    return CoupledResult(
        status=status,
        rhp=rhp,
        repeated_axis=repeated,
        characteristic=tuple(to_float(c) for c in reversed(chi)),
        common=tuple(to_float(c) for c in reversed(common)),
        poles=polynomial_roots(chi),
    )


# ---------------------------------------------------------------- simulation


@dataclass(frozen=True)
class CoupledSimulation:
    """Impulse response of the coupled system (computed, not plotted).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Time [s].
    y : ndarray, shape (n,)
        The output named by ``output``, per unit force impulse.
    output : str
        ``"port displacement"`` [m/(N·s)] or, when that transfer hides the
        unstable mode (a cancelled mode, or an improper transfer),
        ``"characteristic coordinate"`` (the solution ``w`` of ``χ(d/dt) w = δ``).
    growth_rate : float
        Largest real part of the poles of the simulated transfer [1/s].
    growth_factor : float
        ``max|y|`` over the last quarter divided by ``max|y|`` over the first quarter.
    """

    t: np.ndarray
    y: np.ndarray
    output: str
    growth_rate: float
    growth_factor: float

    def to_dict(self, *, samples: bool = False) -> dict[str, Any]:
        out: dict[str, Any] = {
            "output": self.output,
            "growth_rate": self.growth_rate,
            "growth_factor": self.growth_factor,
            "t_end": float(self.t[-1]) if self.t.size else 0.0,
            "samples": int(self.t.size),
        }
        if samples:
            out["t"] = self.t.tolist()
            out["y"] = self.y.tolist()
        return out


def _partial_fractions(num: ep.Poly, den: ep.Poly) -> tuple[np.ndarray, np.ndarray | None]:
    """Poles of strictly proper ``num/den`` and their residues (50 digits).

    Residues are ``None`` when poles are (nearly) repeated.
    """
    roots = polynomial_roots(den)
    if not roots.size or not np.all(np.isfinite(roots)):
        return roots, None
    scale = max(float(np.max(np.abs(roots))), 1e-300)
    pairs = itertools.combinations(roots, 2)
    sep = min((abs(a - b) for a, b in pairs), default=math.inf) / scale
    if sep <= 1e-6:
        return roots, None
    with mpmath.workdps(50):
        nc = [mpmath.mpf(c.numerator) / c.denominator for c in reversed(num)]
        dd = [mpmath.mpf(c.numerator) / c.denominator for c in reversed(ep.derivative(den))]
        res = [
            complex(mpmath.polyval(nc, mpmath.mpc(p.real, p.imag)) / mpmath.polyval(dd, p))
            for p in (mpmath.mpc(r.real, r.imag) for r in roots)
        ]
    return roots, np.array(res, dtype=complex)


def _impulse(
    num: ep.Poly, den: ep.Poly, roots: np.ndarray, res: np.ndarray | None, t: np.ndarray
) -> np.ndarray:
    """Impulse response: a sum of modes, or :func:`scipy.signal.impulse` for repeated poles."""
    if res is not None:
        y = np.zeros_like(t, dtype=complex)
        for r, p in zip(res, roots, strict=True):
            y += r * np.exp(p * t)
        return np.asarray(y.real, dtype=float)
    from scipy import signal

    tf = ([to_float(c) for c in reversed(num)], [to_float(c) for c in reversed(den)])
    with warnings.catch_warnings():
        # badly scaled coefficients: the response is evidence only, the verdict is exact
        warnings.simplefilter("ignore")
        _, y = signal.impulse(tf, T=t)
    return np.asarray(y, dtype=float)


def simulate_coupled(
    system: SystemLike,
    environment: Environment,
    *,
    values: Mapping[str, float] | None = None,
    t_end: float | None = None,
    times: np.ndarray | None = None,
) -> CoupledSimulation:
    """Response of the port displacement to a unit force impulse, SEA held by ``environment``.

    ``X/F = D D_e / (s χ · common)`` (see :mod:`seapass.analysis.coupled`).  When that
    transfer is improper or cancels the fastest-growing mode of ``χ``, the
    characteristic coordinate ``w`` (``χ(d/dt) w = δ``) is simulated instead.
    The response is the sum of modes (poles and residues in multiprecision),
    so no integrator error enters; with repeated poles scipy's impulse
    response is used.

    Parameters
    ----------
    system, environment, values
        As in :func:`seapass.analysis.coupled.coupled_stability`.
    t_end : float, optional
        Horizon [s].  By default long enough for the fastest-growing mode to
        exceed every other mode's initial amplitude and then grow by ``e^6``
        (``σ t <= 700``), or 50 periods of the slowest mode when nothing grows.
    times : ndarray, shape (n,), optional
        Explicit sample times [s] (non-negative, increasing); overrides ``t_end``.

    Returns
    -------
    CoupledSimulation
    """
    zn, zd = _as_polys(system, values)
    ne, de = environment.polynomials()
    chi, common = characteristic_from_polys(zn, zd, ne, de)  # one (zn, zd): consistent signs
    num = ep.pdivmod(ep.mul(zd, de), common)[0]
    den = ep.mul(chi, (Fraction(0), Fraction(1)))
    g = ep.pgcd(num, den)
    num, den = ep.pdivmod(num, g)[0], ep.pdivmod(den, g)[0]
    output = "port displacement"
    status_full = classify_polynomial(chi)[0]
    if ep.degree(num) >= ep.degree(den) or (
        status_full == "unstable" and classify_polynomial(den)[0] != "unstable"
    ):
        num, den, output = (Fraction(1),), chi, "characteristic coordinate"
    roots, res = _partial_fractions(num, den)
    sigma = float(np.max(roots.real)) if roots.size else -math.inf
    if times is not None:
        t = np.asarray(times, dtype=float)
        if t.ndim != 1 or t.size < 2 or not np.all(np.isfinite(t)):
            raise ValueError(
                f"times must be a finite 1-D array of >= 2 samples, got shape {t.shape}"
            )
        if t[0] < 0 or np.any(np.diff(t) <= 0):
            raise ValueError("times must be non-negative and strictly increasing")
    else:
        if t_end is None:
            t_end = _horizon(roots, res)
        if not (math.isfinite(t_end) and t_end > 0):
            raise ValueError(f"t_end must be a positive finite time, got {t_end!r}")
        wmax = float(np.max(np.abs(roots.imag))) if roots.size else 0.0
        n = int(min(MAX_SAMPLES, max(2000, SAMPLES_PER_PERIOD * t_end * wmax / (2 * math.pi))))
        t = np.linspace(0.0, t_end, n)
    n = t.size
    with np.errstate(over="ignore", invalid="ignore"):
        y = _impulse(num, den, roots, res, t)
    q = max(n // 4, 1)
    first = float(np.max(np.abs(y[:q]))) or math.nan
    growth = float(np.max(np.abs(y[-q:]))) / first
    return CoupledSimulation(t=t, y=y, output=output, growth_rate=sigma, growth_factor=growth)


def _horizon(roots: np.ndarray, res: np.ndarray | None) -> float:
    if not roots.size:
        return 1.0
    sigma = float(np.max(roots.real))
    if sigma > 0:
        lead = 0.0
        if res is not None:
            top = roots.real >= sigma * (1 - 1e-9)
            r_top = float(np.sum(np.abs(res[top])))
            r_rest = float(np.sum(np.abs(res[~top])))
            if r_top > 0 and r_rest > 0:
                lead = max(0.0, math.log(r_rest / r_top))
        return min(lead + 6.0, 700.0) / sigma
    nonzero = np.abs(roots[np.abs(roots) > 0])
    slow = float(np.min(nonzero)) if nonzero.size else 1.0
    return 50 * 2 * math.pi / slow
