"""The exact polynomial kernel: rational polynomials on python-flint, the imaginary axis.

What lives here: [`poly`][seapass.exact.poly] (polynomials over the rationals as
`flint.fmpq_poly`; gcd, squarefree parts, certified real-root counting and
isolation, signs at roots), [`axis`][seapass.exact.axis] (polynomials on the
imaginary axis: ``p(jω)``, Routh–Hurwitz, axis factors, a point where an even
polynomial is negative), [`halfline`][seapass.exact.halfline] (sign cells on
``x ≥ 0`` and the certified minimum of a rational function there) and
[`rounding`][seapass.exact.rounding] (exact numbers and roots rounded to doubles and
to decimal text in a chosen direction: reported ends of passive sets round inward).  Nothing
here decides in floating point: every decision is exact, or certified by ball
arithmetic and re-checked exactly.

May import: nothing else in seapass; python-flint only (it knows nothing of SEAs).
"""

from . import axis, halfline, poly, rounding

__all__ = ["axis", "halfline", "poly", "rounding"]
