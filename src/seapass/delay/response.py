"""``Z(jω)`` of a delayed impedance at its delay, for pictures, with certified failing bands.

The curve is sampled in floating point (a picture, never a verdict).  The bands where
``Re Z(jω) < 0`` are the sub-intervals proven negative by ball arithmetic
([`sign.negative_intervals`][seapass.delay.sign.negative_intervals]), merged, never read
off the grid; the dangerous band (where *some* delay makes ``Re Z < 0``) is exact.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
from flint import fmpq

from ..exact import poly as ep
from ..exact.axis import safe_float
from ..model.display import Shown, html_card, short_repr
from .bands import dangerous_bands
from .highfreq import high_frequency
from .sign import negative_intervals
from .structure import DelayedImpedance
from .trig import real_part

__all__ = ["DelayResponse", "delayed_response", "evaluate"]

Band = tuple[float, float]


def evaluate(z: DelayedImpedance, omega: Any, tau: float | None = None) -> np.ndarray:
    """``Z(jω)`` in floating point on a grid (for pictures and independent cross-checks)."""
    w = np.asarray(omega, dtype=float)
    delay = tau if tau is not None else z.tau
    t = float(delay) if delay is not None else 0.0
    s = 1j * w
    e = np.exp(-s * t)

    def value(parts: tuple[Any, ...]) -> np.ndarray:
        out = np.zeros_like(s)
        for k, p in enumerate(parts):
            c = [safe_float(x) for x in p.coeffs()]
            out = out + np.polynomial.polynomial.polyval(s, c) * e**k if c else out
        return out

    with np.errstate(divide="ignore", invalid="ignore"):
        return value(z.num) / value(z.den)


@dataclass(frozen=True, kw_only=True, repr=False)
class DelayResponse:
    """``Z(jω)`` at the delay on a grid, and the certified bands where ``Re Z(jω) < 0``.

    Attributes
    ----------
    omega : ndarray
        Frequencies [rad/s], increasing.
    value : ndarray, complex
        ``Z(jω)`` [N·s/m] (floating point, for the picture).
    negative_bands : tuple of (float, float)
        Proven ``Re Z < 0`` (ball arithmetic), merged.
    undecided_bands : tuple of (float, float)
        Where the balls did not decide within the budget.
    dangerous_bands : tuple of (float, float)
        Where some delay makes ``Re Z < 0`` (exact; first-order delays only).
    """

    omega: np.ndarray
    value: np.ndarray
    tau: float
    delay: str
    negative_bands: tuple[Band, ...] = ()
    undecided_bands: tuple[Band, ...] = ()
    dangerous_bands: tuple[Band, ...] = ()
    label: str = ""
    extra: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def real(self) -> np.ndarray:
        return np.real(self.value)

    def to_dict(self) -> dict[str, Any]:
        return {
            "delay": {"name": self.delay, "tau": self.tau},
            "omega": self.omega.tolist(),
            "real": self.real.tolist(),
            "imag": np.imag(self.value).tolist(),
            "negative_bands": [list(b) for b in self.negative_bands],
            "undecided_bands": [list(b) for b in self.undecided_bands],
            "dangerous_bands": [list(b) for b in self.dangerous_bands],
        }

    def plot(self, kind: str = "real", *, ax: Any = None, **kwargs: Any) -> Any:
        from ..plot.delay import plot_delay_response

        return plot_delay_response(self, kind=kind, ax=ax, **kwargs)

    def __repr__(self) -> str:
        w = self.omega
        return short_repr(
            "DelayResponse",
            {
                "tau": self.tau,
                "omega": Shown(f"[{w[0]:.3g}, {w[-1]:.3g}]") if w.size else None,
                "negative_bands": len(self.negative_bands),
            },
        )

    def _repr_html_(self) -> str:
        rows = [
            ("delay", f"{self.delay} = {self.tau:g} s"),
            ("points", str(self.omega.size)),
            ("Re Z < 0 (proven)", ", ".join(f"{a:.4g}-{b:.4g}" for a, b in self.negative_bands) or "none"),
        ]  # fmt: skip
        return html_card("Delayed impedance on the axis", rows)


def _grid(z: DelayedImpedance, bands: list[Band], points: int) -> np.ndarray:
    mags: list[float] = []
    for p in (*z.num, *z.den):
        c = [safe_float(x) for x in p.coeffs()]
        if len(c) > 1 and all(math.isfinite(v) for v in c):
            mags += [abs(r) for r in np.polynomial.polynomial.polyroots(c) if abs(r) > 0]
    mags += [e for b in bands for e in b if 0 < e < math.inf]
    if z.tau:
        mags.append(1.0 / float(z.tau))
    lo, hi = (min(mags) / 100.0, max(mags) * 100.0) if mags else (0.1, 1e4)
    return np.logspace(math.log10(lo), math.log10(hi), points)


def delayed_response(
    z: DelayedImpedance, omega: Any = None, *, label: str = "", points: int = 800
) -> DelayResponse:
    """`DelayResponse` of ``z`` at its delay (grid: around its poles, zeros and ``1/τ``)."""
    f = real_part(z)
    danger: list[Band] = []
    if f.order == 1 and high_frequency(f).kind == "positive":
        danger = [(safe_float(a), safe_float(b)) for a, b in dangerous_bands(f)]
    w = _grid(z, danger, points) if omega is None else np.asarray(omega, dtype=float)
    if w.ndim != 1 or w.size < 2 or not np.all(np.isfinite(w)) or np.any(w <= 0):
        from ..errors import ParameterError

        raise ParameterError("omega: give positive finite frequencies, at least two")
    w = np.sort(w)
    tau = z.tau if z.tau is not None else fmpq(0)
    neg, und = negative_intervals(f, tau, ep.rational(float(w[0])), ep.rational(float(w[-1])))
    return DelayResponse(
        omega=w, value=evaluate(z, w), tau=safe_float(tau), delay=z.name,
        negative_bands=tuple((safe_float(a), safe_float(b)) for a, b in neg),
        undecided_bands=tuple((safe_float(a), safe_float(b)) for a, b in und),
        dangerous_bands=tuple(danger), label=label or z.label,
    )  # fmt: skip
