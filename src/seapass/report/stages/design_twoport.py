"""Design stage: the SEA as a two-port between the person and the virtual environment it renders.

The passivity stage holds the controller's reference still (a rigid virtual
environment).  Here the reference is the position of a virtual environment
(port 2) and the question is the stronger one of haptics: is the SEA stable
with *every* passive person on port 1 and *every* passive virtual environment
on port 2 (Llewellyn's absolute stability, decided exactly with the failing
bands and the infimum of η)?  Also: two-port passivity and reciprocity, a
verified destabilizing pair of passive terminations when it is not absolutely
stable, the exact absolutely-stable set of every ranged gain, and the friction
certificate at the actuator and in the transmission
([`seapass.ports`][seapass.ports]).

Work is bounded by counted steps: the witness search verifies at most
[`MAX_PAIRS`][seapass.ports.witness.MAX_PAIRS] pairs; the gain sets and the
verdicts are exact (no search).  Split as python-control splits
``*_response`` from ``*_plot``: `twoport_data` computes, `twoport_figures`
draws, `twoport_section` writes the section.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from ...analysis.environment_box import EnvironmentBounds, bounds_from_mapping
from ...model.design_file import Design
from ...outcome import Outcome
from ...plot.ports import plot_eta, plot_minors
from ...ports.bands import Band
from ...ports.bound import Criterion, PortIntervals, port_intervals
from ...ports.check import TwoPortCheck, check_two_port
from ...ports.derive import FRICTION_SITES
from ...ports.friction import FrictionCertificate, friction_certificate
from ...ports.stability import eta_text
from ...ports.twoport import two_port
from ...ports.witness import MAX_PAIRS, VIRTUAL_ENVIRONMENT
from ...progress import NoProgress, Progress, task
from ...robust.portresult import RobustTwoPortResult
from ...robust.twoport import robust_two_port_check
from ..document import FigureData, Finding, Section, Table, Verdict, format_intervals, to_json
from ..pipeline import StageContext

__all__ = [
    "TwoPortData",
    "stage_twoport",
    "twoport_data",
    "twoport_figures",
    "twoport_section",
]


@dataclass(frozen=True, kw_only=True)
class TwoPortData:
    """Every two-port result of one design.

    Attributes
    ----------
    check : TwoPortCheck
        Absolute stability (with η and a witness), passivity, reciprocity.
    person : EnvironmentBounds
        The box the witness searched on port 1 (the design file's ``[environment]``).
    ranges : tuple of (str, PortIntervals)
        The exact absolutely-stable set of each ranged gain, the others at their values.
    friction : tuple of FrictionCertificate
        The friction certificate at each site.
    robust : RobustTwoPortResult or None
        With an ``[uncertainty]`` table: both criteria for every plant of the box
        ([`robust_two_port_check`][seapass.robust.twoport.robust_two_port_check]).
    """

    check: TwoPortCheck
    person: EnvironmentBounds
    ranges: tuple[tuple[str, PortIntervals], ...]
    friction: tuple[FrictionCertificate, ...]
    robust: RobustTwoPortResult | None = None


def twoport_data(design: Design, quick: bool, *, progress: Progress | None = None) -> TwoPortData:
    """The two-port of ``design`` decided exactly, its gain sets and its friction certificates.

    ``progress`` gets one task with a step per decision (default: none).
    """
    shown = NoProgress() if progress is None else progress
    sea = design.sea()
    tp = two_port(sea)
    person = bounds_from_mapping(dict(design.environment))
    ranges = design.analysis_ranges()
    steps = len(ranges) + 1 + len(FRICTION_SITES) + bool(design.uncertainty)
    with task(shown, f"two-port of {design.name}", steps):
        check = check_two_port(tp, bounds=(person, VIRTUAL_ENVIRONMENT))
        shown.advance(note="absolute stability")
        sets = []
        for name, (lo, hi) in ranges.items():
            free = tp.with_values(**{name: None})
            sets.append((name, port_intervals(free, name, lo, hi, criterion=Criterion.ABSOLUTE)))
            shown.advance(note=f"absolutely stable {name}")
        friction = []
        for site in FRICTION_SITES:
            friction.append(friction_certificate(sea, at=site))
            shown.advance(note=f"friction at the {site}")
        robust = None
        if design.uncertainty:
            robust = robust_two_port_check(tp, box=dict(design.uncertainty))
            shown.advance(note="over the [uncertainty] box")
    return TwoPortData(
        check=check, person=person, ranges=tuple(sets), friction=tuple(friction), robust=robust
    )


def twoport_figures(data: TwoPortData) -> tuple[FigureData, ...]:
    """η(ω) with the failing bands (when η exists) and the principal minors of ``Z + Z^H``."""
    figures = []
    stab = data.check.stability
    if not math.isnan(stab.eta.value):
        figures.append(
            FigureData.of(
                "twoport_eta",
                "η(ω) of the two-port (person, virtual environment); absolutely stable means "
                "η ≥ 1 at every ω; shaded: the exact bands where a condition fails.",
                plot_eta(stab),
            )
        )
    figures.append(
        FigureData.of(
            "twoport_minors",
            "Principal minors of Z(jω) + Z(jω)^H; the two-port is passive when none is negative "
            "(shaded: the exact bands where one is).",
            plot_minors(data.check.passivity),
        )
    )
    return tuple(figures)


def _bands(bands: Sequence[Band]) -> str:
    return ", ".join(f"({b.lo:.6g}, {'∞' if math.isinf(b.hi) else f'{b.hi:.6g}'})" for b in bands)


def _holds(outcome: Outcome) -> bool | None:
    return None if outcome is Outcome.UNDECIDED else outcome.passive


_STABILITY_WORDS = {
    Outcome.PASSIVE: "absolutely stable",
    Outcome.NOT_PASSIVE: "not absolutely stable",
    Outcome.UNDECIDED: "undecided (never reported as stable)",
}


def _verdicts_table(check: TwoPortCheck) -> Table:
    stab = check.stability
    rows: list[tuple[str, Any, str]] = [
        ("absolutely stable (Llewellyn)", _holds(stab.outcome), _STABILITY_WORDS[stab.outcome]),
        ("passive two-port (Raisbeck)", _holds(check.outcome), check.outcome.label),
        ("reciprocal (z12 = z21)", check.reciprocal, "exact"),
        ("inf η (Haddadi, Hashtrudi-Zaad)", stab.eta.value, eta_text(stab.eta)),
    ]
    return Table(
        name="twoport_verdicts",
        title="The two-port's verdicts (exact)",
        columns=("question", "answer", "detail"),
        rows=tuple(rows),
        highlight=frozenset({(0, "answer")} if stab.outcome is not Outcome.PASSIVE else ()),
    )


def _conditions_table(check: TwoPortCheck) -> Table:
    rows = [
        (crit, c.name, c.holds, _bands(c.bands) or "none", c.detail)
        for crit, conds in (
            ("absolute stability", check.stability.conditions),
            ("passivity", check.passivity.conditions),
        )
        for c in conds
    ]
    return Table(
        name="twoport_conditions",
        title="Every condition, with its exact failing bands",
        columns=("criterion", "condition", "holds", "fails for ω in [rad/s]", "detail"),
        rows=tuple(rows),
    )


def _ranges_table(design: Design, ranges: Sequence[tuple[str, PortIntervals]]) -> Table:
    rows, flags = [], set()
    for i, (name, res) in enumerate(ranges):
        value = design.values[name]
        inside = res.contains(value) if res.lo <= value <= res.hi else None
        if inside is False:
            flags.add((i, "value is absolutely stable"))
        undecided = format_intervals(res.undecided, res.hi) if res.undecided else ""
        rows.append(
            (
                name,
                value,
                f"[{res.lo:g}, {res.hi:g}]",
                inside,
                format_intervals(res.intervals, res.hi),
                undecided,
            )
        )
    return Table(
        name="twoport_ranges",
        title="Exact absolutely-stable set of each gain (the other parameters at their values)",
        columns=(
            "parameter",
            "value",
            "search range",
            "value is absolutely stable",
            "exact absolutely-stable set",
            "undecided",
        ),
        rows=tuple(rows),
        highlight=frozenset(flags),
    )


def _witness_table(check: TwoPortCheck) -> Table | None:
    w = check.stability.witness
    if w is None or not w.found or w.port1 is None or w.port2 is None:
        return None
    rate = w.closed_loop.max_real_part if w.closed_loop is not None else math.nan
    rows = [
        (port, env.mass, env.damping, env.stiffness, rate)
        for port, env in (("1 (person)", w.port1), ("2 (virtual environment)", w.port2))
    ]
    return Table(
        name="twoport_witness",
        title="A pair of passive terminations that destabilizes the two-port (verified exactly)",
        columns=("port", "mass [kg]", "damping [N·s/m]", "stiffness [N/m]", "growth rate [1/s]"),
        rows=tuple(rows),
        note=w.detail,
    )


def _friction_table(friction: Sequence[FrictionCertificate]) -> Table:
    return Table(
        name="friction",
        title="Friction certificate: every passive friction law keeps the SEA passive",
        columns=("friction at", "certified", "detail"),
        rows=tuple((f.site, f.certified, f.detail) for f in friction),
    )


def _text(design: Design, data: TwoPortData) -> str:
    stab = data.check.stability
    head = (
        "The passivity verdict above holds the controller's reference still: a rigid virtual "
        "environment. Here the SEA is a two-port between the person (port 1: F_L, v_L) and the "
        "virtual environment it renders (port 2: the controllers act on the error to its "
        "position θ, F_2 = f_A, v_2 = sθ), derived from the free-body equations. "
    )
    if stab.outcome is Outcome.PASSIVE:
        verdict = (
            f"**`{design.name}` is absolutely stable**: stable with every passive person and "
            f"every passive virtual environment (Llewellyn, exact); inf η = {eta_text(stab.eta)}."
        )
    elif stab.outcome is Outcome.NOT_PASSIVE:
        w = stab.witness
        found = (
            f" A verified pair: {w.detail}."
            if w is not None and w.found
            else (f" {w.detail}." if w is not None else "")
        )
        verdict = (
            f"**`{design.name}` is NOT absolutely stable**: some passive person together with "
            f"some passive virtual environment makes it unstable; failing: "
            f"{', '.join(c.name for c in stab.failing)}; inf η = {eta_text(stab.eta)}.{found}"
        )
    else:
        verdict = (
            f"Absolute stability of `{design.name}` is **undecided** by the exact test "
            "(never reported as stable)."
        )
    tail = (
        " Every band is decided exactly (real roots of exact polynomials in ω²), not read off "
        f"the plotted grid; the witness search verifies at most {MAX_PAIRS} pairs (port 1 within "
        f"{data.person.describe()}, port 2 within {VIRTUAL_ENVIRONMENT.describe()}); "
        "not finding one is no proof. A friction certificate that fails proves nothing: the "
        "test is sufficient only."
    )
    return head + verdict + tail + _robust_text(data.robust)


def _robust_text(robust: RobustTwoPortResult | None) -> str:
    if robust is None:
        return ""
    span = ", ".join(f"`{k}` ∈ [{a:g}, {b:g}]" for k, (a, b) in robust.box.intervals.items())
    words = {Outcome.PASSIVE: "holds", Outcome.NOT_PASSIVE: "fails",
             Outcome.UNDECIDED: "is undecided"}  # fmt: skip
    out = (
        f" Over the `[uncertainty]` box {span}: absolute stability "
        f"{words[robust.stability.outcome]} for every plant ({robust.stability.detail}); "
        f"two-port passivity {words[robust.passivity.outcome]} ({robust.passivity.detail})."
    )
    if robust.worst is not None:
        at = ", ".join(f"`{k}` = {v:.10g}" for k, v in robust.worst.values.items())
        out += f" Worst plant: {at} (verified by the exact two-port test)."
    return out


def twoport_section(design: Design, data: TwoPortData, figures: Sequence[FigureData]) -> Section:
    """The section of `twoport_data` with the figures of `twoport_figures`."""
    check = data.check
    stab = check.stability
    finding_verdict_of = {
        Outcome.PASSIVE: Verdict.AGREES,
        Outcome.NOT_PASSIVE: Verdict.DIFFERS,
        Outcome.UNDECIDED: Verdict.INFO,
    }
    finding_verdict = finding_verdict_of[stab.outcome]
    findings = [
        Finding(
            f"{design.name} is stable with every passive person and every passive virtual "
            "environment (absolutely stable)",
            finding_verdict,
            f"{_STABILITY_WORDS[stab.outcome]}; inf η = {eta_text(stab.eta)}",
        ),
        *(
            Finding(
                f"every passive friction law at the {f.site} keeps {design.name} passive",
                Verdict.AGREES if f.certified else Verdict.INFO,
                f.detail,
            )
            for f in data.friction
        ),
    ]
    if data.robust is not None:
        findings.append(
            Finding(
                f"{design.name} is absolutely stable for every plant of the [uncertainty] box",
                finding_verdict_of[data.robust.stability.outcome],
                data.robust.stability.detail,
            )
        )
    tables = [_verdicts_table(check), _conditions_table(check)]
    witness = _witness_table(check)
    if witness is not None:
        tables.append(witness)
    if data.ranges:
        tables.append(_ranges_table(design, data.ranges))
    tables.append(_friction_table(data.friction))
    return Section(
        key="twoport",
        title="Two-port: any passive person, any passive virtual environment",
        text=_text(design, data),
        tables=tuple(tables),
        figures=tuple(figures),
        findings=tuple(findings),
        files={
            "twoport.json": to_json(check.to_dict()),
            "twoport_ranges.json": to_json({n: r.to_dict() for n, r in data.ranges}),
            "friction.json": to_json({f.site: f.to_dict() for f in data.friction}),
            **(
                {}
                if data.robust is None
                else {"twoport_robust.json": to_json(data.robust.to_dict())}
            ),
        },
    )


def stage_twoport(design: Design, context: StageContext) -> Section:
    """Absolute stability, η, two-port passivity, gain sets and friction of a design file
    (exact; no budget: the witness search verifies at most ``MAX_PAIRS`` pairs)."""
    data = twoport_data(design, context.quick, progress=context.progress)
    return twoport_section(design, data, twoport_figures(data))
