"""Mean-value (and Taylor) enclosures of the sampled power over a box, decided by pieces.

Ball arithmetic over a whole box (`ParametricPlant.sums`) loses the correlation between
poles and residues (the enclosure of ``N(ω)`` grows like ``10⁴·δ`` for a relative box
width ``δ``), and a global interpolation of ``P̃(x)`` (``x = cos ωT``) cannot resolve it
near ``x = 1``, where the weight makes ``P̃`` tiny.  This module removes both soundly:

* **Mean-value form.** Every quantity is a `Dual` (a ball and the balls of its
  derivatives, forward mode; a simple pole has ``∂p/∂μ = −(∂f/∂μ)/(∂f/∂s)``).  At the
  box's centre it gives ``v_c``, on the box's balls enclosures ``D_i`` of the derivatives:
  every plant's value lies in ``v_c + Σ_i D_i·[−r_i, r_i]``; with a second-order box
  ([`Jet`][seapass.robust.taylor.Jet]) the Taylor form is used and intersected with it.
* **Local interpolation.** ``P̃`` (and ``M̃ = W·|d_A + n_A g|²``, which is ``|χ|²`` on
  the unit circle up to positive factors) is a polynomial in ``x`` of known bounded
  degree, so on any ``[a, b] ⊂ [−1, 1]`` it is recovered exactly from its values at the
  Chebyshev nodes of ``[a, b]`` (never ``x = 1``), where it is evaluated directly: the
  values are all of the size of ``P̃`` on ``[a, b]``, so the ball polynomial in the local
  variable is as accurate as its values.  Its sign on ``[a, b]`` is decided by Descartes
  ([`sign_on`][seapass.sampled.certified.sign_on]); undecided pieces are halved.

Stability with the port held: stable at the centre (the ordinary certified decision) and
``M̃ > 0`` on ``[−1, 1]`` for every plant of the box (no root of ``χ`` crosses the unit
circle; the leading coefficient of ``χ`` does not depend on the plant) proves stability
for every plant of the box.  Only simple non-origin poles are handled (a multiple pole:
``None``, the caller reports the box undecided).
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from fractions import Fraction
from typing import Any

from flint import acb, arb, arb_mat, arb_poly, fmpq, fmpq_poly

from ..outcome import Outcome
from ..sampled.alias import zeta_numerators
from ..sampled.certified import Sign, interpolation_matrix, sign_on
from .sampled_plant import ParametricPlant, Split, isolate
from .taylor import Jet, taylor_enclose

__all__ = ["GEOMETRIC", "Dual", "LocalPower", "Part", "local_outcome"]

GEOMETRIC = 20
"""Pieces ``[1 − 2^-k, 1 − 2^-(k+1)]`` the partition starts with."""


def _conj(x: Any) -> Any:
    return x.conjugate() if isinstance(x, acb) else x


class Dual:
    """A ball value and the balls of its partial derivatives (forward mode)."""

    __slots__ = ("d", "v")

    def __init__(self, v: Any, d: Sequence[Any]) -> None:
        self.v = v
        self.d = tuple(d)

    def _lift(self, o: Any) -> Dual:
        return o if isinstance(o, Dual) else Dual(o, (0,) * len(self.d))

    def __add__(self, o: Any) -> Dual:
        o = self._lift(o)
        return Dual(self.v + o.v, [a + b for a, b in zip(self.d, o.d, strict=True)])

    __radd__ = __add__

    def __neg__(self) -> Dual:
        return Dual(-self.v, [-a for a in self.d])

    def __sub__(self, o: Any) -> Dual:
        return self + (-self._lift(o))

    def __rsub__(self, o: Any) -> Dual:
        return self._lift(o) - self

    def __mul__(self, o: Any) -> Dual:
        if not isinstance(o, Dual):
            return Dual(self.v * o, [a * o for a in self.d])
        return Dual(self.v * o.v, [a * o.v + self.v * b for a, b in zip(self.d, o.d, strict=True)])

    __rmul__ = __mul__

    def __truediv__(self, o: Any) -> Dual:
        if not isinstance(o, Dual):
            return Dual(self.v / o, [a / o for a in self.d])
        inv = 1 / o.v
        return Dual(
            self.v * inv,
            [(a * o.v - self.v * b) * inv * inv for a, b in zip(self.d, o.d, strict=True)],
        )

    def __rtruediv__(self, o: Any) -> Dual:
        return self._lift(o) / self

    def __pow__(self, n: int) -> Dual:
        out: Dual = self._lift(1)
        for _ in range(n):
            out = out * self
        return out

    @property
    def real(self) -> Dual:
        return Dual(self.v.real, [a.real if hasattr(a, "real") else a for a in self.d])

    def conjugate(self) -> Dual:
        return Dual(_conj(self.v), [_conj(a) for a in self.d])

    def exp(self) -> Dual:
        e = self.v.exp()
        return Dual(e, [a * e for a in self.d])


def _horner(coeffs: Sequence[Any], x: Any) -> Any:
    acc: Any = acb(0)
    for c in reversed(coeffs):
        acc = acc * x + c
    return acc


def _horner_q(p: fmpq_poly, x: Any) -> Any:
    return _horner([acb(c) for c in p.coeffs()], x)


def _bilinear(h: tuple, v: Sequence[acb]) -> Any:
    """``vᴴ H v`` for the Hermitian ``H`` of `hermitian_entries` (``H00 = 1``)."""
    h0a, h0l, haa, hal, hll = h
    v0, va, vl = v
    c0, ca, cl = (x.conjugate() for x in v)
    return (
        c0 * v0
        + h0a * (c0 * va)
        + h0a.conjugate() * (ca * v0)
        + h0l * (c0 * vl)
        + h0l.conjugate() * (cl * v0)
        + haa * (ca * va)
        + hal * (ca * vl)
        + hal.conjugate() * (cl * va)
        + hll * (cl * vl)
    )


class LocalPower:
    """Dual alias sums of every plant of one ball (or of one point), evaluated at any ``z``."""

    def __init__(
        self,
        plant: ParametricPlant,
        ball: Mapping[str, arb],
        period: Fraction,
        names: tuple[str, ...],
        *,
        derive: bool = True,
    ) -> None:
        self.ok = False
        self.T = arb(fmpq(period.numerator, period.denominator))
        k = len(plant.names) if derive else 0
        vn = plant.var_names

        def dual_coeffs(split: Split, p: Any) -> list[Dual]:
            vals = split.at(vn, ball)
            ders = [
                Split.of(p.derivative(n), plant.si).at(vn, ball) if not p.is_zero() else []
                for n in plant.names[:k]
            ]
            out = []
            for j, v in enumerate(vals):
                out.append(Dual(acb(v), [acb(d[j]) if j < len(d) else acb(0) for d in ders]))
            return out

        self.poles: list[tuple[Dual | None, int]] = []  # (pole, mult); None = the origin
        self.cols: list[tuple[int, int]] = []
        factors = plant.factors(names)
        owner = []
        for fi, (split, e, is_s) in enumerate(factors):
            if is_s:
                self.poles.append((None, e))
                owner.append(fi)
                continue
            if e != 1:
                return
            roots = isolate(split.at(vn, ball))
            if roots is None or not all(r.real > 0 or r.real < 0 for r in roots):
                return
            coeffs = dual_coeffs(split, plant.factor_poly(fi, names))
            for r in roots:
                fs = _horner([(i + 1) * c.v for i, c in enumerate(coeffs[1:])], r)
                if fs.contains(0):
                    return
                grads = [-_horner([c.d[i] for c in coeffs], r) / fs for i in range(k)]
                self.poles.append((Dual(r, grads), 1))
                owner.append(fi)
        self.cols = [(i, j) for i, (_p, m) in enumerate(self.poles) for j in range(1, m + 1)]
        self.qs = [None if p is None else (p * self.T).exp() for p, _m in self.poles]
        self.res: dict[str, list[Any]] = {}
        for name in names:
            f = plant.summands[name]
            num = dual_coeffs(Split.of(f.num, plant.si), f.num)
            den = dual_coeffs(Split.of(f.den, plant.si), f.den)
            if den[-1].v.contains(0):
                return
            dder = [(i + 1) * c for i, c in enumerate(den[1:])]
            values: dict[tuple[int, int], Any] = {}
            for i, (p, _m) in enumerate(self.poles):
                mm = plant.multiplicity(f.den, factors[owner[i]][0])
                if mm == 0:
                    continue
                if p is None:  # the origin: Laurent coefficients by series division
                    g = den[mm:] + [Dual(acb(0), [acb(0)] * k)] * mm
                    if g[0].v.contains(0):
                        return
                    h = _series_div([*num, *([Dual(acb(0), [acb(0)] * k)] * mm)][:mm], g, mm)
                    for j in range(1, mm + 1):
                        values[(i, j)] = h[mm - j]
                else:
                    if mm != 1:
                        return
                    dp = _horner(dder, p)
                    if dp.v.contains(0):
                        return
                    values[(i, 1)] = _horner(num, p) / dp
            self.res[name] = [values.get(c) for c in self.cols]
        self.ok = True

    @property
    def degree(self) -> int:
        """Degree in ``x`` of the weight: the non-origin pole multiplicities."""
        return sum(m for p, m in self.poles if p is not None)

    def sums_at(self, z: acb) -> dict[str, Any]:
        F = zeta_numerators(max((j for _i, j in self.cols), default=1))
        kern = []
        for i, j in self.cols:
            q = self.qs[i]
            w = z if q is None else z / q
            kern.append(_horner_q(F[j - 1], w) * (self.T / (w - 1)) ** j)
        return {
            name: sum((r * g for r, g in zip(res, kern, strict=True) if r is not None), acb(0))
            for name, res in self.res.items()
        }

    def weight(self, z: acb) -> Any:
        w: Any = arb(1)
        for q, (_p, m) in zip(self.qs, self.poles, strict=True):
            if q is not None:
                d = z - q
                w = w * ((d * d.conjugate()).real) ** m
        return w

    def values(self, z: acb, family: Sequence[Sequence[fmpq_poly]], ka: Any) -> tuple[Any, Any]:
        """``(P̃, M̃)`` at ``z`` (Duals)."""
        from ..sampled.alias import hermitian_entries

        s = self.sums_at(z)
        sums = {k: [v] for k, v in s.items()}
        h = hermitian_entries(sums, z, 0, self.T)
        zinv = 1 / z
        vec = [_horner_q(comp[0], zinv) for comp in family]
        w = self.weight(z)
        power = _bilinear(h, vec).real * w
        g = (1 - zinv) / self.T * s["Sg"]
        na, da = ka
        d = _horner_q(da, zinv) + _horner_q(na, zinv) * g
        chi = (d * d.conjugate()).real * w
        return power, chi


def _series_div(a: Sequence[Any], b: Sequence[Any], n: int) -> list[Any]:
    out: list[Any] = []
    for t in range(n):
        acc = a[t]
        for u in range(t):
            acc = acc - out[u] * b[t - u]
        out.append(acc / b[0])
    return out


def _enclose(centre: Any, box: Any, radii: Sequence[arb]) -> arb:
    """``v_c + Σ D_i [−r_i, r_i]`` (real parts), or `taylor_enclose` for a `Jet` box."""
    if isinstance(box, Jet) and isinstance(centre, Dual) and len(centre.d) == len(box.d):
        return taylor_enclose(centre.v, centre.d, box, radii)
    v = centre.v if isinstance(centre, Dual) else centre
    out = arb(v.real if isinstance(v, acb) else v)
    for d, r in zip(box.d, radii, strict=True):
        dr = d.real if isinstance(d, acb) else arb(d)
        out += dr * (-r).union(r)
    return out


Part = tuple[LocalPower, LocalPower, Sequence[arb]]
"""``(centre, box, radii)``: the dual numbers at a box's centre and over the box."""


