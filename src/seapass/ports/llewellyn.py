"""Llewellyn's absolute stability of a two-port, decided exactly, with η and a witness pair.

A two-port is *absolutely stable* (unconditionally stable) when it is stable
with every pair of passive terminations.  For an immittance matrix ``P`` in
any form (z, y, h, g) this holds if and only if (Llewellyn 1952):

* ``stable_entries``: no entry has a pole in the open right half-plane (the
  two-port itself is stable; a mode hidden from the ports is not in the closed
  right half-plane);
* ``p11_poles``, ``p22_poles``: the poles of ``p11`` and ``p22`` on the
  imaginary axis (``0`` and ``∞`` included) are simple with real positive
  residues;
* ``re_p11``, ``re_p22``: ``Re p11(jω) ≥ 0`` and ``Re p22(jω) ≥ 0`` for all ``ω``;
* ``llewellyn``: ``2 Re p11 Re p22 − Re(p12 p21) − |p12 p21| ≥ 0`` for all ``ω``;
* ``axis_residues``: at every pole on the imaginary axis shared by the entries
  the residues satisfy ``k11 k22 ≥ k12 k21`` (the inequality above only sees
  the frequencies next to a pole; without this,
  ``z = [[1/s + 1, 2/s], [2/s, 1/s + 1]]`` passes them and is unstable with both
  ports free).  This condition is the residue form of the others: with ``T2 = 0``
  port 1 sees ``det P/p22``, whose residue is ``(k11 k22 − k12 k21)/k22``.

The modulus is squared away exactly (see [`seapass.ports.onaxis`][seapass.ports.onaxis])
and every frequency condition comes with its exact failing bands.  The result
also holds the infimum of η ([`seapass.ports.eta`][seapass.ports.eta]) and,
when the two-port is not absolutely stable, a verified destabilizing pair of
passive terminations ([`seapass.ports.witness`][seapass.ports.witness]).

References
----------
.. [1] F. B. Llewellyn, "Some fundamental properties of transmission systems",
   Proc. IRE 40(3), 1952.
.. [2] R. J. Adams and B. Hannaford, "Stable haptic interaction with virtual
   environments", IEEE Trans. Robot. Autom. 15(3), 1999.
.. [3] K. Hashtrudi-Zaad and S. E. Salcudean, "Analysis of control architectures
   for teleoperation systems with impedance/admittance master and slave
   manipulators", Int. J. Robot. Res. 20(6), 2001.
"""

from __future__ import annotations

from flint import fmpq_poly

from ..outcome import Outcome
from .bands import Condition, failing_bands
from .eta import EtaMinimum, eta_infimum
from .matrix import ExactMatrix
from .onaxis import axis_matrix, cmul, llewellyn_polynomials, to_x
from .passivity import axis_pole_condition, stable_entries_condition
from .poles import axis_points, infinity_residues, residue_matrix

__all__ = ["frequency_polynomials", "llewellyn_conditions", "llewellyn_eta"]


def _sub(m: ExactMatrix, i: int) -> ExactMatrix:
    return ExactMatrix(num=((m.num[i][i],),), den=((m.den[i][i],),), hidden=fmpq_poly([1]))


def _frequency_polys(
    m: ExactMatrix,
) -> tuple[fmpq_poly, fmpq_poly, fmpq_poly, fmpq_poly, fmpq_poly]:
    """``(Re G11, Re G22, a, a² − |q|², |q|²)`` in ``x = ω²``."""
    d = m.common_denominator()
    g = axis_matrix(m.numerator_matrix(d), d)
    r11, r22, a, disc = llewellyn_polynomials(g)
    q = cmul(g[0][1], g[1][0])
    return to_x(r11), to_x(r22), to_x(a), to_x(disc), to_x(q[0] * q[0] + q[1] * q[1])


def frequency_polynomials(m: ExactMatrix) -> tuple[fmpq_poly, ...]:
    """``(Re G11, Re G22, a, a² − |q|², |q|²)`` in ``x = ω²`` (see `seapass.ports.onaxis`)."""
    return _frequency_polys(m)


def llewellyn_eta(m: ExactMatrix, polys: tuple[fmpq_poly, ...] | None = None) -> EtaMinimum:
    """The exact infimum of η over ω for the 2×2 exact matrix ``m``."""
    _r11, _r22, a, _disc, qq = polys if polys is not None else _frequency_polys(m)
    return eta_infimum(a, qq)


