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
from typing import Any

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
_SLICE = 1 << 20  # fine-grid points evaluated at once (bounds memory on long logs)


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
    return np.asarray(_velocity_spline(t, x)(fine))


def _velocity_spline(t: FloatArray, x: FloatArray) -> Any:
    from scipy.interpolate import CubicSpline
    from scipy.signal import butter, filtfilt

    if x.size > 27:  # filtfilt's default padding needs 3 × (order + 1) × 2 + 1 samples
        b, a = butter(4, 0.3)
        x = filtfilt(b, a, x)
    return CubicSpline(t, x).derivative()


class _FineGrid:
    """``np.linspace(t0, t1, size)``, evaluated only where asked (no array of ``size`` floats)."""

    def __init__(self, t0: float, t1: float, size: int) -> None:
        self.start, self.stop, self.size = float(t0), float(t1), int(size)
        self.step = (self.stop - self.start) / (self.size - 1)

    def at(self, k: NDArray[np.int64]) -> FloatArray:
        """Points ``k`` of the grid, as linspace computes them (``k·step + t0``, exact end)."""
        y = k.astype(np.float64) * self.step
        y += self.start
        y[k == self.size - 1] = self.stop
        return y


def _velocity_sign(t: FloatArray, x: FloatArray, fine: _FineGrid) -> NDArray[np.int8]:
    """``sign(smoothed_velocity(t, x, fine))`` as int8, evaluated in slices (bounded memory)."""
    spline = _velocity_spline(t, x)
    out = np.empty(fine.size, dtype=np.int8)
    for i in range(0, fine.size, _SLICE):
        out[i : i + _SLICE] = np.sign(spline(fine.at(np.arange(i, min(i + _SLICE, fine.size)))))
    return out


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
    rev = np.zeros(reversal.size + 1, dtype=np.int32 if reversal.size < 2**31 else np.int64)
    np.cumsum(reversal, out=rev[1:])
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

    Memory: of the fine grid (``8 n`` points) only the two velocity signs are
    kept (int8); the grid's points and the positions are computed only where
    the windows being integrated need them.
    """
    from scipy.interpolate import CubicSpline

    t, up = log.t, _UPSAMPLE
    force = applied_force(log, rig, delay)
    delta = log.x_L - log.x_A
    fine = _FineGrid(t[0], t[-1], (t.size - 1) * up + 1)
    signs = {"sgn_A": _velocity_sign(t, log.x_A, fine), "sgn_delta": _velocity_sign(t, delta, fine)}
    signals = _Signals(
        fine, {"x_A": CubicSpline(t, log.x_A), "delta": CubicSpline(t, delta)}, signs
    )
    reversal = np.zeros(fine.size, dtype=bool)
    for sgn in signals.signs.values():
        reversal[1:] |= sgn[1:] != sgn[:-1]
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


class _Signals:
    """The fine-grid signals: splines evaluated where asked, velocity signs stored (int8)."""

    def __init__(self, fine: _FineGrid, splines: dict[str, Any], signs: dict[str, Any]) -> None:
        self.fine, self.splines, self.signs = fine, splines, signs

    def __getitem__(self, key: str) -> _Signal:
        return _Signal(self, key)


class _Signal:
    def __init__(self, signals: _Signals, key: str) -> None:
        self.signals, self.key = signals, key

    def __getitem__(self, idx: NDArray[np.int64]) -> Any:
        s = self.signals
        if self.key in s.signs:
            return s.signs[self.key][idx]
        return s.splines[self.key](s.fine.at(idx))


def _window_rows(
    starts: NDArray[np.int64],
    length: int,
    h: float,
    force: FloatArray,
    signals: _Signals,
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

    values: dict[str, Any] = {}  # each signal evaluated once per chunk

    def moment(w: FloatArray, key: str) -> FloatArray:
        if key not in values:
            values[key] = signals[key][idx]
        return np.asarray(simpson(w[None, :] * values[key], x=tau, axis=1))

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
