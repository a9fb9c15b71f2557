"""A fitted rig's confidence intervals: the ``[intervals]`` table that ``rig fit`` writes.

``seapass rig fit LOG --rig-out FILE`` writes, besides the fitted values, the
intervals of the linear model's parameters the fit reports (``m``, ``b``, ``b1``)
into the rig file it emits::

    [intervals]              # written by seapass rig fit; read by --robust
    confidence = 0.95        # level of the intervals below
    dof = 120                # Student's t degrees of freedom of the fit
    source = "chirp.csv"     # the log
    m = [1.018, 1.022]       # kg
    b = [9.7, 10.3]          # N s/m
    b1 = [29.1, 30.9]        # N s/m
    m_stderr = 0.001         # standard errors: with dof, the intervals at another level
    b_stderr = 0.15
    b1_stderr = 0.45

The intervals are Student's t intervals, symmetric about the estimate, so with the
standard errors and ``dof`` they can be recomputed at another level
(`FitIntervals.at`).  A damping cannot be negative: an interval reaching below 0
is cut at 0 where it becomes a box (`FitIntervals.box`); a mass interval reaching
0 is refused (the log does not bound the mass).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from ..errors import FileFormatError, ParameterError
from ..files import limits
from ..files.schema import Field, check_table

__all__ = ["INTERVAL_FIELDS", "MODEL_PARAMETERS", "FitIntervals", "fit_intervals"]

MODEL_PARAMETERS = ("m", "b", "b1")
"""The fitted parameters of the linear model whose intervals a rig file keeps."""

_PAIR = Field(tuple, -1e12, 1e12, order="<=", required=False)
_STDERR = Field(float, 0.0, 1e12, required=False)

INTERVAL_FIELDS: dict[str, Field] = {
    "confidence": Field(float, 0.0, 1.0, lo_open=True, hint="the level, e.g. 0.95"),
    "dof": Field(int, 1, 10**9, required=False),
    "source": Field(str, hi=limits.MAX_DESCRIPTION_CHARS, line=True, required=False),
    **{name: _PAIR for name in MODEL_PARAMETERS},
    **{f"{name}_stderr": _STDERR for name in MODEL_PARAMETERS},
}
"""Every key of a rig file's ``[intervals]`` table."""


