"""Alias sums of a box of plants in state-space form: no poles, no residues.

Every summand ``ψ = num/L`` of the alias sums (over the common denominator ``L`` of the
needed summands, exact in ``s`` and the uncertain parameters ``μ``) is realized in
controllable companion form ``ψ(s) = C (sI − A)^{-1} B`` (``B = e_n``; ``s`` scaled by a
fixed ``σ > 0`` so that the companion is balanced).  For relative degree ``≥ 1`` the
symmetric alias sum has the closed form

``Σ_k ψ(s + jkΩ) = (T/2) C (zI + Φ)(zI − Φ)^{-1} B = (T/2)(−CB + 2z C (zI − Φ)^{-1} B)``,

``z = e^{sT}``, ``Φ = e^{AT}``, ``Ω = 2π/T`` (scalar case: ``(T/2) coth((s − p)T/2)``;
the matrix case by the holomorphic functional calculus, for any ``A``, also with
repeated or close eigenvalues).  The weight ``Π_{q ≠ 1} |z − q|^{2 mult}`` of
[`seapass.sampled.power`][seapass.sampled.power] is ``|det(zI − Φ)|²/|z − 1|^{2 m0}``
(``m0`` = order of ``L`` at ``s = 0``), the same polynomial weight as the pole route, so
``P̃`` is the same polynomial in ``x = cos ωT``.

Over a box, ``Φ`` is ``arb_mat.exp`` of the ball companion matrix (arb's inclusion
principle: it contains ``e^{A(μ)T}`` for every ``μ`` of the box), and ``∂Φ/∂μ_i`` is the
``(1, 2)`` block of ``exp([[A, ∂A/∂μ_i], [0, A]] T)`` (Van Loan), again over the box.
Everything is a [`Dual`][seapass.robust.sampled_local.Dual]: the mean-value enclosures and
the piecewise decision of [`seapass.robust.sampled_local`][seapass.robust.sampled_local]
apply unchanged.  Close poles (a plant mode next to a mirrored zero of ``Re Z0``), which
make residues large and nearly cancelling, cost nothing here.

References
----------
.. [1] C. F. Van Loan, "Computing integrals involving the matrix exponential", IEEE
   Trans. Automatic Control 23(3), 1978 (the block-triangular exponential).
.. [2] F. Johansson, "Arb: efficient arbitrary-precision midpoint-radius interval
   arithmetic", IEEE Trans. Computers 66(8), 2017 (the inclusion principle).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from flint import acb, acb_mat, arb, arb_mat, fmpq, fmpq_mpoly

from ..sampled.alias import zeta_numerators
from .sampled_local import Dual, LocalPower
from .sampled_plant import ParametricPlant, Split
from .taylor import Jet, pairs

__all__ = ["StatePower", "common_denominator"]


def common_denominator(plant: ParametricPlant, names: Sequence[str]) -> fmpq_mpoly:
    """The least common multiple of the summands' denominators (exact, in ``s`` and ``μ``)."""
    lcm = plant.ctx.constant(1)
    for k in names:
        den = plant.summands[k].den
        lcm = lcm * den / lcm.gcd(den)
    return lcm


class StateData:
    """What `StatePower` needs of a plant family, built once (exact)."""

    def __init__(self, plant: ParametricPlant, names: tuple[str, ...]) -> None:
        self.plant = plant
        self.names = names
        si = plant.si
        L = common_denominator(plant, names)
        self.L = Split.of(L, si)
        self.n = len(self.L.coeffs) - 1
        m0 = 0
        while m0 < self.n and self.L.coeffs[m0].is_zero():
            m0 += 1
        self.m0 = m0
        self.nums: dict[str, Split] = {}
        for k in names:
            f = plant.summands[k]
            q, r = divmod(L, f.den)
            if not r.is_zero():
                raise ArithmeticError("the common denominator is not a multiple")  # never
            self.nums[k] = Split.of(f.num * q, si)
        self.dL = [Split.of(L.derivative(p), si) for p in plant.names]
        self.dnums = {
            k: [Split.of((plant.summands[k].num * divmod(L, plant.summands[k].den)[0]).derivative(p), si)
                for p in plant.names]
            for k in names
        }  # fmt: skip
        self._second: dict[str, Any] | None = None

    def second(self) -> dict[str, Any]:
        """Exact second derivatives (by `pairs`) of ``L`` and of the numerators (once)."""
        if self._second is None:
            plant, si = self.plant, self.plant.si
            ps = pairs(len(plant.names))
            L = common_denominator(plant, self.names)
            out: dict[str, Any] = {
                "": [Split.of(L.derivative(plant.names[i]).derivative(plant.names[j]), si)
                     for i, j in ps]
            }  # fmt: skip
            for k in self.names:
                num = plant.summands[k].num * divmod(L, plant.summands[k].den)[0]
                out[k] = [
                    Split.of(num.derivative(plant.names[i]).derivative(plant.names[j]), si)
                    for i, j in ps
                ]
            self._second = out
        return self._second

    def jets(self, key: str, ball: Mapping[str, arb]) -> list[Jet]:
        """Coefficients (in ``s``) of ``L`` (``key = ""``) or of a numerator as jets on
        the ball: values, first and second derivatives, each enclosed over the ball."""
        vn = self.plant.var_names
        base = self.L if key == "" else self.nums[key]
        firsts = self.dL if key == "" else self.dnums[key]
        vals = base.at(vn, ball)
        d1 = [f.at(vn, ball) for f in firsts]
        d2 = [f.at(vn, ball) for f in self.second()[key]]
        return [
            Jet(_coeff(vals, j), [_coeff(d, j) for d in d1], [_coeff(d, j) for d in d2])
            for j in range(self.n + 1)
        ]

    def proper(self) -> bool:
        """Every summand strictly proper (relative degree ``≥ 1``): the closed form holds."""
        return all(len(s.coeffs) <= self.n for s in self.nums.values())


