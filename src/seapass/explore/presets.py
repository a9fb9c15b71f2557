"""Designs the explorer offers by name: the paper's LP, APD and Ours, and every Table I/II row.

All of them come from the one catalog (`seapass.model.catalog`); their
parameters start at the catalog's reference values (the paper's plant), their
sliders at the catalog's search boxes, and the sampled verdict at the paper's
500 Hz control rate.
"""

from __future__ import annotations

from typing import Any

from ..model.catalog import SIMULATION_DESIGNS, TABLE_ROWS, CatalogDesign
from ..model.design_file import Design

__all__ = ["PAPER_PERIOD", "design_state", "preset_state", "presets"]

#: Control period of the paper's bench (500 Hz), the sampled verdict's starting point.
PAPER_PERIOD = 0.002


def design_state(design: Design) -> dict[str, Any]:
    """The explorer view of a design file (at its tuning load mass)."""
    state: dict[str, Any] = {
        "name": design.name,
        "title": design.title,
        "model": {"D1": design.D1, "D2": design.D2, "CA": design.CA, "CL": design.CL},
        "values": dict(design.values),
        "ranges": {k: list(v) for k, v in design.ranges.items()},
        "load_mass": design.tuning_mass,
        "step": design.step,
        "horizon": design.horizon,
        "period": design.period,
        "delay": design.control_delay,
        "velocity_filter": design.velocity_filter,
        "plant": list(design.plant),
        "uncertainty": {k: list(v) for k, v in design.uncertainty.items()},
        "delay_time": design.delay_time,
    }
    if "kd" in design.values:
        state["gain"] = "kd"
    return state


def preset_state(entry: CatalogDesign) -> dict[str, Any]:
    """The explorer view of a catalog design (values filled in by the state check)."""
    return {
        "name": entry.key.replace("/", "-"),
        "title": entry.title,
        "model": entry.elements(),
        "values": {},  # every parameter gets its reference value
        "ranges": {k: list(v) for k, v in entry.ranges.items()},
        "gain": "kd",
        "period": PAPER_PERIOD,
    }


def presets() -> list[dict[str, Any]]:
    """Every preset as ``{"id", "label", "group", "state"}``, in the paper's order."""
    out = []
    for entry in (*SIMULATION_DESIGNS, *TABLE_ROWS):
        if entry.table in ("I", "II"):
            group = f"Table {entry.table}"
        elif entry.table:
            group = "proposed"
        else:
            group = "paper designs"
        key = "Ours" if entry.key == "ours" else entry.key
        out.append(
            {
                "id": key,
                "label": entry.label if not entry.table else f"{group}: {entry.title}",
                "group": group,
                "state": preset_state(entry),
            }
        )
    return out