@dataclass(frozen=True, kw_only=True)
class FitIntervals:
    """The confidence intervals a fit stored in a rig file.

    Attributes
    ----------
    confidence : float
        Level of `intervals`, in (0, 1).
    intervals : mapping of str to (float, float)
        ``{name: (lo, hi)}`` of ``m``, ``b``, ``b1`` (those the fit reported).
    stderr : mapping of str to float
        Standard errors (empty when the file gives none).
    dof : int or None
        Degrees of freedom of Student's t (None: the level cannot be changed).
    source : str
        The log the fit used.

    Examples
    --------
    >>> f = FitIntervals(confidence=0.95, intervals={"m": (0.9, 1.1)}, stderr={"m": 0.05}, dof=40)
    >>> f.recomputable, round(f.at(0.99).intervals["m"][1], 3)
    (True, 1.135)
    """

    confidence: float
    intervals: Mapping[str, tuple[float, float]]
    stderr: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))
    dof: int | None = None
    source: str = ""

    def __post_init__(self) -> None:
        if not 0 < self.confidence < 1:
            raise ParameterError(f"confidence must lie in (0, 1), got {self.confidence}")
        unknown = sorted(set(self.intervals) - set(MODEL_PARAMETERS))
        if unknown:
            raise ParameterError(f"intervals: {unknown[0]} is not one of {MODEL_PARAMETERS}")
        for name in ("intervals", "stderr"):
            object.__setattr__(self, name, MappingProxyType(dict(getattr(self, name))))

    @property
    def recomputable(self) -> bool:
        """True when every interval has a standard error and ``dof`` is known."""
        return self.dof is not None and all(n in self.stderr for n in self.intervals)

    def at(self, confidence: float) -> FitIntervals:
        """The intervals at another level (Student's t about the same estimates).

        Raises
        ------
        ParameterError
            For a level outside (0, 1), or when the file keeps no standard errors.
        """
        if not isinstance(confidence, int | float) or not 0 < confidence < 1:
            raise ParameterError(f"confidence must lie in (0, 1), got {confidence!r}")
        if confidence == self.confidence:
            return self
        if not self.recomputable:
            raise ParameterError(
                f"the rig file's [intervals] keep no standard errors and dof, so the "
                f"{self.confidence:g} intervals cannot be recomputed at {confidence:g}; drop "
                "the confidence or refit the log"
            )
        from scipy.stats import t as student

        q = float(student.ppf(0.5 + confidence / 2, self.dof))
        out = {}
        for name, (lo, hi) in self.intervals.items():
            centre, half = (lo + hi) / 2, q * self.stderr[name]
            out[name] = (centre - half, centre + half)
        return FitIntervals(
            confidence=confidence, intervals=out, stderr=self.stderr, dof=self.dof,
            source=self.source,
        )  # fmt: skip

    def box(self, parameters: Sequence[str] | None = None) -> dict[str, tuple[float, float]]:
        """The intervals as a box of physical plants: dampings cut at 0.

        ``parameters``: keep only these (the model's); None keeps all.

        Raises
        ------
        ParameterError
            When a mass interval reaches 0 (the log does not bound the mass).
        """
        out = {}
        for name, (lo, hi) in self.intervals.items():
            if parameters is not None and name not in parameters:
                continue
            if name == "m" and lo <= 0:
                raise ParameterError(
                    f"the rig file's {self.confidence:g} interval of m, [{lo:g}, {hi:g}], reaches "
                    "0: the log does not bound the mass; log a longer chirp and refit"
                )
            out[name] = (max(lo, 0.0), max(hi, 0.0))
        return out

    def to_table(self) -> dict[str, Any]:
        """The ``[intervals]`` table as a rig file writes it."""
        out: dict[str, Any] = {"confidence": self.confidence}
        if self.dof is not None:
            out["dof"] = self.dof
        if self.source:
            out["source"] = self.source
        out.update({k: list(v) for k, v in self.intervals.items()})
        out.update({f"{k}_stderr": v for k, v in self.stderr.items()})
        return out

    @classmethod
    def from_table(cls, table: Mapping[str, Any]) -> FitIntervals:
        """Check a rig file's ``[intervals]`` table (a `FileFormatError` names the key)."""
        doc = check_table(table, INTERVAL_FIELDS, where="intervals")
        if doc["confidence"] >= 1:
            raise FileFormatError(
                f"intervals.confidence must lie in (0, 1), got {doc['confidence']}"
            )
        given = {n: tuple(doc[n]) for n in MODEL_PARAMETERS if n in doc}
        if not given:
            raise FileFormatError("[intervals] gives no interval: add m = [LO, HI] (or b, b1)")
        stderr = {n: doc[f"{n}_stderr"] for n in MODEL_PARAMETERS if f"{n}_stderr" in doc}
        for name in stderr:
            if name not in given:
                raise FileFormatError(f"intervals.{name}_stderr: no interval intervals.{name}")
        return cls(
            confidence=doc["confidence"], intervals=given, stderr=stderr, dof=doc.get("dof"),
            source=doc.get("source", ""),
        )  # fmt: skip


def fit_intervals(
    parameters: Sequence[Any], *, confidence: float, dof: int | None, source: str = ""
) -> FitIntervals:
    """The `FitIntervals` of a fit's parameters (``FitParameter``: name, low, high, stderr).

    Only ``m``, ``b``, ``b1`` are kept; an interval that is not finite is left out.
    """
    keep = [
        p for p in parameters
        if p.name in MODEL_PARAMETERS and math.isfinite(p.low) and math.isfinite(p.high)
    ]  # fmt: skip
    finite = all(math.isfinite(p.stderr) for p in keep)
    return FitIntervals(
        confidence=confidence,
        intervals={p.name: (p.low, p.high) for p in keep},
        stderr={p.name: p.stderr for p in keep} if finite else {},
        dof=dof if finite else None,
        source=source,
    )
