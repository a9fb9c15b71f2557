"""Small tools on python-flint arb balls: working precision, exact bounds of a ball.

A ball ``[m ± r]`` is a rigorous enclosure at any working precision; the precision only
decides how wide it is.  The bounds returned here are exact rationals (``m`` and ``r``
are binary floating-point numbers), so a decision taken on them is a proof.

Examples
--------
>>> from flint import fmpq
>>> lo, hi = sqrt_bounds(fmpq(2))
>>> lo * lo <= 2 <= hi * hi, float(hi - lo) < 1e-30
(True, True)
"""

from __future__ import annotations

import math
import threading
from collections.abc import Iterator
from contextlib import contextmanager

from flint import arb, ctx, fmpq

__all__ = [
    "PRECISIONS",
    "arb_of",
    "ball",
    "lower",
    "precision",
    "round_down",
    "round_up",
    "sqrt_bounds",
    "upper",
]

#: Working precisions tried in turn (bits), as ``seapass.sampled`` does.
PRECISIONS = (128, 256, 512, 1024)

_LOCK = threading.RLock()


@contextmanager
def precision(bits: int) -> Iterator[None]:
    """Work at ``bits`` of precision (python-flint's precision is process-wide)."""
    with _LOCK, ctx.workprec(bits):
        yield


def _dyadic(x: arb) -> fmpq:
    m, e = x.man_exp()
    return fmpq(int(m)) * fmpq(2) ** int(e)


def lower(x: arb) -> fmpq:
    """An exact rational ``<=`` every point of the ball ``x`` (finite balls only)."""
    if not x.is_finite():
        raise ArithmeticError("an infinite or NaN ball has no rational bound")
    return _dyadic(x.mid()) - _dyadic(x.rad())


def upper(x: arb) -> fmpq:
    """An exact rational ``>=`` every point of the ball ``x`` (finite balls only)."""
    if not x.is_finite():
        raise ArithmeticError("an infinite or NaN ball has no rational bound")
    return _dyadic(x.mid()) + _dyadic(x.rad())


def arb_of(q: fmpq) -> arb:
    """The ball of a rational (exact when it is dyadic and fits the precision)."""
    return arb(q)


def ball(a: fmpq, b: fmpq) -> arb:
    """A ball containing the interval ``[a, b]``."""
    mid = arb((a + b) / 2)
    return mid.union(arb(a)).union(arb(b))


def sqrt_bounds(x: fmpq, bits: int = 128) -> tuple[fmpq, fmpq]:
    """Rational ``lo <= sqrt(x) <= hi`` for ``x >= 0``."""
    if x < 0:
        raise ValueError("sqrt of a negative number")
    if x == 0:
        return fmpq(0), fmpq(0)
    with precision(bits):
        r = arb(x).sqrt()
        lo, hi = lower(r), upper(r)
    return max(lo, fmpq(0)), hi


def _safe_float(q: fmpq) -> float:
    try:
        return float(q)
    except OverflowError:
        return math.inf if q > 0 else -math.inf


def round_down(q: fmpq) -> float:
    """The largest float ``<= q`` (a printed passive end stays passive)."""
    x = _safe_float(q)
    if math.isfinite(x) and fmpq(*x.as_integer_ratio()) > q:
        x = math.nextafter(x, -math.inf)
    return x


def round_up(q: fmpq) -> float:
    """The smallest float ``>= q``."""
    x = _safe_float(q)
    if math.isfinite(x) and fmpq(*x.as_integer_ratio()) < q:
        x = math.nextafter(x, math.inf)
    return x
