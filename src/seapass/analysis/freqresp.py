"""Frequency response of the rendered stiffness ``F_L/X_L(jω)`` (the paper's "Frequency Response" column)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..files.limits import MAX_FREQUENCY_POINTS
from ..model.display import Shown, html_card, short_repr
from ..model.sea import SEA, Impedance

__all__ = [
    "PHASE_WINDOW",
    "FrequencyResponse",
    "PeakKind",
    "StiffnessPeak",
    "check_points",
    "log_frequencies",
    "phase_curve",
    "stiffness_coefficients",
    "stiffness_peak",
    "stiffness_response",
    "wrap_phase",
]

PHASE_WINDOW = (-90.0, 270.0)
"""Where `wrap_phase` puts a phase [deg]: the passive band ``[0°, 180°]`` of a stiffness
``s·Z`` (``Re Z ≥ 0`` is ``arg Z ∈ [−90°, 90°]``) sits in its middle, 90° from each end."""


def wrap_phase(phase: Any) -> np.ndarray:
    """``phase`` [deg] moved by whole turns into ``[-90°, 270°)`` (`PHASE_WINDOW`).

    An unwrapped phase can drift by whole turns (a right-half-plane pole or a
    high order adds them), so 449° would read as outside ``[0°, 180°]`` although
    it is 89°.  Wrapped, a phase is inside ``[0°, 180°]`` exactly when its
    angle is.

    Examples
    --------
    >>> wrap_phase([449.0, -100.0, 0.0, 180.0, 270.0]).tolist()
    [89.0, 260.0, 0.0, 180.0, -90.0]
    """
    p = np.asarray(phase, dtype=float)
    lo = PHASE_WINDOW[0]
    return np.asarray(np.mod(p - lo, 360.0) + lo)


def phase_curve(omega: Any, phase: Any) -> tuple[np.ndarray, np.ndarray]:
    """The wrapped phase as a curve to draw: a NaN breaks it wherever it wraps.

    Returns ``(omega, wrapped phase)``, one point longer per wrap, so a line
    plot does not draw a vertical stroke across the window at a wrap.

    Examples
    --------
    >>> w, p = phase_curve([1.0, 2.0, 3.0], [260.0, 280.0, 300.0])
    >>> p.tolist()
    [260.0, nan, -80.0, -60.0]
    """
    w = np.asarray(omega, dtype=float)
    p = wrap_phase(phase)
    jumps = np.flatnonzero(np.abs(np.diff(p)) > 180.0) + 1
    return np.insert(w, jumps, np.nan), np.insert(p, jumps, np.nan)


class PeakKind(StrEnum):
    """Where the largest ``|F_L/X_L|`` on a grid lies."""

    INTERIOR = "interior"
    """A true maximum inside the grid."""
    UNBOUNDED_HIGH = "unbounded_high"
    """At the right edge, and ``|F_L/X_L| → ∞`` as ``ω → ∞`` (numerator degree is higher)."""
    UNBOUNDED_LOW = "unbounded_low"
    """At the left edge, and ``|F_L/X_L| → ∞`` as ``ω → 0`` (a pole at ``s = 0``)."""
    EDGE_HIGH = "edge_high"
    """At the right edge of the grid; it may grow beyond it to a finite limit or peak."""
    EDGE_LOW = "edge_low"
    """At the left edge of the grid."""


@dataclass(frozen=True, kw_only=True)
class StiffnessPeak:
    """The largest ``|F_L/X_L|`` on a grid, and whether it is a peak at all.

    Attributes
    ----------
    kind : PeakKind
    magnitude : float
        Largest ``|F_L/X_L|`` on the grid [N/m].
    omega : float
        Where [rad/s].
    limit : float
        ``|F_L/X_L|`` in the limit beyond that edge (``inf``: without bound); for
        ``INTERIOR`` the high-frequency limit.
    """

    kind: PeakKind
    magnitude: float
    omega: float
    limit: float

    @property
    def is_peak(self) -> bool:
        """The largest value is a true maximum inside the grid (not an edge)."""
        return self.kind is PeakKind.INTERIOR

    def describe(self) -> str:
        """One line for a person (no ``peak`` when the maximum is at an edge)."""
        at = f"{self.magnitude:.6g} N/m at w = {self.omega:.6g} rad/s"
        if self.kind is PeakKind.INTERIOR:
            return f"peak |F_L/X_L| = {at}"
        if self.kind is PeakKind.UNBOUNDED_HIGH:
            return f"|F_L/X_L| grows without bound as w -> inf ({at}, the grid's right edge)"
        if self.kind is PeakKind.UNBOUNDED_LOW:
            return f"|F_L/X_L| grows without bound as w -> 0 ({at}, the grid's left edge)"
        side = "right" if self.kind is PeakKind.EDGE_HIGH else "left"
        beyond = "w -> inf" if self.kind is PeakKind.EDGE_HIGH else "w -> 0"
        return (
            f"no peak on the grid: largest |F_L/X_L| = {at} (its {side} edge); "
            f"limit as {beyond}: {self.limit:.6g} N/m"
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "kind": str(self.kind),
            "magnitude": self.magnitude,
            "omega": self.omega,
            "limit": self.limit,
        }


def stiffness_peak(response: FrequencyResponse) -> StiffnessPeak:
    """The largest ``|F_L/X_L|`` of ``response`` on its grid, classified by `PeakKind`.

    A maximum at the right edge of the grid is not called a peak: when the
    numerator's degree exceeds the denominator's the magnitude grows without
    bound (``response.high_frequency`` is ``inf``), otherwise it continues
    beyond the grid.  Likewise at the left edge with a pole at ``s = 0``.

    Examples
    --------
    >>> from seapass.model.sea import Impedance
    >>> r = stiffness_response(Impedance(expr="s + 1"), log_frequencies(1, 100, 50))
    >>> stiffness_peak(r).kind
    <PeakKind.UNBOUNDED_HIGH: 'unbounded_high'>
    """
    mag = np.asarray(response.magnitude, dtype=float)
    w = np.asarray(response.omega, dtype=float)
    finite = np.where(np.isfinite(mag), mag, -np.inf)
    i = int(np.argmax(finite)) if finite.size else 0
    value = float(mag[i]) if mag.size else math.nan
    at = float(w[i]) if w.size else math.nan
    top = mag.size - 1
    if mag.size > 1 and i == top and finite[i] > finite[i - 1]:
        kind = (
            PeakKind.UNBOUNDED_HIGH if math.isinf(response.high_frequency) else PeakKind.EDGE_HIGH
        )
        return StiffnessPeak(kind=kind, magnitude=value, omega=at, limit=response.high_frequency)
    if mag.size > 1 and i == 0 and finite[0] > finite[1]:
        kind = PeakKind.UNBOUNDED_LOW if math.isinf(response.static) else PeakKind.EDGE_LOW
        return StiffnessPeak(kind=kind, magnitude=value, omega=at, limit=abs(response.static))
    return StiffnessPeak(
        kind=PeakKind.INTERIOR, magnitude=value, omega=at, limit=response.high_frequency
    )


@dataclass(frozen=True, repr=False, kw_only=True)
class FrequencyResponse:
    """``|F_L/X_L(jω)|`` and its phase.

    Attributes
    ----------
    omega : ndarray, shape (n,)
        Angular frequencies [rad/s].
    magnitude : ndarray, shape (n,)
        ``|F_L/X_L(jω)|`` [N/m].
    phase : ndarray, shape (n,)
        Phase [deg], unwrapped.
    static : float
        ``F_L/X_L(0)`` [N/m] (``inf`` when the port is held by an integrator).
    high_frequency : float
        ``lim_{ω→∞} |F_L/X_L(jω)|`` [N/m] (``inf`` when it grows without bound).
    """

    omega: np.ndarray
    magnitude: np.ndarray
    phase: np.ndarray
    static: float
    high_frequency: float
    label: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {
            "omega": self.omega.tolist(),
            "magnitude": self.magnitude.tolist(),
            "phase_deg": self.phase.tolist(),
            "static": self.static,
            "high_frequency": self.high_frequency,
        }

    @property
    def wrapped_phase(self) -> np.ndarray:
        """`phase` moved by whole turns into ``[-90°, 270°)`` (`wrap_phase`): passive is ``[0°, 180°]``."""
        return wrap_phase(self.phase)

    def peak(self) -> StiffnessPeak:
        """The largest ``|F_L/X_L|`` on the grid, and whether it is a peak (`stiffness_peak`)."""
        return stiffness_peak(self)

    def plot(self, *, axes: Any = None, **kwargs: Any) -> Any:
        """Bode plot (magnitude and phase); returns the two Axes.

        See [`seapass.plot.passivity.plot_bode`][seapass.plot.passivity.plot_bode].
        """
        from ..plot.passivity import plot_bode

        return plot_bode(self, axes=axes, **kwargs)

    def __repr__(self) -> str:
        w = self.omega
        return short_repr(
            "FrequencyResponse",
            {
                "label": self.label or None,
                "points": w.size,
                "omega": Shown(f"[{w[0]:.4g}, {w[-1]:.4g}]" if w.size else "[]"),
                "static": self.static,
                "high_frequency": self.high_frequency,
            },
        )

    def _repr_html_(self) -> str:
        w = self.omega
        rows: list[tuple[str, Any]] = [
            (
                "frequencies",
                f"{w.size} points" + (f", {w[0]:.4g}..{w[-1]:.4g} rad/s" if w.size else ""),
            ),
            ("static stiffness F_L/X_L(0)", f"{self.static:.6g} N/m"),
            ("high-frequency stiffness", f"{self.high_frequency:.6g} N/m"),
        ]
        if w.size:
            rows.append(("largest |F_L/X_L|", self.peak().describe()))
        return html_card(f"Rendered stiffness {self.label}".strip(), rows)


def stiffness_coefficients(
    sea: SEA | Impedance, values: Mapping[str, float] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Numerator and denominator of ``F_L/X_L`` as float arrays, descending powers of ``s``.

    For a raw `Impedance` ``Z`` (force over velocity) the stiffness is ``s·Z``.
    """
    import sympy as sp  # the symbolic stiffness; the frequency-grid checks need no sympy

    from ..model.expr import S
    from ..model.stiffness import derive_stiffness

    if isinstance(sea, Impedance):
        model: SEA | Impedance = (
            Impedance(expr=sea.expr, values={**sea.values, **values}) if values else sea
        )
    else:
        model = sea.with_values(**values) if values else sea
    if model.free_parameters:
        names = ", ".join(model.free_parameters)
        raise ParameterError(
            f"no value for parameter(s) {names}: give them, e.g. values={{{names.split(', ')[0]!r}: 1.0}}"
        )
    if isinstance(model, Impedance):
        expr = (model.expr * S).xreplace(model.substitutions())
    else:
        expr = derive_stiffness(model).stiffness.xreplace(model.substitutions())
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    n = np.array([float(c) for c in sp.Poly(num, S).all_coeffs()])
    d = np.array([float(c) for c in sp.Poly(den, S).all_coeffs()])
    return n, d


