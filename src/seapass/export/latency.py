"""The latency guard of ``export c``: ``τ*`` must cover the stated loop latency.

A design file's ``[control] delay_time`` (or ``latency=`` / ``--latency SECONDS``) is the
continuous loop latency of the deployed controller: bus, computation, a remote master,
modelled as ``C_A``, ``C_L`` times ``exp(-delay_time*s)``
([`seapass.model.latency`][seapass.model.latency]).  `latency_guard` runs
[`latency_check`][seapass.delay.latency.latency_check] and certifies the export only
when every delay in ``[0, latency]`` is certified passive (``latency <= lo`` of ``τ*``,
or passive for every delay); otherwise it raises
[`NotPassiveError`][seapass.errors.NotPassiveError] (``seapass export c``: one
``error:`` line, exit 2), unless ``allow_nonpassive`` exports it marked NOT CERTIFIED.
This guard is separate from, and in addition to, the sampled-data check at ``[control]
rate`` and ``delay`` (whole samples).  `latency_banner` gives the lines the generated
header records (``τ*`` and the latency; escaped as comments by the template).

Without a stated latency there is no guard (and no lines).
"""

from __future__ import annotations

from typing import Any

from ..delay.latency import LatencyCheck, latency_check
from ..errors import NotPassiveError
from ..exact.rounding import decimal_down, enclosure_text

__all__ = ["latency_banner", "latency_guard"]


def latency_guard(
    design: Any, latency: float | None = None, *, allow_nonpassive: bool = False
) -> LatencyCheck | None:
    """The latency check of an export (None when no latency is stated).

    Parameters
    ----------
    design : Design
        The design file's design; its ``[control] delay_time`` is the latency unless
        ``latency`` is given.
    latency : float, optional
        The loop latency [s] replacing the design's (``0 <= latency <= 1000``).
    allow_nonpassive : bool
        Return a check that is not certified instead of raising.

    Raises
    ------
    NotPassiveError
        When some delay in ``[0, latency]`` is not certified passive (unless
        ``allow_nonpassive``).
    ParameterError
        For a latency out of range.
    """
    if latency is None and getattr(design, "delay_time", None) is None:
        return None
    check = latency_check(design, latency=latency)
    if not check.certified and not allow_nonpassive:
        raise NotPassiveError(
            f"the loop latency {check.latency:g} s is not certified ({check.outcome.label}): "
            f"{check.detail}; lower the latency or the gains, or export anyway with "
            "allow_nonpassive=True (marked NOT CERTIFIED)"
        )
    return check


def latency_banner(check: LatencyCheck | None) -> list[str]:
    """Comment lines of the header: the latency, ``τ*`` and the verdict (none without a check)."""
    if check is None:
        return []
    m = check.margin
    if m.delay_independent:
        star = "passive for every delay (delay-independent)"
    elif m.tau_star is not None and m.tau_star[1] == 0:
        star = f"tau* = 0 (exact): every delay > 0 breaks passivity ({m.loss})"
    elif m.tau_star is not None:
        lo, hi = m.tau_star
        where = f" at w = {m.frequency:.6g} rad/s" if m.frequency is not None else ""
        star = (
            f"tau* in {enclosure_text(lo, hi, digits=6)} s (passive for every delay up to "
            f"{decimal_down(lo, 6)} s; lost{where}, {m.loss})"
        )
    else:
        star = f"tau* none: {m.detail}"
    head = (
        "Loop latency (certified by seapass at export time):"
        if check.certified
        else "*** NOT CERTIFIED for the loop latency (exported on explicit request) ***"
    )
    return [
        "",
        head,
        f"  latency {check.delay} = {check.latency:g} s on C_A and C_L "
        f"(times exp(-{check.delay}*s)): {check.outcome.label}",
        f"  {star}",
        f"  {check.detail}",
    ]
