"""First-principles derivation of the rendered stiffness ``F_L/X_L`` and the port impedance.

The free-body model (Laplace domain, zero initial conditions, references zero):

* actuator, Newton's law: ``(m s^2 + b s) X_A = F_A + D1 (X_L − X_A)``
* massless load port, force balance: ``F_L = D1 (X_L − X_A) + D2 X_L``
* controller: ``F_A = C_A (Θ_A − X_A) + C_L (Θ_L − X_L)`` with ``Θ_A = Θ_L = 0``

``F_L`` is the force the person applies at the port (positive stretching the
transmission).  Solving the linear equations gives

``F_L/X_L = [D1 (α + C_A) + D2 (α + C_A + D1) + D1 C_L] / (α + C_A + D1)``,
``α = m s^2 + b s``.  The paper's Eq. (4) prints ``D2 (α + C_A)`` for the
second term; the two agree exactly when ``D2 = 0`` (see "Notes on the paper").

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Eqs. (1)-(5).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import NamedTuple

import sympy as sp

from ..errors import DegenerateModelError, SymbolicLimitError
from ..files.limits import MAX_MODEL_DEGREE, MAX_MODEL_TERMS
from .budget import TERM_CAP, fraction_size, symbolic_time_limit
from .expr import S, W
from .sea import SEA

__all__ = [
    "StiffnessDerivation",
    "derive_stiffness",
    "load_impedance",
    "model_size",
    "paper_eq4_stiffness",
    "passivity_polynomial",
    "real_part_polynomial",
]


@dataclass(frozen=True, kw_only=True)
class StiffnessDerivation:
    """Result of `derive_stiffness`.

    Attributes
    ----------
    stiffness : sympy.Expr
        ``F_L/X_L`` as a cancelled rational function of ``s``.
    actuator_motion : sympy.Expr
        ``X_A/X_L`` with the port held (the internal actuator response).
    equations : tuple of sympy.Eq
        The free-body equations that were solved.
    """

    stiffness: sp.Expr
    actuator_motion: sp.Expr
    equations: tuple[sp.Eq, ...]


def derive_stiffness(sea: SEA) -> StiffnessDerivation:
    """Solve the free-body equations of ``sea`` for ``F_L/X_L``.

    Parameters
    ----------
    sea : SEA
        The model; its parameter values are not substituted.

    Returns
    -------
    StiffnessDerivation
    """
    from .zcontroller import continuous_only

    continuous_only(sea, "the continuous-time derivation")
    e = sea.elements()
    return _derive(tuple(e[k] for k in ("D1", "D2", "CA", "CL", "m", "b")))


class _PolySize(NamedTuple):
    """Degree in ``s`` and number of terms of a polynomial (upper bounds)."""

    degree: int
    terms: int

    def __add__(self, other: object) -> _PolySize:
        assert isinstance(other, _PolySize)
        return _PolySize(max(self.degree, other.degree), min(self.terms + other.terms, TERM_CAP))

    def __mul__(self, other: object) -> _PolySize:
        assert isinstance(other, _PolySize)
        return _PolySize(self.degree + other.degree, min(self.terms * other.terms, TERM_CAP))


def model_size(sea: SEA) -> tuple[int, int]:
    """Upper bounds ``(deg N + deg D, terms(N) + terms(D))`` of ``F_L/X_L = N/D`` of ``sea``.

    Each element ``E = n_E/d_E`` is bounded by
    [`fraction_size`][seapass.model.budget.fraction_size]; the stiffness is then
    bounded on its structure after the common denominators ``d_D1 d_CA`` (and
    that of ``m, b``) cancel, which they always do:

    ``F_L/X_L = [n_D1 (n_α d_CA + d_α n_CA) d_D2 d_CL + n_D2 q d_CL
    + d_α n_D1 n_CL d_CA d_D2] / (q d_D2 d_CL)``,
    ``q = n_α d_CA d_D1 + d_α (n_CA d_D1 + n_D1 d_CA)``, ``α = m s² + b s = n_α/d_α``.

    So the budget counts the size of the design's impedance, not of the nested
    expression that describes it: a PI actuator controller with a load-side P
    and a dashpot to ground (``D1 = k1, D2 = b2 s, CA = kd + ki/s, CL = kd``)
    is ``deg N + deg D = 7``, as its cancelled form.

    Examples
    --------
    >>> model_size(SEA(D1="k1", D2="b2*s", CA="kd + ki/s", CL="kd"))[0]
    7
    """
    return _structural_size(tuple(sea.elements()[k] for k in ("D1", "D2", "CA", "CL", "m", "b")))


def _structural_size(key: tuple[sp.Expr, ...]) -> tuple[int, int]:
    e = dict(zip(("D1", "D2", "CA", "CL", "m", "b"), key, strict=True))
    sizes = {k: fraction_size(v) for k, v in e.items()}
    n = {k: _PolySize(f.num_degree, f.num_terms) for k, f in sizes.items()}
    d = {k: _PolySize(f.den_degree, f.den_terms) for k, f in sizes.items()}
    alpha = fraction_size(e["m"] * S**2 + e["b"] * S)
    n_alpha, d_alpha = (
        _PolySize(alpha.num_degree, alpha.num_terms),
        _PolySize(alpha.den_degree, alpha.den_terms),
    )
    q = n_alpha * d["CA"] * d["D1"] + d_alpha * (n["CA"] * d["D1"] + n["D1"] * d["CA"])
    num = (
        n["D1"] * (n_alpha * d["CA"] + d_alpha * n["CA"]) * d["D2"] * d["CL"]
        + n["D2"] * q * d["CL"]
        + d_alpha * n["D1"] * n["CL"] * d["CA"] * d["D2"]
    )
    den = q * d["D2"] * d["CL"]
    return num.degree + den.degree, min(num.terms + den.terms, TERM_CAP)


@functools.lru_cache(maxsize=256)
def _derive(key: tuple[sp.Expr, ...]) -> StiffnessDerivation:
    """Cached on the element expressions: the derivation does not depend on values."""
    xa, xl, fa, fl = sp.symbols("X_A X_L F_A F_L")
    e = dict(zip(("D1", "D2", "CA", "CL", "m", "b"), key, strict=True))
    alpha = e["m"] * S**2 + e["b"] * S
    deg, terms = _structural_size(key)
    if deg > MAX_MODEL_DEGREE or terms > MAX_MODEL_TERMS:
        raise SymbolicLimitError(
            f"model too large for symbolic derivation (F_L/X_L up to degree {deg} in s and "
            f"{terms} terms after cancelling common denominators; limits {MAX_MODEL_DEGREE} "
            f"and {MAX_MODEL_TERMS}): use lower-order elements"
        )
    with symbolic_time_limit(what="stiffness derivation"):
        return _solve(e, alpha, (xa, xl, fa, fl))


def _solve(
    e: dict[str, sp.Expr], alpha: sp.Expr, syms: tuple[sp.Symbol, ...]
) -> StiffnessDerivation:
    xa, xl, fa, fl = syms
    eqs = (
        sp.Eq(alpha * xa, fa + e["D1"] * (xl - xa)),
        sp.Eq(fl, e["D1"] * (xl - xa) + e["D2"] * xl),
        sp.Eq(fa, e["CA"] * (0 - xa) + e["CL"] * (0 - xl)),
    )
    # Eliminate in turn: F_A from the controller law, then X_A from Newton's law (its
    # coefficient α + D1 + C_A must not vanish), then F_L from the port balance.  This is what
    # a linear solve does, without its general-purpose overhead (2x faster on every model).
    pivot = sp.cancel(sp.together(alpha + e["D1"] + e["CA"]))
    if pivot == 0:
        raise DegenerateModelError("the free-body equations have no unique solution for this model")
    motion = sp.cancel(sp.together((e["D1"] - e["CL"]) / pivot))
    stiffness = sp.cancel(sp.together(e["D1"] * (1 - motion) + e["D2"]))
    if stiffness == 0:
        raise DegenerateModelError("the rendered stiffness is identically zero")
    return StiffnessDerivation(stiffness=stiffness, actuator_motion=motion, equations=eqs)


def paper_eq4_stiffness(sea: SEA) -> sp.Expr:
    """The paper's Eq. (4), exactly as printed, for comparison."""
    e = sea.elements()
    alpha = e["m"] * S**2 + e["b"] * S
    expr = ((e["D1"] + e["D2"]) * (alpha + e["CA"]) + e["D1"] * e["CL"]) / (
        alpha + e["CA"] + e["D1"]
    )
    return sp.cancel(sp.together(expr))


