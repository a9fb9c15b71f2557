"""The weighted power polynomial of a sampled-data SEA port, as certified balls.

For controller polynomials ``v' = (d_A d_L, n_A d_L, n_L d_A)`` (in ``z⁻¹``) the power
function times its positive weight,

``P̃(x) = N(θ) · |d_A d_L|² · Π_{q ≠ 1} |z − q|^{2 mult}``,  ``x = cos θ``,

is a polynomial in ``x`` of degree at most ``D + 1 + e − m0`` (``D`` = degree of the alias
sums' common denominator, ``m0`` its order at ``z = 1``, ``e`` = degree of ``v'``).  That
it is a polynomial needs one fact: ``N·|d_A d_L|²`` stays bounded as ``θ → 0`` (the
divergent ``k = 0`` alias terms cancel; proof in ``docs/sampled.md``), so the factor
``|z − 1|^{2 m0}`` of the common denominator divides out exactly.  ``P̃`` is therefore
recovered *exactly* (as balls) from its values at ``deg + 1`` Chebyshev nodes, which never
include ``θ = 0``: no division by a vanishing weight, no cancellation near ``θ = 0``.

A *family* ``v'(λ) = Σ_a λ^a V_a`` (controller coefficients polynomial in a parameter)
gives ``P̃(x; λ) = Σ_k λ^k P̃_k(x)``; `weighted_polynomials` returns the ``P̃_k``.
"""

from __future__ import annotations

from collections.abc import Sequence

from flint import acb, arb, arb_mat, arb_poly, fmpq_poly

from .alias import AliasSums, hermitian_entries
from .certified import chebyshev_nodes, interpolation_matrix, precision

__all__ = ["ControllerFamily", "power_values", "weighted_polynomials"]

#: ``family[i][a]``: coefficient of ``λ^a`` of ``v'_i`` as a polynomial in ``z⁻¹``.
ControllerFamily = Sequence[Sequence[fmpq_poly]]


def _horner(p: fmpq_poly, x: acb) -> acb:
    acc = acb(0)
    for c in reversed(p.coeffs()):
        acc = acc * x + c
    return acc


def family_degree(family: ControllerFamily) -> tuple[int, int]:
    """``(degree in z⁻¹, degree in λ)``."""
    e = max((p.degree() for comp in family for p in comp), default=0)
    return max(e, 0), max(len(comp) for comp in family) - 1


def _bilinear(h: tuple, v: Sequence[acb], w: Sequence[acb]) -> acb:
    """``vᴴ H w`` for the Hermitian ``H`` of `hermitian_entries` (``H00 = 1``)."""
    h0a, h0l, haa, hal, hll = h
    v0, va, vl = (x.conjugate() for x in v)
    w0, wa, wl = w
    return (
        v0 * w0
        + v0 * h0a * wa
        + va * h0a.conjugate() * w0
        + v0 * h0l * wl
        + vl * h0l.conjugate() * w0
        + haa * va * wa
        + va * hal * wl
        + vl * hal.conjugate() * wa
        + hll * vl * wl
    )


def polynomial_degree(sums: AliasSums, family: ControllerFamily) -> int:
    e, _ = family_degree(family)
    return sums.degree + 1 + e - sums.origin_order


def weighted_polynomials(sums: AliasSums, family: ControllerFamily) -> list[arb_poly]:
    """``[P̃_0, P̃_1, …]`` (ball polynomials in ``x = cos θ``) at ``sums.prec`` bits."""
    n = polynomial_degree(sums, family)
    _e, k = family_degree(family)
    with precision(sums.prec):
        theta = chebyshev_nodes(n)
        zs = [acb(0, t).exp() for t in theta]
        values = sums.evaluate(zs)
        T = arb(sums.period)
        rows: list[list[arb]] = []
        for i, z in enumerate(zs):
            h = hermitian_entries(values, z, i, T)
            zinv = 1 / z
            vecs = [
                [_horner(comp[a], zinv) if a < len(comp) else acb(0) for comp in family]
                for a in range(k + 1)
            ]
            weight = sums.weight(z)
            row = []
            for power in range(2 * k + 1):
                acc = arb(0)
                for a in range(max(0, power - k), min(k, power) + 1):
                    acc += _bilinear(h, vecs[a], vecs[power - a]).real
                row.append(acc * weight)
            rows.append(row)
        coeffs = interpolation_matrix(n, sums.prec) * arb_mat(rows)
        return [arb_poly([coeffs[j, c] for j in range(n + 1)]) for c in range(2 * k + 1)]


def power_values(sums: AliasSums, family: ControllerFamily, thetas: Sequence[float]) -> list[arb]:
    """``N(θ)`` itself (unweighted) at the given ``θ`` — for figures, never for verdicts."""
    with precision(sums.prec):
        zs = [acb(0, arb(t)).exp() for t in thetas]
        values = sums.evaluate(zs)
        T = arb(sums.period)
        out = []
        for i, z in enumerate(zs):
            zinv = 1 / z
            v = [_horner(comp[0], zinv) for comp in family]
            h = hermitian_entries(values, z, i, T)
            scale = (v[0] * v[0].conjugate()).real
            out.append(_bilinear(h, v, v).real / scale)
        return out
