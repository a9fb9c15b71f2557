"""The exact polynomial kernel: rational polynomials, Sturm sequences, the imaginary axis.

What lives here: [`poly`][seapass.exact.poly] (exact univariate polynomial
arithmetic over the rationals, real-root counting and isolation) and
[`axis`][seapass.exact.axis] (polynomials on the imaginary axis: ``p(jω)``,
Routh–Hurwitz, axis factors, a point where an even polynomial is negative) and
[`halfline`][seapass.exact.halfline] (sign cells on ``x ≥ 0`` and the certified
minimum of a rational function there).
Nothing here decides in floating point.

May import: [`seapass.errors`][seapass.errors] only (it knows nothing of SEAs).
"""

from . import axis, halfline, poly

__all__ = ["axis", "halfline", "poly"]
