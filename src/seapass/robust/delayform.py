"""Certified enclosures of a delayed impedance's real part over frequency × delays × a box.

A delayed design ``Z = N(s, E; p)/D(s, E; p)``, ``E = e^{-sτ}``, with the uncertain
parameters ``p`` kept as exact polynomial variables (every other parameter at its value).
On the imaginary axis a product ``P(jω, E) conj Q(jω, E)`` has the real part

``Σ_m A_m(ω; p) cos(mωτ) + B_m(ω; p) sin(mωτ)``

(as [`seapass.delay.trig`][seapass.delay.trig] for one plant, here with coefficients
polynomial in ``ω`` **and** ``p``).  `AxisForm` holds it and evaluates it on arb balls:

* with ``P = N, Q = D`` it is ``F = |D|² Re Z(jω)``; when every ``A_m`` vanishes at
  ``ω = 0`` for every plant (a pole or a zero at ``s = 0``) it is divided by ``ω²``
  exactly (``sin(mωτ)/ω = mτ·sinc(mωτ)``), so that ``ω = 0`` is an ordinary point;
* with ``P = Q = D/s^k`` it is ``|D(jω, E)/ (jω)^k|²``, positive exactly when no root of
  the loop is on the imaginary axis.

Enclosures over a cell (an ``ω`` interval × a ``τ`` interval × a sub-box) use the
mean-value form ``f(c) + Σ_i ∂_i f(cell)·[−r_i, r_i]`` (forward-mode derivatives in ball
arithmetic; ``|sinc'(y)| ≤ |y|/3``); `positive_on` is the branch and bound with a counted
budget.  Frequencies beyond a cut-off ``Ω`` are handled uniformly by `high_cutoff`: in
``u = 1/ω`` the leading ``A_0`` term dominates every other term (``|cos|, |sin| ≤ 1``)
on ``u ∈ [0, 1/Ω]`` for every plant and delay, proven by one ball evaluation.

Examples
--------
>>> from seapass.model.sea import SEA
>>> sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
...           values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25, tau=None))
>>> st = DelayedFamily.of(sea, ("m",))
>>> st.delay, st.s_order, st.real_part().divided
('tau', 1, True)
"""

from __future__ import annotations

import heapq
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from flint import arb, fmpq

from ..delay.balls import ball, precision
from ..delay.structure import coefficients_in, delay_parameter
from ..errors import DelayError, ParameterError
from ..exact import poly as ep
from ..model.delayatom import delay_variable
from ..model.expr import to_fraction
from ..model.freebody import exact_impedance
from ..model.rational import S_NAME

__all__ = [
    "AxisForm",
    "CellStatus",
    "DelayedFamily",
    "Poly",
    "coeff_of",
    "eval_ball",
    "high_cutoff",
    "negative_on",
    "over_box",
    "positive_on",
    "s_degree",
    "value_at",
]

Poly = dict[tuple[int, ...], fmpq]
"""``{(power of ω or s, powers of the box parameters...): coefficient}``."""

PREC = 128
MAX_CUTOFF_HALVINGS = 80


def _add(out: Poly, p: Poly, sign: int = 1) -> None:
    for k, c in p.items():
        v = out.get(k, fmpq(0)) + sign * c
        if v == 0:
            out.pop(k, None)
        else:
            out[k] = v


def _mul(a: Poly, b: Poly) -> Poly:
    out: Poly = {}
    for ka, ca in a.items():
        for kb, cb in b.items():
            k = tuple(x + y for x, y in zip(ka, kb, strict=True))
            v = out.get(k, fmpq(0)) + ca * cb
            if v == 0:
                out.pop(k, None)
            else:
                out[k] = v
    return out


def _shift(p: Poly, by: int) -> Poly:
    return {(k[0] - by, *k[1:]): c for k, c in p.items()}


def s_degree(p: Poly) -> int:
    return max((k[0] for k in p), default=-1)


