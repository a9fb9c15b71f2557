"""The robust gain envelope of a deployment: the guards narrowed by a box of plants.

With ``export_c(..., robust=True)`` (``seapass export c --robust [RIGFILE]``) the
design's box (its ``uncertainty``: the file's ``[uncertainty]``, or a fitted rig's
intervals resolved by [`robust_box`][seapass.rig.robustbox.robust_box]) narrows
the envelope that ``seapass_ctrl_set_gains`` enforces:

* the design must be passive for every plant in the box
  ([`robust_check`][seapass.robust.verdict.robust_check]), else the export is refused;
* each tunable gain's interval is the intersection of its sampled-data certified
  interval at the nominal plant ([`seapass.export.envelope`][seapass.export.envelope])
  and the robust passive interval of that gain containing its value
  ([`robust_passive_intervals`][seapass.robust.intervals.robust_passive_intervals],
  ends rounded inward), so a gain the guard accepts is passive at the sampling
  rate for the nominal plant and, in continuous time, for every plant of the box.

Robust *sampled-data* passivity over practical boxes is not available yet (see
[`robust_sampled_check`][seapass.robust.sampled_verdict.robust_sampled_check]): the
envelope claims the sampled rate for the nominal plant only, and the header says so.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from fractions import Fraction

from ..errors import NotPassiveError, ParameterError
from ..exact.rounding import exact_text
from ..model.design_file import Design
from ..robust.box import UncertainBox, uncertain_box
from ..robust.intervals import robust_passive_intervals
from ..robust.verdict import DEFAULT_BUDGET, robust_check
from .envelope import GainEnvelope, inward_interval

__all__ = ["design_box", "robust_envelopes"]


def design_box(design: Design) -> UncertainBox:
    """The design's box, checked; a `ParameterError` without ``[uncertainty]``."""
    if not design.uncertainty:
        raise ParameterError(
            f"design {design.name!r} has no [uncertainty] table: add one (e.g. m = [0.9, 1.1]) "
            "or give a fitted rig's box, to bake a robust gain envelope into the guards"
        )
    return uncertain_box(design.sea(), dict(design.uncertainty))


def robust_envelopes(
    design: Design,
    envelopes: Sequence[GainEnvelope],
    *,
    budget: int = DEFAULT_BUDGET,
) -> tuple[tuple[GainEnvelope, ...], tuple[str, ...]]:
    """``envelopes`` narrowed to the robust passive set of each tunable gain, and notes.

    Raises
    ------
    ParameterError
        Without ``[uncertainty]``, or a tunable gain that is also uncertain.
    NotPassiveError
        When the design is not passive for every plant of the box (or undecided).
    """
    box = design_box(design)
    sea = design.sea()
    verdict = robust_check(sea, box=box, budget=budget)
    if not verdict.passive:
        raise NotPassiveError(
            f"refusing a robust export of {design.name!r}: {verdict.outcome.label} for every "
            f"plant of the box ({verdict.detail}); narrow the box or lower the gains"
        )
    out, notes = [], []
    for env in envelopes:
        if not env.tunable or env.search is None:
            out.append(env)
            continue
        if env.name in box.intervals:
            raise ParameterError(f"{env.name} is uncertain; it cannot also be a tunable gain")
        free = sea.with_values(**{env.name: None})
        res = robust_passive_intervals(free, env.name, *env.search, box=box, budget=budget)
        nominal = Fraction(env.nominal)
        hit = [(a, b) for a, b in res.intervals if Fraction(a) <= nominal <= Fraction(b)]
        if not hit:
            notes.append(
                f"{env.name}: its value {env.nominal:g} lies in no certified robust interval; "
                "only that value is allowed"
            )
            exact = (nominal, nominal)
        else:
            a, b = hit[0]
            exact = (max(env.exact[0], Fraction(a)), min(env.exact[1], Fraction(b)))
        low, high = inward_interval(*exact)
        out.append(
            replace(env, low=min(low, env.nominal), high=max(high, env.nominal), exact=exact)
        )
    span = ", ".join(
        f"{k} in [{exact_text(a)}, {exact_text(b)}]" for k, (a, b) in box.intervals.items()
    )
    notes.append(
        f"gain envelope robust for every plant with {span} in continuous time "
        f"({verdict.method}); passive at the sampling rate for the nominal plant only"
    )
    return tuple(out), tuple(notes)
