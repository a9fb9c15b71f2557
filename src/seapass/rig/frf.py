"""Fitting ``m, b, b1`` of a rig to a measured frequency response (``seapass rig fit --frf``).

Some benches measure a frequency response rather than keep a time log: the
responses ``H_A = X_A/F`` and ``H_L = X_L/F`` of the actuator and load
positions to the commanded force, at a list of frequencies.  The actuator's
equation (the linear part of [`seapass.rig.identify`][seapass.rig.identify]'s)
holds at each frequency,

``G(jω) = (m s² + b s) H_A − (k1 + b1 s)(H_L − H_A)``,  ``s = jω``,

where ``G`` is the zero-order hold and the rig's ``control.delay`` samples of
delay between the command and the force, and ``k1`` comes from the rig file.  It
is linear in ``m, b, b1``; its real and imaginary parts are fitted by least
squares, with Student-t intervals.  The intervals treat the misfit as an
error of the force equation; noise on the measured response itself also biases the
estimates (errors in variables: 1 % noise moved ``b`` by 3 % in the tests).  Coulomb friction does not show in a linear
frequency response and is not fitted (the rig file's levels are kept).

The file is CSV: frequency [Hz], ``|x_A/F|`` [m/N], phase of ``x_A/F`` [deg],
``|x_L/F|`` [m/N], phase of ``x_L/F`` [deg]; a header row is optional, ``#``
starts a comment line.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError, ParameterError
from ..files.limits import MAX_FREQUENCY_POINTS, MAX_TEXT_FILE_BYTES
from ..files.textfile import read_text_file
from ..model.display import html_card, short_repr
from .identify import FitParameter
from .intervals import fit_intervals
from .rigfile import Rig

__all__ = ["FRF_COLUMNS", "FrequencyResponseFit", "MeasuredResponse", "fit_frf", "load_frf"]

FRF_COLUMNS = ("frequency", "xa_magnitude", "xa_phase", "xl_magnitude", "xl_phase")
"""The columns of a measured frequency response: Hz, m/N, deg, m/N, deg."""

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, kw_only=True, repr=False)
class MeasuredResponse:
    """``x_A/F`` and ``x_L/F`` at a list of frequencies (complex, m/N)."""

    frequency: FloatArray
    xa: NDArray[np.complex128]
    xl: NDArray[np.complex128]
    source: str = ""

    @classmethod
    def from_polar(cls, rows: FloatArray, source: str = "") -> MeasuredResponse:
        f, ma, pa, ml, pl = (rows[:, i] for i in range(5))
        return cls(
            frequency=f,
            xa=np.asarray(ma * np.exp(1j * np.radians(pa)), dtype=np.complex128),
            xl=np.asarray(ml * np.exp(1j * np.radians(pl)), dtype=np.complex128),
            source=source,
        )

    def __repr__(self) -> str:
        return short_repr(
            "MeasuredResponse", {"source": self.source, "points": self.frequency.size}
        )


def _number(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def load_frf(path: str | os.PathLike[str]) -> MeasuredResponse:
    """Read a measured frequency response (see the module docstring for the columns).

    Raises
    ------
    FileFormatError
        Naming the line: a row without five numbers, a non-finite or non-positive
        frequency or magnitude, frequencies not increasing, fewer than 3 rows or
        more than ``MAX_FREQUENCY_POINTS``.
    """
    text = read_text_file(path, max_bytes=MAX_TEXT_FILE_BYTES, what="frequency-response file")
    name = str(Path(path))
    rows: list[list[float]] = []
    for i, line in enumerate(text.splitlines(), start=1):
        cells = [c.strip() for c in line.split(",")]
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        values = [_number(c) for c in cells]
        if not rows and any(v is None for v in values):
            continue  # a header row
        if len(values) != 5 or any(v is None or not math.isfinite(v) for v in values):
            raise FileFormatError(
                f"{name}, line {i}: expected 5 numbers ({', '.join(FRF_COLUMNS)}), got {line!r}"
            )
        row = [float(v) for v in values if v is not None]
        if row[0] <= 0 or row[1] <= 0 or row[3] <= 0:
            raise FileFormatError(f"{name}, line {i}: frequency and magnitudes must be positive")
        if rows and row[0] <= rows[-1][0]:
            raise FileFormatError(f"{name}, line {i}: frequencies must increase")
        rows.append(row)
        if len(rows) > MAX_FREQUENCY_POINTS:
            raise FileFormatError(f"{name}: more than {MAX_FREQUENCY_POINTS} frequencies")
    if len(rows) < 3:
        raise FileFormatError(f"{name}: need at least 3 frequencies, got {len(rows)}")
    return MeasuredResponse.from_polar(np.array(rows, dtype=float), source=name)


@dataclass(frozen=True, kw_only=True, repr=False)
class FrequencyResponseFit:
    """``m, b, b1`` fitted to a measured frequency response, with intervals.

    Attributes
    ----------
    parameters : tuple of FitParameter
        ``m``, ``b``, ``b1``.
    residual_std : float
        Standard deviation of the equation's residual (dimensionless: the force
        transfer ``G`` is 1 in magnitude).
    confidence : float
    rig : Rig
        The rig file's rig (``k1``, rate and delay were taken from it).
    source : str
    dof : int or None
        Degrees of freedom of the Student-t intervals.
    """

    parameters: tuple[FitParameter, ...]
    residual_std: float
    confidence: float
    rig: Rig
    source: str = ""
    dof: int | None = None

    def __getitem__(self, name: str) -> FitParameter:
        for p in self.parameters:
            if p.name == name:
                return p
        raise KeyError(name)

    def updated_rig(self) -> Rig:
        """The rig with the fitted ``m`` (as ``transmission.carriage_mass``), ``b`` and ``b1``."""
        rig = self.rig
        carriage = self["m"].value - (rig.actuator_mass - rig.transmission.carriage_mass)
        if carriage < 0:
            raise ParameterError(
                f"the fitted mass m = {self['m'].value:.6g} kg is below the rotor inertia the "
                "rig file reflects to the carriage"
            )
        note = f"m, b, b1 fitted from the frequency response {Path(self.source).name or ''}"
        return rig.replace(
            transmission={"carriage_mass": carriage, "viscous": self["b"].value},
            damper={"b1": self["b1"].value},
            description=f"{rig.description} ({note.strip()})" if rig.description else note,
            intervals=fit_intervals(
                self.parameters, confidence=self.confidence, dof=self.dof,
                source=Path(self.source).name,
            ).to_table(),
        )  # fmt: skip

    def to_dict(self) -> dict[str, Any]:
        return {
            "source": self.source,
            "kind": "frequency_response",
            "confidence": self.confidence,
            "k1": self.rig.damper.k1,
            "parameters": {p.name: p.to_dict() for p in self.parameters},
            "residual_std": self.residual_std,
        }

    def __repr__(self) -> str:
        return short_repr(
            "FrequencyResponseFit", {p.name: round(p.value, 6) for p in self.parameters}
        )

    def _repr_html_(self) -> str:
        rows = [(p.name, f"{p.value:.6g} ± {p.stderr:.2g} {p.unit}") for p in self.parameters]
        return html_card(f"Frequency-response fit {self.source}".strip(), rows)


_UNITS = {"m": ("kg", "actuator mass"), "b": ("N·s/m", "actuator damping"),
          "b1": ("N·s/m", "transmission damper")}  # fmt: skip


def fit_frf(
    response: MeasuredResponse,
    rig: Rig,
    *,
    delay: int | None = None,
    confidence: float = 0.95,
) -> FrequencyResponseFit:
    """Fit ``m, b, b1`` to ``response`` (``k1``, rate and delay from ``rig``).

    Parameters
    ----------
    response : MeasuredResponse
    rig : Rig
    delay : int, optional
        Samples between a command and its force (default: ``rig.control.delay``).
    confidence : float, default 0.95
        Level of the Student-t intervals.

    Returns
    -------
    FrequencyResponseFit

    Raises
    ------
    ParameterError
        For a confidence outside (0, 1), a negative delay, or frequencies at or
        above the rig's Nyquist frequency.
    """
    from scipy import stats

    if not 0 < confidence < 1:
        raise ParameterError(
            f"confidence must be in (0, 1), got {confidence!r}", argument="confidence"
        )
    d = rig.control.delay if delay is None else delay
    if isinstance(d, bool) or not isinstance(d, int) or d < 0:
        raise ParameterError(f"delay must be an integer >= 0, got {d!r}", argument="delay")
    T = rig.period
    f = np.asarray(response.frequency, dtype=float)
    if f.max() >= 0.5 / T:
        raise ParameterError(
            f"the response reaches {f.max():g} Hz, at or above the rig's Nyquist frequency "
            f"{0.5 / T:g} Hz",
            argument="response",
        )
    s = 2j * np.pi * f
    hold = np.exp(-s * d * T) * (1 - np.exp(-s * T)) / (s * T)
    ha, dl = response.xa, response.xl - response.xa
    k1 = rig.damper.k1
    cols = np.stack([s**2 * ha, s * ha, -s * dl], axis=1)
    rhs = hold + k1 * dl
    X = np.concatenate([cols.real, cols.imag])
    y = np.concatenate([rhs.real, rhs.imag])
    scale = np.linalg.norm(X, axis=0)
    beta, *_ = np.linalg.lstsq(X / scale, y, rcond=None)
    beta = beta / scale
    resid = y - X @ beta
    dof = max(1, y.size - 3)
    sigma2 = float(resid @ resid) / dof
    cov = sigma2 * np.linalg.pinv(X.T @ X)
    stderr = np.sqrt(np.clip(np.diag(cov), 0, None))
    q = float(stats.t.ppf(0.5 + confidence / 2, dof))
    params = tuple(
        FitParameter(
            name=n,
            value=float(v),
            stderr=float(e),
            low=float(v - q * e),
            high=float(v + q * e),
            unit=_UNITS[n][0],
            description=_UNITS[n][1],
        )
        for n, v, e in zip(("m", "b", "b1"), beta, stderr, strict=True)
    )
    return FrequencyResponseFit(
        parameters=params,
        residual_std=math.sqrt(sigma2),
        confidence=confidence,
        rig=rig,
        source=response.source,
        dof=dof,
    )
