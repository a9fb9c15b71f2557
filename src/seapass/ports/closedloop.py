"""A two-port closed by a passive termination on each port: the exact characteristic polynomial.

Port ``i`` is closed by a mass–spring–damper ``Z_i = m s + b + k/s``
(an [`Environment`][seapass.analysis.coupled.Environment]): ``F_i = −Z_i v_i``.
In the two-port's form the termination is ``y_i = −T_i u_i`` with ``T_i = Z_i``
on an impedance-type port and ``T_i = 1/Z_i`` on an admittance-type one; write
``T_i = t_i/e_i`` in lowest terms (a free port on an admittance-type port is
``t = 1, e = 0``).  The loop is ``(P + T) u = external``, and for minimal
realizations its characteristic polynomial is

``χ = h · χ_P · [e1 e2 det P + e1 t2 p11 + t1 e2 p22 + t1 t2]``

with ``χ_P`` the McMillan pole polynomial of ``P`` (lcm of the denominators of
all its minors) and ``h`` the modes hidden from the ports.  The formula is
applied in the impedance form (converted exactly when the two-port is given in
another form): there a factor of ``χ`` shared by ``χ_P`` and ``e1 e2`` (a port
position, integrated on both sides) is one mode counted twice and is removed,
as [`coupled_polynomial`][seapass.analysis.coupled.coupled_polynomial] does for
a one-port.  When the impedance form does not exist, the form given is used and
every factor ``s`` is removed (such duplicated position modes sit at ``s = 0``;
a root there is then not counted).  Either way only factors with roots in the
closed left half-plane are removed, so no root in the right half-plane is ever
hidden.  The verdict is exact
([`classify_polynomial`][seapass.analysis.coupled.classify_polynomial]); the
roots are floating-point evidence.

The tests check ``χ`` against the closed-loop poles of the physical equations
of the SEA with a person and a virtual environment attached.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from flint import fmpq_poly

from ..analysis.coupled import (
    Environment,
    Stability,
    classify_polynomial,
    polynomial_roots,
    to_float,
)
from ..errors import DegenerateModelError
from ..outcome import Outcome
from .forms import Form, form_of
from .matrix import ExactMatrix, from_polynomials
from .ratfunc import Frac as RFrac
from .ratfunc import context, to_fmpq_poly

__all__ = [
    "ClosedLoop",
    "closed_loop",
    "closed_loop_polynomial",
    "impedance_form",
    "input_immittance",
    "termination",
]

Frac = tuple[fmpq_poly, fmpq_poly]


def termination(env: Environment, impedance_port: bool) -> Frac:
    """``(t, e)`` with ``T = t/e`` the termination in the variables of the port."""
    ne, de = env.polynomials()
    return (ne, de) if impedance_port else (de, ne)


def _exact_div(a: fmpq_poly, b: fmpq_poly) -> fmpq_poly:
    q, r = divmod(a, b)
    if not r.is_zero():  # pragma: no cover - the denominators divide the pole polynomial
        raise ArithmeticError("a denominator does not divide the pole polynomial")
    return q


def impedance_form(m: ExactMatrix, form: Form | str) -> ExactMatrix | None:
    """The same two-port in impedance form, exactly (None when that form does not exist)."""
    f = form_of(form)
    if f is Form.Z:
        return m
    p = [[_frac(m.num[i][j], m.den[i][j]) for j in range(2)] for i in range(2)]
    one, zero = _frac(fmpq_poly([1]), fmpq_poly([1])), _frac(fmpq_poly([]), fmpq_poly([1]))
    # relation rows: out_r − Σ_c P_rc in_c = 0 over w = (F1, v1, F2, v2)
    cols_out, cols_in = [], []
    for port, imp in enumerate(f.impedance_ports):
        cols_out.append(2 * port if imp else 2 * port + 1)
        cols_in.append(2 * port + 1 if imp else 2 * port)
    rel = [[zero] * 4 for _ in range(2)]
    for r in range(2):
        rel[r][cols_out[r]] = one
        for c in range(2):
            rel[r][cols_in[c]] = -p[r][c]
    a = [[rel[r][0], rel[r][2]] for r in range(2)]  # the forces: outputs of z
    b = [[rel[r][1], rel[r][3]] for r in range(2)]  # the velocities: inputs of z
    det = a[0][0] * a[1][1] - a[0][1] * a[1][0]
    if det.is_zero():
        return None
    inv = [[a[1][1] / det, -a[0][1] / det], [-a[1][0] / det, a[0][0] / det]]
    z = [[-(inv[i][0] * b[0][j] + inv[i][1] * b[1][j]) for j in range(2)] for i in range(2)]
    nums = [[to_fmpq_poly(z[i][j].num) for j in range(2)] for i in range(2)]
    dens = [[to_fmpq_poly(z[i][j].den) for j in range(2)] for i in range(2)]
    out = from_polynomials(nums, dens)
    return ExactMatrix(num=out.num, den=out.den, hidden=m.hidden)


def _frac(num: fmpq_poly, den: fmpq_poly) -> RFrac:
    ctx = context(())
    return RFrac.make(
        ctx.from_dict({(i,): c for i, c in enumerate(num.coeffs()) if c != 0}),
        ctx.from_dict({(i,): c for i, c in enumerate(den.coeffs()) if c != 0}),
    )


def closed_loop_polynomial(
    m: ExactMatrix, form: Form | str, env1: Environment, env2: Environment
) -> tuple[fmpq_poly, fmpq_poly]:
    """Exact ``(χ, removed)``: the closed-loop characteristic polynomial and the removed factor."""
    z = impedance_form(m, form)
    if z is not None:
        return _polynomial(z, Form.Z, env1, env2)
    chi, common = _polynomial(m, form_of(form), env1, env2)
    while chi.degree() > 0 and chi[0] == 0:
        chi = chi // fmpq_poly([0, 1])
        common = common * fmpq_poly([0, 1])
    return chi, common


def _polynomial(
    m: ExactMatrix, form: Form, env1: Environment, env2: Environment
) -> tuple[fmpq_poly, fmpq_poly]:
    imp = form.impedance_ports
    t1, e1 = termination(env1, imp[0])
    t2, e2 = termination(env2, imp[1])
    chi_p = m.pole_polynomial()
    dn, dd = m.determinant()
    n11, d11 = m.entry(0, 0)
    n22, d22 = m.entry(1, 1)
    full = (
        e1 * e2 * _exact_div(chi_p, dd) * dn
        + e1 * t2 * _exact_div(chi_p, d11) * n11
        + t1 * e2 * _exact_div(chi_p, d22) * n22
        + t1 * t2 * chi_p
    )
    if full.is_zero():
        raise DegenerateModelError(
            "the terminations cancel the two-port exactly: the closed loop is undetermined"
        )
    # a mode counted on both sides (the port position) divides χ_P, some e_i and the sum
    ends = e1 * e2
    shared = chi_p.gcd(ends) if not ends.is_zero() else fmpq_poly([1])
    common = full.gcd(shared) if shared.degree() > 0 else fmpq_poly([1])
    chi = _exact_div(full, common) * m.hidden
    return chi, common


def input_immittance(m: ExactMatrix, form: Form | str, port: int, env: Environment) -> Frac:
    """What port ``port`` (0 or 1) sees with the other port closed by ``env``, reduced.

    ``p_ii − p_ij p_ji e/(e p_jj + t)`` in the variables of port ``port``
    (an impedance on an impedance-type port, an admittance otherwise).
    """
    imp = form_of(form).impedance_ports
    other = 1 - port
    t, e = termination(env, imp[other])
    nii, dii = m.entry(port, port)
    nij, dij = m.entry(port, other)
    nji, dji = m.entry(other, port)
    njj, djj = m.entry(other, other)
    # p_ii − (nij nji / (dij dji)) · e djj / (e njj + t djj)
    den_b = e * njj + t * djj
    if den_b.is_zero():
        raise DegenerateModelError("the termination cancels the other port exactly")
    num = nii * dij * dji * den_b - dii * nij * nji * e * djj
    den = dii * dij * dji * den_b
    g = num.gcd(den) if not num.is_zero() else den
    num, den = num // g, den // g
    lead = den.leading_coefficient()
    return num / lead, den / lead


@dataclass(frozen=True, kw_only=True)
class ClosedLoop:
    """Exact stability of a two-port closed by a termination on each port.

    Attributes
    ----------
    status : Stability
        Stable, marginally stable or unstable, decided exactly.
    outcome : Outcome
        What this one pair of passive terminations proves about absolute
        stability: ``NOT_PASSIVE`` (not absolutely stable) when the loop is
        unstable, else ``UNDECIDED`` (one stable pair proves nothing).
    rhp : bool
        A closed-loop pole lies in the open right half-plane.
    repeated_axis : bool
        A repeated pole lies on the imaginary axis.
    characteristic : tuple of float
        ``χ``, descending powers of ``s`` (common factors removed).
    poles : numpy.ndarray
        Roots of ``χ`` (floating-point evidence), by decreasing real part.
    """

    status: Stability
    rhp: bool
    repeated_axis: bool
    characteristic: tuple[float, ...]
    poles: np.ndarray

    @property
    def unstable(self) -> bool:
        return self.status is Stability.UNSTABLE

    @property
    def outcome(self) -> Outcome:
        return Outcome.NOT_PASSIVE if self.unstable else Outcome.UNDECIDED

    @property
    def max_real_part(self) -> float:
        return float(np.max(self.poles.real)) if self.poles.size else -np.inf

    def to_dict(self) -> dict[str, Any]:
        return {
            "status": self.status.value,
            "rhp": self.rhp,
            "repeated_axis": self.repeated_axis,
            "characteristic": list(self.characteristic),
            "poles": [[float(p.real), float(p.imag)] for p in self.poles],
            "max_real_part": self.max_real_part,
        }


def closed_loop(
    m: ExactMatrix, form: Form | str, env1: Environment, env2: Environment
) -> ClosedLoop:
    """Exact stability of ``m`` (in ``form``) with ``env1`` on port 1 and ``env2`` on port 2."""
    chi, _common = closed_loop_polynomial(m, form, env1, env2)
    status, rhp, repeated = classify_polynomial(chi)
    if chi.leading_coefficient() < 0:
        chi = -chi
    return ClosedLoop(
        status=status,
        rhp=rhp,
        repeated_axis=repeated,
        characteristic=tuple(to_float(c) for c in reversed(chi.coeffs())),
        poles=polynomial_roots(chi),
    )
