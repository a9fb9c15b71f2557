"""The sampled (digital) control loop as one value: period, delay, velocity filter, discretization.

A controller that runs on a computer samples ``x_A`` and ``x_L`` every ``period``
seconds, computes the command ``delay`` whole samples late, estimates velocities by
finite differences (optionally through a first-order low-pass of cut-off
``velocity_filter`` Hz) and discretizes the strictly proper parts of ``C_A`` and ``C_L``
with ``method``.  `SampledLoop` holds exactly that, checked once at construction, and
is what every sampled analysis, the twin, tuning, the export and the reports take as
``loop=``.

The one file spelling is the ``[control]`` table of design and rig files::

    [control]
    rate = 500.0             # Hz (or period = 0.002, in s; exactly one of the two)
    delay = 1                # samples, optional (0)
    velocity_filter = 50.0   # Hz, optional (absent: no filter)
    method = "tustin"        # optional: tustin, zoh or backward

Rig files written before this spelling used ``delay_samples`` and
``velocity_filter_hz`` (0 for none); they still load for one release with a
[`SeapassDeprecationWarning`][seapass.errors.SeapassDeprecationWarning]
(`rename_rig_control_keys`), as do the old keyword arguments of the public entry
points (`loop_argument`).

Examples
--------
>>> loop = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
>>> loop.rate, loop.label
(500.0, '1-sample delay + 50 Hz filter')
>>> SampledLoop.from_table(loop.to_table()) == loop
True
>>> SampledLoop(period=0.002, velocity_filter=400.0)
Traceback (most recent call last):
...
seapass.errors.ParameterError: velocity_filter: must be a positive cut-off in Hz below the Nyquist frequency 250 Hz (half the rate 1/period), got 400.0
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Literal, get_args

from ..errors import FileFormatError, ParameterError, SeapassDeprecationWarning
from ..files.limits import MAX_DELAY_SAMPLES
from .display import html_card, short_repr

__all__ = [
    "LOOP_KEYS",
    "METHODS",
    "PERIOD_RANGE",
    "LoopAttributes",
    "Method",
    "SampledLoop",
    "loop_argument",
    "rename_rig_control_keys",
    "renamed_keywords",
]

Method = Literal["tustin", "zoh", "backward"]
"""Discretization of the strictly proper controller parts (derivatives always use
backward differences)."""

METHODS: tuple[Method, ...] = get_args(Method)

PERIOD_RANGE = (1e-7, 10.0)
"""Periods (s) accepted: bounds the precision the certified sampled analysis may need."""

LOOP_KEYS = ("rate", "period", "delay", "velocity_filter", "method")
"""The keys of a ``[control]`` table that describe the loop."""

_RATE_RANGE = (1.0, 1e6)  # Hz, as a file states it


def _error(argument: str, text: str) -> ParameterError:
    return ParameterError(f"{argument}: {text}", argument=argument)


def _real(value: object) -> bool:
    return isinstance(value, int | float | Fraction) and not isinstance(value, bool)


@dataclass(frozen=True, kw_only=True, repr=False)
class SampledLoop:
    """The sampled loop a digital controller runs in, checked at construction.

    Parameters
    ----------
    period : float
        Control period ``T`` (s), in `PERIOD_RANGE`; ``0.002`` is 500 Hz.
    rate : float
        Or the sampling rate ``1/T`` (Hz) instead of ``period``; it is kept exactly as
        given (and not compared: two loops are equal when their periods are).
    delay : int, default 0
        Whole samples from sampling to applying the command, 0 to
        [`MAX_DELAY_SAMPLES`][seapass.files.limits.MAX_DELAY_SAMPLES].
    velocity_filter : float, optional
        Cut-off (Hz) of the first-order low-pass on the finite-difference velocity,
        positive and below the Nyquist frequency ``1/(2T)``; None for no filter.
    method : {"tustin", "zoh", "backward"}
        Discretization of the strictly proper controller parts.

    Raises
    ------
    ParameterError
        Naming the argument (``period``, ``rate``, ``delay``, ``velocity_filter``,
        ``method``).

    References
    ----------
    .. [1] G. F. Franklin, J. D. Powell, M. Workman, *Digital Control of Dynamic
       Systems*, 3rd ed., Addison-Wesley, 1998, ch. 6.
    """

    period: float = math.nan
    rate: float = field(default=math.nan, compare=False)
    delay: int = 0
    velocity_filter: float | None = None
    method: Method = "tustin"

    def __post_init__(self) -> None:
        p, r = self.period, self.rate
        given_p = not (isinstance(p, float) and math.isnan(p))
        given_r = not (isinstance(r, float) and math.isnan(r))
        if given_p and given_r and _real(p) and _real(r) and (p == 1 / r or r == 1 / p):
            given_p = False  # a copy (dataclasses.replace): the two agree
        if given_p == given_r:
            raise _error(
                "period",
                "give the control period in s (period=0.002) or the rate in Hz (rate=500.0)"
                + (", not both" if given_p else ""),
            )
        if given_r:
            if not (_real(r) and math.isfinite(r) and r > 0):
                raise _error("rate", f"must be a positive number of Hz, got {r!r}")
            p = 1.0 / float(r)
        elif not (_real(p) and math.isfinite(p) and p > 0):
            raise _error("period", f"must be a positive number of seconds, got {p!r}")
        lo, hi = PERIOD_RANGE
        if not lo <= p <= hi:
            if given_r:
                raise _error(
                    "rate", f"{r!r} Hz is outside the supported range [{1 / hi:g}, {1 / lo:g}] Hz"
                )
            raise _error("period", f"{p!r} s is outside the supported range [{lo:g}, {hi:g}] s")
        d = self.delay
        if not (_real(d) and math.isfinite(d) and int(d) == d and 0 <= d <= MAX_DELAY_SAMPLES):
            raise _error(
                "delay",
                f"must be a whole number of samples from 0 to {MAX_DELAY_SAMPLES}, got {d!r}",
            )
        f = self.velocity_filter
        nyquist = 0.5 / float(p)
        if f is not None and not (_real(f) and math.isfinite(f) and 0 < f < nyquist):
            raise _error(
                "velocity_filter",
                f"must be a positive cut-off in Hz below the Nyquist frequency {nyquist:g} Hz "
                f"(half the rate 1/period), got {f!r}",
            )
        if self.method not in METHODS:
            raise _error("method", f"must be one of {', '.join(METHODS)}, got {self.method!r}")
        object.__setattr__(self, "period", float(p))
        object.__setattr__(self, "rate", float(r) if given_r else 1.0 / float(p))
        object.__setattr__(self, "delay", int(d))
        object.__setattr__(self, "velocity_filter", None if f is None else float(f))

    @property
    def nyquist(self) -> float:
        """Nyquist frequency ``1/(2T)`` (Hz)."""
        return 0.5 / self.period

    @property
    def exact_period(self) -> Fraction:
        """The period as the exact decimal it was written as (``0.002`` is ``1/500``)."""
        return Fraction(repr(self.period))

    @property
    def label(self) -> str:
        """``"ideal ZOH"``, ``"1-sample delay"``, ``"1-sample delay + 50 Hz filter"``, ..."""
        text = f"{self.delay}-sample delay" if self.delay else "ideal ZOH"
        if self.velocity_filter is not None:
            text += f" + {self.velocity_filter:g} Hz filter"
        return text

    @property
    def summary(self) -> str:
        """One line: ``T = 0.002 s, delay 1 samples, velocity filter 50 Hz``."""
        filt = "none" if self.velocity_filter is None else f"{self.velocity_filter:g} Hz"
        return f"T = {self.period:g} s, delay {self.delay} samples, velocity filter {filt}"

    def replace(self, **changes: Any) -> SampledLoop:
        """A checked copy with ``changes`` (``loop.replace(delay=0)``)."""
        if "period" in changes or "rate" in changes:
            changes = {"period": math.nan, "rate": math.nan, **changes}
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """``{"period", "delay", "velocity_filter", "method"}``, JSON-ready."""
        return {
            "period": self.period,
            "delay": self.delay,
            "velocity_filter": self.velocity_filter,
            "method": self.method,
        }

    def to_table(self) -> dict[str, Any]:
        """The ``[control]`` table of a design or rig file that `from_table` reads back equal.

        The rate is written when it gives the period back exactly, else the period.
        """
        exact = 1.0 / self.rate == self.period
        out: dict[str, Any] = {"rate": self.rate} if exact else {"period": self.period}
        out["delay"] = self.delay
        if self.velocity_filter is not None:
            out["velocity_filter"] = self.velocity_filter
        if self.method != "tustin":
            out["method"] = self.method
        return out

    @classmethod
    def from_table(
        cls, table: Mapping[str, Any], *, section: str = "control", max_delay: int | None = None
    ) -> SampledLoop:
        """The loop of a ``[control]`` table (keys `LOOP_KEYS`; other keys are left alone).

        ``max_delay`` caps ``delay`` below `MAX_DELAY_SAMPLES` (the rig twin runs 0 or 1).

        Raises
        ------
        FileFormatError
            Naming the key (``control.rate``) for a missing, mistyped or out-of-range value.
        """
        if ("rate" in table) == ("period" in table):
            raise FileFormatError(
                f"give {section}.rate (the sampling rate in Hz) or {section}.period (in s), "
                "not both"
                if "rate" in table
                else f"missing {section}.rate (the sampling rate in Hz)"
            )
        kw: dict[str, Any] = {}
        if "rate" in table:
            kw["rate"] = _bounded(table["rate"], f"{section}.rate", *_RATE_RANGE, open_lo=False)
        else:
            lo, hi = 1.0 / _RATE_RANGE[1], 1.0 / _RATE_RANGE[0]
            kw["period"] = _bounded(table["period"], f"{section}.period", lo, hi, open_lo=False)
        top = MAX_DELAY_SAMPLES if max_delay is None else max_delay
        if "delay" in table:
            d = table["delay"]
            if isinstance(d, bool) or not isinstance(d, int) or not 0 <= d <= top:
                raise FileFormatError(
                    f"{section}.delay: expected an integer from 0 to {top} samples, got {d!r}"
                )
            kw["delay"] = d
        if "velocity_filter" in table:
            v = table["velocity_filter"]
            kw["velocity_filter"] = _bounded(v, f"{section}.velocity_filter", 0.0, _RATE_RANGE[1])
        if "method" in table:
            kw["method"] = table["method"]
        try:
            return cls(**kw)
        except ParameterError as exc:
            text = str(exc).split(": ", 1)[-1]
            raise FileFormatError(f"{section}.{exc.argument}: {text}") from None

    def __repr__(self) -> str:
        return short_repr(
            "SampledLoop",
            {
                "period": self.period,
                "delay": self.delay,
                "velocity_filter": self.velocity_filter,
                "method": self.method,
            },
        )

    def _repr_html_(self) -> str:
        rows = [
            ("period", f"{self.period:g} s ({self.rate:g} Hz)"),
            ("delay", f"{self.delay} samples"),
            (
                "velocity filter",
                "none" if self.velocity_filter is None else f"{self.velocity_filter:g} Hz",
            ),
            ("discretization", self.method),
        ]
        return html_card(f"Sampled loop: {self.label}", rows)


class LoopAttributes:
    """``delay`` and ``velocity_filter`` of the `SampledLoop` an object holds as ``loop``.

    A mixin for the designs, results and deployments that carry a loop, so that
    ``result.delay`` reads the loop (0 and None without one) in one place.
    """

    loop: SampledLoop | None

    @property
    def delay(self) -> int:
        """Samples of delay of the loop (0 without one)."""
        return 0 if self.loop is None else self.loop.delay

    @property
    def velocity_filter(self) -> float | None:
        """Cut-off (Hz) of the loop's velocity low-pass, or None."""
        return None if self.loop is None else self.loop.velocity_filter


