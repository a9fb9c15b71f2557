"""`TwoPort`: a 2×2 immittance of rational functions of ``s``, from an SEA or given directly.

A `TwoPort` holds its four entries symbolically (cancelled sympy expressions in
``s`` and the parameters), its form (z, y, h or g; see
[`seapass.ports.forms`][seapass.ports.forms]) and parameter values, like
[`Impedance`][seapass.model.impedance.Impedance] does for a one-port.  `two_port`
derives it from an SEA's free-body equations
([`seapass.ports.derive`][seapass.ports.derive]); `TwoPort.from_matrix` takes
four expressions in any form.  `TwoPort.convert` changes the form exactly and
refuses where the target form does not exist; `TwoPort.exact` gives the exact
rational matrix at the values ([`ExactMatrix`][seapass.ports.matrix.ExactMatrix]).
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from ..errors import ModelError, ParameterError
from ..model.display import html_card, short_repr
from ..model.expr import S
from ..model.sea import SEA, check_used
from ..model.zcontroller import continuous_only
from .derive import derive_two_port
from .entries import (
    entry_parameters,
    freeze_values,
    merged_values,
    no_values,
    parse_entries,
    square_entries,
)
from .forms import Form, convert_entries, form_of, reciprocity_sign
from .matrix import ExactMatrix, exact_matrix

__all__ = ["PORT_LABELS", "TwoPort", "two_port"]

PORT_LABELS = ("person", "virtual environment")
"""Default names of port 1 and port 2 of an SEA two-port."""


@dataclass(frozen=True, kw_only=True, repr=False)
class TwoPort:
    """A two-port: four rational functions of ``s`` in one immittance form.

    Parameters
    ----------
    entries : (p11, p12, p21, p22)
        Cancelled sympy expressions in ``s`` and the parameters (build with
        `two_port` or `TwoPort.from_matrix` rather than by hand).
    form : Form or str, default "z"
        Which variables are outputs (see [`Form`][seapass.ports.forms.Form]).
    values : mapping of str to float or None
        Parameter values; None declares a free parameter.
    name : str
        A label for reports.
    ports : (str, str)
        What ports 1 and 2 are, for reports.
    """

    entries: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]
    form: Form = Form.Z
    values: Mapping[str, float | None] = field(default_factory=no_values)
    name: str = ""
    ports: tuple[str, str] = ("port 1", "port 2")

    def __post_init__(self) -> None:
        object.__setattr__(self, "form", form_of(self.form))
        object.__setattr__(self, "values", freeze_values(self.values))
        if len(self.entries) != 4:
            raise ModelError("entries: a two-port has four entries (p11, p12, p21, p22)")
        object.__setattr__(self, "entries", tuple(sp.sympify(e) for e in self.entries))
        object.__setattr__(self, "ports", tuple(str(p) for p in self.ports))

    # ------------------------------------------------------------ construction

    @classmethod
    def from_matrix(
        cls,
        matrix: Any,
        *,
        form: Form | str = Form.Z,
        values: Mapping[str, float | None] | None = None,
        name: str = "",
        ports: tuple[str, str] = ("port 1", "port 2"),
    ) -> TwoPort:
        """A two-port from ``[[p11, p12], [p21, p22]]`` in ``form``.

        Entries are safe text (``"k/s + b"``), sympy expressions or numbers; names
        other than ``s`` and the standard parameters must be keys of ``values``,
        and every key of ``values`` must be used by some entry.

        Examples
        --------
        >>> tp = TwoPort.from_matrix([["b + k/s", "k/s"], ["k/s", "k/s"]],
        ...                          values={"b": 2, "k": 100})
        >>> tp.convert("h").entries[3]
        s/k
        """
        f = form_of(form)
        vals = freeze_values(values)
        raw = square_entries(matrix, 2)
        labels = [f"{f.value}{i}{j}" for i in (1, 2) for j in (1, 2)]
        entries = parse_entries(raw, labels, vals, "the two-port")
        return cls(
            entries=(entries[0], entries[1], entries[2], entries[3]),
            form=f,
            values=vals,
            name=name,
            ports=ports,
        )

    # ------------------------------------------------------------ properties

    @property
    def matrix(self) -> tuple[tuple[sp.Expr, sp.Expr], tuple[sp.Expr, sp.Expr]]:
        """``((p11, p12), (p21, p22))``."""
        e = self.entries
        return ((e[0], e[1]), (e[2], e[3]))

    @functools.cached_property
    def parameters(self) -> tuple[str, ...]:
        """Names of all parameters the entries use, sorted."""
        return entry_parameters(self.entries)

    @property
    def free_parameters(self) -> tuple[str, ...]:
        """Parameters without a numeric value."""
        return tuple(p for p in self.parameters if self.values.get(p) is None)

    @property
    def reciprocal_symbolically(self) -> bool:
        """``p12 = p21`` (z, y) or ``p12 = −p21`` (h, g) for every parameter value."""
        sign = reciprocity_sign(self.form)
        return sp.cancel(sp.together(self.entries[1] - sign * self.entries[2])) == 0

    # ------------------------------------------------------------ transformations

    def convert(self, form: Form | str) -> TwoPort:
        """The same two-port in ``form``; `DegenerateModelError` if that form does not exist."""
        target = form_of(form)
        if target == self.form:
            return self
        entries = convert_entries(self.entries, self.form, target)
        return dataclasses.replace(self, entries=entries, form=target)

    def with_values(self, **values: float | None) -> TwoPort:
        """A copy with some parameter values changed or added (names must be used)."""
        check_used(values, self.parameters, "the two-port")
        return dataclasses.replace(self, values={**self.values, **values})

    def swapped(self) -> TwoPort:
        """The same network with ports 1 and 2 exchanged (z ↔ z, y ↔ y, h ↔ g)."""
        e = self.entries
        swap = {Form.Z: Form.Z, Form.Y: Form.Y, Form.H: Form.G, Form.G: Form.H}
        return dataclasses.replace(
            self, entries=(e[3], e[2], e[1], e[0]), form=swap[self.form], ports=self.ports[::-1]
        )

    def exact(self, values: Mapping[str, float] | None = None) -> ExactMatrix:
        """The exact rational matrix at the parameter values (floats taken as the rationals they are)."""
        merged = merged_values(self.values, values, self.parameters, "the two-port")
        return exact_matrix(self.entries, 2, merged)

    def to_control(self, values: Mapping[str, float] | None = None) -> Any:
        """The 2×2 matrix as a ``control.TransferFunction`` (coefficients exact until rounded).

        Inputs and outputs are named after the form (``v1, v2`` → ``F1, F2`` for z).

        Examples
        --------
        >>> tp = TwoPort.from_matrix([["1 + 1/s", "1/s"], ["1/s", "1/s"]])
        >>> tp.to_control().noutputs, tp.to_control().ninputs
        (2, 2)
        """
        import control

        m = self.exact(values)
        num = [[_floats(m.num[i][j]) for j in range(2)] for i in range(2)]
        den = [[_floats(m.den[i][j]) for j in range(2)] for i in range(2)]
        names = {True: ("F", "v"), False: ("v", "F")}
        outputs = [names[imp][0] + str(i + 1) for i, imp in enumerate(self.form.impedance_ports)]
        inputs = [names[imp][1] + str(i + 1) for i, imp in enumerate(self.form.impedance_ports)]
        return control.tf(num, den, inputs=inputs, outputs=outputs, name=self.name or None)

    # ------------------------------------------------------------ display

    def to_dict(self) -> dict[str, Any]:
        return {
            "form": self.form.value,
            "entries": [[str(e) for e in row] for row in self.matrix],
            "values": dict(self.values),
            "ports": list(self.ports),
            "name": self.name,
        }

    def __repr__(self) -> str:
        f = self.form.value
        fields: dict[str, Any] = {"name": self.name or None, "form": f}
        for (i, j), e in zip(((1, 1), (1, 2), (2, 1), (2, 2)), self.entries, strict=True):
            fields[f"{f}{i}{j}"] = str(e)
        return short_repr("TwoPort", fields)

    def _repr_html_(self) -> str:
        f = self.form.value
        rows: list[tuple[str, Any]] = [("form", self.form.description)]
        rows += [
            (f"{f}{i}{j}(s)", str(e))
            for (i, j), e in zip(((1, 1), (1, 2), (2, 1), (2, 2)), self.entries, strict=True)
        ]
        rows += [("ports", f"1: {self.ports[0]}, 2: {self.ports[1]}")]
        rows += [(k, "free" if v is None else v) for k, v in self.values.items()]
        return html_card(f"Two-port {self.name}".strip(), rows)


def _floats(p: Any) -> list[float]:
    from ..exact.axis import safe_float

    return [safe_float(c) for c in reversed(p.coeffs())] or [0.0]


def two_port(sea: SEA, *, values: Mapping[str, float | None] | None = None) -> TwoPort:
    """The SEA as a two-port between the person (port 1) and the virtual environment (port 2).

    Derived from the free-body equations ([`seapass.ports.derive`][seapass.ports.derive]);
    the result is in impedance form, ``[F_L, F_2] = Z [v_L, v_2]``.  With the
    environment held (``v_2 = 0``), ``z11`` is the one-port ``Z_L`` of
    [`is_passive`][seapass.analysis.passivity.is_passive].

    Parameters
    ----------
    sea : SEA
        The design, with its parameter values.
    values : mapping, optional
        Values overriding or adding to those of ``sea``.

    Returns
    -------
    TwoPort

    Examples
    --------
    >>> from seapass import SEA
    >>> tp = two_port(SEA(D1="k1", CA="kd", values=dict(m=1, b=10, k1=1000, kd=500)))
    >>> tp.entries[0]
    (b*k1*s + k1*kd + k1*m*s**2)/(b*s**2 + k1*s + kd*s + m*s**3)
    """
    if not isinstance(sea, SEA):
        raise ParameterError(
            f"sea: expected an SEA, got {type(sea).__name__} (use TwoPort.from_matrix for a "
            "matrix of expressions)",
            argument="sea",
        )
    continuous_only(sea, "the two-port analysis")
    if values:
        sea = sea.with_values(**values)
    derived = derive_two_port(sea)
    used = set()
    for e in derived.entries:
        used |= {str(x) for x in e.free_symbols if x != S}
    vals = {k: v for k, v in sea.values.items() if k in used}
    return TwoPort(
        entries=derived.entries,
        form=Form.Z,
        values=vals,
        name=sea.name,
        ports=PORT_LABELS,
    )
