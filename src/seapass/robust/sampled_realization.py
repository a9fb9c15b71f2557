"""Second-order realizations of the summands over a ball (one per origin split).

[`StatePower`][seapass.robust.sampled_state.StatePower] with ``order=2`` evaluates the
alias sums and the weight as [`Jet`][seapass.robust.taylor.Jet] numbers (value, first and
second derivatives, each enclosed over a ball of plants) from the `Realization` of each
split and intersects them component by component (`meet`).

References
----------
.. [1] C. F. Van Loan, "Computing integrals involving the matrix exponential", IEEE
   Trans. Automatic Control 23(3), 1978 (the block-triangular exponentials).
.. [2] N. J. Higham, "Functions of Matrices", SIAM, 2008, Section 3.2 (Fréchet
   derivatives of the exponential, the block forms of higher derivatives).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from flint import acb, acb_mat, arb, arb_mat

from ..sampled.alias import zeta_numerators
from .taylor import Jet, pairs

__all__ = ["SPLIT_FROM", "Realization", "meet"]


def _block(At: arb_mat, off: Sequence[arb_mat], size: int, pick: tuple[int, int]) -> list[arb_mat]:
    """Block ``pick`` of ``exp`` of the block upper-triangular matrix with ``At`` on the
    diagonal and ``off`` = ``(E)`` (2 blocks) or ``(E, C, F)`` (3 blocks: ``E`` at (0, 1),
    ``C`` at (0, 2), ``F`` at (1, 2)); the matrices are already scaled by ``τ`` except
    that ``off`` holds ``∂A τ`` (Van Loan [1]_)."""
    n = At.nrows()
    big = arb_mat(size * n, size * n)
    places = [(0, 1)] if size == 2 else [(0, 1), (0, 2), (1, 2)]
    for bi in range(size):
        for i in range(n):
            for j in range(n):
                big[bi * n + i, bi * n + j] = At[i, j]
    for (bi, bj), M in zip(places, off, strict=True):
        for i in range(n):
            for j in range(n):
                big[bi * n + i, bj * n + j] = M[i, j]
    e = big.exp()
    r, c = pick
    return [arb_mat([[e[r * n + i, c * n + j] for j in range(n)] for i in range(n)])]


def _horner_z(p: Any, z: acb) -> acb:
    acc = acb(0)
    for c in reversed(p.coeffs()):
        acc = acc * z + acb(c)
    return acc


def _meet1(a: Any, b: Any) -> Any:
    """The intersection of two enclosures of one number (either if it cannot be formed)."""
    if not b.is_finite():
        return a
    if not a.is_finite():
        return b
    try:
        if isinstance(a, acb) or isinstance(b, acb):
            a, b = acb(a), acb(b)
            return acb(a.real.intersection(b.real), a.imag.intersection(b.imag))
        return a.intersection(b)
    except ValueError:  # never empty (both contain the value); keep one
        return a


def meet(a: Jet, b: Jet) -> Jet:
    """Componentwise intersection of two jets of one function over one ball (sound: each
    component of both encloses the same value, derivative or second derivative)."""
    return Jet(
        _meet1(a.v, b.v),
        [_meet1(x, y) for x, y in zip(a.d, b.d, strict=True)],
        [_meet1(x, y) for x, y in zip(a.h, b.h, strict=True)],
    )


SPLIT_FROM = 0.99
"""``cos ωT`` from which the split realization is evaluated too (below, its enclosures are
far wider than the plain one's: measured, the choice never affects soundness)."""


class Realization:
    """One state-space realization of the summands over a ball, second order.

    ``L = s^{split} L_r``: each summand ``N/L = Σ_{j ≤ split} a_j/s^j + N_r/L_r``
    (partial fractions at ``s = 0`` by series division of jets; the ``a_j`` are rational in
    ``μ``).  The origin's alias sums ``Σ_k s_k^{−j}`` are exact in ``z``, so the divergent
    ``k = 0`` terms near ``z = 1`` carry the narrow jets ``a_j`` and no ball matrix
    inverse; ``N_r/L_r`` is realized on the companion ``A_r``, with ``Φ_r``,
    ``∂Φ_r/∂μ_i`` and ``∂²Φ_r/∂μ_i∂μ_j`` over the ball from Van Loan's block
    exponentials.  ``split = 0`` is the plain realization (tighter away from ``z = 1``,
    where the two parts of the split cancel).
    """

    def __init__(
        self,
        c: Sequence[Jet],
        nums: Mapping[str, Sequence[Jet]],
        split: int,
        sg: arb,
        T: arb,
        k: int,
    ) -> None:
        self.ok = False
        self.split, self.T, self.k = split, T, k
        lr = c[split:]
        nr = len(lr) - 1
        self.nr = nr
        lead = lr[nr]
        if nr < 1 or (split and lr[0].v.contains(0)):
            return
        inv = lead.reciprocal()
        row = [lr[j] * inv * (-(sg ** (j - nr))) for j in range(nr)]  # −c_j σ^{j−nr}/lead
        tau = sg * T
        A = arb_mat(nr, nr)
        for i in range(nr - 1):
            A[i, i + 1] = arb(1)
        for j in range(nr):
            A[nr - 1, j] = row[j].v
        At = A * tau

        def last(vals: Sequence[arb]) -> arb_mat:
            M = arb_mat(nr, nr)
            for j in range(nr):
                M[nr - 1, j] = vals[j] * tau
            return M

        dA = [last([r.d[i] for r in row]) for i in range(k)]
        ps = pairs(k)
        hA = {p: last([r.h[q] for r in row]) for q, p in enumerate(ps)}
        self.phi = At.exp()
        self.dphi = [_block(At, [M], 2, (0, 1))[0] for M in dA]
        self.hphi: dict[tuple[int, int], arb_mat] = {}
        zero = arb_mat(nr, nr)
        for i, j in ps:
            if i == j:
                (h,) = _block(At, [dA[i], hA[(i, i)] * arb(0.5), dA[i]], 3, (0, 2))
                self.hphi[(i, i)] = h * 2
            else:
                (h1,) = _block(At, [dA[i], hA[(i, j)], dA[j]], 3, (0, 2))
                (h2,) = _block(At, [dA[j], zero, dA[i]], 3, (0, 2))
                self.hphi[(i, j)] = h1 + h2
        self.cjets: dict[str, list[Jet]] = {}
        self.origin: dict[str, list[Jet]] = {}
        for name, num in nums.items():
            q: list[Jet] = []  # series quotient of N by L_r at s = 0: q[t] = a_{split − t}
            for t in range(split):
                acc = num[t]
                for u in range(t):
                    acc = acc - q[u] * lr[t - u]
                q.append(acc / lr[0])
            self.origin[name] = [q[split - j] for j in range(1, split + 1)]  # a_1 … a_split
            rest = []
            for i in range(nr):
                acc = num[i + split] if i + split < len(num) else Jet.constant(arb(0), k)
                for j in range(1, split + 1):
                    if i + j <= nr:
                        acc = acc - q[split - j] * lr[i + j]
                rest.append(acc)
            self.cjets[name] = [rest[j] * inv * (sg ** (j - nr + 1)) for j in range(nr)]
        entries = [*self.phi.entries()]
        for M in [*self.dphi, *self.hphi.values()]:
            entries += M.entries()
        self.ok = all(x.is_finite() for x in entries)
        if not self.ok:
            return
        names = list(self.cjets)
        self.names = names
        self._phi = acb_mat(self.phi)
        self._eye = acb_mat([[1 if i == j else 0 for j in range(nr)] for i in range(nr)])
        self._b = acb_mat([[0]] * (nr - 1) + [[1]])
        self._C = acb_mat([[acb(x.v) for x in self.cjets[nm]] for nm in names])
        self._dC = [acb_mat([[acb(x.d[i]) for x in self.cjets[nm]] for nm in names])
                    for i in range(k)]  # fmt: skip
        self._hC = [acb_mat([[acb(x.h[q]) for x in self.cjets[nm]] for nm in names])
                    for q in range(len(ps))]  # fmt: skip
        self._dphi = [acb_mat(d) for d in self.dphi]
        self._hphi = [acb_mat(self.hphi[p]) for p in ps]

    def at(self, z: acb, m0: int) -> tuple[dict[str, Jet], Jet]:
        """Jets of the sums and of the weight ``|det(zI − Φ)|²/|z − 1|^{2 m0}`` at ``z``."""
        k = self.k
        ps = pairs(k)
        names = self.names
        M = self._eye * z - self._phi
        try:
            R = M.inv()
        except ZeroDivisionError:  # not proven invertible on the ball: nothing is known
            inf = acb(arb(0, float("inf")))
            unknown = Jet(inf, [inf] * k, [inf] * len(ps))
            return {name: unknown for name in names}, unknown
        x = R * self._b
        rphi = [R * d for d in self._dphi]
        xs = [r * x for r in rphi]
        xh = [
            R * (self._hphi[q] * x + self._dphi[i] * xs[j] + self._dphi[j] * xs[i])
            for q, (i, j) in enumerate(ps)
        ]
        C, dC, hC = self._C, self._dC, self._hC
        y = C * x
        ys = [dC[i] * x + C * xs[i] for i in range(k)]
        yh = [hC[q] * x + dC[i] * xs[j] + dC[j] * xs[i] + C * xh[q] for q, (i, j) in enumerate(ps)]
        half, z2 = self.T / 2, 2 * z
        cb = C * self._b
        dcb = [d * self._b for d in dC]
        hcb = [h * self._b for h in hC]
        sums = {
            name: Jet(
                half * (y[r, 0] * z2 - cb[r, 0]),
                [half * (g[r, 0] * z2 - dcb[i][r, 0]) for i, g in enumerate(ys)],
                [half * (g[r, 0] * z2 - hcb[q][r, 0]) for q, g in enumerate(yh)],
            )
            for r, name in enumerate(names)
        }
        if self.split:
            F = zeta_numerators(self.split)
            kern = [_horner_z(F[j - 1], z) * (self.T / (z - 1)) ** j
                    for j in range(1, self.split + 1)]  # fmt: skip
            for name in names:
                for a, g in zip(self.origin[name], kern, strict=True):
                    sums[name] = sums[name] + a * g
        det = M.det()
        t = [r.trace() for r in rphi]
        dets = [-det * ti for ti in t]
        hdet = [
            det * (t[i] * t[j] - (rphi[j] * rphi[i]).trace() - (R * self._hphi[q]).trace())
            for q, (i, j) in enumerate(ps)
        ]
        d = Jet(det, dets, hdet)
        weight = (d * d.conjugate()).real
        if m0 > self.split:  # det(zI − Φ) carries (z − 1)^{m0 − split}
            u = z - 1
            weight = weight / ((u * u.conjugate()).real) ** (m0 - self.split)
        return sums, weight