def local_outcome(
    centre: LocalPower,
    box: LocalPower,
    radii: Sequence[arb],
    family: Sequence[Sequence[fmpq_poly]],
    ka: tuple[fmpq_poly, fmpq_poly],
    degree: int,
    prec: int,
    *,
    budget: int = 64,
    refine: Callable[[int], Sequence[Part]] | None = None,
    levels: int = 0,
) -> tuple[Outcome, bool]:
    """Sign of ``P̃`` and positivity of ``M̃`` on ``[−1, 1]`` for every plant of the box.

    Returns ``(outcome of the power, M̃ > 0 proven)``: ``PASSIVE`` when ``P̃ > 0`` is
    proven everywhere, ``NOT_PASSIVE`` when some piece has ``P̃ < 0`` proven for every
    plant, ``UNDECIDED`` when ``budget`` pieces (once per part) did not settle it, or
    when halving a piece at the finest parts twice does not narrow it (`STALL`).

    ``refine(level)`` (optional) returns ``(centre, box, radii)`` parts whose boxes cover
    the box (finer with the level, up to ``levels``): a piece whose node enclosures are
    wide is retried on the parts (each node's enclosure is the union of the parts'), so
    the box is split for that piece of ``[−1, 1]`` only.
    """
    n = degree
    pi = arb.pi()
    nodes = [pi * (2 * i + 1) / (2 * (n + 1)) for i in range(n + 1)]
    ts = [th.cos() for th in nodes]
    cos_table = [[(k * th).cos() for th in nodes] for k in range(n + 1)]
    mat = interpolation_matrix(n, prec)
    bern = chebyshev_bernstein(n)
    # geometric pieces towards x = ±1, where the weight's factors (x_q − x) of slow poles
    # make the power tiny: each piece then holds values of one size
    ends = [Fraction(1) - Fraction(1, 2**k) for k in range(1, GEOMETRIC + 1)]
    # towards x = −1 (a lightly damped mode near the Nyquist frequency) pieces are halved
    # only where needed
    cuts = [Fraction(-1), Fraction(-1, 2), Fraction(0), *ends, Fraction(1)]
    stack = [(a, b, 0, math.inf, 0) for a, b in reversed(list(itertools.pairwise(cuts)))]
    pieces = 0
    power_ok, chi_ok = True, True
    while stack:
        a, b, level, before, stalls = stack.pop()
        parts = [(centre, box, radii)] if level == 0 or refine is None else refine(level)
        pieces += len(parts)  # the work: one part on one piece
        if pieces > budget:
            return Outcome.UNDECIDED, False
        c = arb(fmpq((a + b).numerator, (a + b).denominator)) / 2
        h = arb(fmpq((b - a).numerator, (b - a).denominator)) / 2
        zs = [acb(0, (c + h * t).acos()).exp() for t in ts]
        done, wide = True, 0.0
        for part_c, part_b, part_r in parts:  # each plant is in one part: each must pass
            pv, cv = [], []
            for z in zs:
                p_c, m_c = part_c.values(z, family, ka)
                p_b, m_b = part_b.values(z, family, ka)
                pv.append(_enclose(p_c, p_b, part_r))
                cv.append(_enclose(m_c, m_b, part_r))
            if level == 0 and any(v < 0 for v in pv):  # every plant: a negative power there
                return Outcome.NOT_PASSIVE, False
            if not all(
                _positive(v, cos_table) or _lebesgue_positive(v, mat)
                or _bernstein_positive(v, cos_table, bern)
                for v in (pv, cv)
            ):  # fmt: skip
                done = False
                wide = _spread(pv + cv)
                break
        if done:
            continue
        if refine is not None and level < levels and wide > WIDE:
            stack.append((a, b, min(levels, level + (1 if wide < 10 * WIDE else 2)), wide, 0))
            continue
        if b - a < Fraction(1, 2**40):
            power_ok = chi_ok = False
            continue
        if refine is not None and level == levels and wide > WIDE:
            if (stalls := stalls + 1 if wide > STALL * before else 0) >= 2:
                return Outcome.UNDECIDED, False
        mid = (a + b) / 2
        stack += [(mid, b, level, wide, stalls), (a, mid, level, wide, stalls)]
    if not power_ok:
        return Outcome.UNDECIDED, False
    return Outcome.PASSIVE, chi_ok


