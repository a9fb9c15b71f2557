"""The four immittance forms of a two-port and exact conversions between them.

Each port ``i`` has an effort, the force ``F_i``, and a flow, the velocity
``v_i``; the power into the two-port is ``F_1 v_1 + F_2 v_2``.  A form says which
variable of each port is an output:

====  ==================  ==================  =================
form  outputs             inputs              port 1, port 2
====  ==================  ==================  =================
z     ``F_1, F_2``        ``v_1, v_2``        impedance, impedance
y     ``v_1, v_2``        ``F_1, F_2``        admittance, admittance
h     ``F_1, v_2``        ``v_1, F_2``        impedance, admittance
g     ``v_1, F_2``        ``F_1, v_2``        admittance, impedance
====  ==================  ==================  =================

``outputs = P · inputs`` is one linear relation among the four port variables.
To convert, the relation is written as ``R w = 0`` over ``w = (F_1, v_1, F_2, v_2)``
and solved for the outputs of the target form: ``o = −R_O⁻¹ R_I i``.  The target
form exists exactly when ``det R_O`` is not identically zero; otherwise
[`DegenerateModelError`][seapass.errors.DegenerateModelError] says so and names the
entry that vanishes.  Everything is symbolic and exact (sympy, cancelled).

The pairing of outputs with inputs is per port (``F_i`` with ``v_i``), so the
power is ``Re(u^H y)`` in every form and passivity is ``P + P^H ⪰ 0`` in every
form; reciprocity reads ``p12 = p21`` in z and y and ``p12 = −p21`` in h and g.

References
----------
.. [1] W. K. Chen, *Active Network Analysis*, World Scientific, 1991, ch. 1
   (two-port parameters and their conversions).
"""

from __future__ import annotations

from collections.abc import Sequence
from enum import StrEnum

import sympy as sp

from ..errors import DegenerateModelError, ParameterError
from .ratfunc import from_sympy, to_sympy, variables_of

__all__ = ["Form", "convert_entries", "form_of", "reciprocity_sign"]


class Form(StrEnum):
    """The immittance form of a two-port (the JSON value is the letter)."""

    Z = "z"
    Y = "y"
    H = "h"
    G = "g"

    @property
    def impedance_ports(self) -> tuple[bool, bool]:
        """For each port, whether its output is the force (an impedance-type port)."""
        return _IMPEDANCE[self]

    @property
    def description(self) -> str:
        """``"impedance (z): [F1, F2] = Z [v1, v2]"`` and so on."""
        return _DESCRIPTION[self]


_IMPEDANCE = {
    Form.Z: (True, True),
    Form.Y: (False, False),
    Form.H: (True, False),
    Form.G: (False, True),
}
_DESCRIPTION = {
    Form.Z: "impedance (z): [F1, F2] = Z [v1, v2]",
    Form.Y: "admittance (y): [v1, v2] = Y [F1, F2]",
    Form.H: "hybrid (h): [F1, v2] = H [v1, F2]",
    Form.G: "inverse hybrid (g): [v1, F2] = G [F1, v2]",
}


def form_of(value: str | Form) -> Form:
    """The `Form` named by ``value`` (``"z"``, ``"Y"``, ...).

    >>> form_of("H")
    <Form.H: 'h'>
    """
    if isinstance(value, Form):
        return value
    text = str(value).strip().lower()
    try:
        return Form(text)
    except ValueError:
        raise ParameterError(
            f"form: {value!r} is not a two-port form; choose one of z, y, h, g",
            argument="form",
        ) from None


def reciprocity_sign(form: Form) -> int:
    """``+1`` when reciprocity reads ``p12 = p21`` (z, y), ``−1`` when ``p12 = −p21`` (h, g)."""
    return 1 if form in (Form.Z, Form.Y) else -1


def _columns(form: Form) -> tuple[list[int], list[int]]:
    """Indices of the outputs and inputs of ``form`` in ``w = (F1, v1, F2, v2)``."""
    out, inp = [], []
    for port, imp in enumerate(form.impedance_ports):
        f, v = 2 * port, 2 * port + 1
        out.append(f if imp else v)
        inp.append(v if imp else f)
    return out, inp


def convert_entries(
    entries: Sequence[sp.Expr], source: Form, target: Form
) -> tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]:
    """The entries ``(p11, p12, p21, p22)`` of the same two-port in form ``target``.

    Raises
    ------
    DegenerateModelError
        When the target form does not exist (its outputs are not determined by
        its inputs), naming the quantity that vanishes identically.

    Examples
    --------
    >>> s = sp.Symbol("s")
    >>> convert_entries([1 / s, 1 / s, 1 / s, 1 / s + 1], Form.Z, Form.H)
    (1/(s + 1), 1/(s + 1), -1/(s + 1), s/(s + 1))
    """
    source, target = form_of(source), form_of(target)
    exprs = [sp.sympify(e) for e in entries]
    if source == target:
        return (exprs[0], exprs[1], exprs[2], exprs[3])
    names = variables_of(exprs)
    p = [from_sympy(e, names) for e in exprs]
    one, zero = from_sympy(sp.S.One, names), from_sympy(sp.S.Zero, names)
    out, inp = _columns(source)
    rel = [[zero] * 4 for _ in range(2)]
    for r in range(2):
        rel[r][out[r]] = one
        for c in range(2):
            rel[r][inp[c]] = -p[2 * r + c]
    t_out, t_in = _columns(target)
    ro = [[rel[r][c] for c in t_out] for r in range(2)]
    ri = [[rel[r][c] for c in t_in] for r in range(2)]
    det = ro[0][0] * ro[1][1] - ro[0][1] * ro[1][0]
    if det.is_zero():
        raise DegenerateModelError(
            f"the {target.value} form does not exist for this two-port: "
            f"{_missing(source, target)} vanishes identically; use another form"
        )
    inv = [[ro[1][1] / det, -ro[0][1] / det], [-ro[1][0] / det, ro[0][0] / det]]
    res = [-(inv[i][0] * ri[0][j] + inv[i][1] * ri[1][j]) for i in range(2) for j in range(2)]
    return to_sympy(res[0]), to_sympy(res[1]), to_sympy(res[2]), to_sympy(res[3])


def _missing(source: Form, target: Form) -> str:
    """Which quantity of ``source`` must not vanish for ``target`` to exist (for messages)."""
    name = source.value
    table = {
        (Form.Z, Form.Y): f"det {name.upper()}",
        (Form.Y, Form.Z): f"det {name.upper()}",
        (Form.H, Form.G): f"det {name.upper()}",
        (Form.G, Form.H): f"det {name.upper()}",
    }
    if (source, target) in table:
        return table[(source, target)]
    # between forms that share one port's type, one diagonal entry must not vanish
    same = [a == b for a, b in zip(source.impedance_ports, target.impedance_ports, strict=True)]
    flipped = same.index(False) + 1 if False in same else 1
    return f"{name}{flipped}{flipped}"