def coeff_of(p: Poly, power: int) -> Poly:
    """The coefficient of ``s^power`` (a polynomial in the parameters, key ``(0, e...)``)."""
    return {(0, *k[1:]): c for k, c in p.items() if k[0] == power}


def eval_ball(p: Poly, x: Any, params: Sequence[Any]) -> Any:
    """``p(x, params)`` on balls (natural interval extension)."""
    acc = arb(0)
    for k, c in p.items():
        t = arb(c) * x ** k[0] if k[0] else arb(c)
        for v, e in zip(params, k[1:], strict=True):
            if e:
                t = t * v**e
        acc += t
    return acc


@dataclass(frozen=True, kw_only=True)
class DelayedFamily:
    """``N_k(s; p)``, ``D_k(s; p)`` by powers ``E^k`` (a common ``E`` power cancelled).

    ``s_order``: the power of ``s`` common to every ``D_k`` (for every plant);
    ``dprime``: ``D_k/s^s_order``.
    """

    delay: str
    names: tuple[str, ...]
    num: tuple[Poly, ...]
    den: tuple[Poly, ...]
    s_order: int

    @classmethod
    def of(
        cls, model: Any, names: Sequence[str], values: Mapping[str, Any] | None = None
    ) -> DelayedFamily:
        z = exact_impedance(model)
        delay = delay_parameter(z)
        evar = delay_variable(delay)
        merged = {**model.values, **(values or {})}
        params = sorted(z.names() - {S_NAME, evar})
        if delay in names:
            raise ParameterError(
                f"box[{delay!r}]: {delay} is the delay, not a plant or gain value; give the "
                "delay as a value (a delay margin needs no box over it)",
                argument="box",
            )
        env = {}
        for n in params:
            if n in names:
                continue
            if merged.get(n) is None:
                raise ParameterError(
                    f"no value for parameter {n}: give it, e.g. values={{{n!r}: 1.0}}"
                )
            env[n] = ep.rational(to_fraction(merged[n], n))
        names = tuple(names)  # a name absent from Z is a variable of degree 0

        def parts(p: Any) -> tuple[Poly, ...]:
            coeffs = coefficients_in(p, env, (S_NAME, evar, *names))
            order = max((k[1] for k in coeffs), default=0)
            out: list[Poly] = [{} for _ in range(order + 1)]
            for k, c in coeffs.items():
                if c != 0:
                    out[k[1]][(k[0], *k[2:])] = c
            return tuple(out)

        num, den = parts(z.num), parts(z.den)
        if not any(den):
            raise ParameterError("the impedance has a zero denominator")
        cut = min((k for k, p in enumerate(den) if p), default=0)
        cut = min(cut, min((k for k, p in enumerate(num) if p), default=cut))
        num, den = num[cut:] or ({},), den[cut:]
        if not den[0]:
            raise DelayError("the model contains a prediction exp(+NAME*s); delays only")
        s_order = min(k[0] for p in den for k in p)
        return cls(delay=delay, names=names, num=num, den=den, s_order=s_order)

    @property
    def dprime(self) -> tuple[Poly, ...]:
        return tuple(_shift(p, self.s_order) for p in self.den)

    def real_part(self) -> AxisForm:
        """``F = Re N conj D`` on the axis (divided by ``ω²`` where it vanishes at 0)."""
        return AxisForm.of(self.num, self.den, len(self.names))

    def loop_magnitude(self) -> AxisForm:
        """``|D'(jω, E)|²`` with ``D' = D/s^k``."""
        d = self.dprime
        return AxisForm.of(d, d, len(self.names))

    def at(self, parts: tuple[Poly, ...], point: Sequence[fmpq]) -> tuple[Any, ...]:
        """``parts`` at exact parameter values, as exact polynomials in ``s``."""
        from flint import fmpq_poly

        out = []
        for p in parts:
            deg = s_degree(p)
            coeffs = [fmpq(0)] * (deg + 1)
            for k, c in p.items():
                t = c
                for v, e in zip(point, k[1:], strict=True):
                    t *= v**e
                coeffs[k[0]] += t
            out.append(fmpq_poly(coeffs))
        return tuple(out)


