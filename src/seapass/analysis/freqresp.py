"""Frequency response of the rendered stiffness ``F_L/X_L(jω)`` (the paper's "Frequency Response" column)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..files.limits import MAX_FREQUENCY_POINTS
from ..model.display import Shown, html_card, short_repr
from ..model.sea import SEA, Impedance

__all__ = [
    "FrequencyResponse",
    "check_points",
    "log_frequencies",
    "stiffness_coefficients",
    "stiffness_response",
]


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
        i = int(np.argmax(self.magnitude)) if self.magnitude.size else None
        rows: list[tuple[str, Any]] = [
            (
                "frequencies",
                f"{w.size} points" + (f", {w[0]:.4g}..{w[-1]:.4g} rad/s" if w.size else ""),
            ),
            ("static stiffness F_L/X_L(0)", f"{self.static:.6g} N/m"),
            ("high-frequency stiffness", f"{self.high_frequency:.6g} N/m"),
        ]
        if i is not None:
            rows.append(("peak", f"{self.magnitude[i]:.6g} N/m at ω = {w[i]:.6g} rad/s"))
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
