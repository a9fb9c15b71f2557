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

from .sampled_local import Dual, LocalPower
from .sampled_plant import ParametricPlant, Split
from .sampled_realization import SPLIT_FROM, Realization, meet
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
            if not r.ok and not split:
                return  # the plain realization is needed
            if r.ok:  # the split one only tightens: without it the plain one stands
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
            sums = {name: meet(v, s2[name]) for name, v in sums.items()}
            weight = meet(weight, w2)
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
