"""Design stage: passivity in the frequency domain (Bode with phase, ``Re Z(jω)``, Nyquist).

The bands where ``Re Z(jω) < 0`` are exact (the real roots of the real-part
polynomial, isolated exactly); the curves are sampled only to draw them.  Split as
python-control splits ``*_response`` from ``*_plot``: `frequency_data` computes,
`frequency_figures` draws, `frequency_section` writes the section.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ...analysis.freqresp import FrequencyResponse, stiffness_response
from ...analysis.portresponse import ImpedanceResponse, impedance_response
from ...model.design_file import Design
from ...plot.passivity import plot_bode, plot_nyquist, plot_real_part
from ..document import FigureData, Section, Table, to_json
from ..pipeline import StageContext

__all__ = [
    "FrequencyData",
    "frequency_data",
    "frequency_figures",
    "frequency_section",
    "stage_frequency",
]


def _band_text(a: float, b: float) -> str:
    return f"({a:.6g}, {'∞' if b == float('inf') else f'{b:.6g}'})"


@dataclass(frozen=True, kw_only=True)
class FrequencyData:
    """The port impedance (with its exact negative bands) and the rendered stiffness."""

    impedance: ImpedanceResponse
    stiffness: FrequencyResponse
    reference: float | None


def frequency_data(design: Design, quick: bool, *, points: int | None = None) -> FrequencyData:
    """``Z_L(jω)`` with the exact bands where ``Re Z_L(jω) < 0``, and ``F_L/X_L(jω)``
    (``points`` on the drawn curves: default 600, 300 quick)."""
    sea = design.sea()
    resp = impedance_response(sea, points=points or (300 if quick else 600), label=design.name)
    fr = stiffness_response(sea, resp.omega, label=design.name)
    return FrequencyData(impedance=resp, stiffness=fr, reference=design.values.get("k1"))


def frequency_figures(data: FrequencyData) -> tuple[FigureData, ...]:
    """The one Bode plot of the report (wrapped phase, exact bands), ``Re Z_L``, Nyquist."""
    resp = data.impedance
    name = data.stiffness.label
    title = f"{name}: rendered stiffness" if name else "Rendered stiffness"
    if data.reference is not None:
        title += " (dashed: spring stiffness k1)"
    return (
        FigureData.of(
            "bode",
            "Rendered stiffness F_L/X_L(jω), magnitude and phase (whole turns removed: passive "
            "is within [0°, 180°]); shaded: Re Z_L(jω) < 0 (exact).",
            plot_bode(
                data.stiffness, title=title, reference=data.reference, bands=resp.negative_bands
            ),
        ),
        FigureData.of(
            "real_part",
            "Re Z_L(jω) on a symmetric-log axis; shaded: the exact bands where it is negative.",
            plot_real_part(resp),
        ),
        FigureData.of(
            "nyquist",
            "Nyquist plot of Z_L(jω); a passive port stays in the closed right half-plane.",
            plot_nyquist(resp),
        ),
    )


def frequency_section(data: FrequencyData, figures: Sequence[FigureData]) -> Section:
    """The section of `frequency_data` with the figures of `frequency_figures`."""
    resp = data.impedance
    bands = resp.negative_bands
    if bands:
        shown = ", ".join(_band_text(a, b) for a, b in bands)
        text = (
            f"**Re Z_L(jω) < 0 for ω in {shown} rad/s.** There the port returns energy: "
            "the phase of F_L/X_L leaves [0°, 180°] and the Nyquist curve of Z_L enters the "
            "left half-plane."
        )
    else:
        text = (
            "Re Z_L(jω) ≥ 0 at every frequency: the phase of F_L/X_L stays within [0°, 180°] "
            "and the Nyquist curve of Z_L stays in the closed right half-plane (the pole "
            "conditions of the full verdict are in the passivity section)."
        )
    text += (
        " The bands are decided exactly, from the real roots of the real-part polynomial "
        "Re N(jω)D(−jω), not from the plotted grid."
    )
    return Section(
        key="frequency",
        title="Passivity in the frequency domain",
        text=text,
        tables=(
            Table(
                name="negative_real_bands",
                title="Bands where Re Z_L(jω) < 0 (exact)",
                columns=("from ω [rad/s]", "to ω [rad/s]"),
                rows=tuple((a, b) for a, b in bands),
            ),
        ),
        figures=tuple(figures),
        files={"impedance_response.json": to_json(resp.to_dict())},
    )


def stage_frequency(design: Design, context: StageContext) -> Section:
    """Bode of ``F_L/X_L`` with phase, ``Re Z_L(jω)`` with the failing bands, Nyquist of ``Z_L``.

    Budget: frequency points of the drawn curves (the bands are exact, whatever the grid).
    """
    data = frequency_data(design, context.quick, points=context.budget)
    return frequency_section(data, frequency_figures(data))
