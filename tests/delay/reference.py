"""Independent numerical references for the delay tests, written apart from ``seapass.delay``.

Nothing here uses the exact structure, the trigonometric real part, the asymptotics or the
balls of ``seapass.delay``:

* `sea_impedance` evaluates ``Z_L(jω)`` of an SEA from the free-body formula with each
  element evaluated numerically (``exp(-tau*s)`` as ``numpy.exp``);
* `min_real_part` is a dense log sweep with local refinement (scipy);
* `rhp_roots_quasi` counts roots of ``p(s) + q(s) e^{-sτ}`` in the right half-plane by the
  argument principle on a sampled contour (numpy phase unwrapping);
* `simulate_ours` integrates the delayed SEA loop coupled to a passive mass-spring-damper
  with RK4 and a history buffer, and books the energy that crosses the port.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable

import numpy as np
import sympy as sp
from scipy.optimize import minimize_scalar


def _numeric(expr: sp.Expr, values: dict[str, float], tau: float) -> Callable:
    return _lambdified(expr, tuple(sorted(values.items())), float(tau))


@functools.lru_cache(maxsize=256)
def _lambdified(expr: sp.Expr, items: tuple[tuple[str, float], ...], tau: float) -> Callable:
    # cached: a refinement evaluates the same element hundreds of times, one point at a time
    values = dict(items)
    s = sp.Symbol("s")
    subs = {}
    for a in expr.atoms(sp.Function):
        if type(a).__name__ == "Delay":
            subs[a] = sp.exp(-sp.Float(tau) * s)
    e = expr.xreplace(subs)
    e = e.xreplace({x: sp.Float(values[str(x)]) for x in e.free_symbols if str(x) != "s"})
    return sp.lambdify(s, e, "numpy")


def sea_impedance(sea, omega: np.ndarray, tau: float) -> np.ndarray:
    """``Z_L(jω) = F_L/(s X_L)`` from the free-body equations (paper Eq. (4) with D2 fixed)."""
    values = {k: float(v) for k, v in sea.values.items() if v is not None}
    s = 1j * np.asarray(omega, dtype=float)
    el = {k: _numeric(getattr(sea, k), values, tau)(s) + 0 * s for k in ("D1", "D2", "CA", "CL")}
    m, b = values.get("m", 1.0), values.get("b", 0.0)
    alpha = m * s**2 + b * s
    d1, d2, ca, cl = el["D1"], el["D2"], el["CA"], el["CL"]
    stiffness = (d1 * (alpha + ca) + d2 * (alpha + ca + d1) + d1 * cl) / (alpha + ca + d1)
    return stiffness / s


def expression_impedance(text: str, values: dict[str, float], omega: np.ndarray, tau: float):
    """``Z(jω)`` of an expression such as ``"m*s + b + K*exp(-tau*s)/s"`` (sympy, numerically)."""
    s = sp.Symbol("s")
    names = {k: sp.Symbol(k) for k in values}
    names["s"] = s
    names["tau"] = sp.Float(tau)
    expr = sp.sympify(text.replace("exp", "sp_exp"), locals={**names, "sp_exp": sp.exp})
    expr = expr.xreplace({sp.Symbol(k): sp.Float(v) for k, v in values.items()})
    return sp.lambdify(s, expr, "numpy")(1j * np.asarray(omega, dtype=float))


def min_real_part(re: Callable[[np.ndarray], np.ndarray], lo: float, hi: float, n: int = 20000):
    """Dense log sweep of ``re`` on ``[lo, hi]``, refined around the 5 smallest samples."""
    w = np.geomspace(lo, hi, n)
    v = re(w)
    best_v, best_w = float(np.min(v)), float(w[int(np.argmin(v))])
    for i in np.argsort(v)[:5]:
        a, b = w[max(i - 1, 0)], w[min(i + 1, n - 1)]
        r = minimize_scalar(lambda x: float(re(np.array([x]))[0]), bounds=(a, b),
                            method="bounded", options={"xatol": 1e-12 * b})  # fmt: skip
        if r.fun < best_v:
            best_v, best_w = float(r.fun), float(r.x)
    return best_v, best_w


def rhp_roots_quasi(p: list[float], q: list[float], tau: float, radius: float,
                    n: int = 400000) -> float:  # fmt: skip
    """Roots of ``p(s) + q(s) e^{-sτ}`` (ascending coefficients) in ``Re s > 0, |s| < radius``.

    Argument principle on the right half-disk, indented around ``s = 0`` by ``1e-9``;
    returns the (real-valued) winding number, which should be close to an integer.
    """

    def f(s):
        return np.polynomial.polynomial.polyval(s, p) + np.polynomial.polynomial.polyval(
            s, q
        ) * np.exp(-s * tau)

    eps = 1e-9
    t = np.linspace(0.0, 1.0, n)
    up = 1j * (eps + (radius - eps) * t)  # along the axis upwards
    arc = radius * np.exp(1j * (np.pi / 2 - np.pi * t))  # right half-circle downwards
    down = 1j * (-radius + (radius - eps) * t)
    small = eps * np.exp(1j * (-np.pi / 2 + np.pi * t))  # around 0 through Re s > 0
    path = np.concatenate([up, arc, down, small])
    phase = np.unwrap(np.angle(f(path)))
    return -(phase[-1] - phase[0]) / (2 * math.pi)  # the path runs clockwise


def simulate_ours(values: dict[str, float], tau: float, env: dict[str, float], *,
                  horizon: float, dt: float, v0: float = 1e-2):  # fmt: skip
    """The delayed design ``D1 = k1 + b1 s``, ``C_A = (kd + bd s) e^{-sτ}`` held by a passive
    environment ``M, B_e, K_e`` (a mass-spring-damper at the port), everything at rest and
    unstretched except the environment's velocity ``v0`` (so the SEA starts with no energy).

    Returns ``(t, port_energy, env_energy)``: the energy absorbed by the SEA port
    ``∫ F_L v_L dt`` and the environment's stored energy.  A passive SEA (zero initial
    internal energy) never lets ``port_energy`` fall below 0.
    """
    m, b, k1, b1 = values["m"], values["b"], values["k1"], values["b1"]
    kd, bd = values["kd"], values["bd"]
    big_m, be, ke = env["M"], env["B"], env["K"]
    lag = max(round(tau / dt), 0)
    steps = round(horizon / dt)
    hist_x = np.zeros(steps + 2)
    hist_v = np.zeros(steps + 2)

    def delayed(buf: np.ndarray, i: float) -> float:
        j = i - lag
        if j <= 0:
            return 0.0
        lo = math.floor(j)
        frac = j - lo
        return buf[lo] * (1 - frac) + buf[min(lo + 1, len(buf) - 1)] * frac

    def rhs(state: np.ndarray, i: float) -> np.ndarray:
        xa, va, xl, vl = state
        fa = -(kd * delayed(hist_x, i) + bd * delayed(hist_v, i))
        ft = k1 * (xl - xa) + b1 * (vl - va)  # transmission force on the actuator
        fl = ft  # port force (massless port, D2 = 0)
        return np.array([va, (fa + ft - b * va) / m, vl, (-fl - be * vl - ke * xl) / big_m])

    state = np.array([0.0, 0.0, 0.0, v0])
    t = np.arange(steps + 1) * dt
    port = np.zeros(steps + 1)
    stored = np.zeros(steps + 1)
    stored[0] = 0.5 * big_m * v0**2
    work = 0.0
    for i in range(steps):
        hist_x[i], hist_v[i] = state[0], state[1]
        k1_ = rhs(state, i)
        k2_ = rhs(state + dt / 2 * k1_, i + 0.5)
        k3_ = rhs(state + dt / 2 * k2_, i + 0.5)
        k4_ = rhs(state + dt * k3_, i + 1)
        new = state + dt / 6 * (k1_ + 2 * k2_ + 2 * k3_ + k4_)

        def power(s_: np.ndarray) -> float:
            xa, va, xl, vl = s_
            return (k1 * (xl - xa) + b1 * (vl - va)) * vl

        work += dt / 2 * (power(state) + power(new))  # trapezoid: energy into the SEA port
        state = new
        port[i + 1] = work
        stored[i + 1] = 0.5 * big_m * state[3] ** 2 + 0.5 * ke * state[2] ** 2
    return t, port, stored
