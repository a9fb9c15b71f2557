"""A pair of passive terminations that destabilizes a two-port that is not absolutely stable.

Construction.  Close port 2 with ``T2``; port 1 then sees
``Z_in = p11 − p12 p21/(p22 + T2)``.  At a frequency ``ω0`` where Llewellyn's
inequality fails, the termination with ``Re T2 = 0`` and
``Im T2 = y − Im p22(jω0)``, ``y = Re p22 (|q| − Re q)/Im q`` (``q = p12 p21``),
maximizes ``Re(q/(p22 + T2))`` to ``(|q| + Re q)/(2 Re p22)``, so
``Re Z_in(jω0) = Re p11 − (|q| + Re q)/(2 Re p22) < 0``: ``Z_in`` is not
positive real, and the one-port construction of
[`seapass.analysis.witness_search`][seapass.analysis.witness_search] finds a
termination of port 1 that destabilizes it.  The port-2 termination is fitted
as a mass–spring–damper inside its box (damping at its lower bound, reactance
``m ω0 − k/ω0``); a grid of the box and the free and the stiffest ports compete.
The failing conditions on ``p22`` alone are met the same way with the ports
exchanged.  Every pair is verified by the exact closed-loop polynomial
([`seapass.ports.closedloop`][seapass.ports.closedloop]); the first with a pole
in the open right half-plane wins.

The environments are physical by default: port 1 a human limb
([`HUMAN_LIMB`][seapass.analysis.environment_box.HUMAN_LIMB]), port 2 a virtual
environment (`VIRTUAL_ENVIRONMENT`: up to 100 kg, 1000 N·s/m and 10⁵ N/m, a
stiff virtual wall).  When nothing in the boxes is found, the search is repeated
without bounds and the result says so.

References
----------
.. [1] F. B. Llewellyn, "Some fundamental properties of transmission systems",
   Proc. IRE 40(3), 1952.
.. [2] J. E. Colgate and N. Hogan, "Robust control of dynamically interacting
   systems", Int. J. Control 48(1), 1988.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analysis.coupled import Environment, classify_polynomial
from ..analysis.environment_box import HUMAN_LIMB, EnvironmentBounds
from ..analysis.passivity import positive_real_test
from ..analysis.witness_search import bounded_candidates, unbounded_candidates
from ..outcome import Outcome
from .bands import Band
from .closedloop import (
    ClosedLoop,
    closed_loop,
    closed_loop_polynomial,
    impedance_form,
    input_immittance,
)
from .forms import Form, form_of
from .matrix import ExactMatrix
from .passivity import evaluate

__all__ = ["MAX_PAIRS", "VIRTUAL_ENVIRONMENT", "TerminationWitness", "find_destabilizing_pair"]

VIRTUAL_ENVIRONMENT = EnvironmentBounds(
    mass=(0.0, 100.0), damping=(0.0, 1000.0), stiffness=(0.0, 1e5)
)
"""Default box of the environment on port 2: a virtual object or wall."""

MAX_PAIRS = 600
"""Upper bound on the termination pairs verified exactly in one search (a bound on the work)."""

MAX_ATTACKS = 30
"""Terminations of the attacked port tried against one termination of the other port."""


@dataclass(frozen=True, kw_only=True)
class TerminationWitness:
    """A destabilizing pair of passive terminations, verified exactly.

    Attributes
    ----------
    outcome : Outcome
        ``NOT_PASSIVE`` (proven not absolutely stable) when the closed loop of
        the pair has a pole in the open right half-plane, else ``UNDECIDED``
        (a search that finds nothing proves nothing).
    found : bool
        A pair was found and verified (``outcome`` is ``NOT_PASSIVE``).
    port1, port2 : Environment or None
        The terminations (mass, damping, stiffness) of ports 1 and 2.
    within_bounds : bool
        Both lie in the boxes searched.
    omega : float or None
        The frequency [rad/s] the construction was tuned at.
    closed_loop : ClosedLoop or None
        The exact verdict and the poles of the closed loop.
    pairs : int
        Pairs verified.
    detail : str
        One plain sentence.
    """

    port1: Environment | None = None
    port2: Environment | None = None
    within_bounds: bool = False
    omega: float | None = None
    closed_loop: ClosedLoop | None = None
    pairs: int = 0
    detail: str = ""

    @property
    def outcome(self) -> Outcome:
        """Decided by the exact closed-loop verdict of the pair held."""
        return self.closed_loop.outcome if self.closed_loop is not None else Outcome.UNDECIDED

    @property
    def found(self) -> bool:
        return self.outcome is Outcome.NOT_PASSIVE

    def to_dict(self) -> dict[str, Any]:
        return {
            "found": self.found,
            "port1": self.port1.to_dict() if self.port1 else None,
            "port2": self.port2.to_dict() if self.port2 else None,
            "within_bounds": self.within_bounds,
            "omega": self.omega,
            "pairs": self.pairs,
            "max_real_part": self.closed_loop.max_real_part if self.closed_loop else None,
            "closed_loop": self.closed_loop.to_dict() if self.closed_loop else None,
            "detail": self.detail,
        }


def _fit(z: complex, w0: float, box: EnvironmentBounds | None) -> list[Environment]:
    """Mass–spring–dampers with ``Z(jw0)`` close to ``z`` (damping clipped), inside ``box``."""
    b = max(z.real, 0.0)
    x = z.imag  # m w0 − k/w0 = x
    out = []
    if box is None:
        for m in (max(x / w0, 0.0), max(x / w0, 0.0) * 10 + 1e-3):
            k = m * w0 * w0 - x * w0
            if k >= 0 and math.isfinite(k):
                out.append(Environment(mass=m, damping=b, stiffness=k))
        return out
    (m_lo, m_hi), (b_lo, b_hi), (k_lo, k_hi) = box.mass, box.damping, box.stiffness
    m_a = max(m_lo, (k_lo + w0 * x) / w0**2)
    m_b = min(m_hi, (k_hi + w0 * x) / w0**2)
    masses = {m_a, m_b, math.sqrt(m_a * m_b) if m_a > 0 and m_b > 0 else (m_a + m_b) / 2}
    for m in masses:
        if not math.isfinite(m):
            continue
        for damping in {min(max(b, b_lo), b_hi), b_lo}:
            out.append(box.clip(m, damping, m * w0 * w0 - w0 * x))
    return out


def _targets(p: np.ndarray, port: int, w0: float, imp_other: bool) -> list[complex]:
    """Impedances of the other port's termination that make port ``port`` see ``Re < 0`` at ``w0``."""
    other = 1 - port
    pjj, q = p[other, other], p[port, other] * p[other, port]
    out = []
    if abs(q) > 0 and q.imag != 0 and pjj.real > 0:
        y = pjj.real * (abs(q) - q.real) / q.imag
        out.append(complex(0.0, y - pjj.imag))
    elif abs(q) > 0:
        out.append(complex(0.0, -pjj.imag))  # cancel the reactance: u = Re p_jj
    out.append(complex(0.0, -pjj.imag + abs(pjj) + 1.0))
    targets = []
    for t in out:  # T in the port's own variable → the impedance of the termination
        if imp_other:
            targets.append(t)
        elif t != 0:
            targets.append(1 / t)
    return targets