def stiffness_response(
    sea: SEA | Impedance,
    omega: np.ndarray | None = None,
    *,
    values: Mapping[str, float] | None = None,
    label: str = "",
) -> FrequencyResponse:
    """Evaluate ``F_L/X_L(jω)`` of ``sea``.

    Parameters
    ----------
    sea : SEA or Impedance
        Model with values for all parameters (for a raw impedance ``Z``, the
        stiffness ``s·Z``).
    omega : array_like, shape (n,), optional
        Frequencies [rad/s]; default 400 log-spaced points over 1e-1..1e4.
    values : mapping, optional
        Overriding parameter values.

    Returns
    -------
    FrequencyResponse
    """
    w = np.logspace(-1, 4, 400) if omega is None else np.asarray(omega, dtype=float)
    if w.ndim != 1 or np.any(~np.isfinite(w)) or np.any(w < 0):
        raise ParameterError(
            f"omega must be a 1-D array of finite non-negative values, got shape {w.shape}"
        )
    n, d = stiffness_coefficients(sea, values)
    h = np.polyval(n, 1j * w) / np.polyval(d, 1j * w)
    nz_n = np.trim_zeros(n[::-1], "f")
    nz_d = np.trim_zeros(d[::-1], "f")
    static = (
        float(nz_n[0] / nz_d[0])
        if len(n) - len(nz_n) == len(d) - len(nz_d)
        else (np.inf if len(n) - len(nz_n) < len(d) - len(nz_d) else 0.0)
    )
    deg_gap = (len(n) - 1) - (len(d) - 1)
    high = abs(n[0] / d[0]) if deg_gap == 0 else (np.inf if deg_gap > 0 else 0.0)
    return FrequencyResponse(
        omega=w,
        magnitude=np.abs(h),
        phase=np.degrees(np.unwrap(np.angle(h))),
        static=float(static),
        high_frequency=float(high),
        label=label or getattr(sea, "name", ""),
    )


