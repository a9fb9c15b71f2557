"""A box of uncertain parameters: ``{"m": (0.9, 1.1), ...}``, checked before any work.

Every uncertain parameter is an interval ``[LO, HI]`` instead of a value; a robust
verdict holds "for every value in the box".  `uncertain_box` checks the box once,
where it enters seapass:

* every name is a parameter of the model;
* ``LO <= HI``, both finite;
* physical plant values: the actuator mass ``m`` is positive, the spring
  stiffnesses ``k1, k2`` and the dampings ``b, b1, b2`` are not negative;
* bounded work: at most `MAX_UNCERTAIN` parameters, ``|LO|, |HI| <=``
  `MAX_UNCERTAIN_MAGNITUDE`, and ``HI/LO <=`` `MAX_UNCERTAIN_RATIO` for a
  parameter that must be positive.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from types import MappingProxyType
from typing import Any, Protocol

from ..errors import DelayError, ParameterError, did_you_mean
from ..files.limits import MAX_UNCERTAIN, MAX_UNCERTAIN_MAGNITUDE, MAX_UNCERTAIN_RATIO
from ..model.delayatom import model_delays
from ..model.expr import parse_value, to_fraction
from ..model.sea import SEA, Impedance

__all__ = [
    "NONNEGATIVE",
    "POSITIVE",
    "Parametrized",
    "UncertainBox",
    "parse_uncertain",
    "uncertain_box",
]


class Parametrized(Protocol):
    """Anything with named parameters (a `seapass.ports.twoport.TwoPort`, say)."""

    @property
    def parameters(self) -> tuple[str, ...]: ...


POSITIVE = frozenset({"m"})
"""Parameters that must be positive on the whole box."""

NONNEGATIVE = frozenset({"b", "k1", "k2", "b1", "b2"})
"""Plant parameters that must not be negative on the whole box."""


@dataclass(frozen=True, kw_only=True)
class UncertainBox:
    """A checked box of uncertain parameters.

    Attributes
    ----------
    intervals : mapping of str to (float, float)
        ``{name: (lo, hi)}``, sorted by name.

    Examples
    --------
    >>> from seapass.model.sea import SEA
    >>> sea = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))
    >>> uncertain_box(sea, {"m": (0.9, 1.1)})
    UncertainBox(intervals={'m': (0.9, 1.1)})
    """

    intervals: Mapping[str, tuple[float, float]] = field(
        default_factory=lambda: MappingProxyType({})
    )

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "intervals", MappingProxyType(dict(sorted(self.intervals.items())))
        )

    def __repr__(self) -> str:
        return f"UncertainBox(intervals={dict(self.intervals)!r})"

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.intervals)

    def exact(self) -> list[tuple[Fraction, Fraction]]:
        """The intervals as exact rationals, in the order of `names`."""
        return [(Fraction(lo), Fraction(hi)) for lo, hi in self.intervals.values()]

    def center(self) -> dict[str, float]:
        return {k: (lo + hi) / 2 for k, (lo, hi) in self.intervals.items()}

    def corners(self) -> list[dict[str, float]]:
        """The ``2^k`` corners of the box (a degenerate side gives repeated corners)."""
        return [
            dict(zip(self.names, c, strict=True))
            for c in itertools.product(*self.intervals.values())
        ]

    def to_dict(self) -> dict[str, list[float]]:
        return {k: [lo, hi] for k, (lo, hi) in self.intervals.items()}


def parse_uncertain(
    items: Sequence[str], flag: str = "--uncertain"
) -> dict[str, tuple[float, float]]:
    """``NAME=LO:HI`` texts as a box mapping (a repeated name or bad text is an error).

    >>> parse_uncertain(["m=0.9:1.1", "b=8:12"])
    {'m': (0.9, 1.1), 'b': (8.0, 12.0)}
    """
    out: dict[str, tuple[float, float]] = {}
    for item in items:
        name, sep, rest = item.partition("=")
        name = name.strip()
        parts = rest.split(":")
        if not sep or not name or len(parts) != 2 or not all(p.strip() for p in parts):
            raise ParameterError(f"{flag} {item!r}: expected NAME=LO:HI, e.g. {flag} m=0.9:1.1")
        if name in out:
            raise ParameterError(f"{flag} {name} is given twice; give each name once")
        lo = parse_value(parts[0].strip(), f"{flag} {name} LO")
        hi = parse_value(parts[1].strip(), f"{flag} {name} HI")
        out[name] = (lo, hi)
    return out


def _pair(name: str, value: Any) -> tuple[float, float]:
    try:
        lo, hi = value
    except (TypeError, ValueError):
        raise ParameterError(
            f"box[{name!r}]: expected a (lo, hi) pair, got {value!r}", argument="box"
        ) from None
    lo_f = float(to_fraction(lo, f"box[{name!r}] lo"))
    hi_f = float(to_fraction(hi, f"box[{name!r}] hi"))
    return lo_f, hi_f


def uncertain_box(
    system: SEA | Impedance | Parametrized,
    box: Mapping[str, Any] | UncertainBox,
    *,
    delay_ok: bool = False,
) -> UncertainBox:
    """Check ``box`` against ``system`` and return it as an `UncertainBox`.

    Raises
    ------
    ParameterError
        An unknown name, ``lo > hi``, a non-physical value (``m <= 0``, a negative
        stiffness or damping), or a box too large for bounded work.
    DelayError
        A model with a delay ``exp(-NAME*s)`` unless ``delay_ok`` (the verdicts of
        [`seapass.robust.delayed`][seapass.robust.delayed] take one; the others are rational).
    """
    # a two-port (or any other model with parameters) is rational: no delay to refuse
    delays = model_delays(system) if isinstance(system, SEA | Impedance) else ()
    if delays and not delay_ok:  # the robust kernel works on rational functions of s and the box
        raise DelayError(
            f"a delay exp(-{delays[0]}*s) in the model: robust verdicts over a box need a "
            "delay-free design; decide the delayed design at fixed plant values "
            "(seapass.is_passive, seapass.delay_margin) or use robust_check / robust_delay_margin"
        )
    if isinstance(box, UncertainBox):
        box = dict(box.intervals)
    if not isinstance(box, Mapping) or not box:
        raise ParameterError(
            "box: give at least one uncertain parameter, e.g. box={'m': (0.9, 1.1)}"
        )
    if len(box) > MAX_UNCERTAIN:
        raise ParameterError(
            f"box: {len(box)} uncertain parameters exceed the limit of {MAX_UNCERTAIN}; fix the "
            "ones known best",
            argument="box",
        )
    known = system.parameters
    out: dict[str, tuple[float, float]] = {}
    for name, value in box.items():
        if name not in known:
            raise ParameterError(
                f"box[{name!r}]: not a parameter of the model{did_you_mean(name, known)}; "
                f"known: {', '.join(known) or 'none'}",
                argument="box",
            )
        lo, hi = _pair(name, value)
        if lo > hi:
            raise ParameterError(
                f"box[{name!r}]: empty interval [{lo:g}, {hi:g}]; LO must not exceed HI",
                argument="box",
            )
        if max(abs(lo), abs(hi)) > MAX_UNCERTAIN_MAGNITUDE:
            raise ParameterError(
                f"box[{name!r}]: [{lo:g}, {hi:g}] exceeds the limit |value| <= "
                f"{MAX_UNCERTAIN_MAGNITUDE:g}; give the interval in SI units",
                argument="box",
            )
        if name in POSITIVE and lo <= 0:
            raise ParameterError(
                f"box[{name!r}]: [{lo:g}, {hi:g}] includes non-physical values; {name} must be "
                "positive on the whole box (give LO > 0)",
                argument="box",
            )
        if name in NONNEGATIVE and lo < 0:
            raise ParameterError(
                f"box[{name!r}]: [{lo:g}, {hi:g}] includes non-physical values; {name} must not "
                "be negative (give LO >= 0)",
                argument="box",
            )
        if lo > 0 and hi / lo > MAX_UNCERTAIN_RATIO:
            raise ParameterError(
                f"box[{name!r}]: [{lo:g}, {hi:g}] spans more than {math.log10(MAX_UNCERTAIN_RATIO):g} "
                "decades, too large for a bounded certified verdict; narrow it",
                argument="box",
            )
        out[name] = (lo, hi)
    return UncertainBox(intervals=out)