def load_impedance(sea: SEA) -> sp.Expr:
    """``Z_L(s) = F_L / (s X_L)``, Eq. (5), as a cancelled rational function."""
    return _impedance(derive_stiffness(sea).stiffness)


@functools.lru_cache(maxsize=256)
def _impedance(stiffness: sp.Expr) -> sp.Expr:
    return sp.cancel(sp.together(stiffness / S))


def num_den(expr: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """Numerator and denominator polynomials in ``s``, denominator leading coefficient positive."""
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    lead = sp.Poly(den, S).LC()
    if lead.is_negative or (lead.is_number and lead < 0):
        num, den = -num, -den
    return sp.expand(num), sp.expand(den)


def real_part_polynomial(expr: sp.Expr) -> sp.Expr:
    """``Re(N(jω) D(−jω))`` for ``Z = N/D``, collected in powers of ``w`` (ω).

    Its sign equals the sign of ``Re Z(jω)`` wherever ``D(jω) ≠ 0``, Eqs. (6)-(7).
    """
    num, den = num_den(expr)
    nj = sp.expand(num.subs(S, sp.I * W))
    dmj = sp.expand(den.subs(S, -sp.I * W))
    prod = sp.expand(nj * dmj)
    re = sp.expand((prod + sp.conjugate(prod)) / 2)
    return sp.collect(sp.expand(re), W)


def passivity_polynomial(sea: SEA) -> sp.Expr:
    """`real_part_polynomial` of the load impedance of ``sea``."""
    return real_part_polynomial(load_impedance(sea))