def _at_jw(part: Poly) -> tuple[Poly, Poly]:
    re: Poly = {}
    im: Poly = {}
    for k, c in part.items():
        r = k[0] % 4
        target = re if r in (0, 2) else im
        _add(target, {k: c}, 1 if r in (0, 1) else -1)
    return re, im


@dataclass(frozen=True, kw_only=True)
class AxisForm:
    """``Σ_m A_m cos(mωτ) + T_m S_m`` in ``(ω, τ, p)``; ``S_m = mτ·sinc(mωτ)`` when
    `divided` (then ``A_m`` and ``T_m = B_m/ω`` are the exact quotients by ``ω²`` and ``ω``),
    ``S_m = sin(mωτ)`` and ``T_m = B_m`` otherwise."""

    a: tuple[Poly, ...]
    t: tuple[Poly, ...]
    divided: bool

    @classmethod
    def of(cls, p_parts: Sequence[Poly], q_parts: Sequence[Poly], n: int) -> AxisForm:
        order = max(len(p_parts), len(q_parts)) - 1
        a: list[Poly] = [{} for _ in range(order + 1)]
        b: list[Poly] = [{} for _ in range(order + 1)]
        q_axis = [_at_jw(q) for q in q_parts]
        for k, p in enumerate(p_parts):
            if not p:
                continue
            pr, pi = _at_jw(p)
            for l_, (qr, qi) in enumerate(q_axis):
                u: Poly = {}
                _add(u, _mul(pr, qr))
                _add(u, _mul(pi, qi))
                v: Poly = {}
                _add(v, _mul(pi, qr))
                _add(v, _mul(pr, qi), -1)
                m = k - l_
                _add(a[abs(m)], u)
                _add(b[abs(m)], v, 1 if m >= 0 else -1)
        b[0] = {}
        divided = any(a) and all(k[0] >= 2 for p in a for k in p)
        if divided:
            return cls(a=tuple(_shift(p, 2) for p in a), t=tuple(_shift(p, 1) for p in b),
                       divided=True)  # fmt: skip
        return cls(a=tuple(a), t=tuple(b), divided=False)

    def value(self, w: Any, tau: Any, params: Sequence[Any]) -> Any:
        """The form at ``(ω, τ, p)`` (balls or `Dual` numbers)."""
        powers_w = [w]
        deg = max((k[0] for p in (*self.a, *self.t) for k in p), default=0)
        for _ in range(deg):
            powers_w.append(powers_w[-1] * w)
        cache: dict[tuple[int, ...], Any] = {}

        def mono(k: tuple[int, ...]) -> Any:
            key = k[1:]
            if key not in cache:
                t: Any = None
                for v, e in zip(params, key, strict=True):
                    for _ in range(e):
                        t = v if t is None else t * v
                cache[key] = t
            base = cache[key]
            if k[0]:
                return powers_w[k[0] - 1] if base is None else base * powers_w[k[0] - 1]
            return base

        def poly(p: Poly) -> Any:
            acc: Any = arb(0)
            for k, c in p.items():
                m = mono(k)
                acc = acc + (arb(c) if m is None else m * arb(c))
            return acc

        out = poly(self.a[0])
        for m in range(1, len(self.a)):
            y = w * tau * m
            if self.a[m]:
                out = out + poly(self.a[m]) * _cos(y)
            if self.t[m]:
                s = _sinc(y) * tau * m if self.divided else _sin(y)
                out = out + poly(self.t[m]) * s
        return out


