"""The symbolic passivity data of one configuration, derived once and cached."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from ..analysis.impedance import structural_support
from ..model.expr import S, symbol, to_fraction
from ..model.sea import SEA
from ..model.stiffness import load_impedance
from .bank import PolynomialBank
from .cache import LRUCache
from .inputs import check_batch_params

__all__ = [
    "PassivityKernel",
    "compile_passivity",
]


_X = sp.Symbol("x")


def _hurwitz_dets(desc: Sequence[sp.Expr]) -> list[tuple[int, sp.Expr]]:
    """Liénard–Chipart determinants ``Δ_{n-1}, Δ_{n-3}, …`` of ``a0 s^n + … + an``."""
    n = len(desc) - 1

    def a(i: int) -> sp.Expr:
        return desc[i] if 0 <= i <= n else sp.Integer(0)

    out = []
    for k in range(n - 1, 0, -2):
        H = sp.Matrix(k, k, lambda i, j: a(2 * (j + 1) - (i + 1)))
        out.append((k, sp.expand(H.det(method="berkowitz"))))
    return out


def _x_poly_of_real_part(num: list[sp.Expr], den: list[sp.Expr]) -> list[sp.Expr]:
    """Ascending coefficients in ``x = ω²`` of ``Re N(jω) D(−jω)`` (ascending inputs)."""

    def parts(p: list[sp.Expr]) -> tuple[sp.Expr, sp.Expr]:
        re = sum((c * (-1) ** (k // 2) * _X ** (k // 2) for k, c in enumerate(p) if k % 2 == 0), 0)
        im = sum(
            (c * (-1) ** ((k - 1) // 2) * _X ** ((k - 1) // 2) for k, c in enumerate(p) if k % 2),
            0,
        )
        return sp.sympify(re), sp.sympify(im)

    nr, ni = parts(num)
    dr, di = parts(den)
    px = sp.expand(nr * dr + _X * ni * di)
    if px == 0:
        return []
    return [sp.expand(c) for c in sp.Poly(px, _X).all_coeffs()[::-1]]


@dataclass(frozen=True)
class PassivityKernel:
    """Symbolic data of one configuration, compiled for batch evaluation.

    Build with `compile_passivity`.  ``params`` are the parameters given
    per design (in this order); every other value is taken from the model.
    """

    sea: SEA
    params: tuple[str, ...]
    num_deg: int
    den_deg: int
    s_power: int  # generic multiplicity of the root s = 0 of D
    q_low: int  # generic lowest power of x in P
    q_deg: int  # degree of Q = P / x^q_low
    lc_orders: tuple[int, ...]
    supported: bool
    bank: PolynomialBank = field(repr=False, compare=False)
    n_exact: tuple[str, ...] = field(repr=False, compare=False)
    d_exact: tuple[str, ...] = field(repr=False, compare=False)
    support: tuple[bool, ...] = field(default=(), repr=False, compare=False)


_CACHE: LRUCache[PassivityKernel] = LRUCache(maxsize=256)


def _key(sea: SEA, params: Sequence[str]) -> tuple[Any, ...]:
    vals = tuple(sorted((k, v) for k, v in sea.values.items() if k not in params))
    return (tuple(sorted(sea.describe().items())), vals, tuple(params))


def compile_passivity(sea: SEA, params: Sequence[str]) -> PassivityKernel:
    """Derive (once, cached) the symbolic passivity data of ``sea`` in ``params``.

    Parameters
    ----------
    sea : SEA
        The configuration; values of parameters not in ``params`` are substituted exactly.
    params : sequence of str
        Parameters that will be given per design.  Must include every free
        parameter of ``sea``.
    """
    params = check_batch_params(sea, params)
    key = _key(sea, params)
    cached = _CACHE.get(key)
    if cached is not None:
        return cached
    syms = [symbol(p) for p in params]
    fixed = {
        symbol(k): sp.Rational(to_fraction(v, k))
        for k, v in sea.values.items()
        if v is not None and k not in params
    }
    z = sp.cancel(sp.together(load_impedance(sea).xreplace(fixed)))
    num_e, den_e = sp.fraction(z)
    num = [sp.expand(c) for c in sp.Poly(num_e, S).all_coeffs()[::-1]]
    den = [sp.expand(c) for c in sp.Poly(den_e, S).all_coeffs()[::-1]]
    while num and num[-1] == 0:
        num.pop()
    bank = PolynomialBank(syms)
    n_names = tuple(f"n{i}" for i in range(len(num)))
    d_names = tuple(f"d{i}" for i in range(len(den)))
    for nm, c in zip((*n_names, *d_names), (*num, *den), strict=True):
        bank.add(nm, c)
    s_power = next((i for i, c in enumerate(den) if c != 0), 0)
    dt = den[s_power:]
    # the fast path covers at most a simple generic pole at s = 0
    supported = bool(num) and s_power <= 1 and (s_power == 0 or num[0] != 0)
    lc_orders: list[int] = []
    q_low = q_deg = 0
    if supported:
        for k, det in _hurwitz_dets(list(reversed(dt))):
            bank.add(f"lc{k}", det)
            lc_orders.append(k)
        px = _x_poly_of_real_part(num, den)
        if not px:
            supported = False
        else:
            q_low = next(i for i, c in enumerate(px) if c != 0)
            q = px[q_low:]
            q_deg = len(q) - 1
            for i, c in enumerate(q):
                bank.add(f"q{i}", c)
            if q_deg == 2:
                bank.add("disc", sp.expand(q[1] ** 2 - 4 * q[0] * q[2]))
    bank.freeze()
    kernel = PassivityKernel(
        sea=sea,
        params=params,
        num_deg=len(num) - 1,
        den_deg=len(den) - 1,
        s_power=s_power,
        q_low=q_low,
        q_deg=q_deg,
        lc_orders=tuple(lc_orders),
        supported=supported,
        bank=bank,
        n_exact=n_names,
        d_exact=d_names,
        support=structural_support(num_e, den_e),
    )
    _CACHE.put(key, kernel)
    return kernel
