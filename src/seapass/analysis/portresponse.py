"""The port impedance on the imaginary axis: ``Z(jω)`` for pictures, exact bands where ``Re Z < 0``.

A plot of ``Re Z(jω)`` or a Nyquist plot samples ``Z`` on a grid of
frequencies, which is fine for a picture and useless for a verdict: a dip
below zero narrower than the grid spacing is simply missed.  So the
frequencies where ``Re Z(jω) < 0`` are never read off the grid.  They come
from the real-part polynomial ``P(x) = Re N(jω) D(−jω)``, ``x = ω²``, whose
sign is the sign of ``Re Z(jω)`` wherever ``D(jω) ≠ 0``: its distinct
positive real roots are isolated exactly (certified, re-checked on rationals), the
sign of ``P`` between consecutive roots is evaluated exactly at a rational
point, and only the band edges are rounded to floats (to full double
precision) for display.  The grid of the curve always contains those edges.

References
----------
.. [1] B. D. O. Anderson and S. Vongpanitlerd, *Network Analysis and Synthesis*,
   Prentice-Hall, 1973, sec. 5.1 (positive real functions).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from flint import fmpq_poly

from ..errors import ParameterError
from ..exact import poly as ep
from ..exact.axis import negative_bands, real_part_polynomial, safe_float
from ..model.display import Shown, html_card, short_repr
from ..model.sea import SEA
from .freqresp import check_points
from .impedance import SystemLike, evaluate_system

__all__ = [
    "Band",
    "ImpedanceResponse",
    "default_frequencies",
    "impedance_response",
    "negative_real_bands",
    "real_part_x",
    "reduced_impedance",
]

Band = tuple[float, float]
"""A frequency band ``(lo, hi)`` in rad/s; ``hi`` may be ``inf``."""


def real_part_x(num: ep.PolyLike, den: ep.PolyLike) -> fmpq_poly:
    """``P(x) = Re N(jω) D(−jω)`` as an exact polynomial in ``x = ω²``."""
    return real_part_polynomial(ep.as_poly(num), ep.as_poly(den))


def reduced_impedance(num: ep.PolyLike, den: ep.PolyLike) -> tuple[fmpq_poly, fmpq_poly]:
    """``N/D`` with common factors cancelled and ``D``'s leading coefficient positive."""
    n, d = ep.as_poly(num), ep.as_poly(den)
    if d.is_zero():
        raise ParameterError("den: the denominator is identically zero")
    if not n.is_zero():
        g = n.gcd(d)
        if g.degree() > 0:
            n, d = n // g, d // g
    else:
        d = ep.monic(d)
    if d.leading_coefficient() < 0:
        n, d = -n, -d
    return n, d


def negative_real_bands(num: ep.PolyLike, den: ep.PolyLike) -> tuple[Band, ...]:
    """The frequency bands where ``Re Z(jω) < 0`` for ``Z = num/den``, decided exactly.

    Parameters
    ----------
    num, den : fmpq_poly or sequence of rationals
        Exact coefficients, ascending powers of ``s``.

    Returns
    -------
    tuple of (float, float)
        Disjoint open bands ``(lo, hi)`` in rad/s, increasing; ``lo`` may be 0
        and ``hi`` may be ``inf``.  Empty when ``Re Z(jω) ≥ 0`` everywhere.
        The edges are the exact positive roots of ``P(x)``, ``ω = √x``, rounded
        to double precision; whether ``P < 0`` between them is decided exactly.
        Points where ``P`` only touches zero (a root of even multiplicity)
        inside a band do not split it.

    Examples
    --------
    >>> negative_real_bands([1], [1, 1])   # 1/(1 + s)
    ()
    >>> [round(x, 12) for x in negative_real_bands([-1, 1], [1, 1])[0]]
    [0.0, 1.0]
    """
    return tuple(negative_bands(real_part_x(num, den)))


def default_frequencies(
    num: Sequence[float], den: Sequence[float], bands: Sequence[Band] = (), points: int = 600
) -> np.ndarray:
    """A log-spaced grid covering the poles, zeros and bands of ``num/den`` (descending).

    Two decades below the smallest and above the largest non-zero pole or zero
    magnitude (``0.1..1e4`` rad/s when there is none), widened to show every
    finite band edge; the band edges themselves are inserted into the grid.
    """
    mags = [abs(r) for r in (*_roots(num), *_roots(den)) if abs(r) > 0 and np.isfinite(abs(r))]
    mags += [e for band in bands for e in band if 0 < e < math.inf]
    if mags:
        lo, hi = min(mags) / 100.0, max(mags) * 100.0
    else:
        lo, hi = 0.1, 1e4
    grid = np.logspace(math.log10(lo), math.log10(hi), points)
    extra = [e for band in bands for e in band if lo < e < hi]
    return np.unique(np.concatenate([grid, extra])) if extra else grid


def _roots(coeffs: Sequence[float]) -> np.ndarray:
    c = np.trim_zeros(np.asarray(coeffs, dtype=float), "f")
    if c.size < 2 or not np.all(np.isfinite(c)):
        return np.zeros(0)
    return np.roots(c)


