"""Closed-form alias sums ``Σ_k ψ(s_k)`` with certified enclosures (python-flint balls).

With ``s_k = j(ω + 2πk/T)``, ``z = e^{jωT}`` and a pole ``p`` of ``ψ`` (``q = e^{pT}``),

``Σ_k 1/(s_k − p)^j = T^j F_j(w)/(w − 1)^j``,  ``w = z/q``,

where ``F_1 = (w + 1)/2`` and ``F_{j+1} = w [F_j − (w − 1) F_j'/j]`` (differentiate in
``p``): exact integer-coefficient polynomials, any multiplicity.  The poles are the roots
of the exact denominators, isolated by FLINT (certified balls; multiplicities from an
exact factorization), the residues are ball Taylor coefficients, and ``e^{pT}`` is a ball.
So every value below is an enclosure at the working precision; nothing is rounded silently.

References
----------
.. [1] J. E. Colgate, G. G. Schenkel, "Passivity of a class of sampled-data systems:
   application to haptic interfaces", J. Robotic Systems 14(1), 1997.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, cast

from flint import acb, acb_mat, acb_poly, arb, ctx, fmpq, fmpq_poly

from .plant import RationalFunction

__all__ = ["AliasSums", "Pole", "alias_sums", "hermitian_entries", "zeta_numerators"]

#: Largest pole multiplicity handled (the kernels are exact for any; this bounds the work).
MAX_MULTIPLICITY = 24


@functools.cache
def zeta_numerators(jmax: int) -> tuple[fmpq_poly, ...]:
    """``(F_1, …, F_jmax)`` of the module docstring."""
    out = [fmpq_poly([fmpq(1, 2), fmpq(1, 2)])]
    w, w_minus_1 = fmpq_poly([0, 1]), fmpq_poly([-1, 1])
    for j in range(1, jmax):
        f = out[-1]
        out.append(w * (f - f.derivative() * w_minus_1 / j))
    return tuple(out)


@dataclass(frozen=True)
class Pole:
    """A pole ``p`` of the summands (``q = e^{pT}``); ``origin`` marks the exact ``p = 0``."""

    p: acb
    q: acb
    mult: int
    origin: bool


def _to_acb_poly(p: fmpq_poly) -> acb_poly:
    return acb_poly([acb(c) for c in p.coeffs()]) if not p.is_zero() else acb_poly([0])


def _taylor(p: fmpq_poly, x: acb, order: int) -> list[acb]:
    """First ``order`` Taylor coefficients of ``p`` at ``x``."""
    c = _to_acb_poly(p)(acb_poly([x, 1])).coeffs()
    return [c[i] if i < len(c) else acb(0) for i in range(order)]


def _series_div(a: Sequence[acb], b: Sequence[acb], n: int) -> list[acb]:
    out: list[acb] = []
    for t in range(n):
        acc = a[t]
        for u in range(t):
            acc -= out[u] * b[t - u]
        out.append(acc / b[0])
    return out


def _multiplicity(den: fmpq_poly, f: fmpq_poly) -> int:
    k = 0
    while den.degree() >= f.degree():
        quo, rem = divmod(den, f)
        if not rem.is_zero():
            break
        den, k = quo, k + 1
    return k


@dataclass(frozen=True)
class AliasSums:
    """Alias sums of several summands over one shared pole set, at precision ``prec``.

    ``Σ_k ψ(s_k) = Σ_c residues[name][c] · G_c(z)`` with the kernels ``G_c`` of
    ``columns[c] = (pole index, j)``.
    """

    period: fmpq
    poles: tuple[Pole, ...]
    columns: tuple[tuple[int, int], ...]
    residues: Mapping[str, tuple[acb, ...]]
    prec: int

    @property
    def origin_order(self) -> int:
        """Multiplicity of the pole at ``z = 1`` (``s = 0``) in the common denominator."""
        return sum(p.mult for p in self.poles if p.origin)

    @property
    def degree(self) -> int:
        """Degree in ``z`` of the common denominator ``Π (z − q)^mult``."""
        return sum(p.mult for p in self.poles)

    def kernels(self, z: acb) -> list[acb]:
        """``G_c(z)`` for every column (call under the working precision)."""
        T = arb(self.period)
        F = zeta_numerators(max((j for _i, j in self.columns), default=1))
        row: list[acb] = []
        cache: dict[int, tuple[acb, acb]] = {}
        for i, j in self.columns:
            if i not in cache:
                pole = self.poles[i]
                w = z if pole.origin else z / pole.q
                cache[i] = (w, T / (w - 1))
            w, t_over = cache[i]
            row.append(_to_acb_poly(F[j - 1])(w) * t_over**j)
        return row

    def evaluate(self, zs: Sequence[acb]) -> dict[str, list[acb]]:
        """Every alias sum at every ``z`` in ``zs`` (one matrix product)."""
        names = list(self.residues)
        if not self.columns:
            return {k: [acb(0)] * len(zs) for k in names}
        with ctx.workprec(self.prec):
            G = acb_mat([self.kernels(z) for z in zs])
            A = acb_mat([[self.residues[k][c] for k in names] for c in range(len(self.columns))])
            SA = G * A
            return {k: [SA[r, c] for r in range(len(zs))] for c, k in enumerate(names)}

    def weight(self, z: acb) -> arb:
        """``Π_{q ≠ 1} |z − q|^{2 mult}`` (positive on the unit circle)."""
        w = arb(1)
        for pole in self.poles:
            if not pole.origin:
                d = z - pole.q
                w *= ((d * d.conjugate()).real) ** pole.mult
        return w

    def pulse_transfer(self, name: str = "Sg") -> tuple[acb_poly, acb_poly]:
        """``g = (1 − z⁻¹)/T · Σ_k ψ(s_k)/...`` for ``ψ = P/s`` as ``(num, den)`` in ``z``.

        The ZOH pulse transfer function of ``P`` (the origin pole of ``P/s`` cancels
        against ``1 − z⁻¹`` exactly).
        """
        T = arb(self.period)
        res = self.residues[name]
        F = zeta_numerators(max((j for _i, j in self.columns), default=1))
        used: dict[int, int] = {}
        origin = 0
        for c, (i, j) in enumerate(self.columns):
            if res[c].is_zero():
                continue
            if self.poles[i].origin:
                origin = max(origin, j)
            else:
                used[i] = max(used.get(i, 0), j)
        if origin > 1:
            raise ValueError("P/s has a multiple pole at s = 0")

        def lin(q: acb) -> acb_poly:
            return acb_poly([-q, 1])

        factors = {i: lin(self.poles[i].q) ** m for i, m in used.items()}
        den_rest = acb_poly([1])
        for f in factors.values():
            den_rest *= f
        num = acb_poly([0])
        for c, (i, j) in enumerate(self.columns):
            A = res[c]
            if A.is_zero():
                continue
            pole = self.poles[i]
            q = pole.q
            # q^j F_j(z/q): a polynomial in z (deg F_j <= j)
            fhat = acb_poly([acb(f) * q ** (j - k) for k, f in enumerate(F[j - 1].coeffs())])
            if pole.origin:
                term = fhat * den_rest
            else:
                others = acb_poly([1])
                for i2, f in factors.items():
                    if i2 != i:
                        others *= f
                term = fhat * others * lin(q) ** (used[i] - j) * lin(acb(1)) ** origin
            num += term * (A * T**j)
        z_times = acb_poly([0, 1]) * den_rest * T
        if origin == 1:
            return num, z_times
        return num * lin(acb(1)), z_times


def alias_sums(summands: Mapping[str, RationalFunction], period: fmpq, prec: int) -> AliasSums:
    """Partial fractions of every summand at certified poles (balls at ``prec`` bits).

    Raises
    ------
    ValueError
        If a summand has relative degree below 2 (its alias sum diverges).
    """
    with ctx.workprec(prec):
        lcm = fmpq_poly([1])
        for _num, den in summands.values():
            lcm = lcm * den // lcm.gcd(den)
        T = arb(period)
        poles: list[Pole] = []
        factor_of: list[fmpq_poly] = []
        for f, e in lcm.factor()[1]:
            if e > MAX_MULTIPLICITY:
                raise ValueError(f"a pole of multiplicity {e} in an alias sum")
            if f.degree() == 1 and f[0] == 0:
                poles.append(Pole(acb(0), acb(1), e, True))
                factor_of.append(f)
                continue
            roots: list[tuple[acb, int]] = cast(Any, f.complex_roots())  # (ball, multiplicity)
            for r, _m in roots:  # f irreducible: simple roots
                poles.append(Pole(r, (r * T).exp(), e, False))
                factor_of.append(f)
        columns = tuple((i, j) for i, pole in enumerate(poles) for j in range(1, pole.mult + 1))
        residues: dict[str, tuple[acb, ...]] = {}
        for name, (num, den) in summands.items():
            if num.is_zero():
                residues[name] = tuple(acb(0) for _ in columns)
                continue
            if den.degree() - num.degree() < 2:
                raise ValueError(f"the alias sum {name} diverges (relative degree < 2)")
            values: dict[tuple[int, int], acb] = {}
            mults: dict[str, int] = {}
            for i, pole in enumerate(poles):
                key = str(factor_of[i])
                if key not in mults:
                    mults[key] = _multiplicity(den, factor_of[i])
                m = mults[key]
                if m == 0:
                    continue
                # den(p + e)/e^m: its first m Taylor coefficients vanish exactly
                dt = _taylor(den, pole.p, 2 * m)[m:]
                h = _series_div(_taylor(num, pole.p, m), dt, m)
                for j in range(1, m + 1):
                    values[(i, j)] = h[m - j]
            residues[name] = tuple(values.get(c, acb(0)) for c in columns)
        return AliasSums(period, tuple(poles), columns, residues, prec)


def hermitian_entries(sums: Mapping[str, Sequence[acb]], z: acb, i: int, T: arb) -> tuple:
    """``(H0A, H0L, HAA, HAL, HLL)`` of the power function at node ``i`` (``H00 = 1``).

    ``N = |v0|² + 2 Re(v̄0 H0A vA) + 2 Re(v̄0 H0L vL) + HAA |vA|² + 2 Re(v̄A HAL vL)
    + HLL |vL|²`` with ``v = (1, K_A, K_L)``; see [`seapass.sampled.passivity`][seapass.sampled.passivity].
    """
    zero = acb(0)
    S1 = sums["S1"][i].real if "S1" in sums else arb(0)  # real on the unit circle
    S2 = sums["S2"][i] if "S2" in sums else zero
    S3 = sums["S3"][i] if "S3" in sums else zero
    S4 = sums["S4"][i].real if "S4" in sums else arb(0)
    Sg = sums["Sg"][i] if "Sg" in sums else zero
    S5 = -S3
    u = 1 - 1 / z
    g = u / T * Sg
    c = (u * u.conjugate()).real / (4 * T * T)
    h0a = g + u * S2 / (2 * T)
    h0l = u * S5 / (2 * T)
    haa = (
        (g * g.conjugate()).real
        + (g.conjugate() * u * S2).real / T
        - c * (S1 * S1 - (S2 * S2.conjugate()).real)
    )
    hal = g.conjugate() * u * S5 / (2 * T) - c * (S1 * S3.conjugate() - S2.conjugate() * S5)
    hll = -c * (S1 * S4 - (S5 * S5.conjugate()).real)
    return h0a, h0l, haa, hal, hll