def _rhp(m: ExactMatrix, form: Form, env1: Environment, env2: Environment) -> bool:
    """A closed-loop root in the open right half-plane (exact; no roots computed)."""
    try:
        chi, _common = closed_loop_polynomial(m, form, env1, env2)
        return classify_polynomial(chi)[1]
    except (ValueError, ArithmeticError):
        return False


def _corners(box: EnvironmentBounds | None) -> list[Environment]:
    if box is None:
        return [Environment(), Environment(mass=1.0, damping=1.0, stiffness=1.0)]
    lo = Environment(mass=box.mass[0], damping=box.damping[0], stiffness=box.stiffness[0])
    hi = Environment(mass=box.mass[1], damping=box.damping[1], stiffness=box.stiffness[1])
    return [lo, hi]


def _frequencies(bands: Sequence[Band]) -> list[float]:
    ws: list[float] = []
    for b in bands:
        lo = b.lo if b.lo > 0 else (b.hi / 1e3 if math.isfinite(b.hi) else 1e-2)
        hi = b.hi if math.isfinite(b.hi) else max(lo * 1e3, 1e3)
        ws += [float(v) for v in np.geomspace(max(lo, 1e-12), hi, 7)[1:-1]]
    return ws


def _grid(box: EnvironmentBounds) -> list[Environment]:
    def axis(lo: float, hi: float, n: int) -> list[float]:
        if hi == lo:
            return [lo]
        start = lo if lo > 0 else hi * 1e-3
        vals = [float(v) for v in np.geomspace(start, hi, n - (lo == 0))]
        return [0.0, *vals] if lo == 0 else vals

    return [
        Environment(mass=m, damping=d, stiffness=k)
        for m in axis(*box.mass, 4)
        for d in axis(*box.damping, 2)
        for k in axis(*box.stiffness, 4)
    ]


