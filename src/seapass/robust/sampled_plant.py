"""Alias sums of a *family* of plants: the sampled-data data of every plant in a ball.

[`seapass.sampled.alias`][seapass.sampled.alias] computes the alias sums of one plant
from its exact poles and residues.  Here the uncertain plant parameters (``m``, ``b``,
``k1``, ``b1`` ...) stay variables: `ParametricPlant` builds the summands ``ψ`` of
[`seapass.sampled.plant.Plant.summands`][seapass.sampled.plant.Plant.summands] as exact
rational functions of ``s`` *and* those parameters (python-flint ``fmpq_mpoly``, reduced by
exact gcds, the other values substituted exactly), and factors the common denominator
once over ``Q[params][s]``.  `ParametricPlant.sums` then evaluates every coefficient on a
box of parameter values given as arb balls and returns an
[`AliasSums`][seapass.sampled.alias.AliasSums] whose every number is a ball containing
the value for *every* plant of the box:

* poles: for each irreducible factor (multiplicity ``e``), approximate roots of the
  midpoint polynomial, then the Weierstrass inclusion disks
  ``|z − z_i| ≤ n |p(z_i)| / (|a_n| Π_{j≠i} |z_i − z_j|)`` evaluated in ball arithmetic
  on the *ball* polynomial: the bound holds for every polynomial of the ball, and
  pairwise disjoint disks hold exactly one root each (Smith's theorem), so every
  plant's poles are enclosed one per disk;
* ``q = e^{pT}`` and the residues (Taylor coefficients at the pole ball): arb's
  contract is that an operation on balls contains its value at every point of the
  input balls [1]_, so each residue ball contains the residue of every plant whose
  pole lies in the pole ball (the pairing the ball does not track is only wider);
* a factor whose roots cannot be isolated over the box, a leading coefficient (or a
  constant term of the plant) whose ball contains 0, or a pole ball that touches the
  imaginary axis gives ``None``: the caller splits the box or reports undecided.

The conditions of the physical plant are checked over the box too (`ParametricPlant.sums`
returns ``None`` unless proven): the modes with the port held (roots of ``α + D1`` and of
the denominator of ``D2``) have negative real parts, and ``Re Z0(jω) > 0`` (``R(0) > 0``
and no root of the numerator of ``R`` on the imaginary axis).

References
----------
.. [1] F. Johansson, "Arb: efficient arbitrary-precision midpoint-radius interval
   arithmetic", IEEE Trans. Computers 66(8), 2017 (the inclusion principle).
.. [2] B. T. Smith, "Error bounds for zeros of a polynomial based upon Gerschgorin's
   theorems", J. ACM 17(4), 1970.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from flint import acb, acb_poly, arb, fmpq, fmpq_mpoly, fmpz

from ..errors import ModelError, ParameterError
from ..model.elements import exact_values
from ..model.rational import S_NAME, RatFunc
from ..model.sea import SEA
from ..sampled.alias import MAX_MULTIPLICITY, AliasSums, Pole
from ..sampled.certified import precision

__all__ = ["ParametricPlant", "Split", "ball_of", "isolate"]

PLANT_ELEMENTS = ("m", "b", "D1", "D2")


def ball_of(lo: Fraction, hi: Fraction) -> arb:
    """A ball containing ``[lo, hi]`` (call under a working precision)."""
    a = arb(fmpq(lo.numerator, lo.denominator))
    return a if lo == hi else a.union(arb(fmpq(hi.numerator, hi.denominator)))


def _reflect(p: fmpq_mpoly, i: int) -> fmpq_mpoly:
    """``p(−s)``."""
    d = {e: (-c if e[i] % 2 else c) for e, c in zip(p.monoms(), p.coeffs(), strict=True)}
    return p.context().from_dict(d)


@dataclass(frozen=True, kw_only=True)
class Split:
    """``p`` as coefficients in ``s`` (ascending), each an mpoly in the parameters."""

    coeffs: tuple[fmpq_mpoly, ...]

    @classmethod
    def of(cls, p: fmpq_mpoly, i: int) -> Split:
        ctx = p.context()
        deg = p.degrees()[i] if not p.is_zero() else -1
        parts: list[dict[tuple[int, ...], fmpq]] = [{} for _ in range(deg + 1)]
        for e, c in zip(p.monoms(), p.coeffs(), strict=True):
            k = e[i]
            parts[k][tuple(0 if j == i else x for j, x in enumerate(e))] = c
        return cls(coeffs=tuple(ctx.from_dict(d) for d in parts))

    def at(self, names: Sequence[str], ball: Mapping[str, arb]) -> list[arb]:
        return [_eval(c, names, ball) for c in self.coeffs]


def _eval(p: fmpq_mpoly, names: Sequence[str], ball: Mapping[str, arb]) -> arb:
    """``p`` on the balls (sum of monomials; encloses every value on the box)."""
    acc = arb(0)
    for e, c in zip(p.monoms(), p.coeffs(), strict=True):
        term = arb(c)
        for n, k in zip(names, e, strict=True):
            if k and n != S_NAME:
                term *= ball[n] ** k
        acc += term
    return acc


def _lead_ok(coeffs: Sequence[arb]) -> bool:
    return bool(coeffs) and not coeffs[-1].contains(0)


class ParametricPlant:
    """The summands of a plant whose parameters ``names`` are uncertain (exact, once).

    Raises
    ------
    ParameterError
        A name is not a plant parameter (it appears in neither ``m``, ``b``, ``D1``
        nor ``D2``) or also appears in a controller.
    ModelError
        A summand's alias sum diverges for every plant, or a pole of too high multiplicity.
    """

    def __init__(self, sea: SEA, names: Sequence[str]) -> None:
        elements = sea.exact_elements()
        used_plant = set().union(*(elements[k].parameters() for k in PLANT_ELEMENTS))
        used_ctrl = set().union(*(elements[k].parameters() for k in ("CA", "CL")))
        for n in names:
            if n not in used_plant:
                raise ParameterError(
                    f"box[{n!r}]: not a plant parameter (m, b, D1, D2 do not use it); a sampled "
                    "robust verdict takes plant parameters, bound a gain instead",
                    argument="box",
                )
            if n in used_ctrl:
                raise ParameterError(
                    f"box[{n!r}]: also used by a controller; the deployed controller must not "
                    "depend on an uncertain plant parameter",
                    argument="box",
                )
        self.names = tuple(names)
        fixed = {k: v for k, v in exact_values(sea.values).items() if k not in self.names}
        el = {k: _substitute(elements[k], fixed) for k in PLANT_ELEMENTS}
        missing = set().union(*(f.parameters() for f in el.values())) - set(self.names)
        if missing:
            raise ParameterError("plant parameters without values: " + ", ".join(sorted(missing)))
        ctx = el["m"].context
        self.ctx = ctx
        self.var_names = tuple(ctx.names())
        self.si = ctx.variable_to_index(S_NAME)
        s = RatFunc.variable(ctx, S_NAME)
        one = RatFunc.constant(ctx, 1)
        alpha = el["m"] * s * s + el["b"] * s
        d1, d2 = el["D1"], el["D2"]
        held = alpha + d1
        a, p = d1 / held, one / held
        z0 = (d1 * alpha / held + d2) / s
        r = (z0 + self._reflect(z0)) / RatFunc.constant(ctx, 2)
        a_ref = self._reflect(a)
        over = one / (RatFunc.constant(ctx, -1) * s * s * r)
        self.summands = {
            "S1": a * a_ref * over,
            "S2": a * a / (s * s * r),
            "S3": a * over,
            "S4": over,
            "Sg": p / s,
        }
        self.r = r
        self.modes = [p.den, d2.den]  # roots must have negative real parts
        self.divergent = frozenset(
            name
            for name, f in self.summands.items()
            if name != "S4"
            and f.degrees_in_s()[0] >= 0
            and f.degrees_in_s()[1] - f.degrees_in_s()[0] < 2
        )  # checked for the sums a controller needs (`check_sums`)
        self._factors: dict[tuple[str, ...], list[tuple[Split, int, bool]]] = {}

    def check_sums(self, names: Sequence[str]) -> None:
        """Raise `ModelError` if an alias sum of ``names`` diverges for this plant family."""
        for name in names:
            if name in self.divergent:
                raise ModelError(f"the alias sum {name} diverges for this plant family")

    def _reflect(self, f: RatFunc) -> RatFunc:
        i = self.ctx.variable_to_index(S_NAME)
        return RatFunc.from_polys(_reflect(f.num, i), _reflect(f.den, i))

    def alias_injection(self) -> bool:
        """``Σ 1/(|s_k|² Re Z0)`` diverges for the generic plant of the family."""
        dn, dd = self.summands["S4"].degrees_in_s()
        return dd - dn < 2

    def factors(self, names: tuple[str, ...]) -> list[tuple[Split, int, bool]]:
        """Irreducible factors of the common denominator: ``(coefficients, mult, is s)``."""
        if names not in self._factors:
            lcm = self.ctx.constant(1)
            for k in names:
                den = self.summands[k].den
                lcm = lcm * den / lcm.gcd(den)
            out = []
            for f, e in lcm.factor()[1]:
                if f.degrees()[self.si] == 0:
                    continue  # a factor of the parameters alone: no pole
                if e > MAX_MULTIPLICITY:
                    raise ModelError(f"a pole of multiplicity {e} in an alias sum")
                is_s = f.total_degree() == 1 and f.degrees()[self.si] == 1 and len(f) == 1
                out.append((Split.of(f, self.si), int(e), is_s))
            self._factors[names] = out
        return self._factors[names]

    def factor_poly(self, index: int, names: tuple[str, ...]) -> fmpq_mpoly:
        """The ``index``-th factor of `factors` as a polynomial in ``s`` and the parameters."""
        split = self.factors(names)[index][0]
        f = self.ctx.constant(0)
        for k, c in enumerate(split.coeffs):
            f += c * self.ctx.gen(self.si) ** k
        return f

    def multiplicity(self, den: fmpq_mpoly, factor: Split) -> int:
        """How often ``factor`` divides ``den`` (exactly, for every value of the parameters)."""
        return _multiplicity(den, factor, self.si)

    def _roots(self, split: Split, ball: Mapping[str, arb]) -> list[acb] | None:
        coeffs = split.at(self.var_names, ball)
        if not _lead_ok(coeffs):
            return None
        return isolate(coeffs)

    def plant_ok(self, ball: Mapping[str, arb]) -> bool:
        """The physical plant conditions hold for every plant of the ball (proven)."""
        for den in self.modes:
            split = Split.of(den, self.si)
            if len(split.coeffs) <= 1:
                continue
            roots = self._roots(split, ball)
            if roots is None or not all(r.real < 0 for r in roots):
                return False
        rn, rd = (Split.of(p, self.si) for p in (self.r.num, self.r.den))
        r0 = rn.at(self.var_names, ball)[0] / rd.at(self.var_names, ball)[0]
        if not r0 > 0:
            return False
        roots = self._roots(rn, ball) if len(rn.coeffs) > 1 else []
        return roots is not None and all(r.real > 0 or r.real < 0 for r in roots)

    def sums(
        self, ball: Mapping[str, arb], period: Fraction, names: tuple[str, ...], prec: int
    ) -> AliasSums | None:
        """Enclosures of the alias sums ``names`` for every plant of ``ball`` (or None)."""
        with precision(prec):
            if not self.plant_ok(ball):
                return None
            T = arb(fmpq(period.numerator, period.denominator))
            poles: list[Pole] = []
            owner: list[int] = []
            factors = self.factors(names)
            for fi, (split, e, is_s) in enumerate(factors):
                if is_s:
                    poles.append(Pole(acb(0), acb(1), e, True))
                    owner.append(fi)
                    continue
                roots = self._roots(split, ball)
                if roots is None or not all(r.real > 0 or r.real < 0 for r in roots):
                    return None
                for r in roots:
                    poles.append(Pole(r, (r * T).exp(), e, False))
                    owner.append(fi)
            columns = tuple((i, j) for i, pole in enumerate(poles) for j in range(1, pole.mult + 1))
            residues: dict[str, tuple[acb, ...]] = {}
            for name in names:
                f = self.summands[name]
                num = acb_poly(Split.of(f.num, self.si).at(self.var_names, ball))
                den_split = Split.of(f.den, self.si)
                den_c = den_split.at(self.var_names, ball)
                if not _lead_ok(den_c):
                    return None
                den = acb_poly(den_c)
                mults = [
                    _multiplicity(f.den, factors[fi][0], self.si) for fi in range(len(factors))
                ]
                values: dict[tuple[int, int], acb] = {}
                for i, pole in enumerate(poles):
                    m = mults[owner[i]]
                    if m == 0:
                        continue
                    shift = acb_poly([pole.p, 1])
                    dt = _coeffs(den(shift), 2 * m)[m:]
                    if dt[0].contains(0):
                        return None
                    h = _series_div(_coeffs(num(shift), m), dt, m)
                    for j in range(1, m + 1):
                        values[(i, j)] = h[m - j]
                residues[name] = tuple(values.get(c, acb(0)) for c in columns)
            if any(not x.is_finite() for v in residues.values() for x in v):
                return None
            return AliasSums(fmpq(period.numerator, period.denominator), tuple(poles), columns,
                             residues, prec)  # fmt: skip


def _substitute(f: RatFunc, values: Mapping[str, fmpq]) -> RatFunc:
    used: dict[str | int, int | fmpz | fmpq] = {
        k: v for k, v in values.items() if k in f.parameters()
    }
    if not used:
        return f
    return RatFunc.from_polys(f.num.subs(used), f.den.subs(used))


def _multiplicity(den: fmpq_mpoly, factor: Split, si: int) -> int:
    ctx = den.context()
    f = ctx.constant(0)
    for k, c in enumerate(factor.coeffs):
        f += c * ctx.gen(si) ** k
    k = 0
    while True:
        q, r = divmod(den, f)
        if not r.is_zero():
            return k
        den, k = q, k + 1


def _coeffs(p: acb_poly, n: int) -> list[acb]:
    c = p.coeffs()
    return [c[i] if i < len(c) else acb(0) for i in range(n)]


def _series_div(a: Sequence[acb], b: Sequence[acb], n: int) -> list[acb]:
    out: list[acb] = []
    for t in range(n):
        acc = a[t]
        for u in range(t):
            acc -= out[u] * b[t - u]
        out.append(acc / b[0])
    return out


def isolate(coeffs: Sequence[arb]) -> list[acb] | None:
    """One disk per root, valid for every polynomial of the ball ``Σ coeffs[k] s^k``.

    Approximations from the midpoint polynomial (floating point, then Newton steps at the
    working precision); the Weierstrass radii ``n |p(z_i)| / (|a_n| Π_{j≠i} |z_i − z_j|)``
    are upper bounds over the ball; disjoint disks hold one root each [2]_.  Returns the
    roots as complex balls (squares containing the disks), or None if not isolated.
    """
    n = len(coeffs) - 1
    if n <= 0:
        return []
    mids = [float(c.mid()) for c in coeffs]
    approx = np.roots(mids[::-1])
    if len(approx) != n or not np.all(np.isfinite(approx)):
        return None
    mid_poly = acb_poly([acb(c.mid()) for c in coeffs])
    deriv = mid_poly.derivative()
    zs = []
    for z0 in approx:
        z = acb(complex(z0))
        for _ in range(4):
            d = deriv(z)
            if d.contains(0):
                break
            z = acb((z - mid_poly(z) / d).mid())
        zs.append(acb(z.mid()))
    ball = acb_poly([acb(c) for c in coeffs])
    lead = acb(coeffs[-1])
    radii = []
    for i, z in enumerate(zs):
        den = lead
        for j, w in enumerate(zs):
            if j != i:
                den *= z - w
        if den.contains(0):
            return None
        radii.append((ball(z) / den).abs_upper() * n)
    for i in range(n):
        for j in range(i + 1, n):
            if not (zs[i] - zs[j]).abs_lower() > radii[i] + radii[j]:
                return None
    return [z + acb((-r).union(r), (-r).union(r)) for z, r in zip(zs, radii, strict=True)]
