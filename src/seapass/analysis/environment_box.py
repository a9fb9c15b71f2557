"""Environments within physical bounds, and an exact test that none of them destabilizes a design.

A person (or an object) at the port is modelled as a passive mass-spring-damper
``Z_e = m s + b + k/s`` with ``(m, b, k)`` in a box of `EnvironmentBounds`;
the default `HUMAN_LIMB` spans a relaxed to a co-contracted human arm and the
objects a hand holds.

**Which environments in the box put a coupled pole on the imaginary axis?**
The coupled characteristic polynomial ``F(s) = s N(s) + D(s)(m s² + b s + k)``
of ``Z = N/D`` (reduced) is affine in ``(m, b, k)``.  A pole ``s = jω``,
``ω > 0``, means ``Z(jω) + Z_e(jω) = 0``:
``b = −Re Z(jω)`` and ``k − m ω² = ω Im Z(jω)``.  With ``x = ω²``,
``P = Re N(jω)D(−jω)``, ``W = ω Im N(jω)D(−jω)`` and ``M = |D(jω)|²`` (all
polynomials in ``x``), some ``(m, b, k)`` in the box does this at ``x`` if and
only if ``M(x) > 0`` and

* ``b_lo M + P ≤ 0 ≤ b_hi M + P``,
* ``m_lo x M + W − k_hi M ≤ 0 ≤ m_hi x M + W − k_lo M``.

`crossing_cells` decides this exactly on every sign cell of these polynomials
([`half_line_cells`][seapass.exact.halfline.half_line_cells]).

**Certificate** (`certify_box`).  The number of coupled poles in the open
right half-plane is the same for every environment in the (connected) box when
no pole can cross the imaginary axis anywhere in it and the degree of ``F``
does not change; then one environment with no such pole proves it for all.
Checked exactly: no crossing at ``ω > 0`` (above); none at ``ω = 0`` (with
``Z(0)`` finite and ``k_lo = 0`` the root that leaves ``s = 0`` as ``k`` grows
goes left when ``Z(0) + b_lo > 0``; with a pole of ``Z`` at 0 of residue ``r``,
``−r`` is not in ``[k_lo, k_hi]``); a positive lowest mass (the leading
coefficient ``m·lead D`` or ``lead N + m lead D`` never vanishes); and one
corner of the box, tested exactly.  Anything else is "not certified", never
"safe".

References
----------
.. [1] J. E. Colgate and N. Hogan, "Robust control of dynamically interacting
   systems", Int. J. Control 48(1), 1988.
.. [2] B. R. Barmish, *New Tools for Robustness of Linear Systems*, Macmillan,
   1994, ch. 3 (the zero exclusion principle for polytopes of polynomials).
.. [3] T. Tsuji, P. G. Morasso, K. Goto and K. Ito, "Human hand impedance
   characteristics during maintained posture", Biol. Cybern. 72, 1995;
   F. A. Mussa-Ivaldi, N. Hogan and E. Bizzi, "Neural, mechanical, and
   geometric factors subserving arm posture in humans", J. Neurosci. 5(10), 1985.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from flint import fmpq_poly

from ..errors import ParameterError
from ..exact import poly as ep
from ..exact.axis import at_j_omega, even_to_x, real_part_polynomial, squared_magnitude_polynomial
from ..exact.halfline import HalfLinePoint, half_line_cells
from ..outcome import Outcome
from .coupled import Environment, characteristic_from_polys, classify_polynomial
from .portresponse import reduced_impedance

__all__ = [
    "HUMAN_LIMB",
    "BoxCertificate",
    "EnvironmentBounds",
    "bounds_from_mapping",
    "certify_box",
    "crossing_cells",
]

_UNITS = {"mass": "kg", "damping": "N*s/m", "stiffness": "N/m"}


@dataclass(frozen=True)
class EnvironmentBounds:
    """A box of passive environments ``Z_e = m s + b + k/s``.

    Attributes
    ----------
    mass, damping, stiffness : (float, float)
        ``(lo, hi)`` in kg, N·s/m and N/m; finite, ``0 <= lo <= hi``.
    """

    mass: tuple[float, float] = (0.1, 10.0)
    damping: tuple[float, float] = (0.0, 100.0)
    stiffness: tuple[float, float] = (0.0, 5000.0)

    def __post_init__(self) -> None:
        for name in ("mass", "damping", "stiffness"):
            value = getattr(self, name)
            try:
                lo, hi = (float(v) for v in value)
            except (TypeError, ValueError):
                raise ParameterError(
                    f"bounds.{name}: expected (lo, hi), got {value!r}", argument=f"bounds.{name}"
                ) from None
            if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo <= hi):
                raise ParameterError(
                    f"bounds.{name}: need finite 0 <= lo <= hi (a passive environment), "
                    f"got ({lo:g}, {hi:g})",
                    argument=f"bounds.{name}",
                )
            object.__setattr__(self, name, (lo, hi))

    def contains(self, env: Environment) -> bool:
        return all(lo <= getattr(env, name) <= hi for name, (lo, hi) in self.items())

    def clip(self, mass: float, damping: float, stiffness: float) -> Environment:
        """The environment nearest to ``(mass, damping, stiffness)`` inside the box."""
        vals = (mass, damping, stiffness)
        out = [min(max(v, lo), hi) for v, (_n, (lo, hi)) in zip(vals, self.items(), strict=True)]
        return Environment(mass=out[0], damping=out[1], stiffness=out[2])

    def items(self) -> tuple[tuple[str, tuple[float, float]], ...]:
        return (("mass", self.mass), ("damping", self.damping), ("stiffness", self.stiffness))

    def describe(self) -> str:
        """``m ∈ [0.1, 10] kg, b ∈ [0, 100] N*s/m, k ∈ [0, 5000] N/m``."""
        sym = {"mass": "m", "damping": "b", "stiffness": "k"}
        return ", ".join(
            f"{sym[n]} in [{lo:g}, {hi:g}] {_UNITS[n]}" for n, (lo, hi) in self.items()
        )

    def to_dict(self) -> dict[str, list[float]]:
        return {name: list(box) for name, box in self.items()}


HUMAN_LIMB = EnvironmentBounds()
"""A human limb and what a hand holds: 0.1–10 kg, 0–100 N·s/m, 0–5000 N/m.