class Dual:
    """A real ball and the balls of its partial derivatives (forward mode)."""

    __slots__ = ("d", "v")

    def __init__(self, v: Any, d: Sequence[Any]) -> None:
        self.v = v
        self.d = tuple(d)

    def __add__(self, o: Any) -> Dual:
        if isinstance(o, Dual):
            return Dual(self.v + o.v, [x + y for x, y in zip(self.d, o.d, strict=True)])
        return Dual(self.v + o, self.d)

    __radd__ = __add__

    def __mul__(self, o: Any) -> Dual:
        if isinstance(o, Dual):
            return Dual(self.v * o.v, [x * o.v + self.v * y for x, y in zip(self.d, o.d, strict=True)])  # fmt: skip
        return Dual(self.v * o, [x * o for x in self.d])

    __rmul__ = __mul__


def _cos(y: Any) -> Any:
    if not isinstance(y, Dual):
        return y.cos()
    s, c = y.v.sin_cos()
    return Dual(c, [-s * x for x in y.d])


def _sin(y: Any) -> Any:
    if not isinstance(y, Dual):
        return y.sin()
    s, c = y.v.sin_cos()
    return Dual(s, [c * x for x in y.d])


def _sinc(y: Any) -> Any:
    if not isinstance(y, Dual):
        return y.sinc()
    v = y.v
    if v.contains(0) or not v.is_finite():
        r = v.abs_upper() / 3  # |sinc'(y)| <= |y|/3 for every real y
        der = r.union(-r)
    else:
        s, c = v.sin_cos()
        der = (v * c - s) / (v * v)
    return Dual(v.sinc(), [der * x for x in y.d])


def high_cutoff(form: AxisForm, zero_delay: bool, params: Sequence[Any]) -> fmpq | None:
    """An exact ``Ω`` with ``form > 0`` for every ``ω ≥ Ω``, every delay and every plant in
    ``params`` (balls); None when the leading ``A_0`` term does not dominate.

    ``|cos|, |sin| ≤ 1`` bound the delayed terms for every delay; at ``zero_delay`` only
    (``τ = 0``) the form is the polynomial ``Σ_m A_m`` and is bounded as such.
    """
    if zero_delay:
        total: Poly = {}
        for p in form.a:
            _add(total, p)
        form = AxisForm(a=(total,), t=({},), divided=form.divided)
    top = s_degree(form.a[0])
    if top < 0:
        return None
    lead: Poly = {}
    rest: list[Poly] = []
    for p in form.a[1:]:
        if p and s_degree(p) > top:
            return None
        rest.append({(top - k[0], *k[1:]): c for k, c in p.items()})
    for p in form.t[1:]:
        div = 1 if form.divided else 0
        if p and s_degree(p) - div > top:
            return None
        rest.append({(top - k[0] + div, *k[1:]): c for k, c in p.items()})
    lead = {(top - k[0], *k[1:]): c for k, c in form.a[0].items()}
    with precision(PREC):
        for i in range(MAX_CUTOFF_HALVINGS):
            u1 = fmpq(1, 2**i)
            u = ball(fmpq(0), u1)
            low = eval_ball(lead, u, params)
            for p in rest:
                if p:
                    low -= abs(eval_ball(p, u, params)).abs_upper()
            if low > 0:
                return 1 / u1
    return None


MAX_SPLIT_DEPTH = 8
"""Halvings of the box a ball bound over the box (`over_box`) may use (natural interval
extensions are wide on a wide box)."""


def over_box(exact: Sequence[tuple[fmpq, fmpq]], bound: Any, depth: int = MAX_SPLIT_DEPTH) -> Any:
    """``bound(balls)`` over the box, halving the widest side where it gives None.

    ``bound`` returns a value or None (not proven there); the result is the list of the
    values of every piece, or None when a piece is still unproven at ``depth``.
    """
    with precision(PREC):
        got = bound([ball(a, b) for a, b in exact])
    if got is not None:
        return [got]
    if depth == 0 or not exact:
        return None
    i = max(range(len(exact)), key=lambda j: (exact[j][1] - exact[j][0]) / max(abs(exact[j][1]), fmpq(1)))  # fmt: skip
    a, b = exact[i]
    out = []
    for half in ((a, (a + b) / 2), ((a + b) / 2, b)):
        got = over_box([*exact[:i], half, *exact[i + 1 :]], bound, depth - 1)
        if got is None:
            return None
        out += got
    return out


