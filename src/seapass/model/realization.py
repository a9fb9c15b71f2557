"""State-space realization of the SEA closed loop from its rational elements.

Every element is split into ``p0 + p1 s + N(s)/D(s)``; the strictly proper part
is realized in controllable canonical form and the polynomial part acts on
measured positions and velocities (derivative on measurement).  See
[`seapass.sim.simulate`][seapass.sim.simulate] for the plant equations.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from ..errors import ParameterError, SimulationError, UnrealizableError
from .display import html_card, short_repr
from .expr import S, finite_number, symbol
from .sea import SEA, unrealizable_controllers

__all__ = [
    "INPUTS",
    "OUTPUTS",
    "ClosedLoop",
    "closed_loop",
    "closed_loop_factory",
    "unrealizable_controllers",
]

INPUTS = ("theta_A", "theta_L", "f_ext")
OUTPUTS = ("x_A", "v_A", "x_L", "v_L", "f_A", "f_D1", "a_L")


# --------------------------------------------------------------------------- realization


@dataclass(frozen=True)
class _Element:
    p0: float
    p1: float
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray


def _realize(num: np.ndarray, den: np.ndarray, name: str) -> _Element:
    """Split ``num/den`` (descending coefficients) into ``p0 + p1 s`` + a canonical realization."""
    num = np.trim_zeros(np.asarray(num, dtype=float), "f")
    den = np.trim_zeros(np.asarray(den, dtype=float), "f")
    if den.size == 0:
        raise SimulationError(f"{name} has a denominator that is zero for these values")
    if num.size == 0:
        return _Element(0.0, 0.0, np.zeros((0, 0)), np.zeros(0), np.zeros(0))
    num, den = num / den[0], den / den[0]
    degree = num.size - den.size
    if degree > 1:
        raise UnrealizableError(
            f"{name} is improper with {degree} more zeros than poles: the simulator "
            f"measures only positions and velocities, so at most one derivative "
            f"(e.g. 'kd + bd*s') is realizable; add filter poles, "
            f"e.g. 'kd + bd*s/(1 + s/500)'"
        )
    q, r = np.polydiv(num, den) if degree >= 0 else (np.zeros(1), num)
    q = np.atleast_1d(q)[::-1]
    p0 = float(q[0]) if q.size > 0 else 0.0
    p1 = float(q[1]) if q.size > 1 else 0.0
    n = den.size - 1
    r = np.atleast_1d(r)[::-1][:n]
    C = np.zeros(n)
    C[: r.size] = r
    A = np.zeros((n, n))
    if n:
        A[:-1, 1:] = np.eye(n - 1)
        A[-1, :] = -den[::-1][:n]
    B = np.zeros(n)
    if n:
        B[-1] = 1.0
    return _Element(p0, p1, A, B, C)


@dataclass(frozen=True, repr=False, kw_only=True)
class ClosedLoop:
    """Closed-loop state space ``ẋ = A x + B u``, ``y = C x + D u``.

    Attributes
    ----------
    A : ndarray, shape (n, n)
    B : ndarray, shape (n, 3)
        Input columns ``(θ_A, θ_L, f_ext)``, see `INPUTS`.
    C, D : ndarray, shapes (7, n) and (7, 3)
        Output rows ``(x_A, v_A, x_L, v_L, f_A, f_D1, a_L)``, see `OUTPUTS`.
    states : tuple of str
        State names; plant states ``x_A v_A x_L v_L`` first, then element states.
    load_mass : float
    relaxed : ndarray, shape (n, n)
        Maps a plant configuration to the initial state with mechanical
        element states in equilibrium (used by `LoadDisplaced`).
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: tuple[str, ...]
    load_mass: float
    relaxed: np.ndarray

    def __post_init__(self) -> None:
        n = len(self.states)
        shapes = {"A": (n, n), "B": (n, 3), "C": (7, n), "D": (7, 3), "relaxed": (n, n)}
        for attr, shape in shapes.items():
            arr = np.array(getattr(self, attr), dtype=float)
            if arr.shape != shape:
                raise SimulationError(f"ClosedLoop.{attr} has shape {arr.shape}, expected {shape}")
            arr.flags.writeable = False
            object.__setattr__(self, attr, arr)

    @property
    def poles(self) -> np.ndarray:
        """Closed-loop poles (eigenvalues of ``A``)."""
        return np.linalg.eigvals(self.A) if self.A.size else np.zeros(0, dtype=complex)

    def output(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """Rows of ``C`` and ``D`` for output ``name``."""
        i = OUTPUTS.index(name)
        return self.C[i], self.D[i]

    def to_control(self, *, name: str = "closed_loop") -> Any:
        """This loop as a ``control.StateSpace`` with named inputs, outputs and states.

        Inputs `INPUTS` (``theta_A``, ``theta_L``, ``f_ext``), outputs `OUTPUTS`,
        states ``self.states``; e.g. ``sys["x_L", "f_ext"]`` is the load's
        compliance with the load mass attached.
        """
        from .pycontrol import state_space

        return state_space(self, name=name)

    def __repr__(self) -> str:
        p = self.poles
        return short_repr(
            "ClosedLoop",
            {
                "states": len(self.states),
                "load_mass": self.load_mass,
                "max_pole_real_part": float(p.real.max()) if p.size else None,
            },
        )

    def _repr_html_(self) -> str:
        p = self.poles
        return html_card(
            "Closed loop (state space)",
            [
                ("states", ", ".join(self.states)),
                ("inputs", ", ".join(INPUTS)),
                ("outputs", ", ".join(OUTPUTS)),
                ("load mass", f"{self.load_mass:g} kg"),
                ("largest pole real part", f"{p.real.max():.6g} 1/s" if p.size else "-"),
            ],
        )


def _assemble(
    m: float, b: float, load_mass: float, elems: Mapping[str, _Element | None]
) -> ClosedLoop:
    names = ["x_A", "v_A", "x_L", "v_L"]
    offsets: dict[str, int] = {}
    for key in ("D1", "D2", "CA", "CL"):
        e = elems.get(key)
        offsets[key] = len(names)
        if e is not None:
            names += [f"{key}_z{i}" for i in range(e.A.shape[0])]
    n = len(names)
    width = n + 3  # rows act on [state; input]
    unit = np.eye(width)
    xa, va, xl, vl = unit[0], unit[1], unit[2], unit[3]
    th_a, th_l, f_ext = unit[n], unit[n + 1], unit[n + 2]
    M = np.zeros((n, width))
    relaxed = np.eye(n)

    def force(key: str, pos: np.ndarray, vel: np.ndarray) -> np.ndarray:
        e = elems.get(key)
        if e is None:
            return np.zeros(width)
        k = e.A.shape[0]
        o = offsets[key]
        out = e.p0 * pos + e.p1 * vel
        out[o : o + k] += e.C
        M[o : o + k, :] = e.B[:, None] * pos[None, :]
        M[o : o + k, o : o + k] += e.A
        if key in ("D1", "D2") and k:
            # equilibrium z = -A^{-1} B pos for a held deflection, when A is invertible
            try:
                z_per_pos = -np.linalg.solve(e.A, e.B)
            except np.linalg.LinAlgError:
                z_per_pos = np.zeros(k)
            relaxed[o : o + k, :] = 0.0
            relaxed[o : o + k, :] += np.outer(z_per_pos, pos[:n])
        return out

    f1 = force("D1", xl - xa, vl - va)
    f2 = force("D2", xl, vl)
    fa = force("CA", th_a - xa, -va) + force("CL", th_l - xl, -vl)
    M[0] = va
    M[1] = (fa + f1 - b * va) / m
    M[2] = vl
    M[3] = (f_ext - f1 - f2) / load_mass
    out = np.vstack([xa, va, xl, vl, fa, f1, M[3]])
    return ClosedLoop(
        A=M[:, :n],
        B=M[:, n:],
        C=out[:, :n],
        D=out[:, n:],
        states=tuple(names),
        load_mass=load_mass,
        relaxed=relaxed,
    )


def _coeffs(expr: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    return sp.Poly(num, S), sp.Poly(den, S)


def _plant_values(sea: SEA, values: Mapping[str, float] | None) -> tuple[dict, float, float]:
    subs = sea.substitutions(values)
    mb = []
    for attr in ("m", "b"):
        v = sp.sympify(getattr(sea, attr)).xreplace(subs)
        if v.free_symbols:
            names = sorted(map(str, v.free_symbols))
            raise ParameterError(
                f"{attr} needs values for {', '.join(names)}; "
                f"give them, e.g. values={{{names[0]!r}: 1.0}}"
            )
        mb.append(float(v))
    return subs, mb[0], mb[1]


def closed_loop(
    sea: SEA, *, load_mass: float, values: Mapping[str, float] | None = None
) -> ClosedLoop:
    """Build the closed-loop state space of ``sea`` driving a load of mass ``load_mass``.

    Parameters
    ----------
    sea : SEA
        The design; every parameter needs a value (from ``sea.values`` or ``values``).
    load_mass : float
        Load mass ``m_L`` in kg, positive.
    values : mapping, optional
        Extra or overriding parameter values.

    Raises
    ------
    ParameterError
        For a non-positive load mass or a parameter without a value.
    UnrealizableError
        For an element needing accelerations (polynomial part of degree ≥ 2).
    """
    load_mass = finite_number(load_mass, "load mass m_L", positive=True)
    subs, m, b = _plant_values(sea, values)
    if m <= 0:
        raise ParameterError(f"actuator mass m must be positive, got {m:g}")
    elems: dict[str, _Element | None] = {}
    for key in ("D1", "D2", "CA", "CL"):
        expr = sp.sympify(getattr(sea, key)).xreplace(subs)
        missing = sorted(str(x) for x in expr.free_symbols if x != S)
        if missing:
            raise ParameterError(
                f"{key} needs values for {', '.join(missing)}; give them, "
                f"e.g. values={{{missing[0]!r}: 1.0}}"
            )
        if expr == 0:
            elems[key] = None
            continue
        pn, pd = _coeffs(expr)
        num = np.array([float(c) for c in pn.all_coeffs()])
        den = np.array([float(c) for c in pd.all_coeffs()])
        elems[key] = _realize(num, den, f"{key} = {expr}")
    return _assemble(m, b, load_mass, elems)


def closed_loop_factory(
    sea: SEA, params: Sequence[str], *, load_mass: float
) -> Callable[[Sequence[float]], ClosedLoop]:
    """A fast builder ``f(param_values) -> ClosedLoop`` for repeated evaluation (tuning).

    The element coefficients are compiled once as numeric functions of
    ``params``; other parameters take their values from ``sea``.  Unlike
    `closed_loop` no exact cancellation is done per call, so a common
    factor appearing at special values leaves a (harmless, cancelled) mode.
    """
    load_mass = finite_number(load_mass, "load mass m_L", positive=True)
    syms = [symbol(p) for p in params]
    fixed = {k: v for k, v in sea.substitutions().items() if str(k) not in params}
    m = float(sp.sympify(sea.m).xreplace(fixed))
    b = float(sp.sympify(sea.b).xreplace(fixed))
    funcs: dict[str, Any] = {}
    for key in ("D1", "D2", "CA", "CL"):
        expr = sp.sympify(getattr(sea, key)).xreplace(fixed)
        extra = sorted(str(x) for x in expr.free_symbols if x != S and x not in syms)
        if extra:
            raise ParameterError(f"{key} needs values for {', '.join(extra)}")
        if expr == 0:
            funcs[key] = None
            continue
        pn, pd = _coeffs(expr)
        funcs[key] = sp.lambdify([syms], [pn.all_coeffs(), pd.all_coeffs()], "numpy")

    def build(x: Sequence[float]) -> ClosedLoop:
        elems: dict[str, _Element | None] = {}
        for key, fn in funcs.items():
            if fn is None:
                elems[key] = None
                continue
            num, den = fn(list(x))
            elems[key] = _realize(np.array(num, float), np.array(den, float), key)
        return _assemble(m, b, load_mass, elems)

    return build