WIDE = 0.05
"""A node enclosure wider than this share of its value makes a piece split the box."""

STALL = 0.9  # a halved piece at the finest parts not narrower than this share: a stall


def _spread(values: Sequence[arb]) -> float:
    """The largest relative radius of ``values`` (infinite for a ball around 0)."""
    worst = 0.0
    for v in values:
        mid = abs(float(v.mid()))
        if not v.is_finite() or mid == 0:
            return math.inf
        worst = max(worst, float(v.rad()) / mid)
    return worst


@functools.cache
def chebyshev_bernstein(n: int) -> tuple[tuple[fmpq, ...], ...]:
    """``table[k][j]``: the ``j``-th Bernstein coefficient (degree ``n``, on ``[−1, 1]``) of
    the Chebyshev polynomial ``T_k``, exact."""
    out = []
    for k in range(n + 1):
        tk = fmpq_poly(chebyshev_t(k))
        u = tk(fmpq_poly([-1, 2]))  # T_k(2u − 1), monomials in u on [0, 1]
        a = [u.coeffs()[i] if i < len(u.coeffs()) else fmpq(0) for i in range(n + 1)]
        out.append(
            tuple(
                sum((a[i] * fmpq(math.comb(j, i), math.comb(n, i)) for i in range(j + 1)), fmpq(0))
                for j in range(n + 1)
            )
        )
    return tuple(out)


