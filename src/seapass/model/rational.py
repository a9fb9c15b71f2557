"""Exact rational functions of ``s`` and the parameters, on python-flint, within a size budget.

A [`RatFunc`][seapass.model.rational.RatFunc] is ``num/den`` with ``num`` and ``den``
multivariate polynomials with rational coefficients (``flint.fmpq_mpoly``) in ``s``
and the parameter names of one model, always in lowest terms: every operation
divides by the exact gcd.  Parameters are kept as variables (not replaced by their
values) so that a factor cancels exactly when it cancels for *every* value, as in
sympy's ``cancel``; a factor that cancels only at the given values stays, and the
passivity test reports it as a hidden mode.  Values are substituted at the end
(`RatFunc.evaluate`), which leaves exact univariate polynomials in ``s``.

Every operation checks its size before it runs (`MAX_EXACT_DEGREE`,
`MAX_EXACT_TERMS`, `MAX_EXACT_WORK`, `MAX_EXACT_BITS` in
[`seapass.files.limits`][seapass.files.limits]), so a hostile expression is refused
in microseconds instead of exhausting time or memory.

`canonical` returns the normal form sympy's ``fraction(cancel(...))`` gives
(integer coefficients without a common factor, the denominator's leading
coefficient positive in sympy's order of generators), so results printed from
either path agree to the last bit.

What lives here: `RatFunc`, the variable ordering (`variables`).  May import:
`seapass.model.delayatom` (the delay variable's prefix),
[`seapass.errors`][seapass.errors], [`seapass.files`][seapass.files] and python-flint.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterable, Mapping
from fractions import Fraction

from flint import fmpq, fmpq_mpoly, fmpq_mpoly_ctx, fmpq_poly, fmpz

from ..errors import SymbolicLimitError
from ..files.limits import MAX_EXACT_BITS, MAX_EXACT_DEGREE, MAX_EXACT_TERMS, MAX_EXACT_WORK
from .delayatom import DELAY_PREFIX, delay_refusal

__all__ = ["S_NAME", "RatFunc", "context", "on_axis", "sympy_order", "univariate", "variables"]

S_NAME = "s"
"""Name of the Laplace variable."""

# sympy.polys.polyutils._sort_gens: single letters x, y, z first, then p..w, then a..o,
# then every other name; a trailing number is an index (k1 sorts as ('k', 1))
_GENS_ORDER = {
    **{c: 301 + i for i, c in enumerate("abcdefghijklmno")},
    **{c: 216 + i for i, c in enumerate("pqrstuvw")},
    **{c: 124 + i for i, c in enumerate("xyz")},
}
_MAX_ORDER = 1000
_INDEXED = re.compile(r"^(.*?)(\d*)$")


def _order_key(name: str) -> tuple[int, str, int, str]:
    match = _INDEXED.match(name)
    assert match is not None
    base, index = match.groups()
    return (_GENS_ORDER.get(base, _MAX_ORDER), base, int(index) if index else 0, name)


def sympy_order(names: Iterable[str]) -> tuple[str, ...]:
    """``names`` in the order sympy gives polynomial generators (``_sort_gens``).

    >>> sympy_order(["kd", "s", "k1", "b", "x"])
    ('x', 's', 'b', 'k1', 'kd')
    """
    return tuple(sorted(set(names), key=_order_key))


def variables(names: Iterable[str]) -> tuple[str, ...]:
    """``s`` and the parameter ``names``, in sympy's order of generators."""
    return sympy_order({S_NAME, *names})


@functools.lru_cache(maxsize=256)
def context(names: tuple[str, ...]) -> fmpq_mpoly_ctx:
    """The flint context (lexicographic) of the variables ``names`` (``s`` among them)."""
    return fmpq_mpoly_ctx.get(names, "lex")


def _bits(p: fmpq_mpoly) -> int:
    """Largest numerator or denominator size, in bits, of a coefficient of ``p``."""
    out = 0
    for c in p.coeffs():
        out = max(out, c.p.bit_length(), c.q.bit_length())
    return out