def _bounded(value: Any, key: str, lo: float, hi: float, *, open_lo: bool = True) -> float:
    """A finite number in ``(lo, hi]`` (``[lo, hi]`` unless ``open_lo``), or a
    `FileFormatError` naming ``key``."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise FileFormatError(f"{key}: expected a number, got {type(value).__name__} {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise FileFormatError(f"{key}: must be finite, got {value!r}")
    if (v <= lo if open_lo else v < lo) or v > hi:
        bracket = "(" if open_lo else "["
        raise FileFormatError(f"{key}: {value!r} is out of range {bracket}{lo:g}, {hi:g}]")
    return v


# ----------------------------------------------------------------- old spellings (one release)

_OLD_KEYWORDS = {
    "period": "period",
    "delay": "delay",
    "velocity_filter": "velocity_filter",
    "method": "method",
    "delay_samples": "delay",
    "velocity_filter_hz": "velocity_filter",
}


def loop_argument(
    loop: SampledLoop | None,
    old: Mapping[str, Any],
    *,
    where: str,
    base: SampledLoop | None = None,
) -> SampledLoop:
    """``loop``, or the loop the old keyword arguments ``old`` describe (with a warning).

    The public entry points took ``period=, delay=, velocity_filter=, method=`` (the twin:
    ``delay_samples=, velocity_filter_hz=`` with 0 for no filter); they keep working for
    one release.  Missing values come from ``base`` (the rig's loop, say).

    Raises
    ------
    TypeError
        For a keyword argument that was never a loop setting.
    ParameterError
        When neither ``loop`` nor a period is given, or both spellings are.
    """
    unknown = sorted(set(old) - set(_OLD_KEYWORDS))
    if unknown:
        raise TypeError(f"{where}() got an unexpected keyword argument {unknown[0]!r}")
    given = {k: v for k, v in old.items() if v is not None or k == "velocity_filter"}
    if not given:
        chosen = loop if loop is not None else base
        if chosen is None:
            raise ParameterError(
                "loop: give the sampled loop, e.g. loop=SampledLoop(period=0.002)",
                argument="loop",
            )
        return chosen
    if loop is not None:
        raise ParameterError(
            f"loop: give loop= only; {', '.join(f'{k}=' for k in given)} is its old spelling",
            argument="loop",
        )
    kw = {_OLD_KEYWORDS[k]: v for k, v in given.items()}
    if "velocity_filter_hz" in given and not given["velocity_filter_hz"]:
        kw["velocity_filter"] = None  # the twin's old spelling: 0 meant no filter
    warnings.warn(
        f"{where}({', '.join(f'{k}=' for k in given)}) is deprecated; pass "
        f"loop=SampledLoop({', '.join(f'{k}=...' for k in dict.fromkeys(kw))})",
        SeapassDeprecationWarning,
        stacklevel=3,
    )
    return base.replace(**kw) if base is not None else SampledLoop(**kw)


def renamed_keywords(old: Mapping[str, Any], *, where: str) -> dict[str, Any]:
    """``old`` keyword arguments under their new names, with a warning for each old one.

    ``delay_samples=`` is ``delay=`` now; any other name is a `TypeError`.
    """
    unknown = sorted(set(old) - {"delay_samples"})
    if unknown:
        raise TypeError(f"{where}() got an unexpected keyword argument {unknown[0]!r}")
    if old:
        warnings.warn(
            f"{where}(delay_samples=) is deprecated; pass delay=",
            SeapassDeprecationWarning,
            stacklevel=3,
        )
    return {_OLD_KEYWORDS[k]: v for k, v in old.items()}


_OLD_RIG_KEYS = {"delay_samples": "delay", "velocity_filter_hz": "velocity_filter"}


def rename_rig_control_keys(
    table: Mapping[str, Any], *, section: str = "control"
) -> dict[str, Any]:
    """A rig file's ``[control]`` table in the one spelling (old keys renamed, with a warning).

    ``delay_samples`` is now ``delay`` and ``velocity_filter_hz`` (0 for none) is
    ``velocity_filter`` (left out for none).

    Raises
    ------
    FileFormatError
        When a key is given in both spellings.
    """
    out = dict(table)
    for old, new in _OLD_RIG_KEYS.items():
        if old not in out:
            continue
        if new in out:
            raise FileFormatError(
                f"{section}.{old}: give {section}.{new} only ({old} is its old spelling)"
            )
        value = out.pop(old)
        warnings.warn(
            f"{section}.{old} is deprecated; write {section}.{new}"
            + (" (leave it out for no filter)" if old == "velocity_filter_hz" else ""),
            SeapassDeprecationWarning,
            stacklevel=2,
        )
        if not (old == "velocity_filter_hz" and value == 0):
            out[new] = value
    return out
