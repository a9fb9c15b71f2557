"""Controller gains in a sampled box: the discrete controller as an affine map of the gains.

[`robust_sampled_check`][seapass.robust.sampled_verdict.robust_sampled_check] decides a box
of plant parameters *and* controller gains (``kd``, ``bd`` ...).  The plant's alias sums do
not depend on a gain (their derivative in a gain is 0); the controller's polynomials do.
This module gives them as [`Dual`][seapass.robust.sampled_local.Dual] numbers, so that the
mean-value enclosures of the weighted power ``P̃`` and of ``M̃ = W·|d_A + n_A g|²`` carry
the gain dependence (every quantity that depends on a gain carries its derivative).

Soundness of the affine model
-----------------------------
*Structure (checked exactly on the model, else `ParameterError`)*: every box gain enters
``C_A`` and ``C_L`` only through their numerators, affinely (total degree ≤ 1 in the box
gains, denominators free of them), and the controller is continuous (not given in ``z``).
Each emulation path (error / measurement split of derivative on measurement, the velocity
filter, Tustin, backward difference, ZOH of the strictly proper part over a fixed
denominator) is a *linear* map of the numerator coefficients for a fixed denominator, and
so is the delay ``z^-d``.  Hence the unreduced discrete numerators are affine in the gains
over gain-free denominators.

*Representation (checked exactly at ``1 + 2·#gains + 1`` points)*: the reduced
``(K_A, K_L)`` and hidden modes are computed exactly at a reference point ``g0``, at
``g0 + h e_i``, ``g0 + 2h e_i`` and ``g0 + h Σ e_i`` (``g0`` the box's low corner, never
below it); the denominators and hidden modes must be
identical at all of them, and the numerators must equal the affine model
``N(g) = N(g0) + Σ (g_i − g0_i) S_i`` at every point (the checks at ``g0 + 2h e_i`` and
the mixed point would catch a non-affine implementation).  An affine combination of
numerators that share the reduced denominator's cofactor keeps it, so
``K(g) = N(g)/D`` for every ``g`` with one fixed denominator ``D``.

*Consequences*: the controller family ``v' = (D, n_A·r_A, n_L·r_L)`` is affine in ``g``
with exact slopes, the controller's own modes (and ``open_stable``) do not depend on
``g``, and the leading coefficient of ``χ`` (``d_A(0)·lead(den_g)``) does not depend on
``g`` either: no root of ``χ`` can enter from infinity, so ``M̃ > 0`` on ``[−1, 1]`` for
every (gain, plant) of the box plus a stable centre proves stability on the whole box.
A fixed representation that has a common factor at some exceptional ``g`` only multiplies
``P̃`` and ``χ`` by that factor (``|R|² ≥ 0`` on the unit circle): a root on the circle
makes the box undecided, never passive.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from flint import acb, arb, fmpq, fmpq_poly

from ..errors import ParameterError
from ..model.loop import SampledLoop
from ..model.sea import SEA
from ..sampled.alias import hermitian_entries
from ..sampled.controllers import DiscreteController, controller_parts
from ..sampled.verdict import joint_family
from .sampled_local import Dual
from .sampled_plant import ball_of
from .taylor import Jet, pairs

__all__ = ["GainModel", "GainPower", "check_gain_structure"]


def check_gain_structure(sea: SEA, gains: Sequence[str]) -> None:
    """Raise `ParameterError` unless every gain enters ``C_A``, ``C_L`` affinely in the
    numerators only (the premise of the affine model, see the module docstring)."""
    if sea.discrete is not None:
        raise ParameterError(
            "box: a controller given in z cannot take an uncertain gain; give the gains values",
            argument="box",
        )
    exact = sea.exact_elements()
    for key in ("CA", "CL"):
        rf = exact[key]
        names = rf.context.names()
        idx = [names.index(g) for g in gains if g in names]
        for e in rf.den.monoms():
            if any(e[i] for i in idx):
                raise ParameterError(
                    f"box: a gain in the denominator of {key} is not supported in a sampled "
                    "box (gains must enter the controllers' numerators linearly)",
                    argument="box",
                )
        for e in rf.num.monoms():
            if sum(e[i] for i in idx) > 1:
                raise ParameterError(
                    f"box: the gains enter {key} nonlinearly; a sampled box takes gains that "
                    "enter the controllers' numerators linearly",
                    argument="box",
                )


def _q(x: Fraction) -> fmpq:
    return fmpq(x.numerator, x.denominator)


def _fam(ka: Any, kl: Any) -> tuple[list[fmpq_poly], tuple[fmpq_poly, fmpq_poly], Any]:
    """The family components, ``(n_A, d_A)`` and the denominators (exact)."""
    from ..exact.poly import as_poly

    family, _r = joint_family(ka, kl)
    comps = [comp[0] for comp in family]
    return comps, (as_poly(ka.num), as_poly(ka.den)), (tuple(ka.den), tuple(kl.den))


class GainModel:
    """The exact affine model ``F(g) = F(g0) + Σ (g_i − g0_i) S_i`` of the controller.

    ``F`` holds the family components and ``(n_A, d_A)`` (polynomials in ``z⁻¹``).
    """

    def __init__(
        self,
        sea: SEA,
        loop: SampledLoop,
        gains: tuple[str, ...],
        whole: Sequence[tuple[Fraction, Fraction]],
        plant_values: Mapping[str, float],
    ) -> None:
        check_gain_structure(sea, gains)
        self.gains = gains
        g0 = tuple(Fraction(float(lo)) for lo, _hi in whole)
        h = [Fraction(max(1.0, float(hi - lo))) for lo, hi in whole]
        self.g0 = g0

        def at(g: Sequence[Fraction]) -> tuple[list[fmpq_poly], Any, Any]:
            values = {**plant_values, **{n: float(v) for n, v in zip(gains, g, strict=True)}}
            ctrl = DiscreteController.for_loop(sea.with_values(**values), loop)
            ka, kl, hidden = controller_parts(ctrl, loop.delay)
            comps, kap, dens = _fam(ka, kl)
            return [*comps, *kap], (dens, tuple(hidden)), ka

        base, key, _ka = at(g0)
        self.base = base
        self.slopes: list[list[fmpq_poly]] = []
        points: list[tuple[Fraction, ...]] = []
        for i in range(len(gains)):
            up = tuple(g0[j] + (h[j] if j == i else 0) for j in range(len(gains)))
            got, k2, _ = at(up)
            if k2 != key:
                raise ParameterError(_NOT_AFFINE, argument="box")
            self.slopes.append([(a - b) / _q(h[i]) for a, b in zip(got, base, strict=True)])
            points.append(tuple(g0[j] + (2 * h[j] if j == i else 0) for j in range(len(gains))))
        points.append(tuple(g0[j] + h[j] for j in range(len(gains))))
        for p in points:
            got, k2, _ = at(p)
            if k2 != key or got != self.exact(p):
                raise ParameterError(_NOT_AFFINE, argument="box")

    def exact(self, g: Sequence[Fraction]) -> list[fmpq_poly]:
        """``F(g)`` exactly."""
        out = list(self.base)
        for gi, g0i, sl in zip(g, self.g0, self.slopes, strict=True):
            out = [a + s * _q(gi - g0i) for a, s in zip(out, sl, strict=True)]
        return out

    def zero(self, j: int) -> bool:
        """Component ``j`` of ``F`` is 0 for every gain."""
        return bool(self.base[j].is_zero() and all(sl[j].is_zero() for sl in self.slopes))

    def degree(self) -> int:
        return max(
            (p.degree() for p in (*self.base[:-2], *(s for sl in self.slopes for s in sl[:-2]))),
            default=0,
        )

    def duals(self, box: Sequence[tuple[Fraction, Fraction]], offset: int) -> list[list[Dual]]:
        """``F`` over the gain ``box`` as Dual coefficients: the ball over the box and the
        exact slopes at derivative slots ``offset + i`` (slots before are plant slots)."""
        k = offset + len(self.gains)
        out = []
        for j, p in enumerate(self.base):
            n = max(p.degree(), *(sl[j].degree() for sl in self.slopes), 0) + 1
            coeffs = []
            for c in range(n):
                v = arb(p[c])
                d: list[Any] = [acb(0)] * k
                for i, ((lo, hi), g0i, sl) in enumerate(
                    zip(box, self.g0, self.slopes, strict=True)
                ):
                    v += arb(sl[j][c]) * ball_of(lo - g0i, hi - g0i)
                    d[offset + i] = acb(sl[j][c])
                coeffs.append(Dual(acb(v), d))
            out.append(coeffs)
        return out


_NOT_AFFINE = (
    "box: the discrete controller is not affine in the gains with a fixed denominator "
    "(a gain changes the controller's poles); give the gains values"
)


def _horner(coeffs: Sequence[Any], x: Any) -> Any:
    acc: Any = coeffs[-1] if coeffs else acb(0)
    for c in reversed(coeffs[:-1]):
        acc = acc * x + c
    return acc


def _pad(x: Any, k: int) -> Any:
    if isinstance(x, Jet):
        return x.padded(k)
    if isinstance(x, Dual) and len(x.d) < k:
        return Dual(x.v, [*x.d, *[acb(0)] * (k - len(x.d))])
    return x


def _bilinear(h: tuple, v: Sequence[Any]) -> Any:
    """``vᴴ H v`` (``H00 = 1``), as `seapass.robust.sampled_local` computes it."""
    h0a, h0l, haa, hal, hll = h
    v0, va, vl = v
    c0, ca, cl = (x.conjugate() for x in v)
    return (
        c0 * v0 + h0a * (c0 * va) + h0a.conjugate() * (ca * v0) + h0l * (c0 * vl)
        + h0l.conjugate() * (cl * v0) + haa * (ca * va) + hal * (ca * vl)
        + hal.conjugate() * (cl * va) + hll * (cl * vl)
    )  # fmt: skip


class GainPower:
    """A plant power (`StatePower`) with its own controller: exact polynomials at a
    centre, or Dual coefficients over a gain box (``k`` derivative slots in all)."""

    def __init__(self, power: Any, comps: Sequence[Any], k: int) -> None:
        self.power, self.comps, self.k = power, list(comps), k
        if getattr(power, "order", 1) == 2:  # affine in the gains: Hessian 0
            self.comps = [
                p
                if isinstance(p, fmpq_poly)
                else [Jet(c.v, c.d, [acb(0)] * len(pairs(k))) for c in p]
                for p in self.comps
            ]
        self.ok = power.ok

    @property
    def degree(self) -> int:
        return int(self.power.degree)

    def values(self, z: acb, family: Any, ka: Any) -> tuple[Any, Any]:
        """``(P̃, M̃)`` at ``z`` (the ``family``, ``ka`` arguments are ignored)."""
        k = self.k
        s = {n: _pad(v, k) for n, v in self.power.sums_at(z).items()}
        h = hermitian_entries({n: [v] for n, v in s.items()}, z, 0, self.power.T)
        zinv = 1 / z

        def ev(p: Any) -> Any:
            if isinstance(p, fmpq_poly):
                return _horner([acb(c) for c in p.coeffs()] or [acb(0)], zinv)
            return _horner(p, zinv)

        vec = [ev(p) for p in self.comps[:3]]
        w = _pad(self.power.weight(z), k)
        power = _bilinear(h, vec).real * w
        g = (1 - zinv) / self.power.T * s["Sg"]
        na, da = ev(self.comps[3]), ev(self.comps[4])
        d = da + na * g
        chi = (d * d.conjugate()).real * w
        return power, chi
