"""Float64 certificates of passivity with a-priori rounding-error bounds.

For a fixed configuration (an [`SEA`][seapass.model.sea.SEA] whose free
parameters are given as arrays), the port impedance ``Z = N/D``, the real-part
polynomial ``P(x) = Re N(jω) D(−jω)`` in ``x = ω²`` and the Liénard–Chipart
(Hurwitz) determinants of ``D`` are derived symbolically *once*, as
polynomials in the free parameters.  A batch is then decided in float64 with a
rigorous a-priori rounding-error bound for every quantity:

* every polynomial in the parameters is evaluated as ``Σ c_t · monomial_t``;
  with ``u = 2^-53`` its computed value differs from the exact one by at most
  ``(deg + T + 4) · u · Σ |c_t · monomial_t|`` ([1], Sec. 3.1, with ``T``
  terms of total degree ``≤ deg``; the factor covers the rounding of the
  rational coefficients ``c_t`` to float);
* a sign is *certified* only when ``|value| >`` its bound;
* ``P ≥ 0`` on ``x > 0`` is certified by positive coefficients, by a negative
  discriminant (quadratic ``P/x^k``) or by Pólya's theorem ([2]: all
  coefficients of ``(1 + y)^n Q(σ y)`` positive, with the scale ``σ`` a power
  of two so scaling is exact and the error bounds are propagated through the
  additions); ``P < 0`` somewhere is certified by a point ``x* > 0`` where the
  computed ``P(x*)`` is below minus its Horner error bound.

A design whose every condition is certified gets its verdict from floating
point; any other design (typically within ~1e-12 relative of the boundary, or
with a pole structure the fast path does not cover) falls back to the exact
rational test [`seapass.analysis.passivity.positive_real_test`][seapass.analysis.passivity.positive_real_test] on the exactly
evaluated, reduced ``N/D``.  The verdicts are therefore identical to
[`seapass.analysis.passivity.is_passive`][seapass.analysis.passivity.is_passive] for every design.

The passivity *margin* is the one of [`PassivityResult`][seapass.analysis.passivity.PassivityResult]:
``min_{x ≥ 0} P(x) / A(x)`` in ``[-1, 1]``, where ``A`` is ``P`` computed with
every coefficient product in absolute value, restricted to the powers of ``x``
that ``P`` has for generic parameters (scale-invariant in ``N``, ``D``
and ``x``; a design at relative distance ``ε`` from a boundary has a margin of
order ``ε``).  It measures only condition 4 (``Re Z(jω) ≥ 0``); it is
computed in floating point and is informative, the verdict never depends on it.

References
----------
.. [1] N. J. Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed.,
   SIAM, 2002, ch. 3 (error bounds for sums, products and Horner's rule).
.. [2] G. Pólya, "Über positive Darstellung von Polynomen", Vierteljschr.
   Naturforsch. Ges. Zürich 73, 1928; V. Powers and B. Reznick, "A new bound
   for Pólya's theorem with applications to polynomials positive on polyhedra",
   J. Pure Appl. Algebra 164, 2001.
.. [3] F. R. Gantmacher, *The Theory of Matrices*, vol. 2, ch. XV (Liénard–Chipart).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .bank import UNIT_ROUNDOFF
from .kernel import PassivityKernel

__all__ = ["decide_chunk"]


# parameter magnitudes for which no under/overflow can occur
_SAFE_LO = 1e-30


_SAFE_HI = 1e30


_POLYA_STEPS = 192


def _pos(v: np.ndarray, e: np.ndarray) -> np.ndarray:
    return v > e


def _neg(v: np.ndarray, e: np.ndarray) -> np.ndarray:
    return v < -e


def _horner_bounded(qs: np.ndarray, es: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``Σ qs_i y^i`` and a bound on its error (coefficient errors ``es``, rounding)."""
    d = qs.shape[0] - 1
    val = qs[d].copy()
    mag = np.abs(qs[d]) + es[d]
    err = es[d].copy()
    for i in range(d - 1, -1, -1):
        val = val * y + qs[i]
        mag = mag * y + np.abs(qs[i]) + es[i]
        err = err * y + es[i]
    return val, err * (1 + 4 * (d + 1) * UNIT_ROUNDOFF) + (2 * d + 4) * UNIT_ROUNDOFF * 1.0001 * mag