def check_points(points: int) -> int:
    """``points``, a number of frequencies from 2 to ``MAX_FREQUENCY_POINTS``, or an error.

    >>> check_points(1)
    Traceback (most recent call last):
    ...
    seapass.errors.ParameterError: points must be between 2 and 100000, got points=1
    """
    if (
        isinstance(points, bool)
        or not isinstance(points, int)
        or not (2 <= points <= MAX_FREQUENCY_POINTS)
    ):
        raise ParameterError(
            f"points must be between 2 and {MAX_FREQUENCY_POINTS}, got points={points!r}",
            argument="points",
        )
    return points


def log_frequencies(lo: float, hi: float, points: int) -> np.ndarray:
    """``points`` log-spaced frequencies from ``lo`` to ``hi`` (rad/s), both ends included.

    Raises
    ------
    ParameterError
        Unless ``0 < lo < hi`` are finite and `check_points` accepts ``points``.

    Examples
    --------
    >>> log_frequencies(0.1, 10, 3).tolist()
    [0.1, 1.0, 10.0]
    """
    check_points(points)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
        raise ParameterError(
            f"omega must be positive frequencies 0 < lo < hi (log-spaced), got omega={lo:g}:{hi:g}",
            argument="omega",
        )
    return np.logspace(math.log10(lo), math.log10(hi), points)