def _row(c: Sequence[arb], Q: arb_mat) -> list[arb]:
    n = len(c)
    return [sum((c[i] * Q[i, j] for i in range(n)), arb(0)) for j in range(n)]


def _coeff(vals: Sequence[arb], j: int) -> arb:
    return vals[j] if j < len(vals) else arb(0)


class StatePower(LocalPower):
    """Dual alias sums and weight of every plant of one ball (or one point), state-space form.

    ``ok`` is False when the realization is not proven valid on the ball (a leading
    coefficient whose ball contains 0, a summand that is not strictly proper).
    """

    def __init__(
        self,
        data: StateData,
        ball: Mapping[str, arb],
        period: Fraction,
        sigma: Fraction,
        *,
        derive: bool = True,
        basis: tuple[arb_mat, arb_mat] | None = None,
        order: int | None = None,
    ) -> None:
        self.ok = False
        self.data = data
        self.T = arb(fmpq(period.numerator, period.denominator))
        self.order = (1 if derive else 0) if order is None else order
        k = len(data.plant.names) if self.order else 0
        self.k = k
        n, vn = data.n, data.plant.var_names
        self.n, self.m0 = n, data.m0
        sg = arb(fmpq(sigma.numerator, sigma.denominator))
        self._cache: tuple[Any, Any] | None = None
        if self.order == 2:
            if basis is not None:
                raise ValueError("a second-order state power takes no basis")
            self._second_order(ball, sg)
            return
        c = data.L.at(vn, ball)
        lead = c[n]
        if lead.contains(0) or not data.proper():
            return
        scale = [sg**j / (lead * sg**n) for j in range(n + 1)]  # σ^{j−n}/lead
        A = arb_mat(n, n)
        for i in range(n - 1):
            A[i, i + 1] = arb(1)
        for j in range(n):
            A[n - 1, j] = -c[j] * scale[j]
        dA = []
        for i in range(k):
            dc = data.dL[i].at(vn, ball)
            dlead = _coeff(dc, n)
            M = arb_mat(n, n)
            for j in range(n):
                # d(c_j/lead) = (dc_j − c_j dlead/lead)/lead
                M[n - 1, j] = -(_coeff(dc, j) - c[j] * dlead / lead) * scale[j]
            dA.append((M, dlead))
        tau = sg * self.T
        if basis is not None:  # a fixed similarity: the sums and det(zI − Φ) do not change
            Q, Qi = basis
            A = Qi * A * Q
            dA = [(Qi * M * Q, dl) for M, dl in dA]
        self.phi = (A * tau).exp()
        self.dphi = []
        for M, _dl in dA:
            big = arb_mat(2 * n, 2 * n)
            for i in range(n):
                for j in range(n):
                    big[i, j] = A[i, j] * tau
                    big[n + i, n + j] = A[i, j] * tau
                    big[i, n + j] = M[i, j] * tau
            e = big.exp()
            self.dphi.append(arb_mat([[e[i, n + j] for j in range(n)] for i in range(n)]))
        self.C: dict[str, list[arb]] = {}
        self.dC: dict[str, list[list[arb]]] = {}
        for name, split in data.nums.items():
            v = split.at(vn, ball)
            self.C[name] = [_coeff(v, j) * scale[j] * sg for j in range(n)]
            ders = []
            for i in range(k):
                dv = data.dnums[name][i].at(vn, ball)
                dlead = dA[i][1]
                ders.append(
                    [(_coeff(dv, j) - _coeff(v, j) * dlead / lead) * scale[j] * sg
                     for j in range(n)]
                )  # fmt: skip
            self.dC[name] = ders
            if basis is not None:
                Q = basis[0]
                self.C[name] = _row(self.C[name], Q)
                self.dC[name] = [_row(d, Q) for d in ders]
        self.b = [
            acb(x) for x in (basis[1].entries()[n - 1 :: n] if basis else [0] * (n - 1) + [1])
        ]
        self.ok = all(x.is_finite() for x in self.phi.entries())

    def _second_order(self, ball: Mapping[str, arb], sg: arb) -> None:
        """Jets over the ball from two realizations, intersected at every ``z``: the
        plain one, and one with the origin's alias terms exact (see `Realization`)."""
        data = self.data
        c = data.jets("", ball)
        if c[self.n].v.contains(0) or not data.proper():
            return
        nums = {name: data.jets(name, ball) for name in data.nums}
        splits = [0, self.m0] if 0 < self.m0 < self.n else [0]
        self.reals = []
        for split in splits:
            r = Realization(c, nums, split, sg, self.T, self.k)
            if not r.ok:
                return
            self.reals.append(r)
        self.phi = self.reals[0].phi
        self.C = {name: [x.v for x in cj] for name, cj in self.reals[0].cjets.items()}
        self.ok = True

    @property
    def degree(self) -> int:
        """Degree in ``x`` of the weight: the non-origin part of the common denominator."""
        return self.n - self.m0

    def _matrices(self) -> None:
        n = self.n
        names = list(self.C)
        self._names = names
        self._phi = acb_mat(self.phi)
        self._eye = acb_mat([[1 if i == j else 0 for j in range(n)] for i in range(n)])
        self._b = acb_mat([[x] for x in self.b])
        self._C = acb_mat([[acb(x) for x in self.C[k]] for k in names])
        self._dC = [
            acb_mat([[acb(x) for x in self.dC[k][i]] for k in names]) for i in range(self.k)
        ]
        self._dphi = [acb_mat(d) for d in self.dphi]
        self._cb = self._C * self._b
        self._dcb = [d * self._b for d in self._dC]

    def _at(self, z: acb) -> tuple[dict[str, Dual], Dual]:
        if self._cache is not None and self._cache[0] is z:
            return self._cache[1]
        if not hasattr(self, "_names"):
            self._matrices()
        k, names = self.k, self._names
        M = self._eye * z - self._phi
        try:
            inv = M.inv()
        except ZeroDivisionError:  # not proven invertible on the ball: nothing is known
            unknown = Dual(acb(arb(0, float("inf"))), [acb(arb(0, float("inf")))] * k)
            out = ({name: unknown for name in names}, unknown)
            self._cache = (z, out)
            return out
        x = inv * self._b  # (zI − Φ)^{-1} B
        half = self.T / 2
        value = (self._C * x) * (2 * z) - self._cb
        grads = []
        if k:
            c_inv = self._C * inv
            for i in range(k):
                g = (self._dC[i] * x + c_inv * (self._dphi[i] * x)) * (2 * z) - self._dcb[i]
                grads.append(g)
        sums = {
            name: Dual(half * value[r, 0], [half * g[r, 0] for g in grads])
            for r, name in enumerate(names)
        }
        det = M.det()
        dets = [-det * (inv * d).trace() for d in self._dphi]
        d = Dual(det, dets)
        u = z - 1
        origin = ((u * u.conjugate()).real) ** self.m0
        weight = (d * d.conjugate()).real / origin
        out = (sums, weight)
        self._cache = (z, out)
        return out

    def _at2(self, z: acb) -> tuple[dict[str, Jet], Jet]:
        """Jets of the sums and of the weight at ``z`` (second order, over the ball)."""
        if self._cache is not None and self._cache[0] is z:
            return self._cache[1]
        reals = self.reals
        if len(reals) > 1 and z.real.upper() < SPLIT_FROM:
            reals = reals[:1]  # away from z = 1 the split's two parts cancel: plain only
        outs = [r.at(z, self.m0) for r in reals]
        sums, weight = outs[0]
        for s2, w2 in outs[1:]:
            sums = {name: _meet(v, s2[name]) for name, v in sums.items()}
            weight = _meet(weight, w2)
        out = (sums, weight)
        self._cache = (z, out)
        return out

    def sums_at(self, z: acb) -> dict[str, Any]:
        if self.order == 2:
            return self._at2(z)[0]
        return self._at(z)[0]

    def weight(self, z: acb) -> Any:
        if self.order == 2:
            return self._at2(z)[1]
        return self._at(z)[1]


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


def _meet(a: Jet, b: Jet) -> Jet:
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
