"""Modulating-function moments of a logged run, the data of [`seapass.rig.identify`][seapass.rig.identify].

The applied force (the command after the rig's delay, held and saturated),
samples where an encoder stops counting, velocity signs from a zero-phase
smoothed spline, windows packed greedily where Coulomb's law is exact, and the
integrals over each window of the equation of motion times
``φ = sin²(π τ/T)``, with every derivative moved onto ``φ``.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import ParameterError
from .log import RigLog
from .rigfile import Rig

__all__ = [
    "Moments",
    "applied_force",
    "log_moments",
    "pack_windows",
    "smoothed_velocity",
    "stuck_samples",
    "window_lengths",
]

FloatArray = NDArray[np.float64]

_UPSAMPLE = 8  # fine-grid points per sample for the moment integrals
_STUCK_RUN = 3  # samples without an encoder count: stuck (or too slow to model)
_MAX_CHUNK = 20_000  # windows integrated at once (bounds memory on long logs)
_CENTRAL = 0.75  # no velocity reversal in this central part of a window (where φ > 0.15)


def applied_force(log: RigLog, rig: Rig, delay: int | None = None) -> FloatArray:
    """The force acting in each sample period: the command ``delay`` samples earlier, saturated."""
    d = rig.control.delay if delay is None else int(delay)
    if not 0 <= d < log.size:
        raise ParameterError(f"delay must be between 0 and the log length, got {delay}")
    shifted = np.concatenate([np.zeros(d), log.force[: log.size - d]])
    return np.asarray(np.clip(shifted, -rig.force_limit, rig.force_limit), dtype=float)


def stuck_samples(x: FloatArray, resolution: float, run: int = _STUCK_RUN) -> NDArray[np.bool_]:
    """Samples in a run of at least ``run`` samples over which ``x`` does not move a count.

    A body that sticks (or crawls slower than a count per ``run − 1`` samples)
    shows as an encoder that stops counting; its friction force is unknown
    there.  Axis: sample.
    """
    still = np.abs(np.diff(x)) <= 0.5 * resolution  # step i -> i + 1
    flags = np.zeros(x.size, dtype=bool)
    if not still.any():
        return flags
    edges = np.diff(np.concatenate([[0], still.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # steps [s, e)
    for s, e in zip(starts, ends, strict=True):
        if e - s + 1 >= run:
            flags[max(s - 1, 0) : e + 2] = True
    return flags


def smoothed_velocity(t: FloatArray, x: FloatArray, fine: FloatArray) -> FloatArray:
    """Velocity on the fine grid from a zero-phase low-pass (0.3 × Nyquist) and a spline."""
    from scipy.interpolate import CubicSpline
    from scipy.signal import butter, filtfilt

    if x.size > 27:  # filtfilt's default padding needs 3 × (order + 1) × 2 + 1 samples
        b, a = butter(4, 0.3)
        x = filtfilt(b, a, x)
    return np.asarray(CubicSpline(t, x).derivative()(fine))


def window_lengths(length: int) -> tuple[int, ...]:
    """The window lengths tried, longest first: ``length``, ¾ and ½ of it (at least 4 samples)."""
    return tuple(sorted({max(4, round(length * f)) for f in (1.0, 0.75, 0.5)}, reverse=True))


def pack_windows(
    reversal: NDArray[np.bool_], stuck: NDArray[np.bool_], lengths: Sequence[int], up: int
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Greedy non-overlapping windows: their start indices and lengths (samples).

    At each start the longest of ``lengths`` is taken whose samples are not
    stuck and in whose central three quarters no velocity reverses
    (fine-grid flags ``reversal``, ``up`` points per sample); when none fits
    the start moves on by one sample.  A reversal is where a body may stick
    for a moment, and there Coulomb's law is not exact; near the window's ends
    ``φ`` is small enough to make that harmless.  Shorter windows let faster
    parts of a chirp count.
    """
    n = stuck.size
    rev = np.concatenate([[0], np.cumsum(reversal)])
    stk = np.concatenate([[0], np.cumsum(stuck)])
    bounds = [
        (length, int(length * up * (0.5 - _CENTRAL / 2)), int(length * up * (0.5 + _CENTRAL / 2)))
        for length in lengths
    ]
    starts, sizes = [], []
    s = 0
    while s + min(lengths) < n:
        f = s * up
        for length, lo, hi in bounds:
            if s + length < n and rev[f + hi + 1] == rev[f + lo] and stk[s + length + 1] == stk[s]:
                starts.append(s)
                sizes.append(length)
                s += length
                break
        else:
            s += 1
    return np.asarray(starts, dtype=np.int64), np.asarray(sizes, dtype=np.int64)