class CellStatus(StrEnum):
    """How `positive_on` ended."""

    PROVEN = "proven"
    COUNTER = "counter"
    BUDGET = "budget"


Cell = tuple[tuple[fmpq, fmpq], ...]


def _enclose(form: AxisForm, cell: Cell) -> tuple[Any, Any, list[Any]]:
    """``(value at the centre, lower bound on the cell, |∂_i|·r_i per variable)``."""
    centre = [(a + b) / 2 for a, b in cell]
    radii = [(b - a) / 2 for a, b in cell]
    vc = form.value(arb(centre[0]), arb(centre[1]), [arb(c) for c in centre[2:]])
    n = len(cell)
    duals = [
        Dual(ball(a, b), [arb(1) if j == i else arb(0) for j in range(n)])
        for i, (a, b) in enumerate(cell)
    ]
    vb = form.value(duals[0], duals[1], duals[2:])
    if not isinstance(vb, Dual):  # a constant form
        vb = Dual(vb, [arb(0)] * n)
    spread = [abs(vb.d[i]).abs_upper() * arb(r) for i, r in enumerate(radii)]
    low = vc
    for s in spread:
        low = low - s
    return vc, low, spread


def negative_on(form: AxisForm, cell: Cell) -> bool:
    """``form < 0`` on the whole ``cell`` (``ω, τ, p...``): ``f(c) + Σ |∂_i f|·r_i < 0``."""
    with precision(PREC):
        vc, _low, spread = _enclose(form, cell)
        return bool(sum(spread, vc) < 0)


def value_at(form: AxisForm, point: Sequence[fmpq]) -> float:
    """The form at a point ``(ω, τ, p...)`` as a float (a search heuristic, not a proof)."""
    with precision(64):
        return float(form.value(arb(point[0]), arb(point[1]), [arb(c) for c in point[2:]]).mid())


def positive_on(
    form: AxisForm, cells: list[Cell], *, budget: int
) -> tuple[CellStatus, tuple[fmpq, ...] | None, int]:
    """Prove ``form > 0`` on every cell (variables ``ω, τ, p...``) by branch and bound.

    Returns ``(status, point, cells used)``: ``COUNTER`` with a cell centre where the form
    is proven negative, ``BUDGET`` when ``budget`` cells did not settle it.
    """
    # the most negative centre first: a counterexample is found before the rest is proven
    heap: list[tuple[float, int, Cell]] = [(0.0, i, c) for i, c in enumerate(cells)]
    heapq.heapify(heap)
    used, stuck, tick = 0, False, len(cells)
    with precision(PREC):
        while heap:
            _key, _tick, cell = heapq.heappop(heap)
            used += 1
            if used > budget:
                return CellStatus.BUDGET, None, used - 1
            vc, low, spread = _enclose(form, cell)
            if low > 0:
                continue
            if vc < 0:
                return CellStatus.COUNTER, tuple((a + b) / 2 for a, b in cell), used
            i = max(range(len(cell)), key=lambda j: float(spread[j].mid()))
            a, b = cell[i]
            if b - a <= max(abs(a), abs(b), fmpq(1)) / fmpq(2) ** 80:
                stuck = True  # a tangency: this cell is never decided
                continue
            mid = (a + b) / 2
            for half in (
                (*cell[:i], (a, mid), *cell[i + 1 :]),
                (*cell[:i], (mid, b), *cell[i + 1 :]),
            ):
                tick += 1
                heapq.heappush(heap, (float(vc.mid()), tick, half))
    return (CellStatus.BUDGET if stuck else CellStatus.PROVEN), None, used
