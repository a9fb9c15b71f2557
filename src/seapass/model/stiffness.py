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

import sympy as sp

from ..errors import DegenerateModelError, SymbolicLimitError
from ..files.limits import MAX_MODEL_DEGREE, MAX_MODEL_TERMS
from .expr import S, W, symbolic_size, symbolic_time_limit
from .sea import SEA

__all__ = [
    "StiffnessDerivation",
    "derive_stiffness",
    "load_impedance",
    "paper_eq4_stiffness",
    "passivity_polynomial",
    "real_part_polynomial",
]


@dataclass(frozen=True)
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
    e = sea.elements()
    return _derive(tuple(e[k] for k in ("D1", "D2", "CA", "CL", "m", "b")))


# MAX_MODEL_DEGREE, MAX_MODEL_TERMS: the budget of the derivation, checked on a structural
# bound of the closed form before sympy starts (seapass.files.limits, with every limit)


@functools.lru_cache(maxsize=256)
def _derive(key: tuple[sp.Expr, ...]) -> StiffnessDerivation:
    """Cached on the element expressions: the derivation does not depend on values."""
    xa, xl, fa, fl = sp.symbols("X_A X_L F_A F_L")
    e = dict(zip(("D1", "D2", "CA", "CL", "m", "b"), key, strict=True))
    alpha = e["m"] * S**2 + e["b"] * S
    closed = (e["D1"] * (alpha + e["CA"]) + e["D2"] * (alpha + e["CA"] + e["D1"])) / (
        alpha + e["CA"] + e["D1"]
    ) + e["D1"] * e["CL"] / (alpha + e["CA"] + e["D1"])
    deg, terms = symbolic_size(closed)
    if deg > MAX_MODEL_DEGREE or terms > MAX_MODEL_TERMS:
        raise SymbolicLimitError(
            f"model too large for symbolic derivation (up to degree {deg} in s and {terms} "
            f"terms; limits {MAX_MODEL_DEGREE} and {MAX_MODEL_TERMS}): use lower-order elements"
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
    sol = sp.solve(eqs, [xa, fa, fl], dict=True)
    if len(sol) != 1:
        raise DegenerateModelError("the free-body equations have no unique solution for this model")
    stiffness = sp.cancel(sp.together(sol[0][fl] / xl))
    if stiffness == 0:
        raise DegenerateModelError("the rendered stiffness is identically zero")
    motion = sp.cancel(sp.together(sol[0][xa] / xl))
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
