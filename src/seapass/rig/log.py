"""A logged identification run of a rig: the strict CSV loader, and logs made on the twin.

A log has four columns, one row per control sample: time [s], commanded
actuator force [N], actuator position ``x_A`` [m] and load position ``x_L`` [m]
(SI units).  A header row is optional; ``#`` starts a comment line.  Rows are
uniformly sampled (the control loop's period); the command in a row acts from
that row's time (after the rig's ``control.delay``) until the next row,
as a zero-order hold.

`twin_log` makes such a log on the digital twin
([`TwinPlant`][seapass.rig.plant.TwinPlant]: friction, saturation, encoder
quantization), from a command such as `chirp_command`: the way to try
``seapass rig fit`` before logging on hardware, and the test of the fit.
`twin_step_log` logs the rig's own controller (LP or Ours) tracking a
reference step instead, the closed-loop log a bench records most easily.
"""

from __future__ import annotations

import csv
import io
import math
import os
from array import array
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import FileFormatError, ParameterError
from ..files.limits import MAX_LOG_BYTES, MAX_LOG_ROWS
from ..files.textfile import open_text_file
from ..model.display import html_card, short_repr
from .plant import TwinPlant
from .rigfile import Rig

__all__ = [
    "LOG_COLUMNS",
    "MAX_LOG_BYTES",
    "MAX_LOG_ROWS",
    "RigLog",
    "chirp_command",
    "load_log",
    "parse_log",
    "twin_log",
    "twin_step_log",
]

FloatArray = NDArray[np.float64]

LOG_COLUMNS = ("time", "force", "x_A", "x_L")
"""The columns of a log, in order: s, N, m, m."""

_JITTER = 0.01  # relative deviation of a time step from the median step that is accepted


@dataclass(frozen=True, repr=False)
class RigLog:
    """One logged run: uniformly sampled time, commanded force and the two positions.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Sample times [s], increasing with a constant step.
    force : ndarray, shape (n,)
        Commanded actuator force [N] (before the rig's saturation).
    x_A, x_L : ndarray, shape (n,)
        Actuator and load positions [m] as the encoders read them.
    source : str
        Where the log came from (a file name, or ``"twin"``).
    """

    t: FloatArray
    force: FloatArray
    x_A: FloatArray
    x_L: FloatArray
    source: str = ""

    def __post_init__(self) -> None:
        arrays = {k: np.array(getattr(self, k), dtype=float) for k in ("t", "force", "x_A", "x_L")}
        n = arrays["t"].size
        for name, arr in arrays.items():
            if arr.ndim != 1 or arr.size != n:
                raise ParameterError(f"{name}: expected shape ({n},), got {arr.shape}")
            if not np.all(np.isfinite(arr)):
                raise ParameterError(f"{name}: every value must be finite")
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)
        if n < 3:
            raise ParameterError(f"a log needs at least 3 samples, got {n}")
        step = np.diff(arrays["t"])
        h = float(np.median(step))
        if not h > 0:
            raise ParameterError("t: times must increase")
        bad = np.flatnonzero(np.abs(step - h) > _JITTER * h)
        if bad.size:
            i = int(bad[0])
            raise ParameterError(
                f"t: the log must be sampled uniformly; the step from sample {i} to {i + 1} is "
                f"{step[i]:.6g} s, the median step {h:.6g} s (resample the log first)"
            )

    @property
    def period(self) -> float:
        """The sampling period [s] (median step)."""
        return float(np.median(np.diff(self.t)))

    @property
    def size(self) -> int:
        return int(self.t.size)

    @property
    def warnings(self) -> tuple[str, ...]:
        """What looks wrong in the log without being an error: positions beyond 1 m
        (millimetres given for metres?)."""
        reach = float(max(np.abs(self.x_A).max(), np.abs(self.x_L).max()))
        if reach > 1.0:
            return (
                f"positions reach {reach:g} m; the log's positions must be in metres "
                "(millimetres given?)",
            )
        return ()

    def to_csv(self) -> str:
        """The log as CSV text with a header, readable by `parse_log`."""
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(LOG_COLUMNS)
        for row in zip(self.t, self.force, self.x_A, self.x_L, strict=True):
            w.writerow([repr(float(v)) for v in row])
        return buf.getvalue()

    def __repr__(self) -> str:
        return short_repr(
            "RigLog",
            {
                "source": self.source or None,
                "samples": self.size,
                "period": self.period,
                "duration": float(self.t[-1] - self.t[0]),
            },
        )

    def _repr_html_(self) -> str:
        return html_card(
            f"Rig log {self.source}".strip(),
            [
                ("samples", f"{self.size} at {1 / self.period:.6g} Hz"),
                ("duration", f"{self.t[-1] - self.t[0]:.6g} s"),
                ("force", f"{self.force.min():.4g} .. {self.force.max():.4g} N"),
                ("x_A", f"{self.x_A.min():.4g} .. {self.x_A.max():.4g} m"),
                ("x_L", f"{self.x_L.min():.4g} .. {self.x_L.max():.4g} m"),
            ],
        )


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def parse_log(text: str, *, source: str = "") -> RigLog:
    """A `RigLog` from CSV text (see the module docstring for the format).

    Raises
    ------
    FileFormatError
        Naming the line for a wrong number of columns, a value that is not a
        finite number, too many rows, or time that is not uniformly sampled.
    """
    return _parse_lines(io.StringIO(text), source)