def _search(
    m: ExactMatrix,
    form: Form,
    bands: Sequence[Band],
    bounds: tuple[EnvironmentBounds | None, EnvironmentBounds | None],
    budget: int,
) -> tuple[tuple[Environment, Environment, float | None] | None, int]:
    """The first verified destabilizing pair (or None) and the number of pairs verified."""
    imp = form.impedance_ports
    count = 0
    # corners of the boxes first: an unstable entry (or a hidden mode) shows with any pair
    corners = [_corners(b) for b in bounds]
    for env1 in corners[0]:
        for env2 in corners[1]:
            count += 1
            if _rhp(m, form, env1, env2):
                return (env1, env2, None), count
    for closed in (1, 0):  # close port 2 and attack port 1, then the other way round
        attacked = 1 - closed
        box_c, box_a = bounds[closed], bounds[attacked]
        cands: list[tuple[Environment, float | None]] = []
        for w0 in _frequencies(bands):
            p = evaluate(m, np.array([w0]))[0]
            if not np.all(np.isfinite(p)):
                continue
            for z in _targets(p, attacked, w0, imp[closed]):
                if cmath.isfinite(z):
                    cands += [(e, w0) for e in _fit(z, w0, box_c)]
        extremes = _grid(box_c) if box_c is not None else [Environment()]
        cands += [(e, None) for e in extremes]
        for env_c, tuned in cands:
            zn, zd = input_immittance(m, form, attacked, env_c)
            if not imp[attacked]:  # the port sees an admittance: the witness wants an impedance
                if zn.is_zero():
                    continue
                zn, zd = zd, zn
            if zn.is_zero() or positive_real_test(zn, zd).passive:
                continue
            if box_a is None:
                attack = unbounded_candidates(zn, zd)
            else:
                attack = bounded_candidates(zn, zd, box_a)
            for env_a, wa in attack[:MAX_ATTACKS]:
                if count >= budget:
                    return None, count
                count += 1
                pair = (env_a, env_c) if attacked == 0 else (env_c, env_a)
                if _rhp(m, form, *pair):
                    return (pair[0], pair[1], tuned if tuned is not None else wa), count
    return None, count


def find_destabilizing_pair(
    m: ExactMatrix,
    form: Form | str,
    bands: Sequence[Band],
    *,
    bounds: tuple[EnvironmentBounds | None, EnvironmentBounds | None] = (
        HUMAN_LIMB,
        VIRTUAL_ENVIRONMENT,
    ),
    budget: int = MAX_PAIRS,
) -> TerminationWitness:
    """Search a verified destabilizing pair of passive terminations for the exact two-port ``m``.

    ``bands`` are the failing frequency bands of the absolute-stability test (the
    construction is tuned inside them).  The boxes are searched first; then,
    if nothing was found, any passive mass–spring–damper.
    """
    f = form_of(form)
    z = impedance_form(m, f)  # search in the impedance form when it exists (both ports alike)
    if z is not None:
        m, f = z, Form.Z
    tried = 0
    for within, boxes in ((True, bounds), (False, (None, None))):
        if not within and bounds == (None, None):
            break
        # the unbounded search gets a share of the budget of its own
        share = budget - tried if not within else (2 * budget) // 3
        hit, count = _search(m, f, bands, boxes, share)
        tried += count
        if hit is not None:
            e1, e2, w0 = hit
            loop = closed_loop(m, f, e1, e2)  # the exact verdict again, with the poles
            where = "within the bounds" if within else "outside the bounds (none found inside)"
            return TerminationWitness(
                port1=e1,
                port2=e2,
                within_bounds=within,
                omega=w0,
                closed_loop=loop,
                pairs=tried,
                detail=f"port 1 held by {_text(e1)} and port 2 by {_text(e2)} ({where}) give a "
                f"closed-loop pole at Re s = {loop.max_real_part:.4g} 1/s",
            )
    return TerminationWitness(
        pairs=tried,
        detail="no destabilizing pair of mass-spring-damper terminations was found "
        f"(a search of {tried} pairs, not a proof)",
    )


def _text(e: Environment) -> str:
    return f"m = {e.mass:.4g} kg, b = {e.damping:.4g} N*s/m, k = {e.stiffness:.4g} N/m"
