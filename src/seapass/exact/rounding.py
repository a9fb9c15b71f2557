"""Rounding exact numbers to doubles and to decimal text, in a chosen direction.

A certified set of passive values is reported through doubles (results, JSON) and
through decimal text (the command line, reports, generated code).  Rounding an end
point *to nearest* can put the reported number outside the set, so every end point is
rounded **inward**: a lower end up, an upper end down.  Everything here is decided
exactly (comparisons of rationals, signs of a polynomial at rationals), never in
floating point:

* `float_down` / `float_up`: the nearest double on one side of a rational;
* `float_below_root` / `float_above_root`: the nearest double strictly on one side of
  an irrational root given by an isolating interval (one exact sign per candidate);
* `decimal_down` / `decimal_up`: ``digits`` significant digits on one side (``%g``
  style), so ``float(text)`` lands on the same side as well;
* `inward_text` / `interval_text`: an interval's ends rounded inward (more digits
  when the interval is too narrow for the ones asked for); `enclosure_text`: an
  enclosure rounded outward; `exact_text`: a value a result was computed *at* (a
  design value, a row of a map), in the fewest digits that read back as that double.

Examples
--------
>>> from fractions import Fraction
>>> decimal_down(Fraction(2, 3), 4), decimal_up(Fraction(2, 3), 4)
('0.6666', '0.6667')
>>> interval_text(0.0, 118.46721557324219, digits=10)
'[0, 118.4672155]'
>>> float_up(Fraction(1, 3)) > Fraction(1, 3) > float_down(Fraction(1, 3))
True
"""

from __future__ import annotations

import math
from fractions import Fraction

from flint import fmpq, fmpq_poly

__all__ = [
    "decimal_down",
    "decimal_up",
    "enclosure_text",
    "exact_text",
    "float_above_root",
    "float_below_root",
    "float_down",
    "float_up",
    "interval_text",
    "inward_text",
]

Exact = Fraction | float | int

#: Most bisections, and candidate doubles, next to one root (a bound on the work: an
#: isolating interval of doubles needs at most about 2,100 bisections).
MAX_CANDIDATES = 4096


def _q(x: Exact | fmpq) -> Fraction:
    if isinstance(x, fmpq):
        return Fraction(int(x.p), int(x.q))
    return Fraction(x)


def float_down(x: Exact | fmpq) -> float:
    """The largest double ``<= x`` (``x`` finite and within the double range)."""
    q = _q(x)
    f = float(q)
    return math.nextafter(f, -math.inf) if Fraction(f) > q else f


def float_up(x: Exact | fmpq) -> float:
    """The smallest double ``>= x``."""
    q = _q(x)
    f = float(q)
    return math.nextafter(f, math.inf) if Fraction(f) < q else f


def _root_side(p: fmpq_poly, x: Fraction, upper: Fraction) -> int:
    """``+1`` if ``x`` lies at or after the root in ``(lower, upper]``, ``-1`` if before.

    ``p`` changes sign at its (simple, irrational) root, so ``x`` is past the root iff
    ``p(x)`` has the sign of ``p(upper)``.
    """
    sx = p(fmpq(x.numerator, x.denominator))
    su = p(fmpq(upper.numerator, upper.denominator))
    if sx == 0 or su == 0:
        raise ArithmeticError("the isolating interval does not hold an irrational root")
    return 1 if (sx > 0) == (su > 0) else -1


def _narrowed(p: fmpq_poly, a: Fraction, b: Fraction) -> tuple[Fraction, Fraction]:
    """``(a, b]`` bisected exactly on the root until at most a few doubles lie inside."""
    for _ in range(MAX_CANDIDATES):
        f = float_up(a)
        g = math.nextafter(math.nextafter(f, math.inf), math.inf)
        if Fraction(g) >= b:
            return a, b
        mid = (a + b) / 2
        if _root_side(p, mid, b) > 0:
            b = mid
        else:
            a = mid
    raise ArithmeticError("the isolating interval could not be narrowed")


def float_above_root(p: fmpq_poly, interval: tuple[Exact | fmpq, Exact | fmpq]) -> float:
    """The smallest double strictly greater than the root of ``p`` in ``(a, b]``.

    ``p`` is irreducible of degree >= 2 (its roots are irrational) and changes sign
    across its only root in ``(a, b]``; the interval is bisected exactly until a few
    doubles are left in it, and each of those is placed by the sign of ``p`` there.
    """
    a, b = _narrowed(p, *(_q(v) for v in interval))
    f = float_up(a)
    for _ in range(MAX_CANDIDATES):
        if Fraction(f) == a:
            f = math.nextafter(f, math.inf)
            continue
        if Fraction(f) >= b or _root_side(p, Fraction(f), b) > 0:
            return f
        a = Fraction(f)  # f is before the root: the root is in (f, b]
        f = math.nextafter(f, math.inf)
    raise ArithmeticError("the isolating interval is too wide to round its root")