@dataclass(frozen=True, kw_only=True)
class Moments:
    """Window moments divided by ``∫φ`` (so in newtons): one row per window.

    ``X`` (w, 6) holds the regressors of ``m, b, F_cA, b1, F_c1, c``, ``y`` (w,)
    the response ``F + k1 δ``, ``force`` and ``spring`` its two parts, ``centre``
    the window centres [s] and ``length`` the window lengths [samples].
    """

    X: FloatArray
    y: FloatArray
    centre: FloatArray
    force: FloatArray
    spring: FloatArray
    length: NDArray[np.int64]


def log_moments(log: RigLog, rig: Rig, length: int, *, delay: int | None = None) -> Moments:
    """The modulating-function moments of ``log`` over greedily packed windows.

    Windows are ``length`` samples long, or ¾ or ½ of it where the motion
    reverses too often (`pack_windows`).  Row ``i`` of ``X`` holds, for window
    ``i``, the moments of the regressors of ``m, b, F_cA, b1, F_c1, c`` (see
    [`seapass.rig.identify`][seapass.rig.identify]) and ``y`` the moment of
    ``F + k1 δ``, each divided by ``∫φ``.  Axis 0: window, in time order.
    """
    from scipy.interpolate import CubicSpline

    t, up = log.t, _UPSAMPLE
    force = applied_force(log, rig, delay)
    delta = log.x_L - log.x_A
    fine = np.linspace(t[0], t[-1], (t.size - 1) * up + 1)
    signals = {
        "x_A": CubicSpline(t, log.x_A)(fine),
        "delta": CubicSpline(t, delta)(fine),
        "sgn_A": np.sign(smoothed_velocity(t, log.x_A, fine)),
        "sgn_delta": np.sign(smoothed_velocity(t, delta, fine)),
    }
    reversal = np.zeros(fine.size, dtype=bool)
    for key in ("sgn_A", "sgn_delta"):
        reversal[1:] |= signals[key][1:] != signals[key][:-1]
    stuck = stuck_samples(log.x_A, rig.motor_resolution) | stuck_samples(
        delta, rig.linear_resolution
    )
    starts, sizes = pack_windows(reversal, stuck, window_lengths(length), up)
    rows = np.zeros((starts.size, 8))
    for size in np.unique(sizes):
        pick = np.flatnonzero(sizes == size)
        for chunk in _chunks(pick):
            rows[chunk] = _window_rows(starts[chunk], int(size), log.period, force, signals, rig)
    return Moments(
        X=rows[:, :6],
        y=rows[:, 6] + rows[:, 7],
        centre=t[starts] + sizes * log.period / 2 if starts.size else np.zeros(0),
        force=rows[:, 6],
        spring=rows[:, 7],
        length=sizes,
    )


def _window_rows(
    starts: NDArray[np.int64],
    length: int,
    h: float,
    force: FloatArray,
    signals: dict[str, FloatArray],
    rig: Rig,
) -> FloatArray:
    """Rows ``[X (6), ∫φF, k1∫φδ] / ∫φ`` for windows of one length; axis 0: window."""
    from scipy.integrate import simpson

    up = _UPSAMPLE
    T = length * h
    tau = np.arange(length * up + 1) * (h / up)
    phi = np.sin(np.pi * tau / T) ** 2
    d1 = (np.pi / T) * np.sin(2 * np.pi * tau / T)
    d2 = 2 * (np.pi / T) ** 2 * np.cos(2 * np.pi * tau / T)
    # exact ∫φ over each sample period, for the zero-order-held force
    edges = np.arange(length + 1) * h
    hold = np.diff(edges / 2 - T / (4 * np.pi) * np.sin(2 * np.pi * edges / T))
    idx = starts[:, None] * up + np.arange(tau.size)[None, :]

    def moment(w: FloatArray, key: str) -> FloatArray:
        return np.asarray(simpson(w[None, :] * signals[key][idx], x=tau, axis=1))

    cols = np.column_stack(
        [
            moment(d2, "x_A"),
            -moment(d1, "x_A"),
            moment(phi, "sgn_A"),
            moment(d1, "delta"),
            -moment(phi, "sgn_delta"),
            np.full(starts.size, T / 2),
            force[starts[:, None] + np.arange(length)[None, :]] @ hold,
            rig.damper.k1 * moment(phi, "delta"),
        ]
    )
    return np.asarray(cols / (T / 2))


def _chunks(index: NDArray[np.int64]) -> Iterator[NDArray[np.int64]]:
    for i in range(0, index.size, _MAX_CHUNK):
        yield index[i : i + _MAX_CHUNK]
