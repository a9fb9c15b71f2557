"""Independent floating-point evaluation of two-port conditions, for cross-checks only.

Written separately from ``seapass.ports``: the entries are lambdified from the
sympy expressions with the values substituted (no flint, no exact kernel), the
conditions are evaluated on a dense logarithmic grid, and every local minimum of
the grid is refined with ``scipy.optimize.minimize_scalar``.  Also the physical
closed loop of an SEA with a person and a virtual environment attached, as a
second-order system ``M q'' + C q' + K q = 0``.
"""

from __future__ import annotations

import itertools
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


TERMINATION = sp.symbols("m_h b_h k_h m_v b_v k_v")


def sea_characteristic(
    model: dict[str, str], values: dict[str, float]
) -> tuple[Callable[[np.ndarray], np.ndarray], int]:
    """The characteristic polynomial of any SEA held by a person and a virtual environment.

    ``model`` holds the element expressions ``D1, D2, CA, CL`` (absent: 0).  Written
    out by hand in ``(X_A, X_L, Θ)`` (Laplace domain), each row multiplied by ``s``:
    actuator ``(m s² + b s + D1 + C_A) X_A + (C_L − D1) X_L − (C_A + C_L) Θ = 0``,
    person ``(D1 + D2 + m_h s² + b_h s + k_h) X_L − D1 X_A = 0``,
    environment ``−C_A X_A − C_L X_L + (C_A + C_L + m_v s² + b_v s + k_v) Θ = 0``
    (``F_2 = f_A = −Z_v s Θ``).  The determinant is expanded with sympy and the powers
    of ``s`` common to every termination are divided out.  Returns ``coeffs(env)``, the
    coefficients (highest first) for each row ``env = (m_h, b_h, k_h, m_v, b_v, k_v)``,
    shape ``(len(env), degree + 1)``, and the degree.
    """
    s = sp.Symbol("s")
    m_h, b_h, k_h, m_v, b_v, k_v = TERMINATION
    vals = {sp.Symbol(k): sp.Rational(v) for k, v in values.items()}
    d1, d2, ca, cl = (
        sp.sympify(model.get(k, "0")).xreplace(vals) for k in ("D1", "D2", "CA", "CL")
    )
    m, b = vals[sp.Symbol("m")], vals[sp.Symbol("b")]
    mat = sp.Matrix(
        [
            [m * s**2 + b * s + d1 + ca, cl - d1, -(ca + cl)],
            [-d1, d1 + d2 + m_h * s**2 + b_h * s + k_h, 0],
            [-ca, -cl, ca + cl + m_v * s**2 + b_v * s + k_v],
        ]
    )
    det = sp.cancel(sp.expand((s * mat).det(method="berkowitz")))
    num, den = sp.fraction(det)
    assert not den.free_symbols  # rows times s clear every 1/s of the catalog's elements
    poly = sp.Poly(num, s)
    coeffs = poly.all_coeffs()
    while coeffs and sp.expand(coeffs[-1]) == 0:  # a root at 0 for every termination
        coeffs.pop()
    fns = [sp.lambdify(TERMINATION, c, "numpy") for c in coeffs]

    def f(env: np.ndarray) -> np.ndarray:
        env = np.atleast_2d(env)
        cols = [env[:, i] for i in range(6)]
        return np.stack([np.broadcast_to(np.asarray(fn(*cols), float), (env.shape[0],))
                         for fn in fns], axis=1)  # fmt: skip

    return f, len(coeffs) - 1


def batched_roots(coeffs: np.ndarray) -> np.ndarray:
    """Roots of each row of ``coeffs`` (highest first, nonzero leading coefficient)."""
    c = coeffs / coeffs[:, :1]
    n = c.shape[1] - 1
    comp = np.zeros((c.shape[0], n, n))
    comp[:, 0, :] = -c[:, 1:]
    comp[:, np.arange(1, n), np.arange(n - 1)] = 1.0
    return np.linalg.eigvals(comp)


def exact_coefficients(model: dict[str, str], values: dict[str, float], env) -> list:
    """`sea_characteristic`'s coefficients at one termination pair, as exact rationals."""
    s = sp.Symbol("s")
    m_h, b_h, k_h, m_v, b_v, k_v = TERMINATION
    vals = {sp.Symbol(k): sp.Rational(v) for k, v in values.items()}
    vals |= {t: sp.Rational(float(x)) for t, x in zip(TERMINATION, env, strict=True)}
    d1, d2, ca, cl = (
        sp.sympify(model.get(k, "0")).xreplace(vals) for k in ("D1", "D2", "CA", "CL")
    )
    m, b = vals[sp.Symbol("m")], vals[sp.Symbol("b")]
    mat = sp.Matrix(
        [
            [m * s**2 + b * s + d1 + ca, cl - d1, -(ca + cl)],
            [-d1, d1 + d2 + vals[m_h] * s**2 + vals[b_h] * s + vals[k_h], 0],
            [-ca, -cl, ca + cl + vals[m_v] * s**2 + vals[b_v] * s + vals[k_v]],
        ]
    )
    num, den = sp.fraction(sp.cancel(sp.expand((s * mat).det(method="berkowitz"))))
    assert not den.free_symbols
    coeffs = sp.Poly(num, s).all_coeffs()
    while coeffs and coeffs[-1] == 0:
        coeffs.pop()
    return coeffs


def routh_rhp_count(coeffs: list) -> int:
    """Roots in the open right half-plane of an exact polynomial (highest first), by Routh's
    array; raises ``ArithmeticError`` on a zero in the first column (a special case)."""
    from fractions import Fraction

    c = [Fraction(int(sp.numer(x)), int(sp.denom(x))) for x in coeffs]
    rows = [c[0::2], c[1::2]]
    width = len(rows[0])
    rows = [r + [Fraction(0)] * (width - len(r)) for r in rows]
    for _ in range(len(c) - 2):
        a, b = rows[-2], rows[-1]
        if b[0] == 0:
            raise ArithmeticError("a zero in the first column of the Routh array")
        rows.append(
            [(b[0] * a[i + 1] - a[0] * b[i + 1]) / b[0] for i in range(width - 1)] + [Fraction(0)]
        )
    first = [r[0] for r in rows]
    return sum((x > 0) != (y > 0) for x, y in itertools.pairwise(first))