@dataclass(frozen=True, repr=False, kw_only=True)
class ImpedanceResponse:
    """``Z(jω)`` of a port on a grid, and the exact bands where ``Re Z(jω) < 0``.

    Attributes
    ----------
    omega : ndarray, shape (n,)
        Frequencies [rad/s], increasing; they include every finite band edge.
    value : ndarray, shape (n,), complex
        ``Z(jω)`` [N·s/m] (``inf`` at a pole on the axis).
    negative_bands : tuple of (float, float)
        Where ``Re Z(jω) < 0``, decided exactly (`negative_real_bands`); not
        from the grid.
    num, den : tuple of float
        Reduced ``Z = N/D``, descending powers of ``s``.
    label : str
        Legend label.
    """

    omega: np.ndarray
    value: np.ndarray
    negative_bands: tuple[Band, ...]
    num: tuple[float, ...] = ()
    den: tuple[float, ...] = ()
    label: str = ""
    lossless: bool = field(default=False)

    @property
    def real(self) -> np.ndarray:
        """``Re Z(jω)``, shape (n,)."""
        return np.asarray(self.value.real)

    @property
    def imag(self) -> np.ndarray:
        """``Im Z(jω)``, shape (n,)."""
        return np.asarray(self.value.imag)

    @property
    def passive_real_part(self) -> bool:
        """``Re Z(jω) ≥ 0`` at every frequency (exact; the other PR conditions are not checked)."""
        return not self.negative_bands

    def to_dict(self) -> dict[str, Any]:
        return {
            "label": self.label,
            "omega": self.omega.tolist(),
            "real": self.real.tolist(),
            "imag": self.imag.tolist(),
            "negative_bands": [list(b) for b in self.negative_bands],
            "num": list(self.num),
            "den": list(self.den),
        }

    def plot(self, kind: str = "real", *, ax: Any = None, **kwargs: Any) -> Any:
        """Draw ``Re Z(jω)`` with the failing bands shaded (``kind="real"``) or a Nyquist plot.

        Returns the matplotlib Axes; see [`seapass.plot.passivity`][seapass.plot.passivity].
        """
        from ..plot.passivity import plot_impedance

        return plot_impedance(self, kind=kind, ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "ImpedanceResponse",
            {
                "label": self.label or None,
                "points": self.omega.size,
                "omega": Shown(_span(self.omega)),
                "negative_bands": Shown(
                    _bands_text(self.negative_bands) if self.negative_bands else "()"
                ),
            },
        )

    def _repr_html_(self) -> str:
        return html_card(
            f"Impedance response {self.label}".strip(),
            [
                ("frequencies", f"{self.omega.size} points, {_span(self.omega)} rad/s"),
                ("Re Z(jω) < 0 (exact)", _bands_text(self.negative_bands)),
            ],
        )


def _span(w: np.ndarray) -> str:
    return f"[{w[0]:.4g}, {w[-1]:.4g}]" if w.size else "[]"


def _bands_text(bands: Sequence[Band]) -> str:
    if not bands:
        return "none: Re Z(jω) ≥ 0 everywhere"
    return ", ".join(f"({a:.6g}, {b:.6g})" for a, b in bands)


def impedance_response(
    system: SystemLike,
    omega: Sequence[float] | np.ndarray | None = None,
    *,
    values: Mapping[str, float] | None = None,
    points: int = 600,
    label: str = "",
) -> ImpedanceResponse:
    """``Z(jω)`` of ``system`` and the exact bands where ``Re Z(jω) < 0``.

    Parameters
    ----------
    system : SEA, Impedance, str, sympy.Expr or (num, den)
        As for [`is_passive`][seapass.analysis.passivity.is_passive]: an SEA's
        load impedance ``Z_L = F_L/(s X_L)``, a raw impedance, or descending
        coefficient sequences.
    omega : array_like, shape (n,), optional
        Frequencies [rad/s], positive; default `default_frequencies`.  The
        finite band edges are added to it.
    values : mapping, optional
        Parameter values overriding those stored in ``system``.
    points : int, default 600
        Size of the default grid (ignored when ``omega`` is given).
    label : str, optional
        Legend label (default: the SEA's name).

    Returns
    -------
    ImpedanceResponse

    Examples
    --------
    >>> r = impedance_response("(s - 1)/(s + 2)")
    >>> [round(x, 9) for x in r.negative_bands[0]]
    [0.0, 1.414213562]
    """
    num, den, _support = evaluate_system(system, values)
    if not label and isinstance(system, SEA):
        label = system.name
    return response_of(num, den, omega, points=points, label=label)


def response_of(
    num: ep.PolyLike,
    den: ep.PolyLike,
    omega: Sequence[float] | np.ndarray | None = None,
    *,
    points: int = 600,
    label: str = "",
) -> ImpedanceResponse:
    """`ImpedanceResponse` of the exact ``Z = num/den`` (ascending rational coefficients)."""
    n_exact, d_exact = reduced_impedance(num, den)
    bands = negative_real_bands(n_exact, d_exact) if not n_exact.is_zero() else ()
    n = tuple(safe_float(c) for c in reversed(n_exact.coeffs())) or (0.0,)
    d = tuple(safe_float(c) for c in reversed(d_exact.coeffs()))
    if omega is None:
        w = default_frequencies(n, d, bands, check_points(points))
    else:
        w = np.asarray(omega, dtype=float)
        if w.ndim != 1 or w.size < 2 or np.any(~np.isfinite(w)) or np.any(w <= 0):
            raise ParameterError(
                f"omega must be a 1-D array of at least 2 finite positive frequencies, "
                f"got shape {w.shape}"
            )
        extra = [e for b in bands for e in b if w.min() < e < w.max()]
        w = np.unique(np.concatenate([w, extra]))
    s = 1j * w
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.polyval(n, s) / np.polyval(d, s)
    return ImpedanceResponse(
        omega=w,
        value=z,
        negative_bands=bands,
        num=n,
        den=d,
        label=label,
        lossless=bool(num) and not real_part_x(num, den),
    )
