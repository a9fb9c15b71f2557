"""Second-order Taylor enclosures over a box of plants: value, gradient and Hessian balls.

The mean-value form of [`seapass.robust.sampled_local`][seapass.robust.sampled_local]
encloses ``f(μ)`` for every ``μ`` of a box as ``f(c) + Σ D_i [−r_i, r_i]`` with ``D_i``
the derivative *enclosed over the box*.  Ball arithmetic over the box overestimates
``D_i`` by a width proportional to the box (the dependency problem), so the enclosure's
excess width grows like ``r²``; near ``cos ωT = 1``, where the weighted power ``P̃``
is a tiny difference of large alias sums, that excess decides whether a box of a few
percent can be certified at all.

A `Jet` carries a ball value, the balls of the first derivatives and the balls of the
second derivatives (forward mode, order two).  Taylor's theorem with the Lagrange
remainder, for a real ``C²`` function on the segment from the centre ``c`` to ``μ``
(inside the box),

``f(μ) = f(c) + ∇f(c)·Δ + ½ Δᵀ ∇²f(ξ) Δ``,  ``Δ = μ − c``, ``ξ`` in the box,

gives the enclosure `taylor_enclose`: the value and the gradient at the *centre* (a
point: narrow balls) plus the Hessian enclosed over the box, times ``r_i r_j``.  The
overestimation of the Hessian enters only at order ``r³``.

References
----------
.. [1] K. Makino and M. Berz, "Taylor models and other validated functional inclusion
   methods", Int. J. Pure Appl. Math. 4(4), 2003.
.. [2] R. E. Moore, R. B. Kearfott and M. J. Cloud, "Introduction to Interval Analysis",
   SIAM, 2009, Section 6.4 (mean-value and Taylor forms).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import Any

from flint import acb, arb

__all__ = ["Jet", "pairs", "taylor_enclose"]


@functools.cache
def pairs(k: int) -> tuple[tuple[int, int], ...]:
    """The index pairs ``(i, j)``, ``i ≤ j``, of the stored Hessian entries (row order)."""
    return tuple((i, j) for i in range(k) for j in range(i, k))


def _conj(x: Any) -> Any:
    return x.conjugate() if isinstance(x, acb) else x


def _real(x: Any) -> Any:
    return x.real if isinstance(x, acb) else x


class Jet:
    """A ball value, its gradient ``d`` (``k`` balls) and Hessian ``h`` (the entries of
    `pairs` ``(k)``), all enclosures over the same ball of parameters.

    Examples
    --------
    >>> from flint import arb
    >>> x = Jet(arb(2), [arb(1)], [arb(0)])  # the variable at the point 2
    >>> y = x * x * x
    >>> (y.v, y.d[0], y.h[0])
    (8.00000000000000, 12.0000000000000, 12.0000000000000)
    >>> box = Jet(arb(2, 0.1), [arb(1)], [arb(0)])  # over [1.9, 2.1]
    >>> enc = taylor_enclose(y.v, y.d, box * box * box, [arb(0.1)])
    >>> enc.contains(arb(1.9) ** 3) and enc.contains(arb(2.1) ** 3), enc.rad() < 1.3
    (True, True)
    """

    __slots__ = ("d", "h", "v")

    def __init__(self, v: Any, d: Sequence[Any], h: Sequence[Any]) -> None:
        self.v = v
        self.d = tuple(d)
        self.h = tuple(h)

    @classmethod
    def constant(cls, v: Any, k: int) -> Jet:
        zero = acb(0)
        return cls(v, (zero,) * k, (zero,) * len(pairs(k)))

    def _lift(self, o: Any) -> Jet:
        if isinstance(o, Jet):
            return o
        if hasattr(o, "d"):
            raise TypeError("a Jet cannot be combined with a first-order dual number")
        return Jet.constant(o, len(self.d))

    def __add__(self, o: Any) -> Jet:
        if not isinstance(o, Jet):
            return Jet(self.v + self._lift(o).v, self.d, self.h)
        return Jet(
            self.v + o.v,
            [a + b for a, b in zip(self.d, o.d, strict=True)],
            [a + b for a, b in zip(self.h, o.h, strict=True)],
        )

    __radd__ = __add__

    def __neg__(self) -> Jet:
        return Jet(-self.v, [-a for a in self.d], [-a for a in self.h])

    def __sub__(self, o: Any) -> Jet:
        return self + (-self._lift(o))

    def __rsub__(self, o: Any) -> Jet:
        return self._lift(o) - self

    def __mul__(self, o: Any) -> Jet:
        if not isinstance(o, Jet):
            self._lift(o)  # refuses a first-order dual
            return Jet(self.v * o, [a * o for a in self.d], [a * o for a in self.h])
        a, b = self, o
        h = [
            ah * b.v + a.d[i] * b.d[j] + a.d[j] * b.d[i] + a.v * bh
            for (i, j), ah, bh in zip(pairs(len(a.d)), a.h, b.h, strict=True)
        ]
        return Jet(a.v * b.v, [x * b.v + a.v * y for x, y in zip(a.d, b.d, strict=True)], h)

    __rmul__ = __mul__

    def reciprocal(self) -> Jet:
        """``1/f``: ``−f_i/f²`` and ``−f_ij/f² + 2 f_i f_j/f³``."""
        f = 1 / self.v
        f2 = f * f
        f3 = f2 * f
        d = self.d
        return Jet(
            f,
            [-x * f2 for x in d],
            [
                -x * f2 + 2 * d[i] * d[j] * f3
                for (i, j), x in zip(pairs(len(d)), self.h, strict=True)
            ],
        )

    def __truediv__(self, o: Any) -> Jet:
        if not isinstance(o, Jet):
            self._lift(o)
            return Jet(self.v / o, [a / o for a in self.d], [a / o for a in self.h])
        return self * o.reciprocal()

    def __rtruediv__(self, o: Any) -> Jet:
        return self._lift(o) * self.reciprocal()

    def __pow__(self, n: int) -> Jet:
        out = Jet.constant(acb(1), len(self.d))
        for _ in range(n):
            out = out * self
        return out

    @property
    def real(self) -> Jet:
        return Jet(_real(self.v), [_real(a) for a in self.d], [_real(a) for a in self.h])

    def conjugate(self) -> Jet:
        return Jet(_conj(self.v), [_conj(a) for a in self.d], [_conj(a) for a in self.h])

    def padded(self, k: int) -> Jet:
        """The same jet with ``k`` derivative slots (new slots: derivatives 0)."""
        n = len(self.d)
        if n == k:
            return self
        old = dict(zip(pairs(n), self.h, strict=True))
        zero = acb(0)
        return Jet(
            self.v,
            [*self.d, *[zero] * (k - n)],
            [old.get(p, zero) for p in pairs(k)],
        )


def _sym(r: arb) -> arb:
    return (-r).union(r)


def taylor_enclose(v: Any, grad: Sequence[Any], box: Jet, radii: Sequence[arb]) -> arb:
    """Real part of ``f`` on the box: ``f(c) + Σ ∇f(c)_i [−r_i, r_i] + ½ ΔᵀHΔ`` with ``H``
    the Hessian over the box (``½ H_ii [0, r_i²]`` and ``H_ij [−r_i r_j, r_i r_j]``).

    ``v`` and ``grad`` are the value and the gradient at the centre ``c`` (balls), ``box``
    the jet of ``f`` over the whole box around ``c`` (``|μ_i − c_i| ≤ r_i``).  The mean
    value enclosure ``f(c) + Σ D_i [−r_i, r_i]`` with the box's own gradient ``D`` is
    valid too; the intersection of both is returned.
    """
    out = arb(_real(v))
    mean = arb(_real(v))
    for g, d, r in zip(grad, box.d, radii, strict=True):
        out += arb(_real(g)) * _sym(r)
        mean += arb(_real(d)) * _sym(r)
    for (i, j), h in zip(pairs(len(box.d)), box.h, strict=True):
        hr = arb(_real(h))
        if i == j:
            out += hr * (radii[i] * radii[i] / 2).union(arb(0))
        else:
            out += hr * _sym(radii[i] * radii[j])
    if not (out.is_finite() and mean.is_finite()):
        return out if out.is_finite() else mean
    try:
        return out.intersection(mean)
    except ValueError:  # both contain every value: never empty, but never fail on it
        return out
