"""The command to play on a bench to identify it: a chirp of force, one row per control sample.

``seapass rig chirp --rig FILE --out command.csv`` writes it; the bench plays
``force`` at ``time`` (the rig's control rate), logs time, commanded force,
``x_A`` and ``x_L`` at the same rate, and ``seapass rig fit LOG.csv --rig FILE``
fits the actuator to that log ([`seapass.rig.identify`][seapass.rig.identify]).
The samples are `chirp_command`'s; this module adds the checks against the rig
(the force limit, the Nyquist frequency, the size a log may have) and the file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ParameterError
from ..files.limits import MAX_LOG_ROWS
from ..model.display import html_card, short_repr
from .log import chirp_command
from .rigfile import Rig

__all__ = ["DEFAULT_BAND", "ChirpPlan", "chirp_plan"]

DEFAULT_BAND = (5.0, 25.0)
"""Hz: the band of `chirp_command`, around the paper bench's actuator resonance."""

_DEFAULT_AMPLITUDE = 60.0  # N, chirp_command's default, capped at half the rig's force limit


@dataclass(frozen=True, kw_only=True, repr=False)
class ChirpPlan:
    """A chirp of force to play on a bench, sample by sample.

    Attributes
    ----------
    rig_name : str
    rate : float
        Control (and logging) rate [Hz]; one sample per period.
    amplitude : float
        Peak force [N].
    band : (float, float)
        Start and stop frequency [Hz] of the linear sweep.
    duration : float
        Length [s].
    ramp : float
        Fade in and out [s].
    force : ndarray, shape (n,)
        The commanded force per sample [N].
    """

    rig_name: str
    rate: float
    amplitude: float
    band: tuple[float, float]
    duration: float
    ramp: float
    force: NDArray[np.float64]

    @property
    def time(self) -> NDArray[np.float64]:
        """Sample times [s], ``k / rate``."""
        return np.arange(self.force.size, dtype=float) / self.rate

    def header(self) -> list[str]:
        """The comment lines at the top of the file: what to play and how to log it."""
        lo, hi = self.band
        return [
            f"seapass rig chirp for {self.rig_name or 'a rig'}: play `force` at `time`, one row "
            f"per control sample ({self.rate:g} Hz)",
            f"amplitude {self.amplitude:g} N, band {lo:g}-{hi:g} Hz, duration {self.duration:g} s "
            f"({self.force.size} samples), faded in and out over {self.ramp:g} s",
            "keep the load free to move; log time [s], commanded force [N], x_A [m], x_L [m] "
            "at the same rate",
            "then: seapass rig fit LOG.csv --rig RIG.toml",
        ]

    def to_csv(self) -> str:
        """``# `` comment lines (`header`), then ``time,force`` rows (s, N), exact float text."""
        lines = [f"# {h}" for h in self.header()] + ["time,force"]
        lines += [
            f"{t!r},{f!r}" for t, f in zip(self.time.tolist(), self.force.tolist(), strict=True)
        ]
        return "\n".join(lines) + "\n"

    def to_dict(self) -> dict[str, Any]:
        """The plan without the samples (`to_csv` has them)."""
        return {
            "rig": self.rig_name,
            "rate_hz": self.rate,
            "amplitude_n": self.amplitude,
            "band_hz": list(self.band),
            "duration_s": self.duration,
            "ramp_s": self.ramp,
            "samples": int(self.force.size),
            "peak_force_n": float(np.max(np.abs(self.force))) if self.force.size else 0.0,
        }

    def plot(self, *, ax: Any = None) -> Any:
        """The commanded force against time; returns the Axes."""
        from ..plot.rig import plot_chirp

        return plot_chirp(self, ax=ax)

    def __repr__(self) -> str:
        return short_repr(
            "ChirpPlan",
            {
                "rig": self.rig_name or None,
                "rate": self.rate,
                "amplitude": self.amplitude,
                "band": list(self.band),
                "samples": int(self.force.size),
            },
        )

    def _repr_html_(self) -> str:
        return html_card(f"Chirp for {self.rig_name}".strip(), list(self.to_dict().items()))


def chirp_plan(
    rig: Rig,
    *,
    amplitude: float | None = None,
    band: tuple[float, float] = DEFAULT_BAND,
    duration: float = 8.0,
    rate: float | None = None,
    ramp: float | None = None,
) -> ChirpPlan:
    """The chirp of force to play on ``rig`` to identify it with ``seapass rig fit``.

    Parameters
    ----------
    rig : Rig
    amplitude : float, optional
        Peak force [N]; default 60 N, at most half the rig's force limit.  It
        must not exceed the force limit (a saturated command biases the fit).
    band : (float, float), default DEFAULT_BAND
        Start and stop frequency [Hz], ``0 < lo < hi < rate / 2``.
    duration : float, default 8
        Length [s]; at most ``MAX_LOG_ROWS`` samples, so that the log fits.
    rate : float, optional
        Samples per second [Hz]; default the rig's ``control.rate``.
    ramp : float, optional
        Fade in and out [s], at most half the duration; default 0.2 s, at most
        a quarter of the duration.

    Returns
    -------
    ChirpPlan

    Raises
    ------
    ParameterError
        Naming the argument that is out of range.

    Examples
    --------
    >>> from seapass.rig.rigfile import paper_rig
    >>> plan = chirp_plan(paper_rig())
    >>> plan.force.size, plan.amplitude, float(abs(plan.force).max()) <= 60
    (4000, 60.0, True)
    """
    rate = float(rig.control.rate if rate is None else rate)
    limit = rig.force_limit
    amp = min(_DEFAULT_AMPLITUDE, 0.5 * limit) if amplitude is None else float(amplitude)
    for name, value in (("rate", rate), ("amplitude", amp), ("duration", duration)):
        if not (math.isfinite(value) and value > 0):
            raise ParameterError(f"{name} must be positive and finite, got {name}={value!r}",
                                 argument=name)  # fmt: skip
    if amp > limit:
        raise ParameterError(
            f"amplitude={amp:g} N exceeds the rig's force limit {limit:.6g} N (the command "
            "would saturate and bias the fit); give a smaller amplitude",
            argument="amplitude",
        )
    lo, hi = (float(band[0]), float(band[1]))
    if not (0 < lo < hi < rate / 2):
        raise ParameterError(
            f"band must satisfy 0 < lo < hi < rate/2 = {rate / 2:g} Hz, got band={lo:g}:{hi:g}",
            argument="band",
        )
    samples = round(duration * rate)
    if not 3 <= samples <= MAX_LOG_ROWS:
        raise ParameterError(
            f"duration={duration:g} s at {rate:g} Hz gives {samples} samples; a log holds "
            f"3 to {MAX_LOG_ROWS}",
            argument="duration",
        )
    if ramp is None:
        ramp = min(0.2, duration / 4)
    if not (math.isfinite(ramp) and 0 <= ramp <= duration / 2):
        raise ParameterError(f"ramp must be in [0, duration/2], got ramp={ramp!r}", argument="ramp")
    force = chirp_command(rate, duration=duration, amplitude=amp, f_start=lo, f_stop=hi, ramp=ramp)
    return ChirpPlan(
        rig_name=rig.name,
        rate=rate,
        amplitude=amp,
        band=(lo, hi),
        duration=float(duration),
        ramp=float(ramp),
        force=force,
    )