def _parse_lines(lines: Iterable[str], source: str) -> RigLog:
    """`parse_log` of a stream of lines: only the numbers are kept (32 bytes a row)."""
    where = f"{source}: " if source else ""
    values = array("d")
    n_rows = 0
    header_seen = False
    width = len(LOG_COLUMNS)
    for lineno, row in enumerate(csv.reader(lines), start=1):
        if not row or not "".join(row).strip() or row[0].lstrip().startswith("#"):
            continue
        if len(row) != width:
            raise FileFormatError(
                f"{where}line {lineno}: expected {width} columns "
                f"({', '.join(LOG_COLUMNS)}), got {len(row)}"
            )
        if not n_rows and not header_seen and not all(_is_number(c) for c in row):
            header_seen = True
            continue
        try:
            numbers = [float(c) for c in row]
        except ValueError:
            bad = next(c for c in row if not _is_number(c))
            raise FileFormatError(
                f"{where}line {lineno}: {bad.strip()!r} is not a number"
            ) from None
        if not all(math.isfinite(v) for v in numbers):
            raise FileFormatError(f"{where}line {lineno}: values must be finite")
        n_rows += 1
        if n_rows > MAX_LOG_ROWS:
            raise FileFormatError(f"{where}more than {MAX_LOG_ROWS} rows; split the log")
        values.extend(numbers)
    if n_rows < 3:
        raise FileFormatError(f"{where}a log needs at least 3 rows of data, got {n_rows}")
    data = np.frombuffer(values, dtype=np.float64).reshape(n_rows, width)
    try:
        return RigLog(data[:, 0], data[:, 1], data[:, 2], data[:, 3], source=source)
    except ParameterError as exc:
        raise FileFormatError(f"{where}{exc}") from None


def load_log(path: str | os.PathLike[str]) -> RigLog:
    """Read a log CSV file (see the module docstring), as a stream of lines.

    The file is read through [`open_text_file`][seapass.files.textfile.open_text_file]:
    a FIFO, a device or a file over `MAX_LOG_BYTES` fails before the first
    byte, and memory grows with the rows kept (32 bytes each), not with the
    file's text.

    Raises
    ------
    FileFormatError
        For content `parse_log` rejects, a file over `MAX_LOG_BYTES`, one that
        is not a regular file or not UTF-8 text; the message names the file.
    OSError
        When the file cannot be read.
    """
    with open_text_file(path, max_bytes=MAX_LOG_BYTES, what="log file") as lines:
        return _parse_lines(lines, str(Path(path)))


def chirp_command(
    rate: float,
    *,
    duration: float = 8.0,
    amplitude: float = 60.0,
    f_start: float = 5.0,
    f_stop: float = 25.0,
    ramp: float = 0.2,
) -> FloatArray:
    """A linear chirp of force, one value per control sample, faded in and out over ``ramp`` s.

    Parameters
    ----------
    rate : float
        Control rate [Hz].
    duration : float
        Length [s].
    amplitude : float
        Peak force [N].
    f_start, f_stop : float
        Start and stop frequency [Hz].

    Returns
    -------
    ndarray, shape (round(duration * rate),)
    """
    for name, v in (("rate", rate), ("duration", duration), ("amplitude", amplitude)):
        if not (math.isfinite(v) and v > 0):
            raise ParameterError(f"{name} must be positive and finite, got {v!r}")
    if not (0 < f_start < f_stop < rate / 2):
        raise ParameterError(
            f"need 0 < f_start < f_stop < rate/2 = {rate / 2:g} Hz, got {f_start!r}, {f_stop!r}"
        )
    t = np.arange(round(duration * rate)) / rate
    phase = 2 * np.pi * (f_start * t + 0.5 * (f_stop - f_start) / duration * t**2)
    fade = np.clip(np.minimum(t, duration - t) / ramp, 0.0, 1.0) if ramp > 0 else 1.0
    return np.asarray(amplitude * fade * np.sin(phase), dtype=float)


