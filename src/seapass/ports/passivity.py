"""Exact passivity (positive-realness) of an n×n immittance matrix: two-ports and n-ports.

A real rational matrix ``P(s)`` (any hybrid form whose outputs and inputs pair
up port by port, so that the power is ``Re u^H y``) is positive real, hence
passive, if and only if

1. no entry has a pole in the open right half-plane (``stable_entries``; a
   mode that cancels only for the given numbers must not lie in the closed
   right half-plane either);
2. its poles on the imaginary axis, ``s = ∞`` included, are simple with
   Hermitian positive semidefinite residue matrices (``axis_poles``);
3. ``P(jω) + P(jω)^H ⪰ 0`` at every ``ω`` that is not a pole: every principal
   minor of the Hermitian part is ``≥ 0`` (``minor_1``, ``minor_2``, ...,
   ``minor_12``, ...; all of them, not only the leading ones).

Each condition is decided exactly (see [`seapass.ports.onaxis`][seapass.ports.onaxis]
and [`seapass.ports.poles`][seapass.ports.poles]); the frequency conditions come
with their exact failing bands.

References
----------
.. [1] B. D. O. Anderson and S. Vongpanitlerd, *Network Analysis and Synthesis*,
   Prentice-Hall, 1973, sec. 5.2 (positive real matrices).
.. [2] S. Raisbeck, "A new definition of passivity and its application to
   active networks", IRE Trans. Circuit Theory 1(3), 1954.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from flint import fmpq

from ..model.display import Shown, html_card, short_repr
from ..outcome import Outcome
from .bands import Band, Condition, combine, failing_bands
from .matrix import ExactMatrix
from .onaxis import axis_matrix, cdet, hermitian_part, principal_minors, to_x
from .poles import PoleDefect, axis_points, infinity_residues, pole_defect, residue_matrix

__all__ = [
    "MatrixPassivity",
    "axis_pole_condition",
    "evaluate",
    "frequency_grid",
    "matrix_passivity",
    "minor_conditions",
    "minor_name",
    "stable_entries_condition",
]


def minor_name(subset: Sequence[int]) -> str:
    """``(0, 2)`` → ``"minor_13"`` (1-based port numbers)."""
    return "minor_" + "".join(str(i + 1) for i in subset)


def _entry_name(i: int, j: int, letter: str) -> str:
    return f"{letter}{i + 1}{j + 1}"


def stable_entries_condition(m: ExactMatrix, letter: str = "p") -> Condition:
    """No entry has a pole in the open right half-plane, no hidden mode in the closed one."""
    desc = "no entry has a pole in the open right half-plane"
    for i, j in itertools.product(range(m.n), repeat=2):
        if pole_defect(m.den[i][j]) is PoleDefect.RHP_POLE:
            return Condition(
                name="stable_entries",
                outcome=Outcome.NOT_PASSIVE,
                description=desc,
                detail=f"{_entry_name(i, j, letter)} has a pole in the open right half-plane",
            )
    if pole_defect(m.hidden) is not PoleDefect.NONE:
        return Condition(
            name="stable_entries",
            outcome=Outcome.NOT_PASSIVE,
            description=desc,
            detail="a mode that cancels for these values (hidden from the ports) lies in the "
            "closed right half-plane",
        )
    return Condition(name="stable_entries", outcome=Outcome.PASSIVE, description=desc)


def _psd_rational(k: list[list[fmpq]]) -> bool:
    n = len(k)
    if any(k[i][j] != k[j][i] for i in range(n) for j in range(n)):
        return False
    for r in range(1, n + 1):
        for subset in itertools.combinations(range(n), r):
            sub = [[k[i][j] for j in subset] for i in subset]
            if _det(sub) < 0:
                return False
    return True


def _det(a: list[list[fmpq]]) -> fmpq:
    n = len(a)
    if n == 1:
        return a[0][0]
    total = fmpq(0)
    for c in range(n):
        if a[0][c] != 0:
            minor = [row[:c] + row[c + 1 :] for row in a[1:]]
            total += (-1) ** c * a[0][c] * _det(minor)
    return total


def axis_pole_condition(m: ExactMatrix, name: str = "axis_poles") -> Condition:
    """Imaginary-axis poles (``0`` and ``∞`` included) simple, residue matrices Hermitian PSD."""
    desc = "poles on the imaginary axis (and at infinity) are simple with Hermitian positive semidefinite residues"

    def fail(detail: str) -> Condition:
        return Condition(name=name, outcome=Outcome.NOT_PASSIVE, description=desc, detail=detail)

    d = m.common_denominator()
    poles = axis_points(d)
    if not poles.simple:
        return fail("a pole on the imaginary axis is not simple")
    if poles.points:
        kt = residue_matrix(m.numerator_matrix(d), d)
        for pt in poles.points:
            where = f"s = j*{float(pt):.6g}"
            hermitian = all(pt.sign(kt[i][i][1]) == 0 for i in range(m.n)) and all(
                pt.sign(kt[i][k][0] - kt[k][i][0]) == 0 and pt.sign(kt[i][k][1] + kt[k][i][1]) == 0
                for i in range(m.n)
                for k in range(i + 1, m.n)
            )
            if not hermitian:
                return fail(f"the residue matrix at {where} is not Hermitian")
            for r in range(1, m.n + 1):
                for subset in itertools.combinations(range(m.n), r):
                    if pt.sign(cdet(kt, subset, subset)[0]) < 0:
                        return fail(f"the residue matrix at {where} is not positive semidefinite")
    k_inf, simple = infinity_residues(m)
    if not simple:
        return fail("a pole at infinity is not simple (relative degree below -1)")
    if not _psd_rational(k_inf):
        return fail(
            "the residue matrix at infinity (lim P(s)/s) is not symmetric positive semidefinite"
        )
    return Condition(name=name, outcome=Outcome.PASSIVE, description=desc)


def minor_conditions(m: ExactMatrix) -> list[Condition]:
    """``P(jω) + P(jω)^H ⪰ 0``: one condition per principal minor, with its failing bands."""
    d = m.common_denominator()
    w = hermitian_part(axis_matrix(m.numerator_matrix(d), d))
    out = []
    for subset, minor in principal_minors(w).items():
        px = to_x(minor)
        bands = failing_bands([px], lambda s: s[0] < 0)
        ports = ", ".join(str(i + 1) for i in subset)
        out.append(
            Condition(
                name=minor_name(subset),
                outcome=Outcome.NOT_PASSIVE if bands else Outcome.PASSIVE,
                bands=bands,
                description=f"principal minor of P + P^H on ports {ports} is >= 0 for all w",
                detail=f"negative on {_bands_text(bands)}" if bands else "",
            )
        )
    return out


def _bands_text(bands: Sequence[Band]) -> str:
    parts = [f"({b.lo:.6g}, {b.hi:.6g}) rad/s" for b in bands[:3]]
    more = f" and {len(bands) - 3} more" if len(bands) > 3 else ""
    return ", ".join(parts) + more


@dataclass(frozen=True, kw_only=True, repr=False)
class MatrixPassivity:
    """Exact passivity of an n×n immittance (two-port or multi-DoF).

    Attributes
    ----------
    outcome : Outcome
        ``PASSIVE`` when every condition holds.
    conditions : tuple of Condition
        ``stable_entries``, ``axis_poles`` and one ``minor_*`` per principal minor.
    n : int
        Number of ports.
    form : str
        The immittance form tested (``"z"`` for an impedance matrix).
    matrix : ExactMatrix
        The exact matrix (for `response` and `plot`; not in ``to_dict``).
    """

    outcome: Outcome
    conditions: tuple[Condition, ...]
    n: int
    form: str = "z"
    matrix: ExactMatrix | None = field(default=None, compare=False)

    @property
    def passive(self) -> bool:
        """Certified passive (``outcome`` is ``PASSIVE``)."""
        return self.outcome.passive

    @property
    def failing(self) -> tuple[Condition, ...]:
        return tuple(c for c in self.conditions if c.holds is False)

    @property
    def bands(self) -> tuple[Band, ...]:
        """Every failing frequency band of the minors, sorted."""
        return tuple(sorted((b for c in self.conditions for b in c.bands), key=lambda b: b.lo))

    def to_dict(self) -> dict[str, Any]:
        return {
            "passive": self.passive,
            "outcome": self.outcome.value,
            "ports": self.n,
            "form": self.form,
            "conditions": [c.to_dict() for c in self.conditions],
        }

    def response(self, omega: Any = None) -> dict[str, Any]:
        """Principal minors of ``P(jω) + P(jω)^H`` on a frequency grid (floats, for pictures).

        Returns ``{"omega": array, "minors": {name: array}, "bands": [...]}``.
        """
        if self.matrix is None:
            raise ValueError("this result holds no matrix to evaluate")
        w = (
            frequency_grid(self.matrix, self.bands)
            if omega is None
            else np.asarray(omega, dtype=float)
        )
        p = evaluate(self.matrix, w)
        h = p + np.conj(np.swapaxes(p, -1, -2))
        minors = {}
        for r in range(1, self.n + 1):
            for subset in itertools.combinations(range(self.n), r):
                sub = h[:, list(subset)][:, :, list(subset)]
                minors[minor_name(subset)] = np.real(np.linalg.det(sub))
        return {"omega": w, "minors": minors, "bands": [b.to_list() for b in self.bands]}

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """The principal minors of ``P + P^H`` with the exact failing bands shaded; returns the Axes."""
        from ..plot.ports import plot_minors

        return plot_minors(self, ax=ax, **kwargs)

    def __repr__(self) -> str:
        failing = ", ".join(c.name for c in self.failing)
        return short_repr(
            "MatrixPassivity",
            {
                "outcome": self.outcome.value,
                "ports": self.n,
                "failing": Shown(failing) if failing else None,
            },
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [("verdict", self.outcome.label), ("ports", self.n)]
        rows += [
            (
                c.name,
                "holds" if c.holds else ("undecided" if c.holds is None else f"fails: {c.detail}"),
            )
            for c in self.conditions
        ]
        return html_card(
            f"{self.n}-port passivity: {self.outcome.label}",
            rows,
            note="Exact verdict (rational arithmetic).",
        )


def evaluate(m: ExactMatrix, omega: np.ndarray) -> np.ndarray:
    """``P(jω)`` on a grid, shape ``(len(omega), n, n)`` (floats; for pictures only)."""
    s = 1j * np.asarray(omega, dtype=float)
    out = np.empty((s.size, m.n, m.n), dtype=complex)
    with np.errstate(all="ignore"):
        for i, j in itertools.product(range(m.n), repeat=2):
            num = [float(c) for c in reversed(m.num[i][j].coeffs())] or [0.0]
            den = [float(c) for c in reversed(m.den[i][j].coeffs())]
            out[:, i, j] = np.polyval(num, s) / np.polyval(den, s)
    return out


def frequency_grid(m: ExactMatrix, bands: Sequence[Band]) -> np.ndarray:
    """A log grid around the poles, zeros and band edges (for pictures)."""
    scales = []
    for i, j in itertools.product(range(m.n), repeat=2):
        for p in (m.num[i][j], m.den[i][j]):
            if p.degree() >= 1:
                roots = np.roots([float(c) for c in reversed(p.coeffs())])
                scales += [abs(r) for r in roots if 0 < abs(r) < math.inf]
    edges = [e for b in bands for e in (b.lo, b.hi) if 0 < e < math.inf]
    pts = [x for x in scales + edges if np.isfinite(x) and x > 0]
    lo = min(pts) / 100 if pts else 1e-2
    hi = max(pts) * 100 if pts else 1e4
    return np.unique(np.concatenate([np.geomspace(lo, hi, 800), np.asarray(edges, dtype=float)]))


def matrix_passivity(m: ExactMatrix, *, form: str = "z", letter: str = "p") -> MatrixPassivity:
    """Decide exactly whether the exact matrix ``m`` is positive real (see the module docstring)."""
    conds = [stable_entries_condition(m, letter), axis_pole_condition(m), *minor_conditions(m)]
    return MatrixPassivity(
        outcome=combine([c.outcome for c in conds]),
        conditions=tuple(conds),
        n=m.n,
        form=form,
        matrix=m,
    )
