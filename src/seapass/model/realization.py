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
from .minimal import ControllerRealization, controller_realization, observable_arrays
from .sea import SEA, unrealizable_controllers
from .zcontroller import continuous_only

__all__ = [
    "INPUTS",
    "OUTPUTS",
    "ClosedLoop",
    "closed_loop",
    "closed_loop_factory",
    "plant_realization",
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


@dataclass(frozen=True)
class _Controller:
    """Float form of a `ControllerRealization`: ``f_A = p0·e − p1·v + C ξ``, ``ξ̇ = A ξ + B e``."""

    p0: np.ndarray  # (2,): on the errors (θ_A − x_A, θ_L − x_L)
    p1: np.ndarray  # (2,): on the measured velocities (−v_A, −v_L)
    A: np.ndarray
    B: np.ndarray  # (n, 2)
    C: np.ndarray

    @classmethod
    def of(cls, k: ControllerRealization) -> _Controller:
        A, B, C = k.arrays()
        return cls(
            np.array([float(c) for c in k.proportional]),
            np.array([float(c) for c in k.derivative]),
            A,
            B,
            C,
        )


def _assemble(
    m: float,
    b: float,
    load_mass: float,
    elems: Mapping[str, _Element | None],
    ctrl: _Controller,
) -> ClosedLoop:
    names = ["x_A", "v_A", "x_L", "v_L"]
    offsets: dict[str, int] = {}
    for key in ("D1", "D2"):
        e = elems.get(key)
        offsets[key] = len(names)
        if e is not None:
            names += [f"{key}_z{i}" for i in range(e.A.shape[0])]
    ok = len(names)
    nk = ctrl.A.shape[0]
    names += [f"K_z{i}" for i in range(nk)]
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
        if k:
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
    # the controller: one system with the two errors in, f_A out (derivative on measurement)
    errors = (th_a - xa, th_l - xl)
    fa = ctrl.p0[0] * errors[0] - ctrl.p1[0] * va + ctrl.p0[1] * errors[1] - ctrl.p1[1] * vl
    if nk:
        fa[ok:n] += ctrl.C
        M[ok:n, :] = np.outer(ctrl.B[:, 0], errors[0]) + np.outer(ctrl.B[:, 1], errors[1])
        M[ok:n, ok:n] += ctrl.A
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

    The controller ``K(s) = [C_A  C_L]`` is one minimal system
    ([`controller_realization`][seapass.model.minimal.controller_realization]): a pole
    that ``C_A`` and ``C_L`` share (a force loop's integrator) is one state.

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
    continuous_only(sea, "the continuous closed loop")
    load_mass = finite_number(load_mass, "load mass m_L", positive=True)
    subs, m, b = _plant_values(sea, values)
    if m <= 0:
        raise ParameterError(f"actuator mass m must be positive, got {m:g}")
    elems: dict[str, _Element | None] = {}
    for key in ("D1", "D2"):
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
    ctrl = _Controller.of(controller_realization(sea, values=values))
    return _assemble(m, b, load_mass, elems, ctrl)


def plant_realization(
    sea: SEA, *, load_mass: float, values: Mapping[str, float] | None = None
) -> ClosedLoop:
    """The plant alone (no controller) with a load mass, driven by the actuator force.

    The same realization as [`closed_loop`][seapass.model.realization.closed_loop] (any
    rational ``D1``, ``D2`` with at most one derivative: ``p0 + p1 s`` + a strictly proper
    part in controllable canonical form), with the controller left out: the input slot
    ``theta_A`` of the result carries the actuator force ``f_A`` (N), ``theta_L`` does
    nothing and ``f_ext`` is the external force on the load.  A controller given in ``z``
    is allowed (it is not part of the plant), so the sampled loop can run on this.

    Raises
    ------
    ParameterError
        For a non-positive load mass or mass ``m``, or a plant parameter without a value.
    UnrealizableError
        For ``D1`` or ``D2`` with two derivatives or more (an inerter needs accelerations).

    Examples
    --------
    >>> p = plant_realization(SEA(D1="k1*(1 + s/50)/(1 + s/500)", D2="b2*s",
    ...                           values=dict(m=1, b=10, k1=1000, b2=2)), load_mass=2.0)
    >>> p.states, p.B[:, 0].tolist()
    (('x_A', 'v_A', 'x_L', 'v_L', 'D1_z0'), [0.0, 1.0, 0.0, 0.0, 0.0])
    """
    from .elements import exact_values

    load_mass = finite_number(load_mass, "load mass m_L", positive=True)
    env = exact_values({**sea.values, **(values or {})})
    exact = sea.exact_elements()
    nums: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for key in ("m", "b", "D1", "D2"):
        missing = sorted(exact[key].parameters() - set(env))
        if missing:
            raise ParameterError(
                f"{key} needs values for {', '.join(missing)}; give them, "
                f"e.g. values={{{missing[0]!r}: 1.0}}"
            )
        pn, pd = exact[key].evaluate(env)
        nums[key] = (
            np.array([float(c) for c in reversed(pn.coeffs())] or [0.0]),
            np.array([float(c) for c in reversed(pd.coeffs())]),
        )
    m, b = (float(nums[k][0][-1] / nums[k][1][-1]) for k in ("m", "b"))
    if m <= 0:
        raise ParameterError(f"actuator mass m must be positive, got {m:g}")
    elems: dict[str, _Element | None] = {}
    for key in ("D1", "D2"):
        fnum, fden = nums[key]
        elems[key] = (
            None if not np.any(fnum) else _realize(fnum, fden, f"{key} = {getattr(sea, key)}")
        )
    none = _Controller(np.zeros(2), np.zeros(2), np.zeros((0, 0)), np.zeros((0, 2)), np.zeros(0))
    loop = _assemble(m, b, load_mass, elems, none)
    B = np.array(loop.B)
    B[:, 0], B[1, 0] = 0.0, 1.0 / m  # the force enters the actuator's momentum only
    D = np.zeros((7, 3))
    D[4, 0] = 1.0  # f_A is the input itself
    D[6] = loop.D[6]
    return ClosedLoop(A=loop.A, B=B, C=loop.C, D=D, states=loop.states,
                      load_mass=load_mass, relaxed=loop.relaxed)  # fmt: skip


def _joint_coefficients(
    exprs: Sequence[sp.Expr], syms: Sequence[sp.Symbol]
) -> tuple[list[list[sp.Expr]], list[sp.Expr]]:
    """Descending ``s``-coefficients of ``[N_A D/D_A, N_L D/D_L]`` and ``D = lcm(D_A, D_L)``
    with the gains ``syms`` symbolic (the gcd is taken in ``Q[s, gains]``)."""
    fracs = [sp.fraction(sp.cancel(sp.together(e))) for e in exprs]
    dens = [d for _n, d in fracs]
    g = sp.gcd(dens[0], dens[1])
    rest = [sp.cancel(dens[1] / g), sp.cancel(dens[0] / g)]
    den = sp.expand(dens[0] * rest[0])
    nums = [sp.expand(fracs[0][0] * rest[0]), sp.expand(fracs[1][0] * rest[1])]

    def desc(e: sp.Expr) -> list[sp.Expr]:
        return [sp.sympify(c) for c in sp.Poly(e, S).all_coeffs()]

    return [desc(n) for n in nums], desc(den)


def _numeric_controller(
    nums: Sequence[np.ndarray], den: np.ndarray, names: Sequence[str]
) -> _Controller:
    """The float `_Controller` of ``[N_A, N_L]/D`` (descending coefficients)."""
    den = np.trim_zeros(np.asarray(den, dtype=float), "f")
    if den.size == 0:
        raise SimulationError("the controller has a denominator that is zero for these values")
    lead = den[0]
    den = den / lead
    n = den.size - 1
    p0, p1, rem = np.zeros(2), np.zeros(2), []
    for i, (num, name) in enumerate(zip(nums, names, strict=True)):
        num = np.trim_zeros(np.asarray(num, dtype=float), "f") / lead
        excess = num.size - den.size
        if excess > 1:
            raise UnrealizableError(
                f"{name} is improper with {excess} more zeros than poles: the simulator "
                "measures only positions and velocities, so at most one derivative "
                "(e.g. 'kd + bd*s') is realizable; add filter poles, "
                "e.g. 'kd + bd*s/(1 + s/500)'"
            )
        q, r = np.polydiv(num, den) if num.size and excess >= 0 else (np.zeros(1), num)
        q = np.atleast_1d(q)[::-1]
        p0[i] = float(q[0]) if q.size > 0 else 0.0
        p1[i] = float(q[1]) if q.size > 1 else 0.0
        r = np.atleast_1d(r)[::-1][:n]
        rem.append(np.concatenate([r, np.zeros(n - r.size)]))
    A, B, C = observable_arrays(den[::-1], rem)
    return _Controller(p0, p1, A, B, C)


def closed_loop_factory(
    sea: SEA, params: Sequence[str], *, load_mass: float
) -> Callable[[Sequence[float]], ClosedLoop]:
    """A fast builder ``f(param_values) -> ClosedLoop`` for repeated evaluation (tuning).

    The element coefficients are compiled once as numeric functions of
    ``params``; other parameters take their values from ``sea``.  The controller
    row is put over its common denominator once, with the gains symbolic (so a
    pole both elements share is one state at every gain); unlike `closed_loop`
    no exact cancellation is done per call, so a common factor appearing at
    special values leaves a (harmless, cancelled) mode.
    """
    continuous_only(sea, "the continuous closed loop")
    load_mass = finite_number(load_mass, "load mass m_L", positive=True)
    syms = [symbol(p) for p in params]
    fixed = {k: v for k, v in sea.substitutions().items() if str(k) not in params}
    m = float(sp.sympify(sea.m).xreplace(fixed))
    b = float(sp.sympify(sea.b).xreplace(fixed))
    funcs: dict[str, Any] = {}
    exprs = {}
    for key in ("D1", "D2", "CA", "CL"):
        expr = sp.sympify(getattr(sea, key)).xreplace(fixed)
        extra = sorted(str(x) for x in expr.free_symbols if x != S and x not in syms)
        if extra:
            raise ParameterError(f"{key} needs values for {', '.join(extra)}")
        exprs[key] = expr
        if key in ("CA", "CL"):
            continue
        if expr == 0:
            funcs[key] = None
            continue
        pn, pd = _coeffs(expr)
        funcs[key] = sp.lambdify([syms], [pn.all_coeffs(), pd.all_coeffs()], "numpy")
    knums, kden = _joint_coefficients([exprs["CA"], exprs["CL"]], syms)
    kfunc = sp.lambdify([syms], [knums[0], knums[1], kden], "numpy")

    def build(x: Sequence[float]) -> ClosedLoop:
        elems: dict[str, _Element | None] = {}
        for key, fn in funcs.items():
            if fn is None:
                elems[key] = None
                continue
            num, den = fn(list(x))
            elems[key] = _realize(np.array(num, float), np.array(den, float), key)
        na, nl, dk = kfunc(list(x))
        ctrl = _numeric_controller(
            [np.array(na, float), np.array(nl, float)], np.array(dk, float), ("CA", "CL")
        )
        return _assemble(m, b, load_mass, elems, ctrl)

    return build
