"""The SEA as a two-port, derived from its free-body equations (Laplace domain, zero initial state).

The model of [`seapass.model.stiffness`][seapass.model.stiffness], with the
controllers acting on the error to the virtual environment's position ``θ``:

* actuator, Newton's law: ``(m s² + b s) X_A = F_A + D1 (X_L − X_A)``
* massless load port, force balance: ``F_L = D1 (X_L − X_A) + D2 X_L``
* controller: ``F_A = C_A (Θ − X_A) + C_L (Θ − X_L)``
* port 2 is the virtual environment: ``F_2 = F_A``, ``v_2 = s Θ``.

Port 1 is the person (``F_L``, ``v_L = s X_L``, as in the one-port analysis).
The power into the two-port is ``F_L v_L + F_2 v_2`` and a passive termination
on either port obeys ``F = −Z_term v``: the environment feels ``−F_2`` (Newton's
third law), so a virtual mass obeys ``m_e s v_2 = −F_2``.

The equations are solved symbolically for ``F_L`` and ``F_2`` with both port
velocities given; the impedance matrix follows as
``z_ij = ∂F_i / ∂(s X_j)``.  With ``θ`` held at 0, ``z11`` is the one-port
``Z_L`` exactly (tested on every catalog design).  `friction_equations` cut a
static element out of the plant as port 2 instead (see
[`seapass.ports.friction`][seapass.ports.friction]).

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Eqs. (1)-(5).
.. [2] R. J. Adams and B. Hannaford, "Stable haptic interaction with virtual
   environments", IEEE Trans. Robot. Autom. 15(3), 1999.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from ..errors import DegenerateModelError, ParameterError, SymbolicLimitError
from ..files.limits import MAX_MODEL_DEGREE, MAX_MODEL_TERMS
from ..model.budget import symbolic_time_limit
from ..model.expr import S
from ..model.sea import SEA
from ..model.stiffness import model_size
from .ratfunc import from_sympy, to_sympy, variables_of

__all__ = [
    "FRICTION_SITES",
    "PortEquations",
    "derive_two_port",
    "equation",
    "port_equations",
    "solve_ports",
]

FRICTION_SITES = ("actuator", "transmission")
"""Where a static element can be cut out of the plant as port 2."""

_X_A, _F_A, _F_L, _F_2, _X_L, _X_2 = sp.symbols("X_A F_A F_L F_2 X_L X_2")


@dataclass(frozen=True, kw_only=True)
class PortEquations:
    """The free-body equations of a two-port and the impedance matrix they give.

    Attributes
    ----------
    equations : tuple of sympy.Eq
        In the port positions ``X_L`` (port 1) and ``X_2`` (port 2, ``Θ`` for the
        virtual environment), the internal unknowns and the port forces.
    entries : (z11, z12, z21, z22)
        ``z_ij = ∂F_i/∂(s X_j)``, each a cancelled rational function of ``s``.
    port2 : str
        What port 2 is (``"virtual environment"``, ``"actuator friction"``, ...).
    """

    equations: tuple[sp.Eq, ...]
    entries: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]
    port2: str


def derive_two_port(sea: SEA) -> PortEquations:
    """The impedance matrix of ``sea`` between the person and the virtual environment.

    Parameters
    ----------
    sea : SEA
        The design; its parameter values are not substituted.

    Returns
    -------
    PortEquations

    Examples
    --------
    >>> from seapass.model.sea import SEA
    >>> z = derive_two_port(SEA(D1="k1", CA="kd")).entries
    >>> z[1] == z[2]   # a spring coupling is reciprocal
    True
    """
    return port_equations(sea, "environment")


def port_equations(sea: SEA, site: str) -> PortEquations:
    """`PortEquations` with port 2 at ``site``: ``"environment"`` or one of `FRICTION_SITES`."""
    if site not in ("environment", *FRICTION_SITES):
        raise ParameterError(
            f"at: {site!r} is not a place to cut a port; choose one of {', '.join(FRICTION_SITES)}",
            argument="at",
        )
    deg, terms = model_size(sea)
    if deg > MAX_MODEL_DEGREE or terms > MAX_MODEL_TERMS:
        raise SymbolicLimitError(
            f"model too large for the two-port derivation (up to degree {deg} in s and {terms} "
            f"terms; limits {MAX_MODEL_DEGREE} and {MAX_MODEL_TERMS}): use lower-order elements"
        )
    e = sea.elements()
    key = tuple(e[k] for k in ("D1", "D2", "CA", "CL", "m", "b"))
    return _derive(key, site)


def equation(lhs: sp.Expr, rhs: sp.Expr) -> sp.Eq:
    """``lhs = rhs`` as an unevaluated ``sympy.Eq`` (no costly equality test)."""
    return sp.Eq(lhs, rhs, evaluate=False)


@functools.lru_cache(maxsize=256)
def _derive(key: tuple[sp.Expr, ...], site: str) -> PortEquations:
    d1, d2, ca, cl, m, b = key
    alpha = m * S**2 + b * S
    eqs: tuple[sp.Eq, ...]
    if site == "environment":
        eqs = (
            equation(alpha * _X_A, _F_A + d1 * (_X_L - _X_A)),
            equation(_F_L, d1 * (_X_L - _X_A) + d2 * _X_L),
            equation(_F_A, ca * (_X_2 - _X_A) + cl * (_X_2 - _X_L)),
            equation(_F_2, _F_A),
        )
        unknowns: Sequence[sp.Symbol] = (_X_A, _F_A, _F_L, _F_2)
        what = "virtual environment"
    elif site == "actuator":
        # port 2 is the friction on the actuator: its velocity is s X_A, X_2 = X_A
        eqs = (
            equation(alpha * _X_2, _F_A + d1 * (_X_L - _X_2) + _F_2),
            equation(_F_L, d1 * (_X_L - _X_2) + d2 * _X_L),
            equation(_F_A, ca * (0 - _X_2) + cl * (0 - _X_L)),
        )
        unknowns = (_F_A, _F_L, _F_2)
        what = "actuator friction"
    else:
        # port 2 is a friction element in parallel with D1: stretch X_2 = X_L − X_A, force −F_2
        eqs = (
            equation(alpha * _X_A, _F_A + d1 * _X_2 - _F_2),
            equation(_F_L, d1 * _X_2 + d2 * _X_L - _F_2),
            equation(_F_A, ca * (0 - _X_A) + cl * (0 - _X_L)),
            equation(_X_2, _X_L - _X_A),
        )
        unknowns = (_X_A, _F_A, _F_L, _F_2)
        what = "transmission friction"
    with symbolic_time_limit(what="two-port derivation"):
        z = solve_ports(eqs, unknowns, (_F_L, _F_2), (_X_L, _X_2))
        entries = (z[0], z[1], z[2], z[3])
    if entries[0] == 0:
        raise DegenerateModelError("the rendered stiffness is identically zero")
    return PortEquations(equations=eqs, entries=entries, port2=what)


def solve_ports(
    eqs: Sequence[sp.Eq],
    unknowns: Sequence[sp.Symbol],
    forces: Sequence[sp.Symbol],
    positions: Sequence[sp.Symbol],
) -> list[sp.Expr]:
    """``z_ij = ∂F_i/∂(s X_j)`` of linear equations (row-major), by exact elimination.

    The equations are ``A u + B x = 0`` in the unknowns ``u`` (the port forces
    ``forces`` among them) and the port positions ``x``; Gauss–Jordan
    elimination with exact rational functions
    ([`Frac`][seapass.ports.ratfunc.Frac]) gives ``u = −A⁻¹ B x``.
    """
    columns = [*unknowns, *positions]
    mat, _rhs = sp.linear_eq_to_matrix([e.lhs - e.rhs for e in eqs], columns)
    names = variables_of(mat)
    rows = [[from_sympy(mat[r, c], names) for c in range(len(columns))] for r in range(len(eqs))]
    n = len(unknowns)
    solved: dict[int, int] = {}  # unknown column -> its pivot row
    while len(solved) < n:
        # the simplest nonzero pivot among the unknowns left: least fill-in, small fractions
        best = None
        for col in (c for c in range(n) if c not in solved):
            for r in (r for r in range(len(rows)) if r not in solved.values()):
                f = rows[r][col]
                if not f.is_zero():
                    cost = f.size()
                    if best is None or cost < best[0]:
                        best = (cost, r, col)
        if best is None:
            raise DegenerateModelError(
                "the free-body equations have no unique solution for this model"
            )
        _cost, pr, col = best
        inv = rows[pr][col]
        rows[pr] = [x / inv if not x.is_zero() else x for x in rows[pr]]
        for r in range(len(rows)):
            if r != pr and not rows[r][col].is_zero():
                f = rows[r][col]
                rows[r] = [
                    a if b.is_zero() else a - f * b for a, b in zip(rows[r], rows[pr], strict=True)
                ]
        solved[col] = pr
    rows = [rows[solved[c]] for c in range(n)]
    s_frac = from_sympy(S, names)
    out = []
    for force in forces:
        r = list(unknowns).index(force)
        for c in range(n, n + len(positions)):  # u = -B x after elimination: z = -coef / s
            out.append(to_sympy(-rows[r][c] / s_frac))
    return out
