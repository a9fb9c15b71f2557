"""A design against its loop latency: ``τ*`` and whether the stated latency is within it.

`latency_check` is what ``analyze`` (the ``delay`` stage), ``explore`` (the ``delay``
panel) and ``export c`` (the latency guard) run, so the three show one ``τ*``: the
[`delay_margin`][seapass.delay.margin.delay_margin] of the design with the delay on its
controllers (``C_A``, ``C_L`` times ``exp(-delay_time*s)``, as ``[control] delay_time``
means, [`seapass.model.latency`][seapass.model.latency]), or of the delay written in
the model.

The latency is **certified** only when every delay in ``[0, latency]`` is certified
passive: ``latency <= lo`` of the enclosure of ``τ*`` (compared exactly), or the design
is passive for every delay.  A real latency jitters below its stated value, so a design
passive at the stated delay but not below it is not certified.  ``latency > hi`` is
proven to exceed ``τ*`` (``not_passive``); in between (or when ``τ*`` is undecided) the
answer is ``undecided``, never certified.

Examples
--------
>>> from seapass.model.design_file import parse_design
>>> d = parse_design({"name": "ours", "model": {"D1": "k1 + b1*s", "CA": "kd + bd*s"},
...     "parameters": dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0),
...     "control": {"delay_time": 0.01}})
>>> c = latency_check(d)
>>> str(c.outcome), round(c.margin.tau_star[0], 4), c.at_latency.status
('passive', 0.0413, 'passive')
>>> str(latency_check(d, latency=0.05).outcome)
'not_passive'
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from ..errors import ParameterError
from ..exact.rounding import decimal_down, decimal_up, enclosure_text
from ..model.display import html_card, short_repr
from ..model.latency import LATENCY_PARAMETER, check_delay_time
from ..model.sea import SEA
from ..outcome import Outcome
from .margin import DEFAULT_MARGIN_BUDGET, delay_margin
from .marginresult import DelayMarginResult
from .passivity import DelayPassivityResult, delayed_passivity
from .structure import controller_delay, delay_parameter, has_model_delay

__all__ = ["LatencyCheck", "latency_check"]


@dataclass(frozen=True, kw_only=True, repr=False)
class LatencyCheck:
    """The delay margin of a design and its stated loop latency.

    Attributes
    ----------
    delay : str
        The delay parameter (``delay_time``, or the model's own ``exp(-NAME*s)``).
    latency : float or None
        The stated latency [s] (None: none stated; only ``τ*`` is computed).
    margin : DelayMarginResult
        ``τ*`` (certified enclosure, frequency and kind of loss, delay-independent).
    at_latency : DelayPassivityResult or None
        The certified verdict at the latency (None without a latency > 0).
    outcome : Outcome
        ``passive``: every delay in ``[0, latency]`` is certified passive;
        ``not_passive``: proven not (the latency reaches ``hi``, or the design is not
        passive at zero delay); ``undecided`` otherwise, and without a latency the
        margin's own outcome.
    detail : str
        One sentence for people.
    """

    delay: str
    latency: float | None
    margin: DelayMarginResult
    at_latency: DelayPassivityResult | None = None
    outcome: Outcome
    detail: str = ""

    @property
    def certified(self) -> bool:
        """Every delay up to the latency is certified passive."""
        return self.outcome is Outcome.PASSIVE

    @property
    def tau_star(self) -> tuple[float, float] | None:
        """``[lo, hi]`` of ``τ*`` [s] (the margin's)."""
        return self.margin.tau_star

    def to_dict(self) -> dict[str, Any]:
        return {
            "delay": self.delay,
            "latency": self.latency,
            "outcome": str(self.outcome),
            "certified": self.certified,
            "detail": self.detail,
            "margin": self.margin.to_dict(),
            "at_latency": None if self.at_latency is None else self.at_latency.to_dict(),
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """``Re Z(jω)`` at the latency with its failing bands (needs a latency > 0)."""
        if self.at_latency is None:
            raise ValueError("no latency > 0 was stated: nothing to draw at a delay")
        return self.at_latency.plot(ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "LatencyCheck",
            {
                "latency": self.latency,
                "tau_star": list(self.tau_star) if self.tau_star else None,
                "outcome": str(self.outcome),
            },
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [
            ("latency", "none stated" if self.latency is None else f"{self.latency:g} s"),
            ("τ*", "none" if self.tau_star is None else f"{enclosure_text(*self.tau_star, digits=6)} s"),
            ("every delay independent", self.margin.delay_independent),
            ("verdict", self.outcome.label),
            ("detail", self.detail),
        ]  # fmt: skip
        return html_card("Loop latency against τ*", rows, note="Certified; undecided is never passive.")  # fmt: skip


def _system(design: Any) -> tuple[Any, str, float | None]:
    """The design to run ``delay_margin`` on, its delay and its stated latency."""
    sea = design if isinstance(design, SEA) else None
    if sea is None and hasattr(design, "sea") and callable(design.sea):
        sea = design.sea()
    if sea is not None and has_model_delay(sea):
        name = delay_parameter(sea)
        value = sea.values.get(name)
        return sea, name, None if value is None else float(value)
    if isinstance(design, str):
        raise ParameterError("design: give an SEA, a Design or a CatalogDesign", argument="design")
    return design, LATENCY_PARAMETER, getattr(design, "delay_time", None)


def _at_most(latency: float, bound: Any) -> bool:
    """``latency <= bound`` exactly (the latency as the decimal it was written as, as the
    delay's own checks read it; ``bound`` a float or an exact ``fmpq``)."""
    exact = Fraction(int(bound.p), int(bound.q)) if hasattr(bound, "q") else Fraction(bound)
    return Fraction(repr(float(latency))) <= exact


def latency_check(
    design: Any,
    *,
    latency: float | None = None,
    budget: int = DEFAULT_MARGIN_BUDGET,
) -> LatencyCheck:
    """``τ*`` of a design and the verdict for every delay up to its loop latency.

    Parameters
    ----------
    design : Design, CatalogDesign or SEA
        A design file's ``Design`` (its ``[control] delay_time`` is the latency), or a
        model; a model with its own ``exp(-NAME*s)`` uses that delay (its value is the
        latency).
    latency : float, optional
        The loop latency [s] replacing the design's (``0 <= latency <= 1000``).
    budget : int, default 50000
        Pieces of each certified search (the margin's branch and bound, the ball
        evaluations of the verdict at the latency) before it is undecided.

    Returns
    -------
    LatencyCheck

    Raises
    ------
    ParameterError
        For a latency out of range or a bad budget.
    DelayError
        For a design without a controller to delay.
    """
    system, name, stated = _system(design)
    if latency is not None:
        stated = check_delay_time(latency, argument="latency")
    margin = delay_margin(system, name, budget=budget)
    at = None
    if stated:
        delayed = system if name != LATENCY_PARAMETER else controller_delay(system, name)
        at = delayed_passivity(delayed, values={name: stated}, budget=budget)
    outcome, detail = _verdict(margin, stated, at)
    return LatencyCheck(
        delay=name, latency=stated, margin=margin, at_latency=at, outcome=outcome, detail=detail
    )


def _verdict(
    m: DelayMarginResult, latency: float | None, at: DelayPassivityResult | None
) -> tuple[Outcome, str]:
    if not m.passive_at_zero:
        return Outcome.NOT_PASSIVE, f"not passive even without delay: {m.detail}"
    if latency is None:
        return m.outcome, m.detail
    if m.delay_independent:
        return Outcome.PASSIVE, "passive for every delay: the latency cannot break passivity"
    if at is not None and at.outcome is Outcome.NOT_PASSIVE:
        return Outcome.NOT_PASSIVE, f"not passive at the latency {latency:g} s: {at.detail}"
    if m.tau_star is None or m.outcome is Outcome.UNDECIDED:
        lo_hi = "" if m.tau_star is None else f" (tau* <= {decimal_up(m.tau_star[1], 6)} s)"
        if m.tau_star is not None and not _at_most(latency, m.tau_star[1]):
            return Outcome.NOT_PASSIVE, f"the latency {latency:g} s exceeds tau*{lo_hi}"
        return Outcome.UNDECIDED, f"tau* is undecided{lo_hi}: {m.detail}"
    lo, hi = m.tau_star
    if _at_most(latency, m.exact[0] if m.exact is not None else lo):  # lo certified exactly
        return (
            Outcome.PASSIVE,
            f"every delay up to the latency {latency:g} s is certified passive "
            f"(tau* >= {decimal_down(lo, 6)} s)",
        )
    if _at_most(latency, hi):  # at hi itself the loss may be the exact limit: undecided
        return (
            Outcome.UNDECIDED,
            f"the latency {latency:g} s lies inside the enclosure of tau* "
            f"{enclosure_text(lo, hi, digits=6)} s",
        )
    return (
        Outcome.NOT_PASSIVE,
        f"the latency {latency:g} s exceeds tau* <= {decimal_up(hi, 6)} s: passivity is lost "
        "at a "
        "smaller delay",
    )