class RatFunc:
    """``num/den`` in lowest terms, exact, in the variables of one context.

    Build one with `constant`, `variable` or `from_polys` and combine with
    ``+ - * /``, unary minus and integer ``**``.  Each operation checks the size of
    what it is about to compute first and raises
    [`SymbolicLimitError`][seapass.errors.SymbolicLimitError] (``"too large"``)
    beyond the budget.

    Examples
    --------
    >>> ctx = context(variables(["kd", "ki"]))
    >>> s, kd, ki = (RatFunc.variable(ctx, n) for n in ("s", "kd", "ki"))
    >>> c = kd + ki / s
    >>> c
    RatFunc('(s*kd + ki)/(s)')
    >>> (c * s / (s * kd + ki)).is_one
    True
    """

    __slots__ = ("_bits", "den", "num")

    def __init__(self, num: fmpq_mpoly, den: fmpq_mpoly) -> None:
        self.num = num
        self.den = den
        self._bits = -1

    # ----------------------------------------------------------------- construction

    @classmethod
    def constant(cls, ctx: fmpq_mpoly_ctx, value: Fraction | int) -> RatFunc:
        q = Fraction(value)
        num = ctx.constant(fmpq(q.numerator, q.denominator))
        return cls(num, ctx.constant(1))

    @classmethod
    def variable(cls, ctx: fmpq_mpoly_ctx, name: str) -> RatFunc:
        return cls(ctx.gen(ctx.variable_to_index(name)), ctx.constant(1))

    @classmethod
    def from_polys(cls, num: fmpq_mpoly, den: fmpq_mpoly) -> RatFunc:
        """``num/den`` reduced (``den`` must not be zero)."""
        if den.is_zero():
            raise ZeroDivisionError("denominator is identically zero")
        return cls(num, den).reduced()

    # ----------------------------------------------------------------- properties

    @property
    def context(self) -> fmpq_mpoly_ctx:
        return self.num.context()

    @property
    def is_zero(self) -> bool:
        return bool(self.num.is_zero())

    @property
    def is_one(self) -> bool:
        return bool((self.num - self.den).is_zero())

    @property
    def bits(self) -> int:
        """Largest coefficient size (bits) of ``num`` and ``den``."""
        if self._bits < 0:
            self._bits = max(_bits(self.num), _bits(self.den))
        return self._bits

    def names(self) -> frozenset[str]:
        """The variables ``num/den`` depends on (``s`` included if it does)."""
        used = [max(a, b) > 0 for a, b in zip(self.num.degrees(), self.den.degrees(), strict=True)]
        return frozenset(n for n, u in zip(self.context.names(), used, strict=True) if u)

    def parameters(self) -> frozenset[str]:
        """The parameter names ``num/den`` depends on (without ``s``)."""
        return self.names() - {S_NAME}

    def degrees_in_s(self) -> tuple[int, int]:
        """``(deg num, deg den)`` in ``s`` (-1 for a zero numerator)."""
        i = self.context.variable_to_index(S_NAME)
        return (self.num.degrees()[i] if not self.num.is_zero() else -1, self.den.degrees()[i])

    # ----------------------------------------------------------------- arithmetic

    def reduced(self) -> RatFunc:
        if self.num.is_zero():
            return RatFunc(self.num, self.den.context().constant(1))
        g = self.num.gcd(self.den)
        if g.is_one():
            return self
        return RatFunc(self.num / g, self.den / g)

    def __neg__(self) -> RatFunc:
        return RatFunc(-self.num, self.den)

    def __add__(self, other: RatFunc) -> RatFunc:
        if other.is_zero:
            return self
        if self.is_zero:
            return other
        a, b, c, d = self.num, self.den, other.num, other.den
        g = b.gcd(d)
        if not g.is_one():
            bg, dg = b / g, d / g
        else:
            bg, dg = b, d
        _check_product(a, dg)
        _check_product(c, bg)
        _check_product(b, dg)
        return RatFunc(_check_terms(a * dg + c * bg), _check_terms(b * dg)).reduced()

    def __sub__(self, other: RatFunc) -> RatFunc:
        return self + (-other)

    def __mul__(self, other: RatFunc) -> RatFunc:
        a, b, c, d = self.num, self.den, other.num, other.den
        if a.is_zero() or c.is_zero():
            return RatFunc(a.context().constant(0), a.context().constant(1))
        g1, g2 = a.gcd(d), c.gcd(b)
        if not g1.is_one():
            a, d = a / g1, d / g1
        if not g2.is_one():
            c, b = c / g2, b / g2
        _check_product(a, c)
        _check_product(b, d)
        return RatFunc(_check_terms(a * c), _check_terms(b * d))

    def __truediv__(self, other: RatFunc) -> RatFunc:
        if other.is_zero:
            raise ZeroDivisionError("division by an expression that is identically zero")
        return self * RatFunc(other.den, other.num)

    def __pow__(self, exponent: int) -> RatFunc:
        if exponent < 0:
            if self.is_zero:
                raise ZeroDivisionError("a negative power of zero")
            return RatFunc(self.den, self.num) ** (-exponent)
        out = RatFunc(self.num.context().constant(1), self.num.context().constant(1))
        base = self
        n = exponent
        while n:
            if n & 1:
                out = out * base
            n >>= 1
            if n:
                base = base * base
        return out

    def to_context(self, ctx: fmpq_mpoly_ctx) -> RatFunc:
        """The same function in ``ctx``, whose variables include every name used here."""
        if ctx is self.context:
            return self
        missing = self.names() - set(ctx.names())
        if missing:
            raise ValueError(f"context lacks the variables {sorted(missing)}")
        return RatFunc(self.num.project_to_context(ctx), self.den.project_to_context(ctx))

    # ----------------------------------------------------------------- normal form

    def canonical(self) -> tuple[fmpq_mpoly, fmpq_mpoly]:
        """``(N, D)`` as sympy's ``fraction(cancel(together(.)))`` gives them.

        Integer coefficients with no common factor across ``N`` and ``D``, the
        leading coefficient of ``D`` positive in lexicographic order of sympy's
        generators (the context of `variables` has that order), and, as sympy's
        automatic distribution of a number over a sum does, ``N/c`` over ``1``
        when ``D`` is a constant ``c`` and ``N`` has several terms.

        >>> ctx = context(variables(["kd"]))
        >>> s, kd = RatFunc.variable(ctx, "s"), RatFunc.variable(ctx, "kd")
        >>> n, d = ((s + RatFunc.constant(ctx, 1)) / (RatFunc.constant(ctx, -2) * kd)).canonical()
        >>> str(n), str(d)
        ('-s - 1', '2*kd')
        """
        num, den = self.num, self.den
        ctx = num.context()
        coeffs = [*num.coeffs(), *den.coeffs()]
        lcm = fmpz(1)
        for c in coeffs:
            lcm = lcm * c.q // lcm.gcd(c.q)
        content = fmpz(0)
        for c in coeffs:
            content = content.gcd(c.p * (lcm // c.q))
        scale = fmpq(lcm) / content
        if den.leading_coefficient() < 0:
            scale = -scale
        num, den = num * scale, den * scale
        if den.is_constant() and len(num) > 1 and not den.is_one():
            return num / den.leading_coefficient(), ctx.constant(1)
        return num, den

    # ----------------------------------------------------------------- values

    def evaluate(self, values: Mapping[str, fmpq]) -> tuple[fmpq_poly, fmpq_poly]:
        """Univariate ``(num, den)`` in ``s`` with every parameter replaced by its value."""
        return univariate(self.num, values), univariate(self.den, values)

    def __repr__(self) -> str:
        return f"RatFunc('({self.num})/({self.den})')"


def on_axis(p: fmpq_mpoly) -> tuple[fmpq_mpoly, fmpq_mpoly]:
    """``Re p(jω)`` and ``Im p(jω)`` for real ``ω``, as polynomials in ``ω`` (in the place of
    ``s``) and the parameters."""
    ctx = p.context()
    i = ctx.variable_to_index(S_NAME)
    re: dict[tuple[int, ...], fmpq] = {}
    im: dict[tuple[int, ...], fmpq] = {}
    for exps, c in zip(p.monoms(), p.coeffs(), strict=True):
        k = exps[i]
        (re if k % 2 == 0 else im)[tuple(exps)] = -c if (k // 2) % 2 else c
    return ctx.from_dict(re), ctx.from_dict(im)


_S_ONLY = fmpq_mpoly_ctx.get((S_NAME,), "lex")


def univariate(p: fmpq_mpoly, values: Mapping[str, fmpq]) -> fmpq_poly:
    """``p`` with every variable but ``s`` replaced by ``values[name]``, as an ``fmpq_poly``.

    Raises
    ------
    DelayError
        When ``p`` holds a delay ``E = e^{-sτ}`` (the variable ``_E_tau``): it is no
        number, and a rational analysis does not apply (see [`seapass.delay`][seapass.delay]).
    """
    names = p.context().names()
    for n, d in zip(names, p.degrees(), strict=True):
        if d > 0 and n.startswith(DELAY_PREFIX):
            raise delay_refusal(n[len(DELAY_PREFIX) :])
    args = [_S_ONLY.gen(0) if n == S_NAME else _S_ONLY.constant(values.get(n, 0)) for n in names]
    q = p.compose(*args, ctx=_S_ONLY)
    if q.is_zero():
        return fmpq_poly([])
    coeffs = {e[0]: c for e, c in zip(q.monoms(), q.coeffs(), strict=True)}
    return fmpq_poly([coeffs.get(k, 0) for k in range(max(coeffs) + 1)])


def _check_product(a: fmpq_mpoly, b: fmpq_mpoly) -> None:
    """Refuse the product ``a*b`` before computing it when it would exceed the budget."""
    ta, tb = len(a), len(b)
    if ta * tb > MAX_EXACT_WORK:
        raise SymbolicLimitError(
            f"too large for exact analysis: a product of polynomials with {ta} and {tb} terms "
            f"(limit {MAX_EXACT_WORK:,} term products)"
        )
    if ta * tb > 1:
        names = a.context().names()
        for n, da, db in zip(names, a.degrees(), b.degrees(), strict=True):
            if da + db > MAX_EXACT_DEGREE:
                raise SymbolicLimitError(
                    f"too large for exact analysis: degree {da + db} in {n} "
                    f"(limit {MAX_EXACT_DEGREE})"
                )
    bits = _bits(a) + _bits(b) + max(ta, tb).bit_length()
    if bits > MAX_EXACT_BITS:
        raise SymbolicLimitError(
            f"too large for exact analysis: coefficients of about {bits:,} bits "
            f"(limit {MAX_EXACT_BITS:,})"
        )


def _check_terms(p: fmpq_mpoly) -> fmpq_mpoly:
    """``p`` if it has at most `MAX_EXACT_TERMS` terms (its product was bounded before)."""
    if len(p) > MAX_EXACT_TERMS:
        raise SymbolicLimitError(
            f"too large for exact analysis: a polynomial of {len(p):,} terms "
            f"(limit {MAX_EXACT_TERMS:,})"
        )
    return p