def _pow2_scale(qs: np.ndarray) -> np.ndarray:
    """Power-of-two ``σ`` balancing the lowest and highest coefficients of each column."""
    d = qs.shape[0] - 1
    if d == 0:
        return np.ones(qs.shape[1])
    ratio = np.abs(qs[0]) / np.abs(qs[d])
    with np.errstate(divide="ignore", invalid="ignore"):
        e = np.round(np.log2(ratio) / d)
    e = np.where(np.isfinite(e), np.clip(e, -300 // max(d, 1), 300 // max(d, 1)), 0.0)
    return np.exp2(e)


def _ratio_min(qs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``min_{y>0} Q(y)/Σ|q_i|y^i`` (scaled ``Q``) and the minimizing ``y`` (0/inf at ends)."""
    d, n = qs.shape[0] - 1, qs.shape[1]
    grid = np.logspace(-6.0, 6.0, 241)
    aq = np.abs(qs)

    def ratio(y: np.ndarray) -> np.ndarray:
        num = np.zeros(y.shape)
        den = np.zeros(y.shape)
        for i in range(d, -1, -1):
            num = num * y + qs[i][:, None] if y.ndim == 2 else num * y + qs[i]
            den = den * y + aq[i][:, None] if y.ndim == 2 else den * y + aq[i]
        with np.errstate(invalid="ignore", divide="ignore"):
            return num / den

    vals = ratio(np.broadcast_to(grid, (n, grid.size)))
    k = np.argmin(vals, axis=1)
    lo = np.log10(grid[np.maximum(k - 1, 0)])
    hi = np.log10(grid[np.minimum(k + 1, grid.size - 1)])
    g = (math.sqrt(5) - 1) / 2
    a, b = lo, hi
    c1, c2 = b - g * (b - a), a + g * (b - a)
    f1, f2 = ratio(10.0**c1), ratio(10.0**c2)
    for _ in range(48):
        left = f1 <= f2
        b = np.where(left, c2, b)
        a = np.where(left, a, c1)
        c2n = np.where(left, c1, a + g * (b - a))
        c1n = np.where(left, b - g * (b - a), c2)
        c1, c2 = c1n, c2n
        f1 = ratio(10.0**c1)
        f2 = ratio(10.0**c2)
    ystar = 10.0 ** ((a + b) / 2)
    best = np.minimum(ratio(ystar), vals[np.arange(n), k])
    ystar = np.where(ratio(ystar) <= vals[np.arange(n), k], ystar, grid[k])
    ends = np.minimum(np.sign(qs[0]), np.sign(qs[d]))
    return np.minimum(best, ends), ystar


def _polya(qs: np.ndarray, es: np.ndarray) -> np.ndarray:
    """True where Pólya certifies ``Q(y) > 0`` on ``[0, ∞)`` within the step budget."""
    n = qs.shape[1]
    ok = np.zeros(n, dtype=bool)
    idx = np.arange(n)
    c, e = qs.copy(), es.copy()
    for _ in range(_POLYA_STEPS):
        done = np.all(c > e, axis=0)
        ok[idx[done]] = True
        keep = ~done
        if not np.any(keep):
            break
        idx, c, e = idx[keep], c[:, keep], e[:, keep]
        z = np.zeros((1, c.shape[1]))
        c2 = np.vstack([c, z]) + np.vstack([z, c])
        # the error sums are themselves rounded: inflate them by a few ulps
        e = (np.vstack([e, z]) + np.vstack([z, e])) * (
            1 + 4 * UNIT_ROUNDOFF
        ) + UNIT_ROUNDOFF * 1.0001 * np.abs(c2)
        c = c2
        if not np.all(np.isfinite(c)):
            break
    return ok


def _quadratic_mixed(
    qv: np.ndarray, qe: np.ndarray, mixed: np.ndarray, neg_cert: np.ndarray
) -> None:
    """Witness for ``Q = q0 + q1 x + q2 x²`` with ``q0, q2 > 0 > q1``: its vertex ``−q1/(2 q2)``."""
    sub = np.nonzero(mixed)[0]
    if not sub.size:
        return
    q1, q2 = qv[1, sub], qv[2, sub]
    with np.errstate(invalid="ignore", divide="ignore"):
        x = -q1 / (2.0 * q2)
    good = np.isfinite(x) & (x > 0)
    x = np.where(good, x, 1.0)
    pv, pe = _horner_bounded(qv[:, sub], qe[:, sub], x)
    neg_cert[sub[good & _neg(pv, pe)]] = True


def _general_mixed(
    qv: np.ndarray,
    qe: np.ndarray,
    mixed: np.ndarray,
    q_pos: np.ndarray,
    q_ends: np.ndarray,
    neg_cert: np.ndarray,
) -> None:
    """Pólya certificate and minimum-ratio witness for ``Q`` of any degree."""
    d = qv.shape[0] - 1
    sub = np.nonzero(mixed)[0]
    sig = _pow2_scale(qv[:, sub])
    pw = sig[None, :] ** np.arange(d + 1)[:, None]
    qs, es = qv[:, sub] * pw, qe[:, sub] * pw
    # subnormal scaled coefficients would break the error model
    clean = np.all(np.isfinite(qs) & ((qs == 0) | (np.abs(qs) > 1e-290)), axis=0)
    try_polya = clean & q_ends[sub] & ~q_pos[sub]
    if np.any(try_polya):
        j = np.nonzero(try_polya)[0]
        q_pos[sub[j]] |= _polya(qs[:, j], es[:, j])
    look = clean & ~q_pos[sub]
    if not np.any(look):
        return
    j = np.nonzero(look)[0]
    _m, ystar = _ratio_min(qs[:, j])
    y = np.where(np.isfinite(ystar) & (ystar > 0), ystar, 1.0)
    pv, pe = _horner_bounded(qs[:, j], es[:, j], y)
    wit = _neg(pv, pe) & clean[j]
    neg_cert[sub[j[wit]]] = True


def _pmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Product of ascending coefficient arrays (da+1, N) and (db+1, N)."""
    out = np.zeros((a.shape[0] + b.shape[0] - 1, a.shape[1]))
    for i in range(a.shape[0]):
        out[i : i + b.shape[0]] += a[i] * b
    return out


def _split_jw(c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``Re c(jω)`` and ``Im c(jω)/ω`` as coefficient arrays in ``x = ω²``."""
    k = np.arange(c.shape[0])
    sign = np.where((k // 2) % 2 == 1, -1.0, 1.0)[:, None]
    sc = c * sign
    re, im = sc[0::2], sc[1::2]
    if im.shape[0] == 0:
        im = np.zeros((1, c.shape[1]))
    return re, im


def _margin_batch(nv: np.ndarray, dv: np.ndarray, support: Sequence[bool]) -> np.ndarray:
    """The margin of [`seapass.analysis.passivity.positive_real_test`][seapass.analysis.passivity.positive_real_test], vectorized.

    ``min_{x≥0} P(x)/A(x)`` with ``A`` the real-part polynomial computed with
    every coefficient product in absolute value; the minimum is taken over
    the two ends and the positive real roots of ``P'A − PA'`` (eigenvalues of
    stacked companion matrices), after balancing the scale of ``x``.
    """
    nr, ni = _split_jw(nv)
    dr, di = _split_jw(dv)

    def shift(a: np.ndarray) -> np.ndarray:
        return np.vstack([np.zeros((1, a.shape[1])), a])

    P = _padd(_pmul(nr, dr), shift(_pmul(ni, di)))
    A = _padd(_pmul(np.abs(nr), np.abs(dr)), shift(_pmul(np.abs(ni), np.abs(di))))
    # powers of x that cancel for every parameter value are not a nearby boundary
    mask = np.array([i < len(support) and support[i] for i in range(A.shape[0])])
    A[~mask] = 0.0
    P[~mask] = 0.0
    n_c, N = P.shape
    out = np.zeros(N)
    nzA = A != 0
    has = nzA.any(axis=0) & (P != 0).any(axis=0)
    lo = np.argmax(nzA, axis=0)
    hi = n_c - 1 - np.argmax(nzA[::-1], axis=0)
    cols = np.arange(N)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        span = np.maximum(hi - lo, 1)
        ratio = A[lo, cols] / A[hi, cols]
        scale = np.where(hi > lo, ratio ** (1.0 / span), 1.0)
        pw = scale[None, :] ** np.arange(n_c)[:, None]
        cs, as_ = P * pw, A * pw
        cands = np.minimum(cs[lo, cols] / as_[lo, cols], cs[hi, cols] / as_[hi, cols])
        k = np.arange(1, n_c)[:, None]
        dP, dA = cs[1:] * k, as_[1:] * k
        crit = _padd(_pmul(dP, as_), -_pmul(cs, dA))
    crit = np.where(np.isfinite(crit), crit, 0.0)
    nz = crit != 0
    deg = np.where(nz.any(axis=0), crit.shape[0] - 1 - np.argmax(nz[::-1], axis=0), 0)
    for d in np.unique(deg):
        if d < 1:
            continue
        j = np.nonzero((deg == d) & has)[0]
        if not j.size:
            continue
        c = crit[: d + 1, j]
        comp = np.zeros((j.size, d, d))
        if d > 1:
            idx = np.arange(d - 1)
            comp[:, idx + 1, idx] = 1.0
        comp[:, :, -1] = -(c[:d] / c[d]).T
        roots = np.linalg.eigvals(comp)
        real = (np.abs(roots.imag) <= 1e-9 * np.maximum(1.0, np.abs(roots.real))) & (roots.real > 0)
        x = np.where(real, roots.real, 1.0)
        pv = _peval(cs[:, j], x)
        av = _peval(as_[:, j], x)
        with np.errstate(divide="ignore", invalid="ignore"):
            rv = np.where(real, pv / av, np.inf)
        cands[j] = np.minimum(cands[j], np.min(rv, axis=1))
    out[has] = np.clip(cands[has], -1.0, 1.0)
    return out


def _padd(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    n = max(a.shape[0], b.shape[0])
    out = np.zeros((n, a.shape[1]))
    out[: a.shape[0]] += a
    out[: b.shape[0]] += b
    return out


def _peval(c: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Ascending coefficients (deg+1, N) at points x (N, m)."""
    acc = np.zeros(x.shape)
    for row in c[::-1]:
        acc = acc * x + row[:, None]
    return acc


def decide_chunk(
    kernel: PassivityKernel, cols: Sequence[np.ndarray], want_margin: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Float decision for one chunk: status (1 passive, 0 not, −1 undecided) and margin."""
    n = cols[0].shape[0] if cols else 1
    status = np.full(n, -1, dtype=np.int8)
    margin = np.full(n, np.nan)
    if not kernel.supported:
        return status, margin
    bank = kernel.bank
    safe = np.ones(n, dtype=bool)
    for col in cols:
        a = np.abs(col)
        safe &= (a == 0) | ((a > _SAFE_LO) & (a < _SAFE_HI))
    val, err = bank.evaluate(cols, n)
    ok = np.all(np.isfinite(val), axis=0) & np.all(np.isfinite(err), axis=0) & safe

    def row(name: str) -> tuple[np.ndarray, np.ndarray]:
        i = bank.names[name]
        return val[i], err[i]

    nlead, nlead_e = row(kernel.n_exact[-1])
    dlead, dlead_e = row(kernel.d_exact[-1])
    lead_ok = (np.abs(nlead) > nlead_e) & (np.abs(dlead) > dlead_e)
    sgn = np.sign(dlead)
    rel = kernel.den_deg - kernel.num_deg
    neg_cert = np.zeros(n, dtype=bool)
    pos_cert = ok & lead_ok
    if rel not in (-1, 0, 1):
        neg_cert |= ok & lead_ok
        pos_cert[:] = False
    elif rel == -1:
        r = nlead * dlead
        neg_cert |= ok & lead_ok & (r < 0)
        pos_cert &= r > 0
    # the pole at s = 0 and the rest of D
    if kernel.s_power == 1:
        n0, n0e = row(kernel.n_exact[0])
        d0, d0e = row(kernel.d_exact[1])
        cert0 = (np.abs(n0) > n0e) & (np.abs(d0) > d0e)
        res_sign = np.sign(n0) * np.sign(d0)
        neg_cert |= ok & cert0 & (res_sign < 0)
        pos_cert &= cert0 & (res_sign > 0)
    for name in kernel.d_exact[kernel.s_power :]:
        v, e = row(name)
        pos_cert &= _pos(v * sgn, e)
    for k in kernel.lc_orders:
        v, e = row(f"lc{k}")
        pos_cert &= _pos(v * sgn**k, e)
    # Re Z(jω) >= 0: Q = P / x^q_low
    d = kernel.q_deg
    qv = np.stack([row(f"q{i}")[0] for i in range(d + 1)])
    qe = np.stack([row(f"q{i}")[1] for i in range(d + 1)])
    q_neg_end = _neg(qv[0], qe[0]) | _neg(qv[d], qe[d])
    neg_cert |= ok & q_neg_end
    q_ends = _pos(qv[0], qe[0]) & _pos(qv[d], qe[d])
    all_pos = np.all(qv >= 0, axis=0)
    q_pos = q_ends & np.all((qv > qe) | (qv == 0) & (qe == 0), axis=0)
    if d == 2:
        disc, disc_e = row("disc")
        q_pos |= q_ends & _neg(disc, disc_e)
    mixed = ok & ~all_pos & ~q_neg_end
    if d == 2:
        _quadratic_mixed(qv, qe, mixed, neg_cert)
    elif np.any(mixed):
        _general_mixed(qv, qe, mixed, q_pos, q_ends, neg_cert)
    pos_cert &= q_pos
    if want_margin and np.any(ok):
        nv = np.stack([row(nm)[0] for nm in kernel.n_exact])
        dv = np.stack([row(nm)[0] for nm in kernel.d_exact])
        margin[ok] = _margin_batch(nv[:, ok], dv[:, ok], kernel.support)
    status[pos_cert & ~neg_cert] = 1
    status[neg_cert] = 0
    return status, margin
