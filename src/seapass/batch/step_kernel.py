"""The closed-loop step transfer function of one configuration, compiled once, and its modal form."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..errors import ParameterError, UnrealizableError
from ..model.expr import S, symbol, to_fraction
from ..model.sea import SEA
from .bank import PolynomialBank
from .cache import LRUCache
from .inputs import check_batch_params

__all__ = [
    "COND_LIMIT",
    "LOAD_MASS",
    "ModalForm",
    "SimKernel",
    "companion_roots",
    "compile_step_response",
    "poly_at",
]


LOAD_MASS = "m_L"


COND_LIMIT = 1e6  # Σ|r_i| / |step| above which the modal form is not trusted


def _reference_part(expr: sp.Expr) -> sp.Expr:
    """``C(s)`` without the ``s`` term of its polynomial part (derivative on measurement)."""
    if expr == 0:
        return expr
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    q, _r = sp.div(sp.Poly(num, S), sp.Poly(den, S))
    if q.degree() >= 2:
        raise UnrealizableError(
            f"controller {expr} needs accelerations (polynomial part of degree {q.degree()}); "
            "add filter poles, e.g. 'kd + bd*s/(1 + s/500)'"
        )
    q1 = q.as_expr().coeff(S, 1) if q.degree() == 1 else 0
    return sp.expand(expr - q1 * S)


@dataclass(frozen=True)
class SimKernel:
    """Compiled closed-loop transfer function ``X_L/Θ`` of one configuration."""

    sea: SEA
    params: tuple[str, ...]  # per-design parameters, the load mass last
    num_deg: int
    den_deg: int
    bank: PolynomialBank = field(repr=False, compare=False)


_CACHE: LRUCache[SimKernel] = LRUCache(maxsize=256)


def compile_step_response(sea: SEA, params: Sequence[str]) -> SimKernel:
    """Derive (once, cached) ``G(s) = X_L/Θ`` of ``sea`` with a load mass, in ``params``.

    ``params`` are the model parameters given per design; the load mass
    ``m_L`` is always a per-design input.
    """
    params = check_batch_params(sea, params)
    vals = tuple(sorted((k, v) for k, v in sea.values.items() if k not in params))
    key = (tuple(sorted(sea.describe().items())), vals, params)
    cached = _CACHE.get(key)
    if cached is not None:
        return cached
    fixed = {
        symbol(k): sp.Rational(to_fraction(v, k))
        for k, v in sea.values.items()
        if v is not None and k not in params
    }
    e = {k: sp.sympify(v).xreplace(fixed) for k, v in sea.elements().items()}
    ml = sp.Symbol(LOAD_MASS, positive=True)
    xa, xl, fa, th = sp.symbols("X_A X_L F_A Theta")
    eqs = [
        sp.Eq((e["m"] * S**2 + e["b"] * S) * xa, fa + e["D1"] * (xl - xa)),
        sp.Eq(ml * S**2 * xl, -e["D1"] * (xl - xa) - e["D2"] * xl),
        sp.Eq(
            fa,
            _reference_part(e["CA"]) * th
            - e["CA"] * xa
            + _reference_part(e["CL"]) * th
            - e["CL"] * xl,
        ),
    ]
    sol = sp.solve(eqs, [xa, xl, fa], dict=True)
    if len(sol) != 1:
        raise ParameterError("the closed loop has no unique solution for this configuration")
    g = sp.cancel(sp.together(sol[0][xl] / th))
    num_e, den_e = sp.fraction(g)
    num = sp.Poly(num_e, S).all_coeffs()[::-1]
    den = sp.Poly(den_e, S).all_coeffs()[::-1]
    syms = [symbol(p) for p in params] + [ml]
    bank = PolynomialBank(syms)
    for i, c in enumerate(num):
        bank.add(f"n{i}", c)
    for i, c in enumerate(den):
        bank.add(f"d{i}", c)
    bank.freeze()
    kernel = SimKernel(
        sea=sea,
        params=(*params, LOAD_MASS),
        num_deg=len(num) - 1,
        den_deg=len(den) - 1,
        bank=bank,
    )
    _CACHE.put(key, kernel)
    return kernel


def poly_at(coeffs: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Evaluate ascending coefficients ``coeffs`` (deg+1, N) at ``z`` (N, n)."""
    acc = np.zeros(z.shape, dtype=complex)
    for c in coeffs[::-1]:
        acc = acc * z + c[:, None]
    return acc


def companion_roots(den: np.ndarray) -> np.ndarray:
    """Roots of monic-normalized ascending ``den`` (n+1, N) as (N, n) complex."""
    n = den.shape[0] - 1
    N = den.shape[1]
    comp = np.zeros((N, n, n))
    if n > 1:
        idx = np.arange(n - 1)
        comp[:, idx + 1, idx] = 1.0
    comp[:, :, -1] = -(den[:n] / den[n]).T
    return np.linalg.eigvals(comp)


class ModalForm:
    """Closed-form error ``e(t) = x_L(t) − θ`` for a set of designs.

    Only one pole of each conjugate pair is kept, its residue doubled, so
    ``e = off + Re Σ_k r_k e^{p_k t}`` (padding modes have ``r = 0``).
    """

    def __init__(self, poles: np.ndarray, res: np.ndarray, offset: np.ndarray) -> None:
        self.p, self.r, self.off = poles, res, offset
        self.rp = np.abs(res * poles)
        self.rpp = np.abs(res * poles * poles)
        self.ra = np.abs(res)

    def take(self, idx: np.ndarray) -> ModalForm:
        return ModalForm(self.p[idx], self.r[idx], self.off[idx])

    def err(self, t: np.ndarray) -> np.ndarray:
        """``e`` at times ``t`` of shape (N, m)."""
        z = np.exp(self.p[:, :, None] * t[:, None, :])
        return self.off[:, None] + np.einsum("nk,nkm->nm", self.r, z).real

    def grid(self, t0: np.ndarray, h: np.ndarray, K: int) -> tuple[np.ndarray, np.ndarray]:
        """``e`` (N, K+1) and the envelopes of ``|ė|`` and ``|ë|`` (N, 2, K+1) on ``t0 + h·k``."""
        pw = np.empty((*self.p.shape, K + 1), dtype=complex)
        pw[:, :, 0] = np.exp(self.p * t0[:, None])
        pw[:, :, 1:] = np.exp(self.p * h[:, None])[:, :, None]
        np.cumprod(pw, axis=2, out=pw)
        e = self.off[:, None] + np.einsum("nk,nkm->nm", self.r, pw).real
        dec = np.empty((*self.p.shape, K + 1))
        dec[:, :, 0] = np.exp(self.p.real * t0[:, None])
        dec[:, :, 1:] = np.exp(self.p.real * h[:, None])[:, :, None]
        np.cumprod(dec, axis=2, out=dec)
        env = np.stack(
            [np.einsum("nk,nkm->nm", self.rp, dec), np.einsum("nk,nkm->nm", self.rpp, dec)], axis=1
        )
        return e, env
