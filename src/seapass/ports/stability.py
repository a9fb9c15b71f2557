"""`absolute_stability`: Llewellyn's criterion with η and a witness pair, as one result.

The conditions are those of [`seapass.ports.llewellyn`][seapass.ports.llewellyn];
this module gathers them with the infimum of η
([`seapass.ports.eta`][seapass.ports.eta]) and, when the two-port is not
absolutely stable, a verified pair of destabilizing passive terminations
([`seapass.ports.witness`][seapass.ports.witness]).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..analysis.environment_box import HUMAN_LIMB, EnvironmentBounds
from ..errors import NotPassiveError, ParameterError
from ..model.display import Shown, html_card, short_repr
from ..model.sea import SEA
from ..outcome import Outcome
from .bands import Band, Condition, combine
from .eta import EtaKind, EtaMinimum
from .llewellyn import frequency_polynomials, llewellyn_conditions, llewellyn_eta
from .matrix import ExactMatrix
from .passivity import evaluate, frequency_grid
from .twoport import TwoPort, two_port
from .witness import VIRTUAL_ENVIRONMENT, TerminationWitness, find_destabilizing_pair

__all__ = ["AbsoluteStability", "absolute_stability", "as_two_port", "eta_text"]


def as_two_port(system: TwoPort | SEA, values: Mapping[str, float] | None = None) -> TwoPort:
    """``system`` as a `TwoPort` (an SEA through [`two_port`][seapass.ports.twoport.two_port])."""
    if isinstance(system, SEA):
        return two_port(system, values=values)
    if isinstance(system, TwoPort):
        return system.with_values(**values) if values else system
    raise ParameterError(
        f"system: expected a TwoPort or an SEA, got {type(system).__name__}", argument="system"
    )


@dataclass(frozen=True, kw_only=True, repr=False)
class AbsoluteStability:
    """Exact absolute stability of a two-port (Llewellyn), with η and a witness.

    Attributes
    ----------
    outcome : Outcome
        ``PASSIVE`` means *absolutely stable*: stable with every pair of passive
        terminations; ``NOT_PASSIVE``: some pair destabilizes it; ``UNDECIDED``:
        a case the exact test cannot settle (never reported as stable).
    conditions : tuple of Condition
        Each of Llewellyn's conditions with its failing bands.
    eta : EtaMinimum
        ``inf_ω η(ω)`` (certified enclosure, where it is attained or its limit).
    witness : TerminationWitness or None
        A verified destabilizing pair of passive terminations (only when not
        absolutely stable and a search was asked for).
    form : str
        The form the criterion was applied in.
    matrix : ExactMatrix
        The exact two-port (for `response` and `plot`).
    """

    outcome: Outcome
    conditions: tuple[Condition, ...]
    eta: EtaMinimum
    witness: TerminationWitness | None = None
    form: str = "z"
    matrix: ExactMatrix | None = field(default=None, compare=False)

    @property
    def absolutely_stable(self) -> bool:
        """Certified absolutely stable."""
        return self.outcome.passive

    @property
    def bands(self) -> tuple[Band, ...]:
        """Every failing band of the frequency conditions, sorted."""
        return tuple(sorted((b for c in self.conditions for b in c.bands), key=lambda b: b.lo))

    @property
    def failing(self) -> tuple[Condition, ...]:
        return tuple(c for c in self.conditions if c.holds is False)

    def to_dict(self) -> dict[str, Any]:
        return {
            "absolutely_stable": None
            if self.outcome is Outcome.UNDECIDED
            else self.absolutely_stable,
            "outcome": self.outcome.value,
            "form": self.form,
            **self.eta.to_dict(),
            "conditions": [c.to_dict() for c in self.conditions],
            "witness": self.witness.to_dict() if self.witness and self.witness.found else None,
        }

    def response(self, omega: Any = None) -> dict[str, Any]:
        """η(ω), ``Re p11``, ``Re p22`` on a grid (floats, for pictures) and the exact bands."""
        if self.matrix is None:
            raise ValueError("this result holds no matrix to evaluate")
        w = (
            frequency_grid(self.matrix, self.bands)
            if omega is None
            else np.asarray(omega, dtype=float)
        )
        p = evaluate(self.matrix, w)
        q = p[:, 0, 1] * p[:, 1, 0]
        a = 2 * p[:, 0, 0].real * p[:, 1, 1].real - q.real
        with np.errstate(all="ignore"):
            eta = np.where(np.abs(q) > 0, a / np.abs(q), np.nan)
        return {
            "omega": w,
            "eta": eta,
            "re_p11": p[:, 0, 0].real,
            "re_p22": p[:, 1, 1].real,
            "bands": [b.to_list() for b in self.bands],
            "eta_min": self.eta.value,
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """η(ω) with the line η = 1 and the exact failing bands shaded; returns the Axes."""
        from ..plot.ports import plot_eta

        return plot_eta(self, ax=ax, **kwargs)

    def __repr__(self) -> str:
        failing = ", ".join(c.name for c in self.failing)
        eta = self.eta.value
        return short_repr(
            "AbsoluteStability",
            {
                "outcome": self.outcome.value,
                "eta_min": eta if not math.isnan(eta) else None,
                "failing": Shown(failing) if failing else None,
                "witness": self.witness.found if self.witness else None,
            },
        )

    def _repr_html_(self) -> str:
        label = {Outcome.PASSIVE: "absolutely stable", Outcome.NOT_PASSIVE: "not absolutely stable"}
        verdict = label.get(self.outcome, "undecided")
        rows: list[tuple[str, Any]] = [("verdict", verdict), ("inf η", eta_text(self.eta))]
        rows += [
            (
                c.name,
                "holds" if c.holds else ("undecided" if c.holds is None else f"fails: {c.detail}"),
            )
            for c in self.conditions
        ]
        if self.witness is not None and self.witness.found:
            rows.append(("witness", self.witness.detail))
        return html_card(f"Absolute stability: {verdict}", rows, note="Exact verdict (Llewellyn).")


def eta_text(e: EtaMinimum) -> str:
    """``inf η`` in words: its value and where it is attained or approached."""
    if e.kind is EtaKind.UNDEFINED:
        return "undefined (p12 p21 = 0)"
    if e.kind is EtaKind.UNBOUNDED:
        return f"-inf (next to w = {e.limit:.6g} rad/s)"
    if e.kind is EtaKind.ATTAINED:
        return f"{e.value:.6g} at w = {e.omega:.6g} rad/s"
    return f"{e.value:.6g} as w -> {e.limit:.6g}"


def absolute_stability(
    system: TwoPort | SEA,
    *,
    values: Mapping[str, float] | None = None,
    witness: bool = True,
    bounds: tuple[EnvironmentBounds | None, EnvironmentBounds | None] = (
        HUMAN_LIMB,
        VIRTUAL_ENVIRONMENT,
    ),
    throw: bool = False,
) -> AbsoluteStability:
    """Decide exactly whether a two-port is stable with every pair of passive terminations.

    Parameters
    ----------
    system : TwoPort or SEA
        The two-port (any form), or an SEA (its person–environment two-port).
    values : mapping, optional
        Parameter values overriding those stored in ``system``.
    witness : bool, default True
        When not absolutely stable, search a destabilizing pair of terminations.
    bounds : (EnvironmentBounds or None, EnvironmentBounds or None)
        Boxes of the terminations of port 1 and port 2 for the witness search
        (default: a human limb, a virtual environment); None for unbounded.
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] unless
        certified absolutely stable.

    Returns
    -------
    AbsoluteStability

    Examples
    --------
    >>> from seapass import SEA
    >>> coupling = SEA(D1="k1 + b1*s", CA="kc + bc*s",
    ...                values=dict(m=1, b=10, k1=1000, b1=20, kc=500, bc=25))
    >>> r = absolute_stability(coupling)
    >>> r.absolutely_stable, r.eta.value >= 1
    (True, True)
    """
    tp = as_two_port(system, values)
    m = tp.exact()
    polys = frequency_polynomials(m)
    conds = llewellyn_conditions(m, tp.form.value, polys)
    outcome = combine([c.outcome for c in conds])
    eta = llewellyn_eta(m, polys)
    found = None
    if witness and outcome is Outcome.NOT_PASSIVE:
        bands = [b for c in conds for b in c.bands]
        found = find_destabilizing_pair(m, tp.form, bands, bounds=bounds)
    result = AbsoluteStability(
        outcome=outcome,
        conditions=tuple(conds),
        eta=eta,
        witness=found,
        form=tp.form.value,
        matrix=m,
    )
    if throw and not result.absolutely_stable:
        failing = ", ".join(c.name for c in result.failing) or "undecided"
        raise NotPassiveError(f"not absolutely stable: {failing}")
    return result
