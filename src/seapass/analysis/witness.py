"""Destabilizing passive environments: the physical meaning of "not passive".

For a design that fails the positive-real test, `find_destabilizing_environment`
looks for a passive mass-spring-damper environment ``Z_e = m_e s + b_e + k_e/s``
that makes the coupled system unstable, and returns it with the coupled poles
and a simulation of the growing oscillation as evidence.

By default the environment must be physically meaningful: within
[`HUMAN_LIMB`][seapass.analysis.environment_box.HUMAN_LIMB] (0.1–10 kg,
0–100 N·s/m, 0–5000 N/m) or any other
[`EnvironmentBounds`][seapass.analysis.environment_box.EnvironmentBounds].  Not
passive only means that *some* passive environment destabilizes the design; it
may take a 4 mg environment at 16,000 rad/s.  When nothing in the bounds is
found, seapass tries to prove that nothing in the bounds can
([`certify_box`][seapass.analysis.environment_box.certify_box], exact) and says
plainly which: proven, or only not found; and it names an environment outside
the bounds that does destabilize the design.

The search (`seapass.analysis.witness_search`): the Colgate–Hogan construction at
the frequencies where an environment of the box can reach the imaginary axis,
competing with a grid of the box; every candidate verified exactly
([`coupled_stability`][seapass.analysis.coupled.coupled_stability]); the fastest
growth wins and is refined inside the box.  ``bounds=None`` searches without
bounds, starting with the free port.

References
----------
.. [1] J. E. Colgate and N. Hogan, "Robust control of dynamically interacting
   systems", Int. J. Control 48(1), 1988.
.. [2] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Sec. II.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from enum import StrEnum
from typing import Any, TypeAlias

import numpy as np
import sympy as sp
from flint import fmpq_poly

from ..errors import NotPassiveError, ParameterError
from ..exact.halfline import HalfLinePoint
from ..model.display import Shown, html_card, short_repr
from ..model.sea import SEA, Impedance
from ..outcome import Outcome
from .coupled import CoupledResult, Environment, coupled_stability
from .coupled_response import CoupledSimulation, simulate_coupled
from .environment_box import (
    HUMAN_LIMB,
    BoxCertificate,
    EnvironmentBounds,
    certify_box,
    crossing_cells,
)
from .impedance import exact_rational_function
from .passivity import PassivityResult, Reason, is_passive
from .portresponse import reduced_impedance
from .witness_search import (
    Candidate,
    Growth,
    bounded_candidates,
    refine,
    score,
    unbounded_candidates,
)

__all__ = [
    "WitnessResult",
    "WitnessStatus",
    "find_destabilizing_environment",
]

SystemLike: TypeAlias = SEA | Impedance | str | sp.Expr | tuple[Sequence[Any], Sequence[Any]]


class WitnessStatus(StrEnum):
    """What the search for a destabilizing environment ended with."""

    PASSIVE = "passive"
    """The design is passive: no passive environment destabilizes it."""
    FOUND = "found"
    """A destabilizing passive environment within the bounds, verified exactly."""
    NONE_PROVEN = "none in bounds (proven)"
    """Not passive, but proven that no environment in the bounds destabilizes it."""
    NONE_FOUND = "none found"
    """Not passive; none was found in the bounds (a search, not a proof)."""


@dataclass(frozen=True, repr=False, kw_only=True)
class WitnessResult:
    """Outcome of `find_destabilizing_environment`.

    Attributes
    ----------
    outcome : Outcome
        The exact passivity of the design (``passive`` is ``outcome.passive``);
        when passive, no passive environment destabilizes it and ``found`` is False.
    reason : Reason
        The positive-real test's failure code (``""`` when passive).
    found : bool
        A destabilizing passive environment within ``bounds`` was found and
        verified exactly.
    environment : Environment or None
        The environment (``mass, damping, stiffness >= 0``, within ``bounds``).
    method : str
        ``"free port"``, ``"tuned at w0"`` (the construction) or ``"search"``.
    omega : float or None
        The frequency ``ω0`` [rad/s] the environment was tuned at.
    coupled : CoupledResult or None
        Exact verdict and poles of the coupled system.
    simulation : CoupledSimulation or None
        The growing response.
    candidates : int
        Number of environments verified.
    detail : str
        One plain paragraph: what was found, or that nothing in the bounds can
        (proven) or was found (searched).
    bounds : EnvironmentBounds or None
        The box searched (None: no bounds).
    certified : bool
        Proven exactly that no environment in ``bounds`` destabilizes the design
        (only when nothing was found; see
        [`certify_box`][seapass.analysis.environment_box.certify_box]).
    outside : Environment or None
        When nothing in ``bounds`` destabilizes the design: one found without
        bounds that does.
    budget_exhausted : bool
        The search stopped at ``max_candidates`` before trying every candidate
        (nothing found among those tried).
    """

    outcome: Outcome
    reason: Reason
    found: bool
    environment: Environment | None = None
    method: str = ""
    omega: float | None = None
    coupled: CoupledResult | None = None
    simulation: CoupledSimulation | None = None
    candidates: int = 0
    detail: str = ""
    passivity: PassivityResult | None = field(default=None, repr=False)
    bounds: EnvironmentBounds | None = None
    certified: bool = False
    outside: Environment | None = None
    budget_exhausted: bool = False

    def to_dict(self) -> dict[str, Any]:
        return {
            "passive": self.passive,
            "reason": self.reason,
            "found": self.found,
            "detail": self.detail,
            "environment": self.environment.to_dict() if self.environment else None,
            "method": self.method,
            "omega": self.omega,
            "candidates": self.candidates,
            "bounds": self.bounds.to_dict() if self.bounds else None,
            "certified": self.certified,
            "outside": self.outside.to_dict() if self.outside else None,
            "coupled": self.coupled.to_dict() if self.coupled else None,
            "max_real_part": self.coupled.max_real_part if self.coupled else None,
            "simulation": self.simulation.to_dict() if self.simulation else None,
            "budget_exhausted": self.budget_exhausted,
        }

    @property
    def passive(self) -> bool:
        return self.outcome.passive

    @property
    def status(self) -> WitnessStatus:
        """How the search ended (`WitnessStatus`)."""
        if self.passive or self.found:
            return WitnessStatus.PASSIVE if self.passive else WitnessStatus.FOUND
        return WitnessStatus.NONE_PROVEN if self.certified else WitnessStatus.NONE_FOUND

    def plot(self, *, axes: Any = None, **kwargs: Any) -> Any:
        """The growing coupled response and the coupled poles (needs ``found`` and a simulation).

        Parameters
        ----------
        axes : sequence of two matplotlib.axes.Axes, optional
            Where to draw; a new figure if None.
        **kwargs
            Passed to [`plot_witness`][seapass.plot.witness.plot_witness] (``title``).

        Returns
        -------
        numpy.ndarray of matplotlib.axes.Axes
        """
        from ..plot.witness import plot_witness

        return plot_witness(self, axes=axes, **kwargs)

    def __repr__(self) -> str:
        env = self.environment if self.found else self.outside
        shown = None if env is None else Shown(_environment_repr(env))
        return short_repr(
            "WitnessResult",
            {
                "status": self.status.value,
                "reason": str(self.reason) or None,
                ("environment" if self.found else "outside"): shown,
                "growth_rate": self.coupled.max_real_part if self.coupled else None,
                "omega": self.omega,
            },
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [
            ("verdict", "passive" if self.passive else f"not passive ({self.reason})")
        ]
        if self.environment is not None:
            rows.append(("environment", _environment_text(self.environment)))
        if self.coupled is not None:
            rows.append(
                (
                    "coupled system",
                    f"{self.coupled.status}, max Re s = {self.coupled.max_real_part_text}",
                )
            )
        if self.simulation is not None:
            rows.append(("growth over the run", self.simulation.growth_text))
        if self.outside is not None:
            rows.append(("outside the bounds", _environment_text(self.outside)))
        if self.bounds is not None:
            rows.append(("bounds", self.bounds.describe()))
        rows += [("method", self.method or "-"), ("environments verified", self.candidates)]
        return html_card(f"Destabilizing environment: {self.status}", rows, note=self.detail)


def _environment_repr(env: Environment) -> str:
    fields = {"mass": env.mass, "damping": env.damping, "stiffness": env.stiffness}
    return short_repr("Environment", fields)


def _environment_text(env: Environment) -> str:
    return f"m_e = {env.mass:.4g} kg, b_e = {env.damping:.4g} N*s/m, k_e = {env.stiffness:.4g} N/m"


# ---------------------------------------------------------------- entry point


def find_destabilizing_environment(
    system: SystemLike,
    *,
    bounds: EnvironmentBounds | None = HUMAN_LIMB,
    values: Mapping[str, float] | None = None,
    simulate: bool = True,
    throw: bool = False,
    max_candidates: int | None = None,
) -> WitnessResult:
    """Find a passive environment within ``bounds`` that destabilizes a non-passive design.

    Parameters
    ----------
    system : SEA, Impedance, str, sympy.Expr or (num, den)
        The design (its port impedance is used), with numeric values.
    bounds : EnvironmentBounds or None, default HUMAN_LIMB
        The environments allowed (a human limb: 0.1–10 kg, 0–100 N·s/m,
        0–5000 N/m); None for any passive mass-spring-damper.
    values : mapping, optional
        Parameter values overriding those stored in ``system``.
    simulate : bool, default True
        Also simulate the growing response (`simulate_coupled`).
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] describing the witness
        when one is found (for scripts that must stop on unsafe designs).
    max_candidates : int, optional
        Budget of the search in candidate environments scored exactly (counted, not
        timed; default: every candidate).  When it runs out first,
        ``budget_exhausted`` is set; the exact certificate over ``bounds`` is still
        tried.

    Returns
    -------
    WitnessResult
        ``found`` is False for a passive design (none exists, by the passivity
        theorem) and when nothing in ``bounds`` was found; then ``certified``
        says whether that is proven, and ``outside`` names an environment beyond
        the bounds that does destabilize the design.

    Examples
    --------
    >>> from seapass import SEA
    >>> lp = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=2000))
    >>> w = find_destabilizing_environment(lp, simulate=False)
    >>> w.found, w.coupled.rhp, 0.1 <= w.environment.mass <= 10
    (True, True, True)
    """
    if max_candidates is not None and (
        isinstance(max_candidates, bool)
        or not isinstance(max_candidates, int)
        or max_candidates < 1
    ):
        raise ParameterError(
            f"max_candidates must be a positive whole number, got {max_candidates!r}",
            argument="max_candidates",
        )
    pr = is_passive(system, values=values)
    if pr.passive:
        return WitnessResult(
            outcome=pr.outcome,
            reason=pr.reason,
            found=False,
            detail="passive: no passive environment can destabilize it (passivity theorem)",
            passivity=pr,
            bounds=bounds,
        )
    num, den = exact_rational_function(system, values)
    if den.leading_coefficient() < 0:
        num, den = -num, -den
    rn, rd = reduced_impedance(num, den)  # num != 0: a zero Z is passive, returned above
    stages: list[tuple[str, list[Candidate]]]
    if bounds is None:
        stages = [
            ("free port", [(Environment(), None)]),
            ("tuned at w0", unbounded_candidates(rn, rd)),
        ]
        cells = None
    else:
        cells = crossing_cells(rn, rd, bounds) if not rn.is_zero() else []
        stages = [("tuned at w0", bounded_candidates(rn, rd, bounds, cells))]
    hit, count = _search(num, den, stages, bounds, max_candidates)
    if hit is not None:
        method, env, w0 = hit
        coupled = coupled_stability(system, env, values=values)
        return _found(system, values, pr, method, env, w0, coupled, count, simulate, throw, bounds)
    stopped = max_candidates is not None and max_candidates < sum(len(c) for _m, c in stages)
    return replace(_not_found(num, den, rn, rd, pr, count, bounds, cells), budget_exhausted=stopped)


def _search(
    num: fmpq_poly,
    den: fmpq_poly,
    stages: list[tuple[str, list[Candidate]]],
    bounds: EnvironmentBounds | None,
    budget: int | None = None,
) -> tuple[tuple[str, Environment, float | None] | None, int]:
    """Score every candidate exactly (at most ``budget``), stage by stage; the fastest
    growth of the first stage with one wins and is refined.  ``(method, environment,
    ω0)`` or None."""
    count = 0
    fallback: tuple[str, Environment, float | None] | None = None
    for method, cands in stages:
        best: tuple[float, Environment, float | None] | None = None
        for env, wc in cands:
            if budget is not None and count >= budget:
                break
            count += 1
            growth, rate = score(num, den, env)
            if growth is Growth.RHP and (best is None or rate > best[0]):
                best = (rate, env, wc)
            elif growth is Growth.REPEATED_AXIS and fallback is None:
                fallback = (method, env, wc)
        if best is not None:
            env, extra = refine(num, den, best[1], best[0], bounds)
            count += extra
            if best[2] is None and method != "free port":
                method = "search"
            return (method, env, best[2]), count
    return fallback, count


def _not_found(
    num: fmpq_poly,
    den: fmpq_poly,
    rn: fmpq_poly,
    rd: fmpq_poly,
    pr: PassivityResult,
    count: int,
    bounds: EnvironmentBounds | None,
    cells: list[tuple[HalfLinePoint, bool]] | None,
) -> WitnessResult:
    """Nothing found: prove that nothing in the box can, if possible, and look outside it."""
    where = "" if bounds is None else f" within {bounds.describe()}"
    if bounds is None:
        return WitnessResult(
            outcome=pr.outcome, reason=pr.reason, found=False, candidates=count, passivity=pr,
            detail=f"not passive ({pr.reason.description}), but none of {count} mass-spring-damper "
            "environments tried destabilizes it",
        )  # fmt: skip
    cert = certify_box(num, den, bounds, cells)
    outside, extra = _search(
        num, den, [("free port", [(Environment(), None)]), ("search", unbounded_candidates(rn, rd))],
        None,
    )  # fmt: skip
    beyond = ""
    if outside is not None:
        e = outside[1]
        beyond = (
            f" Outside the bounds, m_e = {e.mass:.4g} kg, b_e = {e.damping:.4g} N*s/m, "
            f"k_e = {e.stiffness:.4g} N/m does."
        )
    return WitnessResult(
        outcome=pr.outcome,
        reason=pr.reason,
        found=False,
        candidates=count + extra,
        passivity=pr,
        bounds=bounds,
        certified=cert.certified,
        outside=None if outside is None else outside[1],
        detail=_not_found_text(pr, count, where, cert) + beyond,
    )


def _not_found_text(pr: PassivityResult, count: int, where: str, cert: BoxCertificate) -> str:
    if cert.certified:
        return (
            f"not passive ({pr.reason.description}), but no passive environment{where} destabilizes it: "
            "proven exactly (no environment in these bounds puts a coupled pole on the "
            "imaginary axis, and one of them is stable)."
        )
    return (
        f"not passive ({pr.reason.description}); none of {count} passive environments{where} tried "
        f"destabilizes it, but this is a search, not a proof ({cert.reason})."
    )


def _found(
    system: SystemLike,
    values: Mapping[str, float] | None,
    pr: PassivityResult,
    method: str,
    env: Environment,
    w0: float | None,
    coupled: CoupledResult,
    count: int,
    simulate: bool,
    throw: bool,
    bounds: EnvironmentBounds | None,
) -> WitnessResult:
    sim, note = None, ""
    if simulate:
        try:
            sim = simulate_coupled(system, env, values=values)
        except (ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
            note = f" (no simulation: {exc})"
    kind = (
        (
            f"a pole at Re s = {coupled.max_real_part:.4g} 1/s"
            if math.isfinite(coupled.max_real_part)
            else "a pole in the open right half-plane (decided exactly)"
        )
        if coupled.rhp
        else "a repeated pole on the imaginary axis"
    )
    within = "" if bounds is None else f" (within {bounds.describe()})"
    detail = (
        f"not passive ({pr.reason.description}); the passive environment m_e = {env.mass:.6g} kg, "
        f"b_e = {env.damping:.6g} N*s/m, k_e = {env.stiffness:.6g} N/m{within} makes the "
        f"coupled system unstable: {kind}{note}"
    )
    if throw:
        raise NotPassiveError(detail)
    return WitnessResult(
        outcome=pr.outcome,
        reason=pr.reason,
        found=True,
        environment=env,
        method=method,
        omega=w0,
        coupled=coupled,
        simulation=sim,
        candidates=count,
        detail=detail,
        passivity=pr,
        bounds=bounds,
    )