def chebyshev_t(k: int) -> list[int]:
    """Integer coefficients (ascending) of ``T_k``."""
    a, b = [1], [0, 1]
    if k == 0:
        return a
    for _ in range(k - 1):
        c = [0, *(2 * x for x in b)]
        for i, x in enumerate(a):
            c[i] -= x
        a, b = b, c
    return b


def _bernstein_positive(
    values: Sequence[arb], cos_table: Sequence[Sequence[arb]], table: Sequence[Sequence[fmpq]]
) -> bool:
    """Every Bernstein coefficient of the interpolant on ``[−1, 1]`` is ``> 0`` (the
    polynomial is a positive combination of the nonnegative Bernstein basis)."""
    n = len(values) - 1
    coeffs = []
    for k, row in enumerate(cos_table):
        acc = arb(0)
        for v, c in zip(values, row, strict=True):
            acc += v * c
        coeffs.append(acc * 2 / (n + 1) / (2 if k == 0 else 1))
    for j in range(n + 1):
        acc = arb(0)
        for k in range(n + 1):
            acc += coeffs[k] * table[k][j]
        if not acc > 0:
            return False
    return True


def _lebesgue_positive(values: Sequence[arb], mat: Any) -> bool:
    """Every degree-``n`` polynomial through the node balls is ``> 0`` on ``[−1, 1]``.

    Such a polynomial is the interpolant of the midpoints plus the interpolant of errors
    ``|e_i| ≤ rad_i``, which is bounded by the Lebesgue constant of the Chebyshev nodes
    times ``max rad_i``; ``Λ_n ≤ (2/π) log(n + 1) + 1`` (Rivlin [1]_, one more is added
    for margin).  So Descartes on the midpoints' interpolant minus ``Λ·max rad`` decides,
    with no amplification of the radii by the change of basis.

    References
    ----------
    .. [1] T. J. Rivlin, "The Chebyshev Polynomials", Wiley, 1974, Theorem 1.2.
    """
    n = len(values) - 1
    mids = [arb(v.mid()) for v in values]
    rad = arb(0)
    for v in values:
        if not v.is_finite():
            return False
        r = arb(v.rad())  # exact points: the comparison is exact
        if r > rad:
            rad = r
    lam = 2 * arb(n + 1).log() / arb.pi() + 2
    col = mat * arb_mat([[v] for v in mids])
    coeffs = [col[j, 0] for j in range(n + 1)]
    coeffs[0] -= lam * rad
    return sign_on([arb_poly(coeffs)], Fraction(-1), Fraction(1), budget=40).sign is Sign.POSITIVE


def _positive(values: Sequence[arb], cos_table: Sequence[Sequence[arb]]) -> bool:
    """The interpolant of ``values`` at the Chebyshev nodes is ``> 0`` on ``[−1, 1]``.

    ``p = Σ c_k T_k`` with ``c_k = (2/(n+1)) Σ_i v_i cos(kθ_i)`` (``c_0`` halved), exact
    for degree ``≤ n``; ``|T_k| ≤ 1`` gives ``p ≥ c_0 − Σ_{k≥1} |c_k|``.  Well conditioned:
    no conversion to monomials, whose radii grow like ``(1 + √2)^n``.
    """
    n = len(values) - 1
    coeffs = []
    for k, row in enumerate(cos_table):
        acc = arb(0)
        for v, c in zip(values, row, strict=True):
            acc += v * c
        coeffs.append(acc * 2 / (n + 1) / (2 if k == 0 else 1))
    lower = coeffs[0]
    for c in coeffs[1:]:
        lower -= c.abs_upper()
    return bool(lower > 0)