Masses from a finger to a forearm with a tool (the issue's 0.1–10 kg); damping
from none (the worst case: a relaxed limb or a free object) to well above the
5–30 N·s/m measured at the hand [3]; stiffness from none (a free mass) to a
strongly co-contracted arm (hand stiffness 0.1–1 kN/m relaxed [3], a few kN/m
co-contracted).
"""


@dataclass(frozen=True)
class _Polys:
    """``P, W, M`` in ``x = ω²`` of a reduced ``Z = N/D``."""

    p: fmpq_poly
    w: fmpq_poly
    m: fmpq_poly

    @classmethod
    def of(cls, num: fmpq_poly, den: fmpq_poly) -> _Polys:
        nr, ni = at_j_omega(num)
        dr, di = at_j_omega(den)
        q = ni * dr - nr * di  # Im N(jω) D(−jω), odd in ω
        w = even_to_x(fmpq_poly([0, 1]) * q)
        return cls(real_part_polynomial(num, den), w, squared_magnitude_polynomial(den))


def _conditions(polys: _Polys, b: EnvironmentBounds) -> tuple[fmpq_poly, ...]:
    """``c1 ≤ 0, c2 ≥ 0, c3 ≤ 0, c4 ≥ 0`` (see the module docstring)."""
    (m_lo, m_hi), (b_lo, b_hi), (k_lo, k_hi) = b.mass, b.damping, b.stiffness
    xm = fmpq_poly([0, 1]) * polys.m
    c1 = ep.rational(b_lo) * polys.m + polys.p
    c2 = ep.rational(b_hi) * polys.m + polys.p
    c3 = ep.rational(m_lo) * xm + polys.w - ep.rational(k_hi) * polys.m
    c4 = ep.rational(m_hi) * xm + polys.w - ep.rational(k_lo) * polys.m
    return c1, c2, c3, c4


def crossing_cells(
    num: ep.PolyLike, den: ep.PolyLike, bounds: EnvironmentBounds
) -> list[tuple[HalfLinePoint, bool]]:
    """Points ``x = ω² > 0`` where some environment in ``bounds`` has a coupled pole at ``jω``.

    One point per sign cell where it happens (exact), with a flag: ``True`` when
    ``Re Z(jω) < −b_lo`` strictly there (an environment with less damping than
    ``−Re Z`` makes ``Re(Z + Z_e)(jω) < 0``: the construction of a witness).
    ``num/den`` must be reduced.
    """
    polys = _Polys.of(ep.as_poly(num), ep.as_poly(den))
    c1, c2, c3, c4 = _conditions(polys, bounds)
    out = []
    for pt in half_line_cells([c1, c2, c3, c4, polys.m]):
        if pt.lower == 0 and pt.is_rational:
            continue
        if pt.sign(polys.m) <= 0:
            continue  # an axis pole of Z: jω N(jω) ≠ 0 there, no coupled pole
        s1, s2, s3, s4 = (pt.sign(c) for c in (c1, c2, c3, c4))
        if s1 <= 0 and s2 >= 0 and s3 <= 0 and s4 >= 0:
            out.append((pt, s1 < 0))
    return out


@dataclass(frozen=True, kw_only=True)
class BoxCertificate:
    """Outcome of `certify_box`.

    Attributes
    ----------
    outcome : Outcome
        Of "is the design coupled-stable with every environment in the box":
        ``PASSIVE`` proven (``certified``), ``NOT_PASSIVE`` when an environment
        of the box is proven to destabilize it, else ``UNDECIDED``.
    reason : str
        Why not, when not certified (one sentence).
    """

    outcome: Outcome
    reason: str = ""

    @property
    def certified(self) -> bool:
        """Proven: no environment in the box gives the coupled system a pole in the
        open right half-plane or a repeated pole on the imaginary axis."""
        return self.outcome.passive


def _undecided(reason: str) -> BoxCertificate:
    return BoxCertificate(outcome=Outcome.UNDECIDED, reason=reason)


def certify_box(
    num: ep.PolyLike,
    den: ep.PolyLike,
    bounds: EnvironmentBounds,
    cells: list[tuple[HalfLinePoint, bool]] | None = None,
) -> BoxCertificate:
    """Prove (exactly) that no environment in ``bounds`` destabilizes ``Z = num/den``.

    ``num/den`` as derived (a common factor is a mode every environment keeps);
    ``cells`` are `crossing_cells` of the reduced ``Z`` when already computed.
    See the module docstring for the argument.
    """
    num, den = ep.as_poly(num), ep.as_poly(den)
    if den.leading_coefficient() < 0:
        num, den = -num, -den
    if num.is_zero():
        return _undecided("Z is identically zero")
    rn, rd = reduced_impedance(num, den)
    m_lo, m_hi = (ep.rational(v) for v in bounds.mass)
    if m_lo == 0:
        return _undecided("the mass bound includes 0, where the coupled order drops")
    if rn.degree() == rd.degree() + 1:
        m_star = -rn.leading_coefficient() / rd.leading_coefficient()  # lead N + m lead D = 0
        if m_lo <= m_star <= m_hi:
            return _undecided(f"the coupled order drops at m = {float(m_star):.6g} kg")
    elif rn.degree() > rd.degree() + 1:
        return _undecided("Z grows faster than s at high frequency")
    zero = _zero_crossing(rn, rd, bounds)
    if zero:
        return _undecided(zero)
    if cells is None:
        cells = crossing_cells(rn, rd, bounds)
    if cells:
        w = math.sqrt(float(cells[0][0]))
        return _undecided(
            f"an environment in the bounds puts a coupled pole on the axis at w = {w:.6g} rad/s"
        )
    b_lo, k_lo, k_hi = bounds.damping[0], bounds.stiffness[0], bounds.stiffness[1]
    corner = Environment(mass=bounds.mass[0], damping=b_lo, stiffness=k_hi if k_hi else k_lo)
    chi, _ = characteristic_from_polys(num, den, *corner.polynomials())
    _status, rhp, repeated = classify_polynomial(chi)
    if rhp or repeated:
        return BoxCertificate(
            outcome=Outcome.NOT_PASSIVE,
            reason=f"the environment {_env_text(corner)} destabilizes it",
        )
    return BoxCertificate(outcome=Outcome.PASSIVE)


def _zero_crossing(rn: fmpq_poly, rd: fmpq_poly, bounds: EnvironmentBounds) -> str:
    """Why a coupled pole may sit at ``s = 0`` for an environment in the box (``""``: none)."""
    (k_lo, k_hi), b_lo = bounds.stiffness, ep.rational(bounds.damping[0])
    if rd[0] != 0:  # Z(0) finite: F(0) = D(0) k
        if k_lo > 0:
            return ""
        z0 = rn[0] / rd[0]
        if z0 + b_lo > 0:
            return ""
        return (
            f"Z(0) + b = {float(z0 + b_lo):.6g} <= 0 at the lowest damping: a soft spring "
            "may pull a coupled pole through s = 0"
        )
    residue = rn[0] / rd[1] if rd[1] != 0 else None
    if residue is None:
        return "Z has a repeated pole at s = 0"
    if ep.rational(k_lo) <= -residue <= ep.rational(k_hi):
        return f"a spring of k = {float(-residue):.6g} N/m cancels Z's static stiffness"
    return ""


def _env_text(env: Environment) -> str:
    return f"m = {env.mass:g} kg, b = {env.damping:g} N*s/m, k = {env.stiffness:g} N/m"


def bounds_from_mapping(data: dict[str, Any]) -> EnvironmentBounds:
    """`EnvironmentBounds` from ``{"mass": (lo, hi), ...}``, missing keys at `HUMAN_LIMB`'s."""
    extra = sorted(set(data) - {"mass", "damping", "stiffness"})
    if extra:
        raise ParameterError(f"bounds: unknown key {extra[0]!r}; use mass, damping, stiffness")
    return EnvironmentBounds(**{**HUMAN_LIMB.to_dict(), **data})
