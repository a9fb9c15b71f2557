"""Independent floating-point evaluation of two-port conditions, for cross-checks only.

Written separately from ``seapass.ports``: the entries are lambdified from the
sympy expressions with the values substituted (no flint, no exact kernel), the
conditions are evaluated on a dense logarithmic grid, and every local minimum of
the grid is refined with ``scipy.optimize.minimize_scalar``.  Also the physical
closed loop of an SEA with a person and a virtual environment attached, as a
second-order system ``M q'' + C q' + K q = 0``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import sympy as sp
from scipy.optimize import minimize_scalar

from seapass.model.expr import S, symbol

OMEGA = np.geomspace(1e-3, 1e5, 40_000)


def matrix_function(entries, values, n: int = 2) -> Callable[[np.ndarray], np.ndarray]:
    """``ω ↦ P(jω)``, shape ``(len(ω), n, n)``, from sympy entries and values (floats)."""
    subs = {symbol(k): sp.Rational(v) for k, v in values.items() if v is not None}
    fns = [sp.lambdify(S, sp.sympify(e).xreplace(subs), "numpy") for e in entries]

    def f(w: np.ndarray) -> np.ndarray:
        s = 1j * np.atleast_1d(np.asarray(w, dtype=float))
        out = np.empty((s.size, n, n), dtype=complex)
        with np.errstate(all="ignore"):
            for k, fn in enumerate(fns):
                out[:, k // n, k % n] = np.broadcast_to(fn(s), s.shape)
        return out

    return f


def llewellyn_terms(p: np.ndarray) -> dict[str, np.ndarray]:
    """Re p11, Re p22, Llewellyn's expression and η at each frequency."""
    q = p[:, 0, 1] * p[:, 1, 0]
    a = 2 * p[:, 0, 0].real * p[:, 1, 1].real - q.real
    with np.errstate(all="ignore"):
        eta = a / np.abs(q)
    return {
        "re_p11": p[:, 0, 0].real,
        "re_p22": p[:, 1, 1].real,
        "llewellyn": a - np.abs(q),
        "eta": eta,
    }


def min_eig_hermitian(p: np.ndarray) -> np.ndarray:
    h = p + np.conj(np.swapaxes(p, -1, -2))
    return np.linalg.eigvalsh(h)[:, 0]


def refined_minimum(g: Callable[[float], float], w: np.ndarray = OMEGA) -> tuple[float, float]:
    """``(min g, argmin)`` over ``w`` and local refinements around every grid minimum."""
    vals = np.array([g(x) for x in w]) if not hasattr(g, "vectorized") else g(w)
    vals = np.where(np.isfinite(vals), vals, np.inf)
    best_v, best_w = float(vals.min()), float(w[int(vals.argmin())])
    idx = np.where((vals[1:-1] <= vals[:-2]) & (vals[1:-1] <= vals[2:]))[0] + 1
    for i in idx[np.argsort(vals[idx])][:20]:
        lo, hi = np.log(w[i - 1]), np.log(w[i + 1])
        r = minimize_scalar(lambda t: g(float(np.exp(t))), bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-12})  # fmt: skip
        if np.isfinite(r.fun) and r.fun < best_v:
            best_v, best_w = float(r.fun), float(np.exp(r.x))
    return best_v, best_w


def vectorized(f: Callable[[np.ndarray], np.ndarray]) -> Callable:
    """Mark a vectorized function for `refined_minimum` (it also accepts scalars)."""

    def g(x):
        out = f(np.atleast_1d(x))
        return out if np.ndim(x) else float(out[0])

    g.vectorized = True  # type: ignore[attr-defined]
    return g


def sea_closed_loop_poles(par: dict[str, float], env: np.ndarray) -> np.ndarray:
    """Poles of an SEA (D1 = k1 + b1 s, C_A = kd + bd s, C_L = kl) held by a person (port 1)
    and a virtual environment (port 2): ``env[:, 0:3] = (m, b, k)`` of the person and
    ``env[:, 3:6]`` of the environment (masses > 0).  Shape ``(len(env), 6)``.

    Free-body equations in ``q = (x_A, x_L, θ)``, written out by hand:
    actuator ``m ẍ_A + b ẋ_A = f_A + k1 (x_L − x_A) + b1 (ẋ_L − ẋ_A)``,
    person ``m_h ẍ_L + b_h ẋ_L + k_h x_L = −(k1 (x_L − x_A) + b1 (ẋ_L − ẋ_A))``,
    environment ``m_v θ̈ + b_v θ̇ + k_v θ = −f_A``,
    controller ``f_A = kd (θ − x_A) + bd (θ̇ − ẋ_A) + kl (θ − x_L)``.
    """
    m, b, k1, b1, kd, bd, kl = (par[k] for k in ("m", "b", "k1", "b1", "kd", "bd", "kl"))
    n = env.shape[0]
    mh, bh, kh, mv, bv, kv = (env[:, i] for i in range(6))
    M = np.zeros((n, 3))
    M[:, 0], M[:, 1], M[:, 2] = m, mh, mv
    C = np.zeros((n, 3, 3))
    K = np.zeros((n, 3, 3))
    C[:, 0] = [b + b1 + bd, -b1, -bd]
    K[:, 0] = [k1 + kd, kl - k1, -(kd + kl)]
    C[:, 1, 0], C[:, 1, 1] = -b1, bh + b1
    K[:, 1, 0], K[:, 1, 1] = -k1, kh + k1
    C[:, 2, 0], C[:, 2, 2] = -bd, bv + bd
    K[:, 2, 0], K[:, 2, 1], K[:, 2, 2] = -kd, -kl, kv + kd + kl
    A = np.zeros((n, 6, 6))
    A[:, :3, 3:] = np.eye(3)
    A[:, 3:, :3] = -K / M[:, :, None]
    A[:, 3:, 3:] = -C / M[:, :, None]
    return np.linalg.eigvals(A)
