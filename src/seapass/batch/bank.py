"""Polynomials in the free parameters, evaluated for a whole batch with error bounds."""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction

import numpy as np
import sympy as sp

__all__ = [
    "UNIT_ROUNDOFF",
    "PolynomialBank",
]


UNIT_ROUNDOFF = 2.0**-53
"""Unit roundoff of IEEE double precision (round to nearest)."""


class PolynomialBank:
    """Polynomials in the free parameters, evaluated together with error bounds.

    All polynomials share one list of monomials; values are ``C @ monomials``
    and the bounds ``κ · |C| @ |monomials|`` with a per-row factor ``κ``.
    """

    def __init__(self, syms: Sequence[sp.Symbol]) -> None:
        self.syms = tuple(syms)
        self.mon_index: dict[tuple[int, ...], int] = {}
        self.rows: list[dict[int, Fraction]] = []
        self.row_deg: list[int] = []
        self.names: dict[str, int] = {}

    def add(self, name: str, expr: sp.Expr) -> int:
        expr = sp.expand(expr)
        row: dict[int, Fraction] = {}
        deg = 0
        if expr != 0:
            poly = sp.Poly(expr, *self.syms) if self.syms else None
            terms = poly.terms() if poly is not None else [((), expr)]
            for exps, coeff in terms:
                c = sp.Rational(coeff)
                idx = self.mon_index.setdefault(tuple(exps), len(self.mon_index))
                row[idx] = Fraction(int(c.p), int(c.q))
                deg = max(deg, sum(exps))
        self.rows.append(row)
        self.row_deg.append(deg)
        self.names[name] = len(self.rows) - 1
        return len(self.rows) - 1

    def freeze(self) -> None:
        n_mon = max(len(self.mon_index), 1)
        C = np.zeros((len(self.rows), n_mon))
        for i, row in enumerate(self.rows):
            for j, c in row.items():
                C[i, j] = float(c)
        self.C = C
        self.Cabs = np.abs(C)
        cmin = float(np.min(self.Cabs[self.Cabs > 0], initial=1.0))
        self.tiny = 1e-290 / min(cmin, 1.0)
        self.kappa = np.array(
            [
                (d + len(r) + 4) * UNIT_ROUNDOFF * 1.0001
                for d, r in zip(self.row_deg, self.rows, strict=True)
            ]
        )
        self.exps: list[tuple[int, ...] | None] = [None] * n_mon
        for e, j in self.mon_index.items():
            self.exps[j] = e
        self.max_pow = [
            max((e[k] for e in self.mon_index), default=0) for k in range(len(self.syms))
        ]

    def evaluate(self, cols: Sequence[np.ndarray], n: int) -> tuple[np.ndarray, np.ndarray]:
        """Values and error bounds, each of shape (rows, n); the bound is ``inf`` on underflow."""
        pows: list[list[np.ndarray]] = []
        for k, col in enumerate(cols):
            lst = [np.ones(n), col]
            for _ in range(2, self.max_pow[k] + 1):
                lst.append(lst[-1] * col)
            pows.append(lst)
        mons = np.empty((len(self.exps), n))
        for j, e in enumerate(self.exps):
            if e is None:
                mons[j] = 1.0
                continue
            acc: np.ndarray | None = None
            for k, a in enumerate(e):
                if a:
                    acc = pows[k][a] if acc is None else acc * pows[k][a]
            mons[j] = 1.0 if acc is None else acc
        val = self.C @ mons
        amons = np.abs(mons)
        bound = (self.Cabs @ amons) * self.kappa[:, None]
        # a product that underflows breaks the relative error model: no bound there
        tiny = np.any((amons != 0) & (amons < self.tiny), axis=0)
        bound[:, tiny] = np.inf
        return val, bound

    def exact(self, name: str, vals: Sequence[Fraction]) -> Fraction:
        acc = Fraction(0)
        for j, c in self.rows[self.names[name]].items():
            term = c
            for v, a in zip(vals, self.exps[j] or (), strict=False):
                if a:
                    term *= v**a
            acc += term
        return acc