def _axis_residue_condition(m: ExactMatrix, frequency_ok: bool, poles_ok: bool) -> Condition:
    name = "axis_residues"
    desc = "at every pole on the imaginary axis the residues satisfy k11 k22 >= k12 k21 >= 0"

    def cond(outcome: Outcome, detail: str = "") -> Condition:
        return Condition(name=name, outcome=outcome, description=desc, detail=detail)

    if not poles_ok:  # a pole of p11 or p22 already fails: the verdict is known
        return cond(Outcome.UNDECIDED, "not examined: a pole of p11 or p22 already fails")
    d = m.common_denominator()
    poles = axis_points(d)
    if not poles.simple:
        return cond(
            Outcome.UNDECIDED,
            "p12 or p21 has a repeated pole on the imaginary axis"
            if frequency_ok
            else "not examined: a frequency condition already fails",
        )
    kt = residue_matrix(m.numerator_matrix(d), d)
    f = cmul(kt[0][1], kt[1][0])
    e = (
        kt[0][0][0] * kt[1][1][0] - kt[0][0][1] * kt[1][1][1] - f[0],
        kt[0][0][0] * kt[1][1][1] + kt[0][0][1] * kt[1][1][0] - f[1],
    )
    for pt in poles.points:
        where = f"s = j*{float(pt):.6g}"
        if pt.sign(f[1]) != 0 or pt.sign(f[0]) < 0:
            if frequency_ok:  # then the inequality fails next to the pole; seen here only if not
                return cond(Outcome.UNDECIDED, f"k12 k21 at {where} is not real and >= 0")
            continue
        if pt.sign(e[1]) != 0 or pt.sign(e[0]) < 0:
            return cond(Outcome.NOT_PASSIVE, f"k11 k22 < k12 k21 at the pole {where}")
    k, simple = infinity_residues(m)
    if not simple:
        return cond(
            Outcome.UNDECIDED,
            "an entry has a repeated pole at infinity"
            if frequency_ok
            else "not examined: a frequency condition already fails",
        )
    f_inf = k[0][1] * k[1][0]
    if f_inf < 0 and frequency_ok:
        return cond(Outcome.UNDECIDED, "k12 k21 at infinity is negative")
    if f_inf >= 0 and k[0][0] * k[1][1] < f_inf:
        return cond(Outcome.NOT_PASSIVE, "k11 k22 < k12 k21 at the pole at infinity")
    return cond(Outcome.PASSIVE)


def llewellyn_conditions(
    m: ExactMatrix, letter: str = "p", polys: tuple[fmpq_poly, ...] | None = None
) -> list[Condition]:
    """The conditions of Llewellyn's criterion for the 2×2 exact matrix ``m`` (module docstring)."""
    if m.n != 2:
        raise ValueError("Llewellyn's criterion is for two-ports")
    out = [stable_entries_condition(m, letter)]
    for i in (0, 1):
        c = axis_pole_condition(_sub(m, i), name=f"{letter}{i + 1}{i + 1}_poles")
        out.append(
            Condition(
                name=f"p{i + 1}{i + 1}_poles",
                outcome=c.outcome,
                description=f"poles of {letter}{i + 1}{i + 1} on the imaginary axis (and at "
                "infinity) are simple with real positive residues",
                detail=c.detail,
            )
        )
    r11, r22, a, disc, _qq = polys if polys is not None else _frequency_polys(m)
    freq = []
    for i, r in ((1, r11), (2, r22)):
        bands = failing_bands([r], lambda s: s[0] < 0)
        freq.append(
            Condition(
                name=f"re_p{i}{i}",
                outcome=Outcome.NOT_PASSIVE if bands else Outcome.PASSIVE,
                bands=bands,
                description=f"Re {letter}{i}{i}(jw) >= 0 for all w",
                detail="negative in the bands" if bands else "",
            )
        )
    bands = failing_bands([a, disc], lambda s: s[0] < 0 or s[1] < 0)
    freq.append(
        Condition(
            name="llewellyn",
            outcome=Outcome.NOT_PASSIVE if bands else Outcome.PASSIVE,
            bands=bands,
            description="2 Re p11 Re p22 - Re(p12 p21) - |p12 p21| >= 0 for all w",
            detail="violated in the bands" if bands else "",
        )
    )
    out += freq
    frequency_ok = all(c.outcome is Outcome.PASSIVE for c in freq)
    poles_ok = all(c.outcome is Outcome.PASSIVE for c in out[1:3])
    out.append(_axis_residue_condition(m, frequency_ok, poles_ok))
    return out
