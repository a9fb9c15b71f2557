"""The free-body equations of an SEA solved exactly: ``F_L/X_L`` and ``Z_L`` without sympy.

The same model as [`seapass.model.stiffness`][seapass.model.stiffness] (Laplace
domain, zero initial conditions, references zero), written as linear equations in
the unknowns ``X_A, X_L, F_A, F_L`` with exact rational-function coefficients
([`RatFunc`][seapass.model.rational.RatFunc], ``α = m s² + b s``):

* actuator, Newton's law: ``α X_A − F_A − D1 (X_L − X_A) = 0``
* massless load port, force balance: ``F_L − D1 (X_L − X_A) − D2 X_L = 0``
* controller: ``F_A + C_A X_A + C_L X_L = 0``

`derive` eliminates ``F_A`` with the controller law and solves the remaining 2×2
system in ``X_A, X_L`` for the input ``F_L`` by Cramer's rule, so
``F_L/X_L = det A / det A_L`` and ``X_A/X_L = det A_A / det A_L`` (``A_A``, ``A_L``:
``A`` with the column of ``X_A``, ``X_L`` replaced by the right-hand side).  Every
entry is a rational function of ``s`` and the parameters, reduced by the exact gcd at
each step, so the result equals sympy's ``cancel`` of the same expression and the
factors that cancel only at particular values stay (they are hidden modes).

What lives here: `FreeBody`, `derive`.  May import: [`seapass.errors`][seapass.errors]
and the modules of [`seapass.model`][seapass.model] below it (`rational`, `sea`).
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Mapping
from dataclasses import dataclass

from ..errors import DegenerateModelError, SymbolicLimitError
from .rational import RatFunc
from .sea import SEA, Impedance

__all__ = ["UNKNOWNS", "FreeBody", "derive", "exact_impedance"]

UNKNOWNS = ("X_A", "X_L", "F_A", "F_L")
"""The unknowns of the free-body equations (``F_L`` is the port input)."""

Equation = Mapping[str, RatFunc]
"""A linear equation ``Σ coefficient × unknown = 0``, as ``{unknown: coefficient}``."""


@dataclass(frozen=True, kw_only=True)
class FreeBody:
    """The exact solution of the free-body equations of one model (no values substituted).

    Attributes
    ----------
    equations : tuple of mapping
        The three equations as ``{unknown: coefficient}`` (``Σ = 0``).
    stiffness : RatFunc
        ``F_L/X_L``, reduced.
    actuator_motion : RatFunc
        ``X_A/X_L`` with the port held.
    impedance : RatFunc
        ``Z_L = F_L/(s X_L)``, reduced.
    """

    equations: tuple[Equation, ...]
    stiffness: RatFunc
    actuator_motion: RatFunc
    impedance: RatFunc


def free_body_equations(e: Mapping[str, RatFunc]) -> tuple[Equation, ...]:
    """The three equations of the module docstring, from the elements ``D1 D2 CA CL m b``."""
    s = _variable(e["D1"], "s")
    one = _constant(e["D1"], 1)
    alpha = e["m"] * s * s + e["b"] * s
    newton = {"X_A": alpha + e["D1"], "X_L": -e["D1"], "F_A": -one}
    port = {"F_L": one, "X_L": -(e["D1"] + e["D2"]), "X_A": e["D1"]}
    control = {"F_A": one, "X_A": e["CA"], "X_L": e["CL"]}
    return newton, port, control


def _eliminate(target: Equation, pivot: Equation, unknown: str) -> dict[str, RatFunc]:
    """``target − (target[u]/pivot[u]) pivot``: ``target`` without the unknown ``u``."""
    factor = target[unknown] / pivot[unknown]
    out = dict(target)
    for name, coeff in pivot.items():
        out[name] = out[name] - factor * coeff if name in out else -(factor * coeff)
    del out[unknown]
    return out


def _det2(a: RatFunc, b: RatFunc, c: RatFunc, d: RatFunc) -> RatFunc:
    """``det [[a, b], [c, d]]``."""
    return a * d - b * c


def _solve(equations: tuple[Equation, ...]) -> FreeBody:
    newton, port, control = equations
    rows = [_eliminate(newton, control, "F_A"), dict(port)]  # unknowns X_A, X_L; input F_L
    zero = _constant(newton["X_A"], 0)
    a = [[row.get(x, zero) for x in ("X_A", "X_L")] for row in rows]
    rhs = [-row.get("F_L", zero) for row in rows]  # per unit F_L
    det = _det2(a[0][0], a[0][1], a[1][0], a[1][1])
    det_a = _det2(rhs[0], a[0][1], rhs[1], a[1][1])  # X_A column replaced
    det_l = _det2(a[0][0], rhs[0], a[1][0], rhs[1])  # X_L column replaced
    if det_l.is_zero:
        raise DegenerateModelError("the free-body equations have no unique solution for this model")
    stiffness = det / det_l
    if stiffness.is_zero:
        raise DegenerateModelError("the rendered stiffness is identically zero")
    motion = det_a / det_l
    return FreeBody(
        equations=equations,
        stiffness=stiffness,
        actuator_motion=motion,
        impedance=stiffness / _variable(stiffness, "s"),
    )


def derive(sea: SEA) -> FreeBody:
    """Solve the free-body equations of ``sea`` exactly (cached on its elements).

    Raises
    ------
    DegenerateModelError
        When the equations have no unique solution or the stiffness is zero.
    SymbolicLimitError
        When the derivation exceeds the exact size budget
        ([`seapass.files.limits`][seapass.files.limits]).

    Examples
    --------
    >>> num, den = derive(SEA(D1="k1", CL="kd")).stiffness.canonical()
    >>> print(num, "/", den)
    s^2*k1*m + s*b*k1 + k1*kd / s^2*m + s*b + k1
    """
    from .zcontroller import continuous_only

    continuous_only(sea, "the continuous-time analysis")
    key = sea.sources()
    with _LOCK:
        found = _CACHE.get(key)
        if found is not None:
            _CACHE.move_to_end(key)
            return found
    try:
        result = _solve(free_body_equations(sea.exact_elements()))
    except SymbolicLimitError as exc:
        raise SymbolicLimitError(
            f"model too large for exact derivation ({exc}): use lower-order elements"
        ) from None
    with _LOCK:
        _CACHE[key] = result
        if len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    return result


# the derivation depends on the elements only (not on values): cached on their sources
_CACHE: OrderedDict[tuple[object, ...], FreeBody] = OrderedDict()
_CACHE_SIZE = 256
_LOCK = threading.Lock()


def exact_impedance(system: SEA | Impedance) -> RatFunc:
    """``Z`` of ``system`` as an exact rational function: ``Z_L`` of an SEA, or a raw ``Z``."""
    if isinstance(system, SEA):
        return derive(system).impedance
    return system.exact()


def _variable(like: RatFunc, name: str) -> RatFunc:
    return RatFunc.variable(like.context, name)


def _constant(like: RatFunc, value: int) -> RatFunc:
    return RatFunc.constant(like.context, value)
