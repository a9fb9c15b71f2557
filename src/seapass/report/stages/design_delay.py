"""Design stage ``delay``: the passivity delay margin ``τ*`` and the stated loop latency.

``τ*`` is the certified enclosure of
[`latency_check`][seapass.delay.latency.latency_check] (the same number as
``seapass.delay_margin(design, "delay_time")`` and ``seapass delay-margin delay_time
DESIGN``): the largest delay such that the design with ``C_A``, ``C_L`` times
``exp(-delay_time*s)`` stays passive for every delay up to it, with the frequency and the
kind of loss, and whether it is passive for every delay.  With ``[control] delay_time``,
also the certified verdict for every delay up to the latency and ``Re Z(jω)`` at it.

Budget: pieces of each certified search (the margin's branch and bound, the ball
evaluations at the latency); a search that reaches it answers *undecided*, never passive,
and the section is *stopped at budget*.  Split as the other stages: `delay_data` computes,
`delay_figures` draws, `delay_section` writes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ...delay.latency import LatencyCheck, latency_check
from ...exact.rounding import decimal_down, decimal_up, enclosure_text
from ...model.delayatom import model_delays
from ...model.design_file import Design
from ...outcome import Outcome
from ..document import FigureData, Finding, Section, SectionStatus, Table, Verdict, to_json
from ..pipeline import StageContext

__all__ = ["DelayData", "delay_data", "delay_figures", "delay_section", "stage_delay"]

QUICK_BUDGET = 50_000
"""Pieces per certified search with ``--quick``."""

FULL_BUDGET = 200_000
"""Pieces per certified search by default (at least the defaults of ``delay_margin`` and
``check``, so the stage gives their answers)."""


@dataclass(frozen=True, kw_only=True)
class DelayData:
    """The latency check of a design (None: no controller to delay) and the budget used."""

    check: LatencyCheck | None
    budget: int

    @property
    def stopped(self) -> bool:
        """A certified search reached the budget (its answer is undecided)."""
        c = self.check
        if c is None:
            return False
        spent = [c.margin.evaluations]
        if c.at_latency is not None:
            spent.append(c.at_latency.evaluations)
        return c.outcome is Outcome.UNDECIDED and max(spent) >= self.budget


def delay_data(design: Design, quick: bool, *, budget: int | None = None) -> DelayData:
    """`latency_check` of the design at its ``[control] delay_time`` (if any)."""
    used = budget if budget is not None else (QUICK_BUDGET if quick else FULL_BUDGET)
    if design.CA == "0" and design.CL == "0" and not model_delays(design.sea()):
        return DelayData(check=None, budget=used)
    return DelayData(check=latency_check(design, budget=used), budget=used)


def delay_figures(data: DelayData) -> tuple[FigureData, ...]:
    """The first failing delay per frequency with ``τ*``; ``Re Z(jω)`` at the latency."""
    c = data.check
    out: list[FigureData] = []
    if c is None:
        return ()
    m = c.margin
    if m.tau_star is not None and m.impedance is not None:
        out.append(
            FigureData.of(
                "delay_margin",
                "The first delay at which Re Z(jω) < 0, per frequency (sampled, a picture), "
                "and the certified enclosure of τ* (band).",
                m.plot(),
            )
        )
    if c.at_latency is not None and c.at_latency.impedance is not None:
        out.append(
            FigureData.of(
                "real_part_at_latency",
                f"Re Z(jω) with the loop latency {c.delay} = {c.latency:g} s; shaded: the "
                "certified bands where it is negative.",
                c.plot(),
            )
        )
    return tuple(out)


def _star_text(c: LatencyCheck) -> str:
    m = c.margin
    if not m.passive_at_zero:
        return "**Not passive even without delay**: no delay margin (τ* is undefined)."
    if m.delay_independent:
        return "**Passive for every delay** (delay-independent, exact): τ* = ∞."
    if m.tau_star is None:
        return f"τ* is **undecided**: {m.detail}"
    lo, hi = m.tau_star
    if hi == 0:
        return f"**τ* = 0** (exact): every delay > 0 breaks passivity ({m.loss}): {m.detail}."
    where = {
        "interior": f"at ω = {m.frequency:.6g} rad/s" if m.frequency else "inside the band",
        "low_frequency": "in the limit ω → 0",
        "unbounded_band": "at arbitrarily high frequencies, for every delay > 0",
    }.get(str(m.loss or ""), "")
    head = "τ* lies in" if m.outcome is Outcome.PASSIVE else "τ* is undecided, at most"
    return (
        f"{head} **{enclosure_text(lo, hi, digits=6)} s**: passive for every loop latency up "
        f"to {decimal_down(lo, 6)} s (certified); passivity is lost {where} ({m.loss})."
    )


def _end(star: tuple[float, float] | None, i: int) -> str:
    """An end of ``τ*`` as text rounded outward (the lower end down, the upper up)."""
    if star is None:
        return "none"
    return decimal_down(star[0], 12) if i == 0 else decimal_up(star[1], 12)


def delay_section(design: Design, data: DelayData, figures: Sequence[FigureData]) -> Section:
    """The section of `delay_data` with the figures of `delay_figures`."""
    c = data.check
    if c is None:
        return Section(
            key="delay",
            title="Delay margin and loop latency",
            text="The model has no controller (C_A = C_L = 0): a loop latency changes nothing.",
        )
    m = c.margin
    text = (
        f"A loop latency τ delays both controllers: C_A and C_L times exp(-{c.delay}·s) "
        "(`[control] delay_time`). " + _star_text(c)
    )
    if c.latency is not None:
        text += f" With the stated latency {c.delay} = {c.latency:g} s: **{c.outcome.label}** ({c.detail})."
    else:
        text += " No latency is stated (`[control] delay_time`)."
    star = m.tau_star
    rows: list[tuple[str, object]] = [
        ("τ* lower end (certified, rounded down) [s]", _end(star, 0)),
        ("τ* upper end (rounded up) [s]", _end(star, 1)),
        ("frequency of the loss [rad/s]", "none" if m.frequency is None else m.frequency),
        ("kind of loss", str(m.loss or "none")),
        ("delay-independent", "yes" if m.delay_independent else "no"),
        ("passive without delay", "yes" if m.passive_at_zero else "no"),
        ("margin", m.outcome.label),
        ("stated latency [s]", "none" if c.latency is None else c.latency),
        ("verdict up to the latency", c.outcome.label if c.latency is not None else "none"),
    ]
    findings: tuple[Finding, ...] = ()
    if c.latency is not None:
        verdict = {
            Outcome.PASSIVE: Verdict.AGREES,
            Outcome.NOT_PASSIVE: Verdict.DIFFERS,
            Outcome.UNDECIDED: Verdict.INFO,
        }[c.outcome]
        findings = (
            Finding(
                f"{design.name} stays passive for every loop latency up to "
                f"{c.delay} = {c.latency:g} s",
                verdict,
                c.detail,
            ),
        )
    stopped = data.stopped
    if stopped:
        text += (
            f" A certified search reached its budget of {data.budget} pieces; raise it with "
            "`--budget delay=N`."
        )
    return Section(
        key="delay",
        title="Delay margin and loop latency",
        text=text,
        tables=(
            Table(
                name="delay_margin",
                title="Passivity delay margin τ* (certified)",
                columns=("quantity", "value"),
                rows=tuple(rows),
            ),
        ),
        figures=tuple(figures),
        findings=findings,
        files={"delay_margin.json": to_json(c.to_dict())},
        status=SectionStatus.STOPPED_AT_BUDGET if stopped else SectionStatus.OK,
    )


def stage_delay(design: Design, context: StageContext) -> Section:
    """``τ*`` and the verdict at ``[control] delay_time`` (budget: pieces per certified search)."""
    data = delay_data(design, context.quick, budget=context.budget)
    return delay_section(design, data, delay_figures(data))
