"""The explorer's ``delay`` panel: the passivity delay margin ``τ*`` at the slider values.

A readout beside the continuous and sampled verdicts: the certified enclosure of ``τ*``
of the current design with ``C_A`` and ``C_L`` delayed (``exp(-delay_time*s)``, as a
design file's ``[control] delay_time`` means), the frequency and the kind of the loss, and
whether the design is passive for every delay, and with the view's loop latency
(``delay_time``) whether every delay up to it is certified passive; a model with its own ``exp(-NAME*s)`` uses
that delay.  Computed by [`latency_check`][seapass.delay.latency.latency_check] with the
default ``rtol`` and a counted budget (`PANEL_BUDGET` pieces of the branch and bound), so
the panel shows the same ``τ*`` as ``seapass.delay_margin``; what the budget does not
settle is shown as ``undecided``, never as a margin.  The printed ends round outward (the
lower end down: every delay up to it is certified passive).
"""

from __future__ import annotations

from typing import Any

from ..delay.latency import latency_check
from ..delay.margin import DEFAULT_MARGIN_BUDGET
from ..exact.rounding import decimal_down, decimal_up
from ..model.delayatom import model_delays
from .state import ExploreState

__all__ = ["PANEL_BUDGET", "delay_panel"]

PANEL_BUDGET = DEFAULT_MARGIN_BUDGET
"""Pieces of each certified search of the panel (the default of ``delay_margin``)."""


def delay_panel(state: ExploreState) -> dict[str, Any]:
    """``τ*`` of the state's design as plain JSON data (see the module)."""
    sea = state.sea()
    if state.model.get("CA", "0") == "0" and state.model.get("CL", "0") == "0":
        if not model_delays(sea):
            return {"analysed": False, "detail": "no controller (C_A = C_L = 0) to delay"}
    latency = state.delay_time or None  # 0 s: no latency, only tau*
    c = latency_check(sea, latency=latency, budget=PANEL_BUDGET)
    m = c.margin
    star = m.tau_star
    return {
        "analysed": True,
        "delay": c.delay,
        "outcome": str(m.outcome),
        "status": m.outcome.label,
        "tau_star": None if star is None else list(star),
        "shown": None if star is None else [decimal_down(star[0], 6), decimal_up(star[1], 6)],
        "frequency": m.frequency,
        "loss": None if m.loss is None else str(m.loss),
        "delay_independent": m.delay_independent,
        "passive_at_zero": m.passive_at_zero,
        "certified": m.certified,
        "detail": m.detail,
        "latency": c.latency,
        "at_latency": None if c.at_latency is None else c.at_latency.status,
        "latency_outcome": str(c.outcome),  # every delay in [0, latency] (certified)
        "latency_detail": c.detail,
        "evaluations": m.evaluations,
        "budget": PANEL_BUDGET,
    }