def twin_log(
    rig: Rig,
    command: ArrayLike,
    *,
    load_mass: float,
    seed: int | None = None,
    **plant: Any,
) -> RigLog:
    """Run ``command`` open loop on the twin of ``rig`` and log it like the bench would.

    Row ``k`` holds the time ``k·T``, ``command[k]`` and the encoder readings at
    that time; ``command[k]`` acts ``rig.control.delay`` later, held
    for one period and saturated at the rig's force limit.

    Parameters
    ----------
    rig : Rig
    command : array_like, shape (n,)
        Commanded force per control sample [N].
    load_mass : float
        Mass attached to the output carriage [kg].
    seed : int or None
        Encoder phase offsets (see [`TwinPlant`][seapass.rig.plant.TwinPlant]).
    **plant
        ``friction``, ``quantize``, ``saturate`` switches of the plant.
    """
    u = np.asarray(command, dtype=float)
    if u.ndim != 1 or u.size < 3 or not np.all(np.isfinite(u)):
        raise ParameterError("command must be a 1-D array of at least 3 finite forces")
    twin = TwinPlant(rig, load_mass=load_mass, seed=seed, **plant)
    twin.reset()
    period, delay = rig.period, rig.control.delay
    xa, xl = np.empty(u.size), np.empty(u.size)
    for k in range(u.size):
        xa[k], xl[k] = twin.measured_positions()
        twin.apply(u[k - delay] if k >= delay else 0.0, period)
    t = np.arange(u.size, dtype=float) * period
    return RigLog(t, u, xa, xl, source="twin")


def twin_step_log(
    rig: Rig,
    *,
    design: str,
    kd: float,
    step: float,
    load_mass: float,
    duration: float = 1.0,
    bd: float | None = None,
    seed: int | None = None,
    **plant: Any,
) -> RigLog:
    """Log the twin of ``rig`` tracking a reference step under one of its controllers.

    The loop is [`simulate_loop`][seapass.rig.twin.simulate_loop]: the rig
    starts at rest at 0 and the reference jumps to ``step`` at ``t = 0``.  Row
    ``k`` holds the time ``k·T``, the controller's output at that sample (before
    the rig's delay and saturation, as `twin_log` and the fit expect) and the
    encoder readings the controller used.

    Parameters
    ----------
    rig : Rig
    design : {"LP", "ours"}
        Load-side P (``C_L = kd``) or Ours' actuator-side PD (``C_A = kd + bd s``).
    kd : float
        Proportional gain [N/m].
    step : float
        Reference step [m].
    load_mass : float
        Mass attached to the output carriage [kg].
    duration : float, default 1.0
        Length of the log [s].
    bd : float, optional
        Ours' derivative gain [N·s/m] (default: ``rig.experiment.bd_ours``).
    seed : int or None
        Encoder phase offsets (see [`TwinPlant`][seapass.rig.plant.TwinPlant]).
    **plant
        ``friction``, ``quantize``, ``saturate`` switches of the plant.

    Examples
    --------
    >>> from seapass.rig.rigfile import paper_rig
    >>> log = twin_step_log(paper_rig(), design="ours", kd=1000.0, step=0.02,
    ...                     load_mass=0.1, duration=0.1)
    >>> log.size, float(log.force[0])
    (50, 20.0)
    """
    from .predictions import controller_gains
    from .twin import simulate_loop

    if not (math.isfinite(step) and step != 0):
        raise ParameterError(f"step must be a non-zero distance, got {step!r}")
    bdv = rig.experiment.bd_ours if bd is None else float(bd)
    res = simulate_loop(
        rig, load_mass=load_mass, duration=duration, reference=step, seed=seed,
        **controller_gains(design, kd, bdv), **plant,
    )  # fmt: skip
    n = res.command.shape[1]
    return RigLog(res.t[:n], res.command[0], res.x_A_measured[0, :n], res.x_L_measured[0, :n],
                  source="twin")  # fmt: skip