def float_below_root(p: fmpq_poly, interval: tuple[Exact | fmpq, Exact | fmpq]) -> float:
    """The largest double strictly smaller than the root of ``p`` in ``(a, b]``
    (see `float_above_root`)."""
    a, b = _narrowed(p, *(_q(v) for v in interval))
    f = float_down(b)
    for _ in range(MAX_CANDIDATES):
        if Fraction(f) <= a or _root_side(p, Fraction(f), b) < 0:
            return f
        b = Fraction(f)  # f is past the root: the root is in (a, f]
        f = math.nextafter(f, -math.inf)
    raise ArithmeticError("the isolating interval is too wide to round its root")


def _decimal(x: Exact | fmpq, digits: int, up: bool) -> str:
    q = _q(x)
    if not 1 <= digits <= 40:
        raise ValueError(f"digits must be in [1, 40], got {digits!r}")
    if q == 0:
        return "0"
    e = math.floor(math.log10(abs(q.numerator)) - math.log10(q.denominator))
    # log10 in floating point may be off by one near a power of ten: fix it exactly
    while abs(q) >= Fraction(10) ** (e + 1):
        e += 1
    while abs(q) < Fraction(10) ** e:
        e -= 1
    shift = e - digits + 1
    scaled = q / Fraction(10) ** shift
    m = math.ceil(scaled) if up else math.floor(scaled)
    text = _g_text(m, shift, digits)
    assert (Fraction(text) >= q) if up else (Fraction(text) <= q)
    return text


def _g_text(m: int, shift: int, digits: int) -> str:
    """``m · 10^shift`` written like ``%.{digits}g`` writes a double (exactly)."""
    sign = "-" if m < 0 else ""
    s = str(abs(m))
    stripped = s.rstrip("0")
    shift += len(s) - len(stripped)
    s = stripped
    exp = len(s) - 1 + shift  # scientific exponent of the leading digit
    if -4 <= exp < digits:
        if shift >= 0:
            return sign + s + "0" * shift
        point = len(s) + shift
        if point > 0:
            return sign + s[:point] + "." + s[point:]
        return sign + "0." + "0" * (-point) + s
    mant = s[0] + ("." + s[1:] if len(s) > 1 else "")
    return f"{sign}{mant}e{'-' if exp < 0 else '+'}{abs(exp):02d}"


def decimal_down(x: Exact | fmpq, digits: int = 10) -> str:
    """The largest decimal of ``digits`` significant digits ``<= x``, as ``%g`` text."""
    return _decimal(x, digits, up=False)


def decimal_up(x: Exact | fmpq, digits: int = 10) -> str:
    """The smallest decimal of ``digits`` significant digits ``>= x``, as ``%g`` text."""
    return _decimal(x, digits, up=True)


def inward_text(lo: Exact | fmpq, hi: Exact | fmpq, digits: int = 10) -> tuple[str, str]:
    """``lo`` rounded up and ``hi`` rounded down, both inside ``[lo, hi]`` (``lo <= hi``).

    Uses more digits when ``digits`` would make the rounded ends meet; a single point
    (``lo == hi``) is shown by the shortest text of at least ``digits`` digits that reads
    back as the same double (`exact_text`).
    """
    qlo, qhi = _q(lo), _q(hi)
    if qlo > qhi:
        raise ValueError(f"empty interval [{lo}, {hi}]")
    if qlo == qhi:
        text = exact_text(float(qlo), digits) if Fraction(float(qlo)) == qlo else str(qlo)
        return text, text
    for n in range(digits, 41):  # two distinct ends stay distinct when they can
        a, b = decimal_up(qlo, n), decimal_down(qhi, n)
        if Fraction(a) < Fraction(b):
            return a, b
    a, b = decimal_up(qlo, digits), decimal_down(qhi, digits)
    if Fraction(a) <= Fraction(b):
        return a, b
    raise ArithmeticError(f"no decimal of at most 40 digits inside [{lo}, {hi}]")


def interval_text(lo: Exact | fmpq, hi: Exact | fmpq, *, digits: int = 6) -> str:
    """``[a, b]`` with the ends rounded inward (``{a}`` for a single point)."""
    a, b = inward_text(lo, hi, digits)
    return f"{{{a}}}" if _q(lo) == _q(hi) else f"[{a}, {b}]"


def enclosure_text(lo: Exact | fmpq, hi: Exact | fmpq, *, digits: int = 12) -> str:
    """``[a, b]`` with the ends rounded outward: it still encloses ``[lo, hi]``."""
    return f"[{decimal_down(lo, digits)}, {decimal_up(hi, digits)}]"


def exact_text(x: float, digits: int = 6) -> str:
    """The shortest ``%g`` text of at least ``digits`` digits that reads back as ``x``.

    >>> exact_text(30.0), exact_text(0.1 + 0.2)
    ('30', '0.30000000000000004')
    """
    for n in range(digits, 18):
        text = f"{x:.{n}g}"
        if float(text) == x:
            return text
    return repr(x)
