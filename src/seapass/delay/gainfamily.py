"""A certificate that a delayed design is passive for **every** gain in ``[a, b]`` at one delay.

``N(s, E; k)`` and ``D(s, E; k)`` are polynomials in the gain ``k`` (the exact free-body
derivation keeps ``k`` a variable, `gain_family`).  On ``k = a + t (b - a)``,
``t ∈ [0, 1]``:

1. **Real part.**  ``F(ω; k) = Re N conj D`` is a polynomial in ``k`` whose coefficients
   are trigonometric real parts; written in the Bernstein basis of ``t``,
   ``F = Σ_j β_j(ω) b_j(t)`` with ``b_j ≥ 0`` and ``Σ b_j = 1``.  Every ``β_j`` is certified
   ``≥ 0`` on ``ω > 0`` by [`certify`][seapass.delay.sign.certify] (exact asymptotics and
   arb balls), so ``F ≥ 0`` on the whole box.
2. **Stability.**  ``D = s^p D̃`` with ``p`` the same for every ``k`` and
   ``D̃ = P + Q E``.  No root crosses the imaginary axis for ``k ∈ [a, b]``:
   ``D̃(0; k) ≠ 0`` exactly, ``|P|² - |Q|²`` (a polynomial in ``ω²`` and ``k``) has Bernstein
   coefficients of one strict sign outside compact ``ω``-ranges, and on those ranges a
   complex ball of ``D̃(jω; [a, b])`` excludes 0.  ``|P|² > |Q|²`` at high frequency with
   the leading degree the same at both ends (so on all of ``[a, b]``) keeps the roots of this
   retarded (or ``|q_n/p_n| < 1`` neutral) loop in ``Re s ≥ 0`` bounded, so the number of
   right-half-plane roots is that at ``k = a``.
3. **The pole at 0 and growth at infinity.**  The residue ``N(0, 1; k)/D̃(0; k)`` does not
   change sign on ``(a, b)``; the leading ``s``-degrees do not drop and a ``c s`` growth keeps
   ``c(k)`` of one sign (exact identities and root counts in ``k``).

With the verdict at ``a`` (passive, [`decide`][seapass.delay.passivity.decide]) these give
passive for every ``k ∈ [a, b]``; a condition that is not proven makes the certificate
fail (the caller splits the interval), never passive.

Examples
--------
>>> from seapass.model.sea import SEA
>>> wall = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=10, k1=1000, kd=None, tau=0.002))
>>> fam = gain_family(wall, "kd", tau=fmpq(1, 500))
>>> fam.degree, family_certificate(fam, fmpq(0), fmpq(4000)).ok
(2, True)
>>> family_certificate(fam, fmpq(4000), fmpq(6000)).ok     # kd > b/tau = 5000 fails
False
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from math import comb
from typing import Any

from flint import acb, arb, fmpq, fmpq_poly

from ..errors import DelayError, ParameterError
from ..exact import poly as ep
from ..exact.axis import at_j_omega, even_to_x
from ..model.delayatom import delay_variable
from ..model.expr import to_fraction
from ..model.freebody import exact_impedance
from ..model.rational import S_NAME
from ..model.sea import SEA, Impedance
from ..outcome import Outcome
from .balls import arb_of, ball, precision, sqrt_bounds
from .sign import certify
from .structure import DelayedImpedance, coefficients_in, delay_parameter
from .trig import TrigRealPart, real_part

__all__ = ["FamilyCertificate", "GainFamily", "family_certificate", "gain_family"]

Parts = tuple[tuple[fmpq_poly, ...], ...]
"""``parts[i][m]``: the coefficient of ``k^i E^m``, a polynomial in ``s``."""

STABILITY_PIECES = 4000
"""Sub-intervals of ``ω`` tried when a complex ball must exclude ``D̃(jω) = 0``."""


@dataclass(frozen=True, kw_only=True)
class GainFamily:
    """``N(s, E; k)`` and ``D(s, E; k)`` as polynomials in the gain ``k``, at the delay ``tau``."""

    gain: str
    delay: str
    tau: fmpq
    num: Parts
    den: Parts

    @property
    def degree(self) -> int:
        """Degree of ``F = Re N conj D`` in ``k`` (at most)."""
        return len(self.num) + len(self.den) - 2


@dataclass(frozen=True, kw_only=True)
class FamilyCertificate:
    """Outcome of `family_certificate`: ``ok`` (passive for every gain, given the verdict
    at the lower end) or the first condition that was not proven (``why``)."""

    ok: bool
    why: str = ""
    evaluations: int = 0


def _parts(p: Any, env: Mapping[str, fmpq], evar: str, gain: str) -> Parts:
    coeffs = coefficients_in(p, env, (gain, evar, S_NAME))
    top_g = max((g for g, _, _ in coeffs), default=0)
    top_m = max((m for _, m, _ in coeffs), default=0)
    out = []
    for g in range(top_g + 1):
        row = []
        for m in range(top_m + 1):
            deg = max((i for gg, mm, i in coeffs if (gg, mm) == (g, m)), default=-1)
            row.append(fmpq_poly([coeffs.get((g, m, i), fmpq(0)) for i in range(deg + 1)]))
        out.append(tuple(row))
    return tuple(out)


def gain_family(
    system: SEA | Impedance,
    gain: str,
    *,
    tau: fmpq,
    values: Mapping[str, float | None] | None = None,
) -> GainFamily:
    """The exact structure of ``system`` with the gain ``gain`` left a variable."""
    z = exact_impedance(system)
    name = delay_parameter(z)
    evar = delay_variable(name)
    merged: dict[str, Any] = dict(system.values)
    merged.update(values or {})
    params = sorted(z.names() - {S_NAME, evar})
    if gain not in params:
        raise ParameterError(
            f"gain: {gain!r} does not appear in the impedance ({', '.join(params) or 'none'})",
            argument="gain",
        )
    missing = [n for n in params if n != gain and merged.get(n) is None]
    if missing:
        raise ParameterError(f"no value for parameter(s) {', '.join(missing)}")
    env = {n: ep.rational(to_fraction(merged[n], n)) for n in params if n != gain}
    num, den = _parts(z.num, env, evar, gain), _parts(z.den, env, evar, gain)
    if all(p.is_zero() for p in (row[0] for row in den)):
        raise DelayError("the denominator vanishes without the delay: a prediction, not a delay")
    return GainFamily(gain=gain, delay=name, tau=tau, num=num, den=den)


# ---------------------------------------------------------------- exact pieces in k


def _shift(coeffs: list[Any], a: fmpq, h: fmpq, zero: Any) -> list[Any]:
    """Coefficients of ``Σ c_i (a + t h)^i`` in powers of ``t``."""
    d = len(coeffs) - 1
    out = [zero for _ in range(d + 1)]
    for i, c in enumerate(coeffs):
        for r in range(i + 1):
            out[r] = out[r] + c * (fmpq(comb(i, r)) * a ** (i - r) * h**r)
    return out


def _bernstein(coeffs: list[Any], a: fmpq, b: fmpq, zero: Any) -> list[Any]:
    """Bernstein coefficients on ``[a, b]`` of ``Σ c_i k^i`` (any ring with rational scaling)."""
    g = _shift(coeffs, a, b - a, zero)
    d = len(g) - 1
    return [
        sum((g[r] * fmpq(comb(j, r), comb(d, r)) for r in range(j + 1)), zero) for j in range(d + 1)
    ]


def _kpoly(values: list[fmpq]) -> fmpq_poly:
    return fmpq_poly(values)


def _no_root(p: fmpq_poly, a: fmpq, b: fmpq) -> bool:
    """``p`` has no root in the closed ``[a, b]`` (and is not the zero polynomial)."""
    if p.is_zero():
        return False
    return p(a) != 0 and ep.count_real_roots(p, a, b) == 0


def _positive_inside(p: fmpq_poly, a: fmpq, b: fmpq) -> bool:
    """``p ≥ 0`` on ``[a, b]``: no sign change in ``(a, b)`` and positive at the midpoint."""
    if p.is_zero() or p((a + b) / 2) <= 0:
        return False
    odd = ep.positive_roots_odd_multiplicity(p)
    if odd.degree() <= 0:
        return True
    return ep.count_real_roots(odd, a, b) - (1 if odd(b) == 0 else 0) == 0


# ---------------------------------------------------------------- trigonometric sums


def _add(f: TrigRealPart, g: TrigRealPart) -> TrigRealPart:
    n = max(len(f.cos), len(g.cos))
    pad = fmpq_poly([])
    fc = list(f.cos) + [pad] * (n - len(f.cos))
    fs = list(f.sin) + [pad] * (n - len(f.sin))
    gc = list(g.cos) + [pad] * (n - len(g.cos))
    gs = list(g.sin) + [pad] * (n - len(g.sin))
    return TrigRealPart(cos=tuple(x + y for x, y in zip(fc, gc, strict=True)),
                        sin=tuple(x + y for x, y in zip(fs, gs, strict=True)))  # fmt: skip


class _Trig:
    """A `TrigRealPart` with ``+`` and rational scaling (for the Bernstein sums)."""

    def __init__(self, f: TrigRealPart) -> None:
        self.f = f

    def __add__(self, other: _Trig) -> _Trig:
        return _Trig(_add(self.f, other.f))

    def __mul__(self, q: fmpq) -> _Trig:
        return _Trig(TrigRealPart(cos=tuple(p * q for p in self.f.cos),
                                  sin=tuple(p * q for p in self.f.sin)))  # fmt: skip


def _real_part_in_k(fam: GainFamily) -> list[_Trig]:
    zero = TrigRealPart(cos=(fmpq_poly([]),), sin=(fmpq_poly([]),))
    out = [_Trig(zero) for _ in range(fam.degree + 1)]
    for i, n in enumerate(fam.num):
        for j, d in enumerate(fam.den):
            part = real_part(DelayedImpedance(name=fam.delay, tau=fam.tau, num=n, den=d))
            out[i + j] = out[i + j] + _Trig(part)
    return out


# ---------------------------------------------------------------- the certificate


def _real_part_ok(fam: GainFamily, a: fmpq, b: fmpq, budget: int) -> tuple[bool, int]:
    zero = _Trig(TrigRealPart(cos=(fmpq_poly([]),), sin=(fmpq_poly([]),)))
    used = 0
    for beta in _bernstein(_real_part_in_k(fam), a, b, zero):
        try:
            cert = certify(beta.f, fam.tau, budget=budget)
        except DelayError:
            return False, used
        used += cert.evaluations
        if cert.outcome is not Outcome.PASSIVE:
            return False, used
    return True, used


def _s_order(rows: Parts) -> int:
    orders = [
        next(i for i, c in enumerate(p.coeffs()) if c != 0)
        for row in rows
        for p in row
        if not p.is_zero()
    ]
    return min(orders, default=0)


def _drop_s(rows: Parts, p: int) -> Parts:
    return tuple(tuple(fmpq_poly(q.coeffs()[p:]) if not q.is_zero() else q for q in row) for row in rows)  # fmt: skip


def _in_k(rows: Parts, m: int, f: Any) -> fmpq_poly:
    """The polynomial in ``k`` of ``f(part)`` over the rows (``E^m`` part)."""
    return _kpoly([f(row[m]) if m < len(row) else fmpq(0) for row in rows])


def _magnitude_in_k(rows: Parts, m: int) -> list[fmpq_poly]:
    """``|X_m(jω; k)|²`` as polynomials in ``x = ω²``, by powers of ``k``."""
    parts = [at_j_omega(row[m]) if m < len(row) else (fmpq_poly([]), fmpq_poly([])) for row in rows]
    out = [fmpq_poly([]) for _ in range(max(2 * len(rows) - 1, 1))]
    for i, (ri, ii) in enumerate(parts):
        for j, (rj, ij) in enumerate(parts):
            out[i + j] += even_to_x(ri * rj + ii * ij)
    return out


def _bad_ranges(polys: list[fmpq_poly]) -> list[tuple[fmpq, fmpq]] | None:
    """Closed ``x``-ranges (``x ≥ 0``) outside of which every poly has one common strict
    sign; None when that fails at infinity (not retarded for every gain)."""
    live = [p for p in polys if not p.is_zero()]
    if not live or any(p.leading_coefficient() <= 0 for p in live) or len(live) < len(polys):
        return None
    top = max(p.degree() for p in live)
    if polys[0].degree() != top or polys[-1].degree() != top:
        return None  # the degree of the loop may drop at an end: a root from infinity
    ivs = sorted(iv for p in live for iv in ep.isolate_real_roots(p, fmpq(-1), None))
    merged: list[list[fmpq]] = []
    for a, b in ivs:
        a = max(a, fmpq(0))
        if merged and a <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], b)
        elif b >= 0:
            merged.append([a, b])
    edges = [fmpq(0)] + [x for iv in merged for x in iv]
    bad = [(a, b) for a, b in merged]
    # gaps between the root ranges: one sample decides the sign vector there
    for lo, hi in zip(edges[::2], edges[1::2], strict=False):
        if lo >= hi:
            continue
        mid = (lo + hi) / 2
        signs = {ep.sign(p(mid)) for p in live}
        if len(signs) != 1 or 0 in signs:
            bad.append((lo, hi))
    return sorted(bad)


def _ball_nonzero(rows: Parts, tau: fmpq, a: fmpq, b: fmpq, w0: fmpq, w1: fmpq) -> tuple[bool, int]:
    """``D̃(jω; k) ≠ 0`` for ``ω ∈ [w0, w1]``, ``k ∈ [a, b]`` (complex balls, bisection)."""
    todo = [(w0, w1)]
    count = 0
    with precision(128):
        kb = ball(a, b)
        t = arb_of(tau)
        coeffs = [[[arb(c) for c in p.coeffs()] for p in row] for row in rows]
        while todo:
            lo, hi = todo.pop()
            count += 1
            if count > STABILITY_PIECES:
                return False, count
            w = ball(lo, hi)
            s = acb(0, w)
            e = (-s * t).exp()
            total = acb(0)
            kp = acb(1)
            for row in coeffs:
                em = acb(1)
                for part in row:
                    val = acb(0)
                    for c in reversed(part):
                        val = val * s + c
                    total += kp * em * val
                    em *= e
                kp *= kb
            if not (total.real.contains(0) and total.imag.contains(0)):
                continue
            if hi - lo < max(hi, fmpq(1)) / fmpq(2) ** 40:
                return False, count
            mid = (lo + hi) / 2
            todo += [(lo, mid), (mid, hi)]
    return True, count


def _stability_ok(fam: GainFamily, a: fmpq, b: fmpq) -> tuple[str, int]:
    rows = fam.den
    if any(len(row) > 2 for row in rows):
        return "a delay beyond the first power in the denominator", 0
    p = _s_order(rows)
    if p > 1:
        return "a pole of order >= 2 at s = 0", 0
    red = _drop_s(rows, p)
    at0 = _kpoly([sum((q(0) for q in row), fmpq(0)) for row in red])
    if not _no_root(at0, a, b):
        return "the loop may have a root at s = 0 inside the gain interval", 0
    if p == 1:
        n0 = _kpoly([sum((q(0) for q in row), fmpq(0)) for row in fam.num])
        if not _positive_inside(n0 * at0, a, b):
            return "the residue of the pole at s = 0 changes sign", 0
    pm = _magnitude_in_k(red, 0)
    qm = _magnitude_in_k(red, 1)
    h = [x - y for x, y in zip(pm + [fmpq_poly([])] * (len(qm) - len(pm)),
                               qm + [fmpq_poly([])] * (len(pm) - len(qm)), strict=True)]  # fmt: skip
    while len(h) > 1 and h[-1].is_zero():
        h.pop()
    bern = _bernstein(h, a, b, fmpq_poly([]))
    bad = _bad_ranges(bern)
    if bad is None:
        return "|P| > |Q| at high frequency is not proven for every gain", 0
    used = 0
    for x0, x1 in bad:
        w0, w1 = sqrt_bounds(x0)[0], sqrt_bounds(x1)[1]
        ok, n = _ball_nonzero(red, fam.tau, a, b, w0, w1)
        used += n
        if not ok:
            return "a root of the loop may reach the imaginary axis inside the gain interval", used
    return "", used


def _growth_ok(fam: GainFamily, a: fmpq, b: fmpq) -> str:
    def top(rows: Parts) -> int:
        return max((q.degree() for row in rows for q in row), default=-1)

    dn, dd = top(fam.num), top(fam.den)
    d0 = _in_k(fam.den, 0, lambda q: q[dd] if q.degree() >= dd else fmpq(0))
    if not _no_root(d0, a, b):
        return "the degree of the denominator may drop inside the gain interval"
    if dn <= dd:
        return ""
    if dn > dd + 1:
        return "Z may grow faster than s"
    width = max(len(row) for row in (*fam.num, *fam.den))
    n_top = [
        _in_k(fam.num, m, lambda q: q[dn] if q.degree() >= dn else fmpq(0)) for m in range(width)
    ]
    d_top = [
        _in_k(fam.den, m, lambda q: q[dd] if q.degree() >= dd else fmpq(0)) for m in range(width)
    ]
    if any(n_top[m] * d_top[0] != n_top[0] * d_top[m] for m in range(width)):
        return "the leading terms are not a multiple of s for every gain"
    if not _no_root(n_top[0], a, b):
        return "the coefficient of s at high frequency may vanish"
    return ""


def family_certificate(
    fam: GainFamily, a: fmpq, b: fmpq, *, budget: int = 200_000
) -> FamilyCertificate:
    """Prove that passive at ``k = a`` implies passive for every ``k ∈ [a, b]`` (module
    docstring); ``ok=False`` names the first condition not proven."""
    if not a < b:
        raise ValueError("a < b")
    why = _growth_ok(fam, a, b)
    if why:
        return FamilyCertificate(ok=False, why=why)
    why, used = _stability_ok(fam, a, b)
    if why:
        return FamilyCertificate(ok=False, why=why, evaluations=used)
    ok, more = _real_part_ok(fam, a, b, budget)
    if not ok:
        return FamilyCertificate(ok=False, why="Re Z >= 0 not proven for every gain", evaluations=used + more)  # fmt: skip
    return FamilyCertificate(ok=True, evaluations=used + more)
